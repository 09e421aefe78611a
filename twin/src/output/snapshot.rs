//! Golden-image comparison shared by every rendering test.
//!
//! A test renders a frame and calls [`assert_matches_snapshot`] with a name
//! such as `"pick-and-place-0040"`. The reference is
//! `<snapshots_dir>/<name>.png`; the comparison is per pixel with a
//! tolerance ([`Tolerance::default`] explains the numbers). On a mismatch
//! `<artifacts_dir>/<name>.actual.png` and `<name>.diff.png` are written
//! (use a folder under `target/`) and the error carries the numbers.
//!
//! References change only on purpose:
//! - `UPDATE_SNAPSHOTS=1` rewrites the reference and passes.
//! - A missing reference is written and reported as
//!   [`SnapshotOutcome::Created`] on a developer machine, but is an error
//!   when the `CI` environment variable is set, so CI never invents one.
//!
//! # Examples
//! ```no_run
//! use std::path::Path;
//! # let frame = image::RgbaImage::new(4, 4);
//! let outcome = twin::output::snapshot::assert_matches_snapshot(
//!     "home-0000",
//!     &frame,
//!     Path::new("snapshots"),
//!     Path::new("target/snapshot-artifacts"),
//! )?;
//! # Ok::<(), twin::output::snapshot::SnapshotError>(())
//! ```

use std::path::{Path, PathBuf};

/// How far two images may drift apart and still match.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    /// A pixel differs when any RGBA channel differs by more than this (0..255).
    /// (default: 12)
    pub channel_delta: u8,
    /// The images mismatch when more than this fraction of pixels differ
    /// (0..1). (default: 0.005, i.e. 0.5 %)
    pub differing_fraction: f64,
}

impl Default for Tolerance {
    /// The thresholds, and why:
    ///
    /// - `channel_delta = 12` (about 5 % of full scale): lavapipe computes
    ///   the lighting in LLVM-generated SIMD code and a GPU in its own ALUs
    ///   with different fused-multiply-add, `pow` and sRGB-encoding
    ///   rounding; flat shaded areas then differ by one to three levels,
    ///   occasionally more in highlights. Twelve absorbs that while a wrong
    ///   colour, a missing light or a changed background (tens of levels)
    ///   still counts.
    /// - `differing_fraction = 0.005`: with 4x MSAA the coverage of pixels on
    ///   silhouettes and on the one-pixel grid and trail lines depends on
    ///   sample positions and rasterisation rules that differ between
    ///   drivers, so those edge pixels can differ by far more than twelve.
    ///   They are a thin set — well under 0.5 % of a 640x480 scene frame —
    ///   whereas a moved, missing or extra object changes whole areas.
    fn default() -> Tolerance {
        Tolerance {
            channel_delta: 12,
            differing_fraction: 0.005,
        }
    }
}

/// What the environment asks of a snapshot check.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SnapshotPolicy {
    /// Rewrite the reference instead of comparing (`UPDATE_SNAPSHOTS=1`). (default: false)
    pub update: bool,
    /// Running in CI (`CI` set): a missing reference is an error. (default: false)
    pub ci: bool,
}

impl SnapshotPolicy {
    /// Reads `UPDATE_SNAPSHOTS` (exactly `1` enables it) and `CI` (set to
    /// anything but empty, `0` or `false`).
    #[must_use]
    pub fn from_env() -> SnapshotPolicy {
        let ci = std::env::var_os("CI").is_some_and(|v| !(v.is_empty() || v == "0" || v == "false"));
        SnapshotPolicy {
            update: std::env::var_os("UPDATE_SNAPSHOTS").is_some_and(|v| v == "1"),
            ci,
        }
    }
}

