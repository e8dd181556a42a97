//! `filmsplat view` as a program: its inputs are `render`'s (scene files, frame patterns,
//! globs), it prints a URL with a token, refuses what it cannot serve with one line and exit
//! code 2, and stops cleanly on Ctrl-C (SIGINT).

mod view_support;

use std::io::{BufRead, BufReader, Read};
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use view_support::{get_no_token, temp};

const BIN: &str = env!("CARGO_BIN_EXE_filmsplat");

fn scene_file() -> PathBuf {
    let p = temp("scene.toml");
    std::fs::write(
        &p,
        "[input]\nsample = \"bubble\"\nparticles = 2000\n[render]\nwidth = 64\nheight = 36\n",
    )
    .unwrap();
    p
}

/// A running `filmsplat view`, killed if a test fails before it is stopped.
struct Viewer(Child);

impl Drop for Viewer {
    fn drop(&mut self) {
        if self.0.try_wait().ok().flatten().is_none() {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
}

/// Starts `filmsplat view ARGS --port 0` and reads its output up to the URL: the child, the
/// server's address, the token and the lines read.
fn start(args: &[&str]) -> (Viewer, SocketAddr, String, Vec<String>) {
    let mut child = Viewer(
        Command::new(BIN)
            .arg("view")
            .args(args)
            .args(["--port", "0"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    let mut lines = Vec::new();
    let mut out = BufReader::new(child.0.stdout.take().unwrap());
    loop {
        let mut line = String::new();
        assert!(out.read_line(&mut line).unwrap() > 0, "no URL in {lines:?}");
        lines.push(line.trim_end().to_string());
        if let Some(url) = line.trim().strip_prefix("http://") {
            let (host, token) = url.split_once("/?token=").unwrap();
            let addr = host.parse().unwrap();
            std::thread::spawn(move || {
                let mut rest = String::new();
                let _ = out.read_to_string(&mut rest);
                rest
            });
            return (child, addr, token.to_string(), lines);
        }
    }
}

/// Sends Ctrl-C (SIGINT) and returns the exit code.
fn interrupt(mut child: Viewer) -> Option<i32> {
    let status = Command::new("kill")
        .args(["-INT", &child.0.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    child.0.wait().unwrap().code()
}

fn scene_json(addr: SocketAddr, token: &str) -> serde_json::Value {
    let r = get_no_token(addr, &format!("/api/scene?token={token}"));
    assert_eq!(r.status, 200, "{}", r.text());
    serde_json::from_slice(&r.body).unwrap()
}

#[test]
fn it_prints_a_loopback_url_with_a_random_token_and_stops_cleanly_on_ctrl_c() {
    let scene = scene_file();
    let (child, addr, token, lines) = start(&[scene.to_str().unwrap()]);
    assert!(addr.ip().is_loopback(), "binds loopback by default: {addr}");
    assert_eq!(token.len(), 32);
    // stdout is for data: the URL alone (the tunnel hint and the rest go to stderr).
    assert_eq!(lines.len(), 1, "{lines:?}");
    assert_eq!(scene_json(addr, &token)["particles"], 2000);
    assert_eq!(get_no_token(addr, "/api/scene").status, 403);
    assert_eq!(interrupt(child), Some(0), "Ctrl-C is a clean stop");
    assert!(
        std::net::TcpStream::connect(addr).is_err(),
        "the port is closed"
    );
    // A second server gets another token.
    let (child, addr, other, _) = start(&[scene.to_str().unwrap()]);
    assert_ne!(token, other);
    assert_eq!(
        scene_json(addr, &other)["frames"].as_array().unwrap().len(),
        1
    );
    assert_eq!(interrupt(child), Some(0));
}

/// Two PLY frames of a small bubble in a fresh folder.
fn two_frames() -> PathBuf {
    let dir = temp("frames");
    std::fs::create_dir_all(&dir).unwrap();
    let pattern = dir.join("f_{:02}.ply");
    let status = Command::new(BIN)
        .args([
            "sample",
            "bubble",
            "--particles",
            "800",
            "--frames",
            "0..2",
            "-o",
        ])
        .arg(&pattern)
        .output()
        .unwrap();
    assert!(status.status.success());
    dir
}

#[test]
fn frame_patterns_and_globs_are_sequences_as_for_render() {
    let dir = two_frames();
    let pattern = dir.join("f_{:02}.ply");
    let (child, addr, token, _) = start(&[pattern.to_str().unwrap(), "--frames", "0..2"]);
    assert_eq!(
        scene_json(addr, &token)["frames"],
        serde_json::json!(["0", "1"])
    );
    let q = "pos=0,0,3&look=0,0,0&up=0,1,0&w=16&h=9&frame=1";
    assert_eq!(
        get_no_token(addr, &format!("/api/render?token={token}&{q}")).status,
        200
    );
    assert_eq!(interrupt(child), Some(0));
    let glob = dir.join("f_*.ply");
    let (child, addr, token, _) = start(&[glob.to_str().unwrap()]);
    assert_eq!(
        scene_json(addr, &token)["frames"],
        serde_json::json!(["f_00", "f_01"])
    );
    assert_eq!(interrupt(child), Some(0));
}

/// Runs `filmsplat view ARGS` expecting a refusal: exit code 2 and one line naming `says`.
fn refused(args: &[&str], says: &str) {
    let out = Command::new(BIN).arg("view").args(args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert_eq!(err.trim().lines().count(), 1, "{args:?}: one line: {err}");
    assert!(err.contains(says), "{args:?}: {err}");
}

#[test]
fn what_it_cannot_serve_is_refused_with_one_line_and_exit_code_2() {
    let scene = scene_file();
    let s = scene.to_str().unwrap();
    let missing = temp("missing.ply");
    refused(&[missing.to_str().unwrap(), "--port", "0"], "missing.ply");
    refused(&[s, "-o", "x.png"], "-o/--output");
    refused(&[s, "--resume"], "--resume");
    refused(&["-"], "standard input");
    let plain = two_frames().join("f_00.ply");
    refused(
        &[plain.to_str().unwrap(), "--frames", "0..2"],
        "frame pattern",
    );
    refused(
        &[s, "--bind", "203.0.113.7", "--port", "0"],
        "cannot listen on 203.0.113.7",
    );
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port().to_string();
    refused(&[s, "--port", &port], "cannot listen on 127.0.0.1");
    refused(&[s, "--bind", "not-an-address"], "not-an-address");
    assert!(!Path::new("x.png").exists());
}
