//! What the run's thread hands the recording thread: batches of updates
//! and the items logged as they happen, and how often they are sent.

use planner::instruction::{FbOutputs, MotionInstructionBits};

use super::super::TextLevel;
use crate::plant::mesh::TriMesh;

/// Samples gathered for a file are sent to Rerun every this many coarse
/// updates (and at the end).
pub const FLUSH_UPDATES: u64 = 16_384;

/// The recording thread, when it has nothing else to do, sends the
/// samples gathered over at least this many updates at first (so that
/// little is left to send at the end of a short run), twice as many after
/// each such flush.
pub const IDLE_FLUSH_UPDATES: u64 = 512;

/// Samples gathered for a live viewer are sent at least this often (wall
/// time), so the plots follow the run.
pub const LIVE_FLUSH: std::time::Duration = std::time::Duration::from_millis(100);

/// Colour of the tool trails.
pub(super) const TRAIL_RGBA: [f32; 4] = [1.0, 0.45, 0.0, 1.0];

/// One colour per axis, in axis order (repeating); the actual value is
/// drawn lighter than the command.
pub(super) const AXIS_RGBA: [[f32; 4]; 8] = [
    [0.12, 0.47, 0.71, 1.0],
    [0.84, 0.15, 0.16, 1.0],
    [0.17, 0.63, 0.17, 1.0],
    [0.58, 0.40, 0.74, 1.0],
    [1.00, 0.50, 0.05, 1.0],
    [0.55, 0.34, 0.29, 1.0],
    [0.89, 0.47, 0.76, 1.0],
    [0.09, 0.75, 0.81, 1.0],
];

/// Updates gathered on the run's thread: per update its time, the world
/// poses of the links, its row of values (the trace's after `time_s`, then
/// each axis' actual velocity), the function blocks' outputs and the
/// control structures' bits;
/// and what is logged as it happens, after the update it follows.
#[derive(Default, Clone)]
pub(super) struct Batch {
    pub(super) times_ns: Vec<i64>,
    pub(super) world_from_link: Vec<([f64; 3], [f64; 4])>,
    pub(super) values: Vec<f64>,
    pub(super) fbs: Vec<FbOutputs>,
    pub(super) instructions: Vec<MotionInstructionBits>,
    /// (updates of this batch before it, `sim_time` in ns, what).
    pub(super) items: Vec<(usize, i64, Item)>,
}

/// Something logged as it happens.
#[derive(Clone)]
pub(super) enum Item {
    Trail {
        path: String,
        points: Vec<[f64; 3]>,
    },
    Arrows {
        origins: Vec<[f64; 3]>,
        vectors: Vec<[f64; 3]>,
    },
    Text {
        path: std::borrow::Cow<'static, str>,
        level: TextLevel,
        text: String,
    },
    /// A new state in an entity's lane.
    State {
        path: String,
        label: String,
    },
    Clear {
        path: String,
    },
    /// A mesh in a named frame.
    Mesh {
        path: String,
        frame: String,
        mesh: TriMesh,
    },
    /// A part's pose; with its mesh and colour the first time.
    Part {
        path: String,
        mesh: Option<(TriMesh, [f32; 4])>,
        pose: ([f64; 3], [f64; 4]),
    },
    /// A sensor's beams or ray, coloured by its state.
    Lines {
        path: String,
        segments: Vec<([f64; 3], [f64; 3])>,
        color: [f32; 4],
    },
    /// A camera's rendered frame, 8-bit RGB.
    Image {
        path: String,
        rgb: Vec<u8>,
        size_px: [u32; 2],
    },
}

impl Batch {
    /// Empties the batch, keeping its buffers. The recording threads give
    /// their batches back to the run's thread emptied: memory is then
    /// allocated and freed by the run's thread alone, whose allocator
    /// arena the simulation would otherwise share, lock and wait for.
    pub(super) fn clear(&mut self) {
        self.times_ns.clear();
        self.world_from_link.clear();
        self.values.clear();
        self.fbs.clear();
        self.instructions.clear();
        self.items.clear();
    }
}