/// A successful snapshot check.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum SnapshotOutcome {
    /// The image matched its reference within the tolerance.
    Matched {
        /// Pixels that differed by more than the channel tolerance.
        differing_pixels: u64,
        /// Largest channel difference seen anywhere (0..255).
        max_channel_delta: u8,
    },
    /// There was no reference; it was written from this image (not in CI).
    Created {
        /// The new reference file.
        reference: PathBuf,
    },
    /// `UPDATE_SNAPSHOTS=1`: the reference was rewritten from this image.
    Updated {
        /// The rewritten reference file.
        reference: PathBuf,
    },
}

/// A failed snapshot check.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SnapshotError {
    /// Too many pixels differ from the reference.
    #[error(
        "snapshot {name}: {differing_pixels} of {total_pixels} pixels differ (max channel delta {max_channel_delta}); see {} and {}",
        actual.display(), diff.display()
    )]
    Mismatch {
        /// Snapshot name.
        name: String,
        /// Pixels that differed by more than the channel tolerance.
        differing_pixels: u64,
        /// Pixels in the image.
        total_pixels: u64,
        /// Largest channel difference (0..255).
        max_channel_delta: u8,
        /// Where this run's image was written.
        actual: PathBuf,
        /// Where the highlighted differences were written.
        diff: PathBuf,
    },
    /// The image and the reference differ in size.
    #[error(
        "snapshot {name}: image is {}x{} px but the reference is {}x{} px; see {}",
        actual_size[0], actual_size[1], reference_size[0], reference_size[1], actual.display()
    )]
    SizeMismatch {
        /// Snapshot name.
        name: String,
        /// Width and height of this run's image (px).
        actual_size: [u32; 2],
        /// Width and height of the reference (px).
        reference_size: [u32; 2],
        /// Where this run's image was written.
        actual: PathBuf,
    },
    /// No reference exists and `CI` is set.
    #[error("snapshot {name}: reference {} is missing (run locally, or with UPDATE_SNAPSHOTS=1, and commit it)", reference.display())]
    MissingReference {
        /// Snapshot name.
        name: String,
        /// The expected reference file.
        reference: PathBuf,
    },
    /// The name is empty or not a plain file stem (`[A-Za-z0-9._-]`, no leading dot).
    #[error("snapshot name {name:?} must be a plain file stem of [A-Za-z0-9._-]")]
    InvalidName {
        /// The rejected name.
        name: String,
    },
    /// A file or folder could not be created, read or written.
    #[error("snapshot file {}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What went wrong.
        #[source]
        source: std::io::Error,
    },
    /// A PNG could not be decoded or encoded.
    #[error("snapshot image {}", path.display())]
    Image {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        #[source]
        source: image::ImageError,
    },
}

/// Per-pixel comparison of two equally sized images.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Comparison {
    /// Pixels where some channel differs by more than the tolerance.
    pub differing_pixels: u64,
    /// Largest channel difference anywhere (0..255).
    pub max_channel_delta: u8,
}

/// Compares `actual` with `<snapshots_dir>/<name>.png` using the default
/// [`Tolerance`] and the environment's [`SnapshotPolicy`] (`UPDATE_SNAPSHOTS`,
/// `CI`). Artifacts of a failure go to `artifacts_dir`.
///
/// # Errors
/// [`SnapshotError::Mismatch`], [`SnapshotError::SizeMismatch`],
/// [`SnapshotError::MissingReference`] (in CI), [`SnapshotError::InvalidName`],
/// or [`SnapshotError::Io`] / [`SnapshotError::Image`] for file trouble.
pub fn assert_matches_snapshot(
    name: &str,
    actual: &image::RgbaImage,
    snapshots_dir: &Path,
    artifacts_dir: &Path,
) -> Result<SnapshotOutcome, SnapshotError> {
    check_snapshot(
        name,
        actual,
        snapshots_dir,
        artifacts_dir,
        Tolerance::default(),
        SnapshotPolicy::from_env(),
    )
}

