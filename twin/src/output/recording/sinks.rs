//! Where a recording goes: the sinks a user names (files, standard
//! output, viewers, servers), checked and opened before the run, and what
//! keeps serving after it.

use std::collections::BTreeSet;
use std::net::{SocketAddr, TcpStream, ToSocketAddrs as _};
use std::path::{Path, PathBuf};
use std::time::Duration;

use rerun::RecordingStreamBuilder;
use rerun::external::re_uri::ProxyUri;
use rerun::grpc_server::GrpcServerSink;
use rerun::sink::{FileSink, FileSinkError, GrpcSink, LogSink};

use super::{Recorder, RecordingError};

/// Address of a Rerun viewer's gRPC proxy on this machine (`rerun` listens there by default).
pub const DEFAULT_CONNECT_ADDR: &str = "127.0.0.1:9876";

/// Where [`Sink::Serve`] listens by default: this machine only (give
/// `0.0.0.0:9876` to let other machines connect).
pub const DEFAULT_SERVE_ADDR: &str = "127.0.0.1:9876";

/// How long [`Recorder::new`] waits for a TCP connection to a viewer.
const CONNECT_PROBE_TIMEOUT: Duration = Duration::from_secs(2);

/// Where a [`Recorder`] sends its data.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum Sink {
    /// Write an `.rrd` file at this path (created or truncated), with
    /// Rerun's footer (a manifest of every chunk, which `rerun rrd verify`
    /// checks; it is about half of a short recording's fixed cost).
    File(PathBuf),
    /// Stream to a running Rerun viewer over gRPC.
    ///
    /// Either `host:port` (default: [`DEFAULT_CONNECT_ADDR`]) or a full
    /// `rerun+http://host:port/proxy` URL.
    Connect(String),
    /// Start a Rerun viewer (the `rerun` executable on `PATH`; one already
    /// listening on the default port is used instead) and stream to it.
    Spawn,
    /// Write the `.rrd` stream to standard output (for `| rerun -`); refused
    /// when standard output is a terminal.
    Stdout,
    /// Host a Rerun gRPC server at this `host:port` (default:
    /// [`DEFAULT_SERVE_ADDR`]) that viewers connect to, as Rerun's own
    /// `--serve-grpc` does: `rerun rerun+http://host:port/proxy`.
    /// It keeps up to 1 GiB of the recording for viewers that connect late,
    /// and goes on serving after the run while [`Served::wait`](super::Served::wait) waits.
    Serve(String),
}

impl Sink {
    /// Stream to a viewer at [`DEFAULT_CONNECT_ADDR`].
    pub fn connect_default() -> Self {
        Self::Connect(DEFAULT_CONNECT_ADDR.to_owned())
    }
}

/// A recording's sinks, opened and checked, and what its stream is made
/// with; [`OpenSinks::start`] starts the stream (its threads, the
/// blueprint, the view coordinates).
pub struct OpenSinks {
    app_id: rerun::ApplicationId,
    /// The recording's name and id (`<name>-<unix ms>`).
    recording: Option<(String, String)>,
    blueprint: Option<rerun::blueprint::Blueprint>,
    sinks: Vec<Box<dyn LogSink>>,
    names: String,
    /// The addresses of the [`Sink::Serve`] servers.
    served: Vec<String>,
}

impl std::fmt::Debug for OpenSinks {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OpenSinks")
            .field("sinks", &self.names)
            .finish_non_exhaustive()
    }
}

impl OpenSinks {
    /// Makes this stream the same recording as `other` (its id), so that
    /// sinks opened as two streams show one recording.
    pub fn same_recording_as(&mut self, other: &OpenSinks) {
        if let (Some((_, id)), Some((_, other_id))) = (&mut self.recording, &other.recording) {
            id.clone_from(other_id);
        }
    }

