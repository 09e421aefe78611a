//! The outputs of a run, read from the [`crate::run::Twin`] after each
//! coarse update.
//!
//! **In:** the twin's state (planner, program, plant). **Out:** the CSV
//! trace ([`trace`]), the JSON summary, PNG frames and the Rerun
//! recording ([`session`]: one type per output, written as the run goes),
//! with the renderer ([`render`], cargo feature `render`), the Rerun
//! logging layer and what a run logs there (`recording`, cargo feature
//! `rerun`) and the golden-image comparison of the snapshot tests
//! ([`snapshot`]).

pub mod axis_faults;
pub mod expect;
#[cfg(feature = "rerun")]
pub mod recording;
#[cfg(feature = "render")]
pub mod render;
pub mod session;
#[cfg(feature = "render")]
pub mod snapshot;
pub(crate) mod status;
pub mod trace;

/// A rendered frame kept for the recording (`twin run --save-frames`,
/// `session::Frames::keep_images`): the camera's name, 8-bit RGB pixels
/// (rows top to bottom), width and height.
pub type KeptImage = (String, Vec<u8>, [u32; 2]);

/// Tint of a link in collision, in frames and the Rerun highlight (red).
pub const COLLISION_TINT_RGBA: [f32; 4] = [1.0, 0.05, 0.05, 0.8];

/// Where a run's Rerun recording goes: `--save`, `--connect`, `--spawn`,
/// `--stdout` (none: no recording).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RecordingTargets {
    /// An `.rrd` file.
    pub save: Option<std::path::PathBuf>,
    /// A viewer's address (`host:port` or a `rerun+http://…/proxy` URL).
    pub connect: Option<String>,
    /// Start a viewer and stream to it.
    pub spawn: bool,
    /// The `.rrd` stream on standard output.
    pub stdout: bool,
    /// A gRPC server's `host:port` that viewers connect to.
    pub serve: Option<String>,
}

impl RecordingTargets {
    /// The flag of the first target asked for, if any.
    pub fn first_flag(&self) -> Option<&'static str> {
        [
            (self.save.is_some(), "--save"),
            (self.connect.is_some(), "--connect"),
            (self.spawn, "--spawn"),
            (self.stdout, "--stdout"),
            (self.serve.is_some(), "--serve"),
        ]
        .into_iter()
        .find_map(|(asked, flag)| asked.then_some(flag))
    }

    /// Whether a viewer may watch as the run goes (`--connect`, `--spawn`,
    /// `--serve`).
    pub fn live(&self) -> bool {
        self.connect.is_some() || self.spawn || self.serve.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::RecordingTargets;
    use super::session::OutputError;

    #[test]
    fn the_first_recording_flag_is_named_in_a_lean_builds_refusal() {
        assert_eq!(RecordingTargets::default().first_flag(), None);
        let targets = RecordingTargets {
            connect: Some("127.0.0.1:9876".into()),
            stdout: true,
            ..RecordingTargets::default()
        };
        assert_eq!(targets.first_flag(), Some("--connect"));
        assert!(targets.live());
        let stdout_only = RecordingTargets {
            stdout: true,
            ..RecordingTargets::default()
        };
        assert_eq!(stdout_only.first_flag(), Some("--stdout"));
        let serve_only = RecordingTargets {
            serve: Some("127.0.0.1:9876".into()),
            ..RecordingTargets::default()
        };
        assert_eq!(serve_only.first_flag(), Some("--serve"));
        assert!(serve_only.live());
        assert!(!stdout_only.live());
        // What a build without the `rerun` feature prints (README, "Errors
        // and exit codes"); the refusal itself is `Recording::new` there.
        let message = OutputError::NoRerun { flag: "--save" }.to_string();
        assert!(
            message.starts_with("--save: ") && message.contains("cargo feature `rerun`"),
            "{message}"
        );
    }
}