/// [`assert_matches_snapshot`] with an explicit tolerance and policy (no
/// environment lookups), for tests and callers with their own settings.
///
/// # Errors
/// As [`assert_matches_snapshot`].
pub fn check_snapshot(
    name: &str,
    actual: &image::RgbaImage,
    snapshots_dir: &Path,
    artifacts_dir: &Path,
    tolerance: Tolerance,
    policy: SnapshotPolicy,
) -> Result<SnapshotOutcome, SnapshotError> {
    let plain = |c: char| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-');
    if name.is_empty() || name.starts_with('.') || !name.chars().all(plain) {
        return Err(SnapshotError::InvalidName { name: name.to_owned() });
    }
    let reference = snapshots_dir.join(format!("{name}.png"));
    let actual_path = artifacts_dir.join(format!("{name}.actual.png"));
    let diff_path = artifacts_dir.join(format!("{name}.diff.png"));

    if policy.update {
        write_png(actual, &reference)?;
        return Ok(SnapshotOutcome::Updated { reference });
    }
    if !reference.exists() {
        if policy.ci {
            return Err(SnapshotError::MissingReference {
                name: name.to_owned(),
                reference,
            });
        }
        write_png(actual, &reference)?;
        return Ok(SnapshotOutcome::Created { reference });
    }
    let expected = image::open(&reference)
        .map_err(|source| SnapshotError::Image {
            path: reference.clone(),
            source,
        })?
        .into_rgba8();
    if expected.dimensions() != actual.dimensions() {
        write_png(actual, &actual_path)?;
        return Err(SnapshotError::SizeMismatch {
            name: name.to_owned(),
            actual_size: [actual.width(), actual.height()],
            reference_size: [expected.width(), expected.height()],
            actual: actual_path,
        });
    }
    let comparison = compare(actual, &expected, tolerance.channel_delta);
    let total_pixels = u64::from(actual.width()) * u64::from(actual.height());
    let allowed = tolerance.differing_fraction * total_pixels as f64;
    if comparison.differing_pixels as f64 > allowed {
        write_png(actual, &actual_path)?;
        write_png(&diff_image(actual, &expected, tolerance.channel_delta), &diff_path)?;
        return Err(SnapshotError::Mismatch {
            name: name.to_owned(),
            differing_pixels: comparison.differing_pixels,
            total_pixels,
            max_channel_delta: comparison.max_channel_delta,
            actual: actual_path,
            diff: diff_path,
        });
    }
    // A pass clears artifacts left by an earlier failure.
    for stale in [&actual_path, &diff_path] {
        match std::fs::remove_file(stale) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(SnapshotError::Io {
                    path: stale.clone(),
                    source: e,
                });
            }
            _ => {}
        }
    }
    Ok(SnapshotOutcome::Matched {
        differing_pixels: comparison.differing_pixels,
        max_channel_delta: comparison.max_channel_delta,
    })
}

/// Counts pixels of two equally sized images whose channels differ by more
/// than `channel_delta`. Extra pixels of a larger image are ignored.
#[must_use]
pub fn compare(actual: &image::RgbaImage, expected: &image::RgbaImage, channel_delta: u8) -> Comparison {
    let mut differing_pixels = 0;
    let mut max_channel_delta = 0;
    for (a, e) in actual.pixels().zip(expected.pixels()) {
        let delta = pixel_delta(a.0, e.0);
        max_channel_delta = max_channel_delta.max(delta);
        if delta > channel_delta {
            differing_pixels += 1;
        }
    }
    Comparison {
        differing_pixels,
        max_channel_delta,
    }
}

fn pixel_delta(a: [u8; 4], b: [u8; 4]) -> u8 {
    (0..4).map(|k| a[k].abs_diff(b[k])).max().unwrap_or(0)
}

