//! `filmsplat view` through its HTTP API, as the page drives it: the bubble as disks in the
//! studio (samples/bubble.toml's scene at N particles), orbited one picture at a time while
//! moving (the move pass at ¼ of 960×540 in each side, 240×135, 1 spp), then let go: the first
//! refinement (480×270 at 1 spp) and the final picture (960×540 at the scene's 4 spp).
//!
//! Then a sequence of three frames: the first picture of a new frame, built on demand and
//! prepared ahead, against one final picture.
//!
//! `cargo bench --bench view_http` (1 000 000 and 100 000 particles), or
//! `cargo bench --bench view_http -- 200000` for other counts. Prints frames per second and
//! latencies, with the machine's load (`/proc/loadavg`) beside them.

use filmsplat::scene::SceneDesc;
use filmsplat::view::{App, Frames, Server, token::Token};
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

const TOKEN: &str = "bench";
/// Pictures per orbit measurement.
const ORBIT_FRAMES: usize = 60;

fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|l| l.split(' ').take(3).collect::<Vec<_>>().join(", "))
        .unwrap_or_default()
}

/// CPU seconds this process has used (all threads, user + system), from /proc/self/stat.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map(|(_, r)| r.split_whitespace().collect())
        .unwrap_or_default();
    let ticks = |i: usize| {
        fields
            .get(i)
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    // utime and stime are fields 14 and 15 of the line, 11 and 12 after the command name;
    // clock ticks are 100 a second on Linux.
    (ticks(11) + ticks(12)) / 100.0
}

/// One request on a kept-alive connection; returns the status and the body length.
fn get(c: &mut TcpStream, target: &str) -> (u16, usize) {
    let q = format!("GET {target}&token={TOKEN} HTTP/1.1\r\nHost: bench\r\n\r\n");
    c.write_all(q.as_bytes()).unwrap();
    let mut got = Vec::new();
    let mut buf = [0u8; 65536];
    loop {
        let n = c.read(&mut buf).unwrap();
        assert!(n > 0, "the server closed the connection");
        got.extend_from_slice(&buf[..n]);
        let Some(end) = got.windows(4).position(|w| w == b"\r\n\r\n") else {
            continue;
        };
        let head = String::from_utf8_lossy(&got[..end]).to_lowercase();
        let len: usize = head
            .split("content-length: ")
            .nth(1)
            .and_then(|r| r.split("\r\n").next())
            .and_then(|v| v.parse().ok())
            .unwrap();
        if got.len() >= end + 4 + len {
            let status = head[9..12].parse().unwrap();
            return (status, len);
        }
    }
}

/// The camera `deg` degrees around the bubble.
fn camera(deg: f64) -> String {
    let a = deg.to_radians();
    let (x, z) = (3.8 * a.sin(), 3.8 * a.cos());
    format!("pos={x:.5},0.75,{z:.5}&look=0,-0.15,0&up=0,1,0&fov=40")
}

/// `samples/bubble.toml`'s scene at `particles` particles, `n` frames (frame i at sample time
/// i/4 when there are several).
fn bubble_frames(particles: usize, n: usize) -> Frames {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/samples/bubble.toml"))
        .unwrap()
        .replace("particles = 200000", &format!("particles = {particles}"));
    Frames {
        labels: (0..n).map(|i| i.to_string()).collect(),
        scene: Box::new(move |i| {
            let mut d = SceneDesc::from_toml(&text, "bubble.toml")?;
            if n > 1 {
                d.input.time = Some(i as f32 * 0.25);
            }
            Ok((
                d,
                PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/samples")),
            ))
        }),
        title: "bubble.toml".into(),
    }
}

/// A server for `App` on its own thread and one kept-alive connection to it.
struct Served {
    stop: Arc<AtomicBool>,
    thread: std::thread::JoinHandle<()>,
    conn: TcpStream,
}

impl Served {
    fn start(app: App) -> Served {
        let stop = Arc::new(AtomicBool::new(false));
        let server =
            Arc::new(Server::bind("127.0.0.1:0".parse().unwrap(), app, stop.clone()).unwrap());
        let addr: SocketAddr = server.local_addr();
        let thread = std::thread::spawn(move || server.run());
        let conn = TcpStream::connect(addr).unwrap();
        conn.set_nodelay(true).unwrap();
        Served { stop, thread, conn }
    }

