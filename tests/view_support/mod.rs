//! A preview server run in-process on a free port, and a raw HTTP/1.1 client for it.
#![allow(dead_code)]

use filmsplat::scene::SceneDesc;
use filmsplat::view::{App, Frames, Server, token::Token};
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;

// A test that takes both support modules loads this one twice: two sweeps, no harm.
#[allow(clippy::duplicate_mod)]
#[path = "../scratch/mod.rs"]
mod scratch;

/// A small bubble at a small size: quick to prepare and render.
pub const SCENE: &str =
    "[input]\nsample = \"bubble\"\nparticles = 2000\n[render]\nwidth = 64\nheight = 36\n";
/// The token of every test server.
pub const TOKEN: &str = "0123456789abcdef0123456789abcdef";
/// A camera looking at the bubble.
pub const CAMERA: &str = "pos=0.9,0.8,2.9&look=0,0,0&up=0,1,0&fov=40";

/// A server running on its own thread; stopped and joined when dropped.
pub struct Running {
    pub server: Arc<Server>,
    pub addr: SocketAddr,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Drop for Running {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            t.join().unwrap();
        }
    }
}

impl Running {
    pub fn stats(&self) -> &filmsplat::view::session::Stats {
        &self.server.app().session().stats
    }

    /// Raises the stop flag and waits for the accept loop to return.
    pub fn stop(mut self) {
        self.stop.store(true, Ordering::Relaxed);
        self.thread.take().unwrap().join().unwrap();
    }
}

/// `n` frames of `toml`, frame i at sample time i/4.
pub fn frames(toml: &'static str, n: usize) -> Frames {
    Frames {
        labels: (0..n).map(|i| format!("{i}")).collect(),
        scene: Box::new(move |i| {
            let mut d = SceneDesc::from_toml(toml, "test.toml")?;
            d.input.time = Some(i as f32 * 0.25);
            Ok((d, PathBuf::new()))
        }),
        title: "test.toml".into(),
    }
}

/// Starts a server for `frames`, keeping `budget` bytes of prepared variants.
pub fn start_frames(frames: Frames, budget: u64) -> Running {
    serve(App::new(frames, Token::fixed(TOKEN), budget).unwrap())
}

/// Starts a server for one frame of `toml`, giving each request `deadline` to arrive whole.
pub fn start_with_deadline(toml: &'static str, deadline: std::time::Duration) -> Running {
    let mut app = App::new(frames(toml, 1), Token::fixed(TOKEN), u64::MAX).unwrap();
    app.request_deadline = deadline;
    serve(app)
}

/// Serves `app` on a free port of 127.0.0.1.
pub fn serve(app: App) -> Running {
    let stop = Arc::new(AtomicBool::new(false));
    let server = Arc::new(Server::bind("127.0.0.1:0".parse().unwrap(), app, stop.clone()).unwrap());
    let addr = server.local_addr();
    let s = server.clone();
    let thread = Some(std::thread::spawn(move || s.run()));
    Running {
        server,
        addr,
        stop,
        thread,
    }
}

/// Starts a server for one frame of `toml`.
pub fn start(toml: &'static str) -> Running {
    start_frames(frames(toml, 1), u64::MAX)
}

/// A response.
#[derive(Debug)]
pub struct Resp {
    pub status: u16,
    pub headers: Vec<(String, String)>,
    pub body: Vec<u8>,
}

impl Resp {
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(name))
            .map(|(_, v)| v.as_str())
    }

    pub fn text(&self) -> String {
        String::from_utf8_lossy(&self.body).into_owned()
    }
}

/// Parses one response from `bytes` (the whole of what the server sent).
pub fn parse(bytes: &[u8]) -> Resp {
    let end = bytes
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .unwrap_or_else(|| panic!("no header end in {:?}", String::from_utf8_lossy(bytes)));
    let head = String::from_utf8(bytes[..end].to_vec()).unwrap();
    let mut lines = head.split("\r\n");
    let status = lines
        .next()
        .unwrap()
        .split(' ')
        .nth(1)
        .unwrap()
        .parse()
        .unwrap();
    let headers = lines
        .map(|l| {
            let (k, v) = l.split_once(':').unwrap();
            (k.to_string(), v.trim().to_string())
        })
        .collect();
    Resp {
        status,
        headers,
        body: bytes[end + 4..].to_vec(),
    }
}

/// Sends `raw` bytes on a new connection and reads until the server closes it.
pub fn raw(addr: SocketAddr, raw: &[u8]) -> Resp {
    let mut s = TcpStream::connect(addr).unwrap();
    s.write_all(raw).unwrap();
    let mut out = Vec::new();
    s.read_to_end(&mut out).unwrap();
    parse(&out)
}

/// GET `target` (token added unless it has one or `token` is false).
pub fn get(addr: SocketAddr, target: &str) -> Resp {
    let sep = if target.contains('?') { '&' } else { '?' };
    let target = if target.contains("token=") {
        target.to_string()
    } else {
        format!("{target}{sep}token={TOKEN}")
    };
    raw(
        addr,
        format!("GET {target} HTTP/1.1\r\nHost: test\r\nConnection: close\r\n\r\n").as_bytes(),
    )
}

/// GET without any token.
pub fn get_no_token(addr: SocketAddr, target: &str) -> Resp {
    raw(
        addr,
        format!("GET {target} HTTP/1.1\r\nHost: test\r\nConnection: close\r\n\r\n").as_bytes(),
    )
}

/// A PNG's size and RGB8 pixels.
pub fn decode(png: &[u8]) -> (u32, u32, Vec<u8>) {
    let img = image::load_from_memory(png).unwrap().to_rgb8();
    let (w, h) = img.dimensions();
    (w, h, img.into_raw())
}

/// A fresh temporary path ending in `name`.
pub fn temp(name: &str) -> PathBuf {
    static N: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = N.fetch_add(1, Ordering::Relaxed);
    scratch::dir("view").join(format!("{n}-{name}"))
}