/// The reference dimmed to grey, with differing pixels in red (brighter for
/// larger differences) and differences within tolerance in dim yellow.
fn diff_image(actual: &image::RgbaImage, expected: &image::RgbaImage, channel_delta: u8) -> image::RgbaImage {
    let mut out = image::RgbaImage::new(actual.width(), actual.height());
    for ((o, a), e) in out.pixels_mut().zip(actual.pixels()).zip(expected.pixels()) {
        let delta = pixel_delta(a.0, e.0);
        let [r, g, b, _] = e.0;
        let luma = (u16::from(r) * 3 + u16::from(g) * 6 + u16::from(b)) / 10;
        let grey = (luma / 3) as u8;
        o.0 = if delta > channel_delta {
            [128 + delta / 2, 0, 0, 255]
        } else if delta > 0 {
            [grey.saturating_add(60), grey.saturating_add(60), grey, 255]
        } else {
            [grey, grey, grey, 255]
        };
    }
    out
}

fn write_png(img: &image::RgbaImage, path: &Path) -> Result<(), SnapshotError> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|source| SnapshotError::Io {
            path: dir.to_owned(),
            source,
        })?;
    }
    img.save_with_format(path, image::ImageFormat::Png)
        .map_err(|source| SnapshotError::Image {
            path: path.to_owned(),
            source,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh folder under `target/` for one test.
    fn scratch(test: &str) -> PathBuf {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../target/snapshot-tests")
            .join(test);
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create scratch folder");
        dir
    }

    fn gradient(width: u32, height: u32) -> image::RgbaImage {
        image::RgbaImage::from_fn(width, height, |x, y| {
            image::Rgba([(x * 7) as u8, (y * 5) as u8, 100, 255])
        })
    }

    const LOCAL: SnapshotPolicy = SnapshotPolicy {
        update: false,
        ci: false,
    };
    const CI: SnapshotPolicy = SnapshotPolicy {
        update: false,
        ci: true,
    };
    const UPDATE: SnapshotPolicy = SnapshotPolicy { update: true, ci: true };

    fn check(
        name: &str,
        img: &image::RgbaImage,
        dir: &Path,
        policy: SnapshotPolicy,
    ) -> Result<SnapshotOutcome, SnapshotError> {
        check_snapshot(
            name,
            img,
            &dir.join("snapshots"),
            &dir.join("artifacts"),
            Tolerance::default(),
            policy,
        )
    }

    #[test]
    fn missing_reference_is_created_locally() {
        let dir = scratch("created");
        let img = gradient(20, 10);
        let outcome = check("scene-0000", &img, &dir, LOCAL).expect("created");
        let reference = dir.join("snapshots/scene-0000.png");
        assert_eq!(
            outcome,
            SnapshotOutcome::Created {
                reference: reference.clone()
            }
        );
        let written = image::open(&reference).expect("reference readable").into_rgba8();
        assert_eq!(written, img);
        // The second run compares against it.
        let again = check("scene-0000", &img, &dir, LOCAL).expect("matches");
        assert_eq!(
            again,
            SnapshotOutcome::Matched {
                differing_pixels: 0,
                max_channel_delta: 0
            }
        );
    }

    #[test]
    fn missing_reference_is_an_error_in_ci() {
        let dir = scratch("missing-ci");
        let err = check("scene-0001", &gradient(4, 4), &dir, CI).expect_err("must fail in CI");
        assert!(matches!(err, SnapshotError::MissingReference { ref name, .. } if name == "scene-0001"));
        assert!(
            !dir.join("snapshots/scene-0001.png").exists(),
            "CI must not write references"
        );
    }

    #[test]
    fn small_differences_within_tolerance_match() {
        let dir = scratch("within");
        let img = gradient(40, 30);
        check("near", &img, &dir, LOCAL).expect("created");
        let mut shifted = img.clone();
        // Every pixel off by the full channel tolerance, plus a few edge
        // pixels far off (below 0.5 % of 1200 pixels = 6).
        for p in shifted.pixels_mut() {
            p.0[0] = p.0[0].saturating_add(12);
        }
        for x in 0..5 {
            shifted.put_pixel(x, 0, image::Rgba([255, 255, 255, 255]));
        }
        match check("near", &shifted, &dir, CI).expect("within tolerance") {
            SnapshotOutcome::Matched {
                differing_pixels,
                max_channel_delta,
            } => {
                assert_eq!(differing_pixels, 5);
                assert!(max_channel_delta > 200);
            }
            other => panic!("unexpected outcome {other:?}"),
        }
    }

    #[test]
    fn mismatch_writes_actual_and_diff_and_reports_numbers() {
        let dir = scratch("mismatch");
        let img = gradient(40, 30);
        check("far", &img, &dir, LOCAL).expect("created");
        let mut changed = img.clone();
        for y in 10..20 {
            for x in 10..20 {
                changed.put_pixel(x, y, image::Rgba([0, 0, 0, 255]));
            }
        }
        let err = check("far", &changed, &dir, CI).expect_err("100 of 1200 pixels changed");
        let SnapshotError::Mismatch {
            differing_pixels,
            total_pixels,
            max_channel_delta,
            actual,
            diff,
            ..
        } = err
        else {
            panic!("unexpected error {err:?}");
        };
        assert_eq!((differing_pixels, total_pixels), (100, 1200));
        assert!(max_channel_delta >= 100);
        assert_eq!(image::open(&actual).expect("actual written").into_rgba8(), changed);
        let diff_img = image::open(&diff).expect("diff written").into_rgba8();
        assert!(diff_img.get_pixel(15, 15).0[0] >= 128 && diff_img.get_pixel(15, 15).0[1] == 0);
        let calm = diff_img.get_pixel(2, 2).0;
        assert_eq!(calm[0], calm[1], "unchanged pixels are grey");
        // The reference is untouched, and a passing run clears the artifacts.
        check("far", &img, &dir, CI).expect("original still matches");
        assert!(!actual.exists() && !diff.exists());
    }

    #[test]
    fn size_mismatch_reports_both_sizes() {
        let dir = scratch("size");
        check("sized", &gradient(8, 6), &dir, LOCAL).expect("created");
        let err = check("sized", &gradient(6, 8), &dir, CI).expect_err("sizes differ");
        let SnapshotError::SizeMismatch {
            actual_size,
            reference_size,
            actual,
            ..
        } = err
        else {
            panic!("unexpected error {err:?}");
        };
        assert_eq!((actual_size, reference_size), ([6, 8], [8, 6]));
        assert!(actual.exists());
    }

    #[test]
    fn update_rewrites_the_reference_even_in_ci() {
        let dir = scratch("update");
        check("upd", &gradient(8, 8), &dir, LOCAL).expect("created");
        let new = image::RgbaImage::from_pixel(8, 8, image::Rgba([1, 2, 3, 255]));
        let outcome = check("upd", &new, &dir, UPDATE).expect("updated");
        assert!(matches!(outcome, SnapshotOutcome::Updated { .. }));
        check("upd", &new, &dir, CI).expect("new reference matches");
    }

    #[test]
    fn path_like_names_are_rejected() {
        let dir = scratch("names");
        for bad in ["", "../escape", "a/b", ".hidden", "sp ace"] {
            let err = check(bad, &gradient(2, 2), &dir, LOCAL).expect_err("bad name");
            assert!(matches!(err, SnapshotError::InvalidName { .. }), "{bad:?}");
        }
    }

    #[test]
    fn corrupt_reference_is_an_image_error() {
        let dir = scratch("corrupt");
        std::fs::create_dir_all(dir.join("snapshots")).expect("mkdir");
        std::fs::write(dir.join("snapshots/bad.png"), b"not a png").expect("write");
        let err = check("bad", &gradient(2, 2), &dir, CI).expect_err("corrupt");
        assert!(matches!(err, SnapshotError::Image { .. }));
    }
}