    /// Starts the stream over the sinks and logs the static Z-up view
    /// coordinates.
    ///
    /// # Errors
    ///
    /// [`RecordingError::Stream`] when Rerun cannot start the stream,
    /// [`RecordingError::Log`] when it refuses the view coordinates.
    pub fn start(self) -> Result<Recorder, RecordingError> {
        let mut builder = RecordingStreamBuilder::new(self.app_id);
        if let Some((name, id)) = &self.recording {
            builder = builder
                .recording_id(id.clone())
                .send_properties(true)
                .recording_name(name);
        }
        if let Some(blueprint) = self.blueprint {
            builder = builder.with_default_blueprint(blueprint);
        }
        let stream = builder
            .set_sinks(self.sinks)
            .map_err(|source| RecordingError::Stream { source })?;
        // Simulated time is the recording's clock: the wall-clock `log_time`
        // Rerun would add to every logged row means nothing to a replay and
        // costs an index column per component in the file's footer.
        stream.set_log_time_enabled(false);
        let mut recorder = Recorder {
            stream,
            sim_time_ns: None,
            sink_names: self.names,
            served: self.served,
        };
        recorder.log_static("/", &rerun::archetypes::ViewCoordinates::RIGHT_HAND_Z_UP())?;
        Ok(recorder)
    }
}

impl Recorder {
    /// Opens a recording that tees to every sink in `sinks`, and logs the
    /// static Z-up view coordinates.
    ///
    /// # Errors
    ///
    /// [`RecordingError::NoSinks`] for an empty list,
    /// [`RecordingError::InvalidApplicationId`] for an empty id,
    /// [`RecordingError::DuplicateFile`], [`RecordingError::CreateFile`] (the
    /// path is named), [`RecordingError::InvalidAddress`] and
    /// [`RecordingError::Connect`] when no viewer listens at the address
    /// (the address is named; nothing is buffered).
    pub fn new(application_id: &str, sinks: &[Sink]) -> Result<Self, RecordingError> {
        Self::open(application_id, None, None, sinks)
    }

    /// [`Recorder::new`] with a recording id and name (`recording`: the id
    /// is `<recording>-<unix time in ms>`, unique per run, and the name is
    /// `recording`), and a blueprint the viewer takes as the application's
    /// default layout (a user's own layout, once saved, still wins).
    ///
    /// # Errors
    ///
    /// As [`Recorder::new`].
    pub fn open(
        application_id: &str,
        recording: Option<&str>,
        blueprint: Option<rerun::blueprint::Blueprint>,
        sinks: &[Sink],
    ) -> Result<Self, RecordingError> {
        Self::open_sinks(application_id, recording, blueprint, sinks)?.start()
    }

    /// The part of [`Recorder::open`] that can fail on the user's input
    /// (the application id, addresses, files, viewers), done at once;
    /// [`OpenSinks::start`] then starts the stream, on any thread.
    ///
    /// # Errors
    ///
    /// As [`Recorder::new`].
    pub fn open_sinks(
        application_id: &str,
        recording: Option<&str>,
        blueprint: Option<rerun::blueprint::Blueprint>,
        sinks: &[Sink],
    ) -> Result<OpenSinks, RecordingError> {
        if sinks.is_empty() {
            return Err(RecordingError::NoSinks);
        }
        let app_id =
            rerun::ApplicationId::try_new(application_id).map_err(|_| RecordingError::InvalidApplicationId {
                application_id: application_id.to_owned(),
            })?;
        let mut seen_files = BTreeSet::new();
        for sink in sinks {
            if let Sink::File(path) = sink
                && !seen_files.insert(path.as_path())
            {
                return Err(RecordingError::DuplicateFile { path: path.clone() });
            }
            if matches!(sink, Sink::Stdout) && std::io::IsTerminal::is_terminal(&std::io::stdout()) {
                return Err(RecordingError::StdoutIsTerminal);
            }
        }

        // Check every viewer address (and start a viewer if asked) before
        // creating any file, so a failed connect leaves no empty .rrd behind.
        let mut viewers = Vec::new();
        for sink in sinks {
            match sink {
                Sink::Connect(addr) => {
                    let (uri, socket_addrs) = parse_viewer_address(addr)?;
                    probe_viewer(addr, &socket_addrs)?;
                    viewers.push(uri);
                }
                Sink::Spawn => {
                    let spawned = rerun::spawn(&rerun::SpawnOptions::default())
                        .map_err(|source| RecordingError::Spawn { source })?;
                    let addr = format!("127.0.0.1:{}", spawned.port);
                    let (uri, _) = parse_viewer_address(&addr)?;
                    viewers.push(uri);
                }
                Sink::Serve(addr) => {
                    let socket = parse_serve_address(addr)?;
                    // The server binds on its own thread and only logs when it
                    // cannot: try the address here, so a busy port is an error.
                    std::net::TcpListener::bind(socket).map_err(|source| RecordingError::Serve {
                        addr: addr.clone(),
                        source,
                    })?;
                }
                Sink::File(_) | Sink::Stdout => {}
            }
        }

        let mut log_sinks: Vec<Box<dyn LogSink>> = Vec::with_capacity(sinks.len());
        let mut names = Vec::with_capacity(sinks.len());
        let mut served = Vec::new();
        let mut viewers = viewers.into_iter();
        for sink in sinks {
            match sink {
                Sink::File(path) => {
                    log_sinks.push(Box::new(create_file_sink(path)?));
                    names.push(format!("file {}", path.display()));
                }
                Sink::Connect(_) | Sink::Spawn => {
                    if let Some(uri) = viewers.next() {
                        names.push(format!("viewer {uri}"));
                        log_sinks.push(Box::new(GrpcSink::new(uri)));
                    }
                }
                Sink::Stdout => {
                    let sink = FileSink::stdout().map_err(|source| RecordingError::FileSink {
                        path: PathBuf::from("-"),
                        source,
                    })?;
                    log_sinks.push(Box::new(sink));
                    names.push("standard output".to_owned());
                }
                Sink::Serve(addr) => {
                    let socket = parse_serve_address(addr)?;
                    let server =
                        GrpcServerSink::new(&socket.ip().to_string(), socket.port(), rerun::ServerOptions::default())
                            .map_err(|e| RecordingError::Serve {
                            addr: addr.clone(),
                            source: std::io::Error::new(std::io::ErrorKind::InvalidInput, e),
                        })?;
                    let uri = server.uri().to_string();
                    names.push(format!("server {uri}"));
                    served.push(uri);
                    log_sinks.push(Box::new(server));
                }
            }
        }

        Ok(OpenSinks {
            app_id,
            recording: recording.map(|name| {
                let millis = std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0, |d| d.as_millis());
                (name.to_owned(), format!("{name}-{millis}"))
            }),
            blueprint,
            sinks: log_sinks,
            names: names.join(", "),
            served,
        })
    }
}