    /// Stops the server, closes the connection and waits for the server's thread.
    fn stop(self) {
        self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
        drop(self.conn);
        self.thread.join().unwrap();
    }
}

fn bench(particles: usize) {
    let t = Instant::now();
    let app = App::new(bubble_frames(particles, 1), Token::fixed(TOKEN), u64::MAX).unwrap();
    let prepared = t.elapsed().as_secs_f64();
    let mut served = Served::start(app);
    let c = &mut served.conn;
    println!(
        "{particles} particles as disks: prepared in {prepared:.1} s (load {})",
        load()
    );
    // Warm up: one picture of each pass.
    for pass in ["move", "draft"] {
        get(
            c,
            &format!(
                "/api/render?{}&w=240&h=135&pass={pass}&client=b",
                camera(0.0)
            ),
        );
    }
    let (t, cpu) = (Instant::now(), cpu_seconds());
    let mut bytes = 0;
    for k in 0..ORBIT_FRAMES {
        let (status, n) = get(
            c,
            &format!(
                "/api/render?{}&w=240&h=135&pass=move&client=b",
                camera(k as f64 * 1.5)
            ),
        );
        assert_eq!(status, 200);
        bytes += n;
    }
    let orbit = t.elapsed().as_secs_f64();
    let cpu = (cpu_seconds() - cpu) / ORBIT_FRAMES as f64;
    println!(
        "  orbit, move pass 240x135 at 1 spp: {:.1} frames/s ({:.1} ms each, {:.1} CPU-ms each, {} KiB PNG) (load {})",
        ORBIT_FRAMES as f64 / orbit,
        orbit * 1e3 / ORBIT_FRAMES as f64,
        cpu * 1e3,
        bytes / ORBIT_FRAMES / 1024,
        load()
    );
    let cam = camera(ORBIT_FRAMES as f64 * 1.5);
    let t = Instant::now();
    let (status, _) = get(
        c,
        &format!("/api/render?{cam}&w=480&h=270&pass=draft&client=b"),
    );
    assert_eq!(status, 200);
    let draft = t.elapsed().as_secs_f64();
    let (status, _) = get(
        c,
        &format!("/api/render?{cam}&w=960&h=540&pass=final&client=b"),
    );
    assert_eq!(status, 200);
    let fin = t.elapsed().as_secs_f64();
    println!(
        "  let go: first refined picture (480x270, 1 spp) after {draft:.2} s, final 960x540 at 4 spp after {fin:.2} s (load {})",
        load()
    );
    served.stop();
}

/// A sequence of the bubble (frames at sample times 0, ¼, ½): how long the first picture of a
/// new frame takes (the move pass, 240x135), without and with the frame prepared ahead (the
/// page asks `/api/prepare` for the next frame once the current one's final picture shows),
/// against one final picture of a prepared frame (960x540 at the scene's 4 spp).
fn next_frame(particles: usize) {
    let app = App::new(bubble_frames(particles, 3), Token::fixed(TOKEN), u64::MAX).unwrap();
    let mut served = Served::start(app);
    let c = &mut served.conn;
    let cam = camera(0.0);
    let mut timed = |target: String| {
        let t = Instant::now();
        assert_eq!(get(c, &target).0, 200, "{target}");
        t.elapsed().as_secs_f64()
    };
    let single = timed(format!(
        "/api/render?{cam}&w=960&h=540&pass=final&client=b&frame=0"
    ));
    let cold = timed(format!(
        "/api/render?{cam}&w=240&h=135&pass=move&client=b&frame=1"
    ));
    let ahead = timed("/api/prepare?frame=2".to_string());
    let warm = timed(format!(
        "/api/render?{cam}&w=240&h=135&pass=move&client=b&frame=2"
    ));
    println!(
        "{particles} particles, a new frame's first picture: {cold:.2} s as it is built ({:.2} × one final picture, {single:.2} s); \
         prepared ahead ({ahead:.2} s while the last frame is looked at): {warm:.3} s ({:.3} ×) (load {})",
        cold / single,
        warm / single,
        load()
    );
    served.stop();
}

fn main() {
    let counts: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let counts = if counts.is_empty() {
        vec![1_000_000, 100_000]
    } else {
        counts
    };
    for n in counts {
        bench(n);
        next_frame(n);
    }
}
