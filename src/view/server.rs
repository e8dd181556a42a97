//! The preview server's connections: an accept loop that stops when asked, one thread per
//! connection, HTTP/1.1 keep-alive with an idle timeout, a deadline for the whole of each
//! request, and a clear status for every request that cannot be read.
//!
//! Connections are admitted in two classes ([`admission`](super::admission)): a new connection
//! is *pending* (a quota of its own, the oldest closed when it is full, closed at its deadline)
//! until it sends a request with the token; then it holds one of [`MAX_CONNECTIONS`] trusted
//! slots (beyond, 503). Slow or tokenless clients therefore never lock token holders out.

use super::admission::{Deadlined, Pending};
use super::api::App;
use super::http::{ReadError, Response, read_request, write_response};
use crate::{Error, Result};
use std::io::BufReader;
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Most connections of token holders served at once (a browser opens ~6 a tab).
pub const MAX_CONNECTIONS: usize = 64;
/// An idle keep-alive connection is closed after this long.
const IDLE: Duration = Duration::from_secs(30);
/// How often waiting loops look at the stop flag.
const TICK: Duration = Duration::from_millis(25);

/// A bound server, ready to run.
pub struct Server {
    listener: TcpListener,
    shared: Arc<Shared>,
}

/// What the connections' threads share.
struct Shared {
    app: App,
    /// Trusted connections (a request with the token was read on them).
    active: AtomicUsize,
    pending: Pending,
    stop: Arc<AtomicBool>,
}

/// A trusted slot, given back when dropped.
struct Slot<'a>(&'a AtomicUsize);

impl Drop for Slot<'_> {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

impl Shared {
    /// One of the [`MAX_CONNECTIONS`] trusted slots, or `None` if all are held.
    fn take_slot(&self) -> Option<Slot<'_>> {
        let taken = self
            .active
            .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |n| {
                (n < MAX_CONNECTIONS).then_some(n + 1)
            });
        taken.ok().map(|_| Slot(&self.active))
    }
}

impl Server {
    /// Binds `addr` (port 0: any free port) for `app`; [`Server::run`] serves until `stop`
    /// is raised.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the address if it cannot be bound (in use, not local).
    pub fn bind(addr: SocketAddr, app: App, stop: Arc<AtomicBool>) -> Result<Server> {
        let listener = TcpListener::bind(addr)
            .map_err(|e| Error::invalid(format!("cannot listen on {addr}: {e}")))?;
        listener
            .set_nonblocking(true)
            .map_err(|e| Error::invalid(format!("{addr}: {e}")))?;
        let shared = Shared {
            app,
            active: AtomicUsize::new(0),
            pending: Pending::default(),
            stop,
        };
        Ok(Server {
            listener,
            shared: Arc::new(shared),
        })
    }

    /// The address bound (with the port chosen for port 0).
    pub fn local_addr(&self) -> SocketAddr {
        self.listener
            .local_addr()
            .expect("a bound listener has an address")
    }

    /// The URL to open, token included. A server bound to every address (0.0.0.0, ::) is
    /// shown at localhost.
    pub fn url(&self) -> String {
        let a = self.local_addr();
        let host = match a.ip() {
            ip if ip.is_unspecified() => "localhost".to_string(),
            std::net::IpAddr::V6(ip) => format!("[{ip}]"),
            ip => ip.to_string(),
        };
        format!(
            "http://{host}:{}/?token={}",
            a.port(),
            self.app().token().as_str()
        )
    }

    /// The routes' shared state.
    pub fn app(&self) -> &App {
        &self.shared.app
    }

    /// How many connections are pending (have not yet sent a request with the token).
    pub fn pending(&self) -> usize {
        self.shared.pending.len()
    }

    /// Serves until the stop flag is raised; then closes the pending connections, cancels the
    /// pictures in flight and waits (at most 2 s) for the connections to finish.
    pub fn run(&self) {
        let stop = &self.shared.stop;
        while !stop.load(Ordering::Relaxed) {
            match self.listener.accept() {
                Ok((stream, _)) => self.serve(stream),
                Err(_) => std::thread::sleep(TICK),
            }
        }
        self.shared.pending.close_all();
        self.app().session().cancel_all();
        let deadline = Instant::now() + Duration::from_secs(2);
        while self.shared.active.load(Ordering::SeqCst) > 0 && Instant::now() < deadline {
            std::thread::sleep(TICK);
        }
    }

