//! Why a recording cannot be made or a value cannot be logged.

use std::path::PathBuf;

use rerun::RecordingStreamError;
use rerun::sink::{FileSinkError, SinkFlushError};

/// What is wrong with a mesh handed to [`super::Recorder::log_link_mesh_static`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum MeshDefect {
    /// The index count is not a multiple of three.
    PartialTriangle {
        /// Number of indices.
        index_count: usize,
    },
    /// An index points past the last vertex.
    IndexOutOfRange {
        /// The offending index value.
        index: u32,
        /// Number of vertex positions.
        vertex_count: usize,
    },
    /// There are normals, but not one per position.
    NormalCountMismatch {
        /// Number of normals.
        normal_count: usize,
        /// Number of vertex positions.
        vertex_count: usize,
    },
    /// A position or normal is NaN or infinite.
    NonFiniteVertex {
        /// Index of the vertex.
        vertex: usize,
    },
}

/// Which input of a log call held a NaN or infinite value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Quantity {
    /// A translation.
    Translation,
    /// A rotation quaternion (also: zero length).
    Rotation,
    /// A scale factor (also: zero).
    Scale,
    /// A line-strip point.
    Point,
    /// The lengths of a column's times and values (they must be equal).
    ColumnLength,
}

/// Failures of [`super::Recorder`].
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RecordingError {
    /// [`super::Recorder::new`] was given no sink.
    #[error("no recording sink given")]
    NoSinks,
    /// The application id is empty.
    #[error("invalid Rerun application id {application_id:?}")]
    InvalidApplicationId {
        /// The id as given.
        application_id: String,
    },
    /// The same file was named twice.
    #[error("recording file {path} given more than once")]
    DuplicateFile {
        /// The repeated path.
        path: PathBuf,
    },
    /// The `.rrd` file could not be created.
    #[error("cannot create recording file {path}")]
    CreateFile {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The file sink failed to start (other than creating the file).
    #[error("cannot start writing recording file {path}")]
    FileSink {
        /// The file.
        path: PathBuf,
        /// Rerun's error.
        #[source]
        source: FileSinkError,
    },
    /// A [`super::sinks::Sink::Connect`] address is neither `host:port` nor a Rerun proxy URL.
    #[error("invalid Rerun viewer address {addr:?}")]
    InvalidAddress {
        /// The address as given.
        addr: String,
    },
    /// [`super::sinks::Sink::Spawn`] could not start a viewer.
    #[error("cannot start a Rerun viewer (is the `rerun` executable on PATH? `pip install rerun-sdk==0.36.3`)")]
    Spawn {
        /// Rerun's error.
        #[source]
        source: rerun::SpawnError,
    },
    /// [`super::sinks::Sink::Stdout`] with standard output a terminal.
    #[error("standard output is a terminal: pipe it into a viewer (`twin run SCENE --stdout | rerun -`)")]
    StdoutIsTerminal,
    /// Nothing accepted a connection at a [`super::sinks::Sink::Connect`] address.
    #[error("cannot connect to a Rerun viewer at {addr} (is `rerun` running?)")]
    Connect {
        /// The address as given.
        addr: String,
        /// The last connection error.
        #[source]
        source: std::io::Error,
    },
    /// Rerun refused to create the recording stream.
    #[error("cannot create the Rerun recording stream")]
    Stream {
        /// Rerun's error.
        #[source]
        source: RecordingStreamError,
    },
    /// Rerun refused to log data at an entity.
    #[error("cannot log to Rerun entity {entity_path}")]
    Log {
        /// The entity path.
        entity_path: String,
        /// Rerun's error.
        #[source]
        source: RecordingStreamError,
    },
    /// A value handed to a log call was NaN, infinite or degenerate.
    #[error("invalid {quantity:?} for Rerun entity {entity_path}")]
    InvalidValue {
        /// The entity path.
        entity_path: String,
        /// Which input.
        quantity: Quantity,
    },
    /// A mesh handed to [`super::Recorder::log_link_mesh_static`] is malformed.
    #[error("invalid mesh for Rerun entity {entity_path}: {defect:?}")]
    InvalidMesh {
        /// The entity path.
        entity_path: String,
        /// What is wrong.
        defect: MeshDefect,
    },
    /// A [`super::sinks::Sink::Serve`] address cannot be listened on (in use, not
    /// this machine's, not allowed).
    #[error("cannot serve a recording at {addr}")]
    Serve {
        /// The address as given.
        addr: String,
        /// Why binding failed.
        #[source]
        source: std::io::Error,
    },
    /// The recording thread could not start, or stopped without a result.
    #[error("{why}")]
    Worker {
        /// What happened.
        why: String,
    },
    /// Not all data reached the sinks when the recording was finished.
    #[error("flushing the recording to {sinks} failed")]
    Flush {
        /// The sinks, as "file PATH, viewer ADDR".
        sinks: String,
        /// Rerun's error.
        #[source]
        source: SinkFlushError,
    },
}
