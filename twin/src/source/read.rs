//! Reading an input file with a bound on its size, so that a `/proc`
//! file or a giant never takes the machine's memory: every file the twin
//! reads goes through [`read_bounded`], with the bound of its
//! [`InputKind`] (the README's budget table). Only regular files are read:
//! a device (`/dev/zero`) never ends and a FIFO blocks until written.

use std::io::Read;
use std::path::Path;

/// What an input file is: each kind has its own size bound.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InputKind {
    /// A scene (`*.toml`).
    Scene,
    /// A Structured Text or ladder routine, or an Add-On Instruction export.
    Routine,
    /// A Studio 5000 project export (`*.L5X`).
    L5x,
    /// A robot description (`*.urdf`).
    Urdf,
    /// A mesh (STL or COLLADA).
    Mesh,
}

/// One mebibyte.
const MIB: u64 = 1 << 20;

impl InputKind {
    /// Every kind, in the README's budget-table order.
    pub const ALL: [InputKind; 5] = [
        InputKind::Scene,
        InputKind::Routine,
        InputKind::L5x,
        InputKind::Urdf,
        InputKind::Mesh,
    ];

    /// The largest file of this kind the twin reads, in bytes. A routine
    /// takes about 130 bytes of memory per byte of text once parsed and
    /// compiled, so its bound keeps the largest near half a gigabyte. The
    /// others are many times the largest real file of their kind (a
    /// scene of a few kB, a URDF of a few hundred kB); an L5X export
    /// holds a whole project (the load benchmark's generated one is
    /// 49 MB and takes 0.93 GB), and a binary STL of 10⁶ triangles is
    /// 48 MiB.
    pub const fn max_bytes(self) -> u64 {
        match self {
            InputKind::Scene => 16 * MIB,
            InputKind::Routine => 4 * MIB,
            InputKind::L5x => 64 * MIB,
            InputKind::Urdf => 16 * MIB,
            InputKind::Mesh => 64 * MIB,
        }
    }

    /// The kind in words, as messages name it.
    pub const fn name(self) -> &'static str {
        match self {
            InputKind::Scene => "a scene",
            InputKind::Routine => "a routine",
            InputKind::L5x => "an L5X export",
            InputKind::Urdf => "a URDF",
            InputKind::Mesh => "a mesh",
        }
    }
}

/// Reads the whole file at `path`, refusing one longer than its kind's
/// bound before reading past it. The error is the I/O error, or
/// `InvalidData` saying the bound (callers wrap it with the path).
///
/// # Errors
/// The file cannot be opened or read, or is longer than
/// [`InputKind::max_bytes`].
pub fn read_bounded(path: &Path, kind: InputKind) -> std::io::Result<Vec<u8>> {
    let max = kind.max_bytes();
    // Only a regular file: opening a FIFO waits for a writer forever, and
    // a device (`/dev/zero`, a terminal) is not an input a scene names.
    if !std::fs::metadata(path)?.is_file() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file (a folder, a device or a FIFO)",
        ));
    }
    let file = std::fs::File::open(path)?;
    // The length a regular file states sizes the buffer (never past the
    // bound); a device or pipe states none and grows it as it is read.
    let stated = file.metadata().map(|m| m.len()).unwrap_or(0).min(max);
    let mut bytes = Vec::with_capacity(stated as usize);
    file.take(max + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "longer than {} MiB, the most the twin reads for {}",
                max / MIB,
                kind.name()
            ),
        ));
    }
    Ok(bytes)
}

/// [`read_bounded`] as UTF-8 text.
///
/// # Errors
/// As [`read_bounded`], or `InvalidData` when the bytes are not UTF-8.
pub fn read_text_bounded(path: &Path, kind: InputKind) -> std::io::Result<String> {
    String::from_utf8(read_bounded(path, kind)?)
        .map_err(|_| std::io::Error::new(std::io::ErrorKind::InvalidData, "stream did not contain valid UTF-8"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_device_or_fifo_is_refused_before_it_is_opened() {
        let err = read_bounded(Path::new("/dev/zero"), InputKind::Routine).unwrap_err();
        assert!(err.to_string().contains("not a regular file"), "{err}");
        // A FIFO with no writer: opening it would wait forever.
        let dir = std::env::temp_dir().join(format!("twin-fifo-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fifo = dir.join("scene.toml");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            let err = read_bounded(&fifo, InputKind::Scene).unwrap_err();
            assert!(err.to_string().contains("not a regular file"), "{err}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_file_at_its_kinds_bound_is_read_and_one_byte_more_is_refused() {
        let dir = std::env::temp_dir().join(format!("twin-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("input");
        for kind in InputKind::ALL {
            let max = kind.max_bytes();
            // Sparse files: no disk is written.
            std::fs::File::create(&path).and_then(|f| f.set_len(max)).unwrap();
            assert_eq!(read_bounded(&path, kind).unwrap().len() as u64, max, "{kind:?}");
            std::fs::File::create(&path).and_then(|f| f.set_len(max + 1)).unwrap();
            let err = read_bounded(&path, kind).unwrap_err();
            assert!(err.to_string().contains(kind.name()), "{kind:?}: {err}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