    /// Admits a new connection as pending (closing the oldest pending one if their quota is
    /// full) and hands it to a thread of its own.
    fn serve(&self, stream: TcpStream) {
        let _ = stream.set_nonblocking(false);
        let _ = stream.set_nodelay(true);
        let id = self.shared.pending.admit(&stream);
        let shared = self.shared.clone();
        let spawned = std::thread::Builder::new()
            .name("filmsplat-view".into())
            .spawn(move || {
                connection(&stream, &shared, id);
                shared.pending.leave(id);
            });
        if spawned.is_err() {
            self.shared.pending.leave(id);
        }
    }
}

/// Waits until a request starts on `stream` (true) or the peer closes it, `until` passes or
/// the server stops (false).
fn wait_for_request(
    stream: &TcpStream,
    reader: &BufReader<Deadlined>,
    stop: &AtomicBool,
    until: Instant,
) -> bool {
    if !reader.buffer().is_empty() {
        return true;
    }
    let mut byte = [0u8; 1];
    while !stop.load(Ordering::Relaxed) {
        let left = until.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return false;
        }
        let _ = stream.set_read_timeout(Some(left.min(TICK * 10)));
        match stream.peek(&mut byte) {
            Ok(0) => return false,
            Ok(_) => return true,
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock
                        | std::io::ErrorKind::TimedOut
                        | std::io::ErrorKind::Interrupted
                ) => {}
            Err(_) => return false,
        }
    }
    false
}

/// Serves the requests of one connection until it closes, breaks the protocol, misses its
/// deadline, idles out or the server stops. Pending (`id`) until a request with the token
/// takes a trusted slot; a pending connection is closed after its one answer.
fn connection(stream: &TcpStream, shared: &Shared, id: u64) {
    let Ok(clone) = stream.try_clone() else {
        return;
    };
    let app = &shared.app;
    let opened = Instant::now();
    let mut reader = BufReader::new(Deadlined::new(clone, app.request_timeout));
    let _ = stream.set_write_timeout(Some(Duration::from_secs(60)));
    let mut slot = None;
    loop {
        let pending_until = opened + app.request_deadline;
        let idle_until = match slot {
            None => pending_until,
            Some(_) => Instant::now() + IDLE,
        };
        if !wait_for_request(stream, &reader, &shared.stop, idle_until) {
            return;
        }
        reader.get_mut().until = match slot {
            None => pending_until,
            Some(_) => Instant::now() + app.request_deadline,
        };
        let req = match read_request(&mut reader) {
            Ok(r) => r,
            Err(ReadError::Closed) => return,
            Err(ReadError::Bad(status, message)) => {
                return refuse(stream, &mut reader, &Response::error(status, &message));
            }
        };
        if slot.is_none() && app.authorized(&req) {
            let Some(s) = shared.take_slot() else {
                let busy = format!("too many connections (at most {MAX_CONNECTIONS}); try again");
                return refuse(stream, &mut reader, &Response::error(503, &busy));
            };
            slot = Some(s);
            shared.pending.leave(id);
        }
        let resp = app.handle(&req, Some(stream));
        let keep = req.keep_alive && slot.is_some() && !shared.stop.load(Ordering::Relaxed);
        if write_response(&mut &*stream, &resp, req.method == "HEAD", keep).is_err() || !keep {
            return;
        }
    }
}

/// Answers `resp` and closes, after draining what the client still sends.
fn refuse(stream: &TcpStream, reader: &mut BufReader<Deadlined>, resp: &Response) {
    let _ = write_response(&mut &*stream, resp, false, false);
    drain(stream, reader);
}

/// Before closing after a refused request: stops writing and reads (briefly, at most 1 MiB) what
/// the client still sends, so the close does not reset the connection before the client has
/// read the answer.
fn drain(stream: &TcpStream, reader: &mut BufReader<Deadlined>) {
    use std::io::Read;
    let _ = stream.shutdown(std::net::Shutdown::Write);
    reader.get_mut().until = Instant::now() + Duration::from_millis(200);
    let mut buf = [0u8; 8192];
    let mut total = 0;
    while total < 1 << 20 {
        match reader.read(&mut buf) {
            Ok(0) | Err(_) => return,
            Ok(n) => total += n,
        }
    }
}
