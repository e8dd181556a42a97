//! The preview server's connections: an accept loop that stops when asked, one thread per
//! connection (at most [`MAX_CONNECTIONS`]; beyond, 503), HTTP/1.1 keep-alive with an idle
//! timeout, and a clear status for every request that cannot be read.

use super::api::App;
use super::http::{ReadError, Response, read_request, write_response};
use crate::{Error, Result};
use std::io::BufReader;
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Most connections served at once (a browser opens ~6 a tab).
pub const MAX_CONNECTIONS: usize = 64;
/// An idle keep-alive connection is closed after this long.
const IDLE: Duration = Duration::from_secs(30);
/// How often waiting loops look at the stop flag.
const TICK: Duration = Duration::from_millis(25);

/// A bound server, ready to run.
pub struct Server {
    listener: TcpListener,
    app: Arc<App>,
    active: Arc<AtomicUsize>,
    refusing: Arc<AtomicUsize>,
    stop: Arc<AtomicBool>,
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
        Ok(Server {
            listener,
            app: Arc::new(app),
            active: Arc::new(AtomicUsize::new(0)),
            refusing: Arc::new(AtomicUsize::new(0)),
            stop,
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
            self.app.token().as_str()
        )
    }

    /// The routes' shared state.
    pub fn app(&self) -> &App {
        &self.app
    }

    /// Serves until the stop flag is raised; then cancels the pictures in flight and waits
    /// (at most 2 s) for the connections to finish.
    pub fn run(&self) {
        while !self.stop.load(Ordering::Relaxed) {
            match self.listener.accept() {
                Ok((stream, _)) => self.serve(stream),
                Err(_) => std::thread::sleep(TICK),
            }
        }
        self.app.session().cancel_all();
        let deadline = Instant::now() + Duration::from_secs(2);
        while self.active.load(Ordering::SeqCst) > 0 && Instant::now() < deadline {
            std::thread::sleep(TICK);
        }
    }

    /// Hands a new connection to a thread of its own, or answers 503 when there are too many.
    fn serve(&self, stream: TcpStream) {
        let _ = stream.set_nonblocking(false);
        let _ = stream.set_nodelay(true);
        if self.active.load(Ordering::SeqCst) >= MAX_CONNECTIONS {
            self.refuse_busy(stream);
            return;
        }
        self.active.fetch_add(1, Ordering::SeqCst);
        let (app, active, stop) = (self.app.clone(), self.active.clone(), self.stop.clone());
        let spawned = std::thread::Builder::new()
            .name("filmsplat-view".into())
            .spawn(move || {
                connection(&stream, &app, &stop);
                active.fetch_sub(1, Ordering::SeqCst);
            });
        if spawned.is_err() {
            self.active.fetch_sub(1, Ordering::SeqCst);
        }
    }
}

impl Server {
    /// Answers 503 on a thread of its own (at most [`MAX_CONNECTIONS`] such; beyond, the
    /// connection is dropped): reads what the client sent first, so closing does not reset
    /// the connection before the client reads the answer.
    fn refuse_busy(&self, stream: TcpStream) {
        if self.refusing.fetch_add(1, Ordering::SeqCst) >= MAX_CONNECTIONS {
            self.refusing.fetch_sub(1, Ordering::SeqCst);
            return;
        }
        let refusing = self.refusing.clone();
        let spawned = std::thread::Builder::new()
            .name("filmsplat-view-busy".into())
            .spawn(move || {
                let busy = Response::error(
                    503,
                    &format!("too many connections (at most {MAX_CONNECTIONS}); try again"),
                );
                let _ = stream.set_read_timeout(Some(Duration::from_millis(500)));
                let _ = stream.set_write_timeout(Some(Duration::from_secs(1)));
                let mut reader = BufReader::new(&stream);
                let _ = read_request(&mut reader);
                let _ = write_response(&mut &stream, &busy, false, false);
                let _ = stream.shutdown(std::net::Shutdown::Write);
                refusing.fetch_sub(1, Ordering::SeqCst);
            });
        if spawned.is_err() {
            self.refusing.fetch_sub(1, Ordering::SeqCst);
        }
    }
}

/// Waits until a request starts on `stream` (true) or the peer closes it, it idles for
/// [`IDLE`] or the server stops (false).
fn wait_for_request(stream: &TcpStream, reader: &BufReader<TcpStream>, stop: &AtomicBool) -> bool {
    if !reader.buffer().is_empty() {
        return true;
    }
    let deadline = Instant::now() + IDLE;
    let _ = stream.set_read_timeout(Some(TICK * 10));
    let mut byte = [0u8; 1];
    while !stop.load(Ordering::Relaxed) && Instant::now() < deadline {
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

/// Serves the requests of one connection until it closes, breaks the protocol, idles out or
/// the server stops.
fn connection(stream: &TcpStream, app: &App, stop: &AtomicBool) {
    let Ok(clone) = stream.try_clone() else {
        return;
    };
    let mut reader = BufReader::new(clone);
    let _ = stream.set_write_timeout(Some(Duration::from_secs(60)));
    loop {
        if !wait_for_request(stream, &reader, stop) {
            return;
        }
        let _ = stream.set_read_timeout(app.request_timeout);
        let req = match read_request(&mut reader) {
            Ok(r) => r,
            Err(ReadError::Closed) => return,
            Err(ReadError::Bad(status, message)) => {
                let resp = Response::error(status, &message);
                let _ = write_response(&mut &*stream, &resp, false, false);
                drain(stream, &mut reader);
                return;
            }
        };
        let resp = app.handle(&req, Some(stream));
        let keep = req.keep_alive && !stop.load(Ordering::Relaxed);
        if write_response(&mut &*stream, &resp, req.method == "HEAD", keep).is_err() || !keep {
            return;
        }
    }
}

/// Before closing after a refused request: stops writing and reads (briefly, at most 1 MiB) what
/// the client still sends, so the close does not reset the connection before the client has
/// read the answer.
fn drain(stream: &TcpStream, reader: &mut BufReader<TcpStream>) {
    use std::io::Read;
    let _ = stream.shutdown(std::net::Shutdown::Write);
    let _ = stream.set_read_timeout(Some(Duration::from_millis(200)));
    let mut buf = [0u8; 8192];
    let mut total = 0;
    while total < 1 << 20 {
        match reader.read(&mut buf) {
            Ok(0) | Err(_) => return,
            Ok(n) => total += n,
        }
    }
}