fn create_file_sink(path: &Path) -> Result<FileSink, RecordingError> {
    FileSink::new(path).map_err(|err| match err {
        FileSinkError::CreateFile { source, path } => RecordingError::CreateFile { path, source },
        source => RecordingError::FileSink {
            path: path.to_owned(),
            source,
        },
    })
}

/// A [`Sink::Serve`] address, `host:port`, as the socket address to bind.
fn parse_serve_address(addr: &str) -> Result<SocketAddr, RecordingError> {
    addr.trim()
        .to_socket_addrs()
        .ok()
        .and_then(|mut a| a.next())
        .ok_or_else(|| RecordingError::Serve {
            addr: addr.to_owned(),
            source: std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "expected host:port, e.g. 127.0.0.1:9876",
            ),
        })
}

/// Turns `host:port` or a `rerun+http(s)://host:port/proxy` URL into Rerun's
/// proxy URI and the socket addresses to probe.
fn parse_viewer_address(addr: &str) -> Result<(ProxyUri, Vec<SocketAddr>), RecordingError> {
    let invalid = || RecordingError::InvalidAddress { addr: addr.to_owned() };
    let trimmed = addr.trim();
    let (url, host_port) = match trimmed.split_once("://") {
        Some((_, rest)) => {
            let host_port = rest.split('/').next().unwrap_or_default();
            (trimmed.to_owned(), host_port)
        }
        None => (format!("rerun+http://{trimmed}/proxy"), trimmed),
    };
    let uri: ProxyUri = url.parse().map_err(|_| invalid())?;
    let socket_addrs: Vec<SocketAddr> = host_port.to_socket_addrs().map_err(|_| invalid())?.collect();
    if socket_addrs.is_empty() {
        return Err(invalid());
    }
    Ok((uri, socket_addrs))
}

/// Fails unless something accepts a TCP connection at one of `socket_addrs`.
fn probe_viewer(addr: &str, socket_addrs: &[SocketAddr]) -> Result<(), RecordingError> {
    let mut last_error = None;
    for socket_addr in socket_addrs {
        match TcpStream::connect_timeout(socket_addr, CONNECT_PROBE_TIMEOUT) {
            Ok(_) => return Ok(()),
            Err(err) => last_error = Some(err),
        }
    }
    Err(RecordingError::Connect {
        addr: addr.to_owned(),
        source: last_error.unwrap_or_else(|| std::io::ErrorKind::AddrNotAvailable.into()),
    })
}
