//! `filmsplat view` against slow clients (slowloris): connections that trickle a request a byte
//! at a time, or send nothing, must neither lock token holders out nor be held past the
//! request deadline. Loopback only; every wait has a generous cap, so no test can hang.

mod view_support;

use filmsplat::view::admission::MAX_PENDING;
use filmsplat::view::server::MAX_CONNECTIONS;
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;
use view_support::*;

/// Opens `n` connections that each send `request` one byte per `every` until `stop` (or the
/// server closes them); returns the thread doing the trickling.
fn trickle(
    addr: SocketAddr,
    n: usize,
    request: &'static [u8],
    every: Duration,
    stop: Arc<AtomicBool>,
) -> std::thread::JoinHandle<()> {
    let mut conns: Vec<TcpStream> = (0..n).map(|_| TcpStream::connect(addr).unwrap()).collect();
    std::thread::spawn(move || {
        for &byte in request {
            if stop.load(Ordering::Relaxed) {
                return;
            }
            for c in &mut conns {
                let _ = c.write_all(&[byte]);
            }
            std::thread::sleep(every);
        }
    })
}

/// Reads until the server closes the connection (at most 20 s, less than the 30 s idle timeout
/// a pending connection had before deadlines: a server that holds it longer
/// fails the test instead of hanging it).
fn read_until_closed(c: &mut TcpStream) -> Vec<u8> {
    c.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
    let mut out = Vec::new();
    c.read_to_end(&mut out)
        .expect("the server should close the connection at its deadline");
    out
}

#[test]
fn slow_tokenless_connections_do_not_lock_out_token_holders() {
    let s = start(SCENE);
    let stop = Arc::new(AtomicBool::new(false));
    // More slow connections than every slot of both classes together.
    let slow = MAX_PENDING + MAX_CONNECTIONS + 8;
    let t = trickle(
        s.addr,
        slow,
        b"GET /api/scene HTTP/1.1\r\nHost: slow\r\n\r\n",
        Duration::from_secs(1),
        stop.clone(),
    );
    for _ in 0..3 {
        let r = get(s.addr, &format!("/api/render?{CAMERA}&w=16&h=9"));
        assert_eq!(r.status, 200, "a token holder was refused: {}", r.text());
        assert!(s.server.pending() <= MAX_PENDING, "the pending quota holds");
        std::thread::sleep(Duration::from_millis(700));
    }
    stop.store(true, Ordering::Relaxed);
    t.join().unwrap();
}

#[test]
fn a_request_trickled_past_its_deadline_gets_408_and_is_closed() {
    let s = start_with_deadline(SCENE, Duration::from_secs(1));
    let mut c = TcpStream::connect(s.addr).unwrap();
    let request = format!("GET /api/scene?token={TOKEN} HTTP/1.1\r\nHost: slow\r\n\r\n");
    let mut writer = c.try_clone().unwrap();
    // ~65 bytes at one per 200 ms: 13 s whole, each byte well inside any per-read timeout.
    let t = std::thread::spawn(move || {
        for b in request.bytes() {
            if writer.write_all(&[b]).is_err() {
                return;
            }
            std::thread::sleep(Duration::from_millis(200));
        }
    });
    let r = parse(&read_until_closed(&mut c));
    assert_eq!(r.status, 408, "{}", r.text());
    assert!(r.text().contains("timed out"), "{}", r.text());
    drop(c);
    t.join().unwrap();
    // The server still serves.
    assert_eq!(get(s.addr, "/api/scene").status, 200);
}

#[test]
fn a_connection_that_sends_nothing_is_dropped_at_the_deadline() {
    let s = start_with_deadline(SCENE, Duration::from_secs(1));
    let mut c = TcpStream::connect(s.addr).unwrap();
    assert!(
        read_until_closed(&mut c).is_empty(),
        "no answer to no request"
    );
    // A tokenless request is answered, and its connection closed (it never holds a slot).
    let mut c = TcpStream::connect(s.addr).unwrap();
    c.write_all(b"GET /favicon.ico HTTP/1.1\r\nHost: t\r\n\r\n")
        .unwrap();
    let r = parse(&read_until_closed(&mut c));
    assert_eq!((r.status, r.header("connection")), (204, Some("close")));
}
