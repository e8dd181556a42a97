//! `filmsplat view` under abuse: malformed requests, huge sizes, bad parameters, closed tabs,
//! competing tabs, too many connections, a frame that fails, a stop: each gets a clear HTTP
//! error or is ignored, and the server keeps serving. No test depends on timing: waits are for
//! events, with generous caps.

mod view_support;

use std::io::{Read, Write};
use std::net::TcpStream;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};
use view_support::*;

/// Waits (up to a minute) for `cond`.
fn wait_for(what: &str, cond: impl Fn() -> bool) {
    let deadline = Instant::now() + Duration::from_secs(60);
    while !cond() {
        assert!(Instant::now() < deadline, "gave up waiting for {what}");
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// A picture that takes seconds on any machine: 2048x2048 at 16 spp.
const SLOW: &str = "w=2048&h=2048&pass=final&preset=final";

fn still_serving(s: &Running) {
    let r = get(s.addr, &format!("/api/render?{CAMERA}&w=16&h=9"));
    assert_eq!(r.status, 200, "the server stopped serving: {}", r.text());
}

#[test]
fn malformed_requests_get_a_4xx_and_the_server_keeps_serving() {
    let s = start(SCENE);
    let long_line = format!("GET /{} HTTP/1.1\r\n\r\n", "a".repeat(10_000));
    let many_headers = format!("GET / HTTP/1.1\r\n{}\r\n", "X-A: b\r\n".repeat(200));
    let cases: Vec<(&[u8], u16)> = vec![
        (b"HELLO\r\n\r\n", 400),
        (b"GET / HTTP/1.1\r\nbroken header\r\n\r\n", 400),
        (
            b"POST /api/render HTTP/1.1\r\nContent-Length: 4\r\n\r\nabcd",
            413,
        ),
        (b"PUT / HTTP/1.1\r\n\r\n", 405),
        (b"GET / HTTP/3\r\n\r\n", 505),
        (b"GET /?a=%zz HTTP/1.1\r\n\r\n", 400),
        (b"GET / HTTP/1.1\r\n\xff\xfe\r\n\r\n", 400),
        (long_line.as_bytes(), 431),
        (many_headers.as_bytes(), 431),
    ];
    for (request, status) in cases {
        let r = raw(s.addr, request);
        assert_eq!(
            r.status,
            status,
            "{:?}: {}",
            String::from_utf8_lossy(request),
            r.text()
        );
        assert!(!r.text().trim().is_empty(), "a reason is given");
        assert_eq!(r.header("connection"), Some("close"));
    }
    // Half a request, then the client goes away.
    let mut half = TcpStream::connect(s.addr).unwrap();
    half.write_all(b"GET /api/sce").unwrap();
    drop(half);
    still_serving(&s);
}

#[test]
fn bad_parameters_and_huge_sizes_are_refused_with_their_reason() {
    let s = start_frames(frames(SCENE, 2), u64::MAX);
    for (query, status, says) in [
        ("/api/render?w=16&h=9", 400, "pos"),
        (
            &format!("/api/render?{CAMERA}&w=100000&h=100000") as &str,
            413,
            "100000x100000",
        ),
        (&format!("/api/save?{CAMERA}&w=9000&h=10"), 413, "9000x10"),
        (
            &format!("/api/render?{CAMERA}&w=16&h=9&frame=2"),
            400,
            "frame",
        ),
        (
            &format!("/api/render?{CAMERA}&w=16&h=9&view=x"),
            400,
            "view",
        ),
        (
            &format!("/api/render?{CAMERA}&w=16&h=9&client=a%20b"),
            400,
            "client",
        ),
        (
            "/api/camera?pos=1,1,1&look=1,1,1&up=0,1,0",
            400,
            "same point",
        ),
    ] {
        let r = get(s.addr, query);
        assert_eq!(r.status, status, "{query}: {}", r.text());
        assert!(r.text().contains(says), "{query}: {}", r.text());
    }
    assert!(filmsplat::view::engine::check_pixels(100_000, 100_000).is_err());
    assert!(filmsplat::view::engine::check_pixels(100, 100).is_ok());
    still_serving(&s);
}

#[test]
fn a_frame_that_fails_to_load_is_a_422_and_the_others_still_work() {
    let mut f = frames(SCENE, 2);
    let good = f.scene;
    f.scene = Box::new(move |i| match i {
        1 => Err(filmsplat::Error::invalid("frame_0001.ply: no such file")),
        _ => good(i),
    });
    let s = start_frames(f, u64::MAX);
    for _ in 0..2 {
        // Not cached: asked again, it is tried again.
        let r = get(s.addr, &format!("/api/render?{CAMERA}&w=16&h=9&frame=1"));
        assert_eq!(r.status, 422);
        assert!(
            r.text().contains("frame_0001.ply: no such file"),
            "{}",
            r.text()
        );
    }
    still_serving(&s);
}

#[test]
fn a_tab_closed_in_mid_render_cancels_its_render() {
    let s = start(SCENE);
    let mut tab = TcpStream::connect(s.addr).unwrap();
    let request = format!("GET /api/render?token={TOKEN}&{CAMERA}&{SLOW} HTTP/1.1\r\n\r\n");
    tab.write_all(request.as_bytes()).unwrap();
    wait_for("the render to start", || {
        s.stats().active.load(Ordering::SeqCst) == 1
    });
    drop(tab);
    wait_for("the render to end", || {
        s.stats().active.load(Ordering::SeqCst) == 0
    });
    assert_eq!(s.stats().cancelled.load(Ordering::SeqCst), 1);
    assert_eq!(s.stats().rendered.load(Ordering::SeqCst), 0);
    still_serving(&s);
}

#[test]
fn a_tabs_new_picture_cancels_its_old_one_but_not_another_tabs() {
    let s = start(SCENE);
    let slow = |client: &str| {
        let mut tab = TcpStream::connect(s.addr).unwrap();
        let q = format!(
            "GET /api/render?token={TOKEN}&{CAMERA}&{SLOW}&client={client} HTTP/1.1\r\nConnection: close\r\n\r\n"
        );
        tab.write_all(q.as_bytes()).unwrap();
        tab
    };
    let mut first = slow("tab-a");
    wait_for("tab a's render", || {
        s.stats().active.load(Ordering::SeqCst) == 1
    });
    // Tab a asks for a new (small) picture: its slow one stops with 409.
    let r = get(
        s.addr,
        &format!("/api/render?{CAMERA}&w=16&h=9&client=tab-a"),
    );
    assert_eq!(r.status, 200);
    let mut out = Vec::new();
    first.read_to_end(&mut out).unwrap();
    let old = parse(&out);
    assert_eq!(old.status, 409, "{}", old.text());
    assert!(old.text().contains("cancelled"));
    // Tab b's picture is not tab c's business: both finish.
    let small = |client: &'static str| {
        let addr = s.addr;
        std::thread::spawn(move || {
            get(
                addr,
                &format!("/api/render?{CAMERA}&w=40&h=30&pass=final&client={client}"),
            )
            .status
        })
    };
    let (b, c) = (small("tab-b"), small("tab-c"));
    assert_eq!((b.join().unwrap(), c.join().unwrap()), (200, 200));
}

#[test]
fn many_tabs_at_once_all_get_their_pictures() {
    let s = start_frames(frames(SCENE, 2), u64::MAX);
    let tabs: Vec<_> = (0..8)
        .map(|t| {
            let addr = s.addr;
            std::thread::spawn(move || {
                (0..3)
                    .map(|k| {
                        let q = format!(
                            "/api/render?{CAMERA}&w={}&h=9&frame={}&client=t{t}&view={}",
                            16 + k,
                            (t + k) % 2,
                            ["shaded", "thickness"][k % 2]
                        );
                        let r = get(addr, &q);
                        (r.status, decode(&r.body).0)
                    })
                    .collect::<Vec<_>>()
            })
        })
        .collect();
    for t in tabs {
        assert_eq!(t.join().unwrap(), vec![(200, 16), (200, 17), (200, 18)]);
    }
    // Two frames, each built once however many tabs asked at the same time.
    assert_eq!(s.stats().builds.load(Ordering::SeqCst), 2);
}

#[test]
fn beyond_the_connection_limit_a_503_and_then_service_again() {
    let s = start(SCENE);
    let limit = filmsplat::view::server::MAX_CONNECTIONS;
    // Hold `limit` keep-alive connections of token holders open, each with one answered
    // request.
    let held: Vec<TcpStream> = (0..limit)
        .map(|_| {
            let mut c = TcpStream::connect(s.addr).unwrap();
            let req = format!("GET /api/camera?token={TOKEN}&{CAMERA} HTTP/1.1\r\n\r\n");
            c.write_all(req.as_bytes()).unwrap();
            assert_eq!(read_one(&mut c).status, 200);
            c
        })
        .collect();
    let r = get(s.addr, "/api/scene");
    assert_eq!(r.status, 503);
    assert!(r.text().contains("too many connections"), "{}", r.text());
    drop(held);
    wait_for("the server to serve again", || {
        get(s.addr, "/api/scene").status == 200
    });
}

#[test]
fn keep_alive_serves_several_requests_on_one_connection() {
    let s = start(SCENE);
    let mut c = TcpStream::connect(s.addr).unwrap();
    for _ in 0..3 {
        c.write_all(format!("GET /api/camera?token={TOKEN}&{CAMERA} HTTP/1.1\r\n\r\n").as_bytes())
            .unwrap();
        let r = read_one(&mut c);
        assert_eq!(r.status, 200);
        assert_eq!(r.header("connection"), Some("keep-alive"));
        assert!(r.text().starts_with("[camera]"));
    }
}

#[test]
fn stopping_cancels_the_render_in_flight_and_returns() {
    let s = start(SCENE);
    let addr = s.addr;
    let tab = std::thread::spawn(move || {
        get(addr, &format!("/api/render?{CAMERA}&{SLOW}&client=busy")).status
    });
    wait_for("the render", || {
        s.stats().active.load(Ordering::SeqCst) == 1
    });
    s.stop();
    assert_eq!(tab.join().unwrap(), 409);
    assert!(TcpStream::connect(addr).is_err() || get_is_refused(addr));
}

/// Reads one response (head and `Content-Length` body) from a kept-alive connection.
fn read_one(c: &mut TcpStream) -> Resp {
    let mut got = Vec::new();
    let mut buf = [0u8; 4096];
    loop {
        let n = c.read(&mut buf).unwrap();
        assert!(n > 0, "closed early");
        got.extend_from_slice(&buf[..n]);
        if let Some(end) = got.windows(4).position(|w| w == b"\r\n\r\n") {
            let r = parse(&got);
            let len: usize = r.header("content-length").unwrap().parse().unwrap();
            if got.len() >= end + 4 + len {
                return r;
            }
        }
    }
}

/// After a stop, a connection may still be accepted by the OS backlog but gets no answer.
fn get_is_refused(addr: std::net::SocketAddr) -> bool {
    let Ok(mut c) = TcpStream::connect(addr) else {
        return true;
    };
    let _ = c.set_read_timeout(Some(Duration::from_secs(2)));
    let _ = c.write_all(b"GET / HTTP/1.1\r\n\r\n");
    let mut buf = [0u8; 16];
    !matches!(c.read(&mut buf), Ok(n) if n > 0)
}
