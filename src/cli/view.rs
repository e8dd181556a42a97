//! `filmsplat view`: the interactive preview in the browser. Takes its inputs exactly as
//! `render` does (the same flags, frame patterns, globs, scene files) and hands the frames to
//! the [`crate::view`] server.

use super::glob;
use super::render_args::RenderArgs;
use super::render_scene::scene_from_args;
use crate::pipeline::sequence;
use crate::view::{App, Frames, Server, token::Token};
use crate::{Error, Result};
use clap::Args;
use std::io::{IsTerminal, Write};
use std::net::{IpAddr, SocketAddr};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Arguments of `filmsplat view`: `render`'s inputs and scene flags, and where to listen.
/// `render`'s output flags mean nothing to a preview: hidden from the help, and refused.
#[derive(Debug, Args)]
#[command(
    mut_arg("output", |a| a.hide(true)),
    mut_arg("exr", |a| a.hide(true)),
    mut_arg("shard", |a| a.hide(true)),
    mut_arg("resume", |a| a.hide(true)),
    mut_arg("keep_going", |a| a.hide(true)),
    mut_arg("frame_all", |a| a.hide(true)),
)]
pub struct ViewArgs {
    #[command(flatten)]
    render: RenderArgs,
    /// Port to listen on (0: any free port).
    #[arg(long, default_value_t = 8765)]
    port: u16,
    /// Address to listen on. The default, 127.0.0.1, admits only this machine: from another
    /// one, tunnel with `ssh -L 8765:localhost:8765 HOST` and open the printed URL there.
    /// 0.0.0.0 listens on every interface (anyone who can reach it and has the token can
    /// look).
    #[arg(long, default_value = "127.0.0.1")]
    bind: IpAddr,
    /// Memory for prepared frames, e.g. 4G (default: half of the memory available at
    /// start); the least recently used frame is dropped beyond it.
    #[arg(long, value_name = "SIZE", value_parser = cache_size)]
    cache_memory: Option<u64>,
}

/// clap value parser for `--cache-memory`: a size (see `--max-memory`) of at most 1 PiB.
fn cache_size(s: &str) -> std::result::Result<u64, String> {
    let bytes = crate::pipeline::memory::parse_size(s)?;
    if bytes > 1 << 50 {
        return Err(format!("cache memory '{s}' is more than 1P (1 PiB)"));
    }
    Ok(bytes)
}

/// Set by SIGINT or SIGTERM.
static SIGNALLED: AtomicBool = AtomicBool::new(false);

extern "C" fn on_signal(_: i32) {
    SIGNALLED.store(true, Ordering::Relaxed);
}

/// Ctrl-C (SIGINT) and SIGTERM raise [`SIGNALLED`] instead of killing the process, so the
/// server can stop cleanly.
#[cfg(unix)]
fn catch_interrupts() {
    unsafe extern "C" {
        fn signal(signum: i32, handler: extern "C" fn(i32)) -> usize;
    }
    // SAFETY: `signal` is the C library's; the handler only stores to an atomic, which is
    // async-signal-safe.
    unsafe {
        signal(2, on_signal);
        signal(15, on_signal);
    }
}

#[cfg(not(unix))]
fn catch_interrupts() {}

/// Refuses the `render` flags that mean nothing to a preview.
fn refuse_render_only(a: &RenderArgs) -> Result<()> {
    let given = [
        (a.output.is_some(), "-o/--output"),
        (a.exr.is_some(), "--exr"),
        (a.shard.is_some(), "--shard"),
        (a.resume, "--resume"),
        (a.keep_going, "--keep-going"),
        (a.frame_all, "--frame-all"),
        (a.crf.is_some(), "--crf"),
    ];
    if let Some((_, flag)) = given.iter().find(|(g, _)| *g) {
        return Err(Error::invalid(format!(
            "view: {flag} is a flag of `filmsplat render` (files, sequences, farms), not of the \
             interactive preview; run `filmsplat render` with the same inputs for that"
        )));
    }
    if a.inputs.iter().any(|i| i.as_os_str() == "-") {
        return Err(Error::invalid(
            "view: reads its inputs again for each frame, primitive and preset, so not from \
             standard input (`-`); save the cloud to a file first",
        ));
    }
    Ok(())
}

/// The frames of the preview: `--frames` of a frame pattern, the matches of a quoted glob, or
/// the one scene; each frame's seed is the seed plus its number, as `render` gives it.
fn frames(a: &RenderArgs) -> Result<Frames> {
    let title = a.first_input();
    if let Some(list) = &a.frames {
        let numbers = list.0.clone();
        if a.scene_file()?.is_none() {
            let mut patterned = false;
            for i in &a.inputs {
                patterned |= sequence::expand(&i.to_string_lossy(), 0)?.is_some();
            }
            if !patterned {
                return Err(Error::invalid(format!(
                    "{title}: --frames needs a frame pattern ({{}} or {{:04}}) in an input"
                )));
            }
        }
        let base = a.clone();
        return Ok(Frames {
            labels: numbers.iter().map(u64::to_string).collect(),
            scene: Box::new(move |i| {
                let mut one = base.clone();
                let f = numbers[i];
                (one.frames, one.frame) = (None, Some(f));
                one.seed = Some(base.seed.unwrap_or(0).wrapping_add(f));
                scene_from_args(&one)
            }),
            title,
        });
    }
    if let [only] = a.inputs.as_slice()
        && glob::is_glob(only)
        && !only.exists()
    {
        let matches = glob::expand(only)?;
        let base = a.clone();
        let labels = matches
            .iter()
            .map(|m| {
                m.file_stem()
                    .unwrap_or_default()
                    .to_string_lossy()
                    .into_owned()
            })
            .collect();
        return Ok(Frames {
            labels,
            scene: Box::new(move |i| {
                let mut one = base.clone();
                one.inputs = vec![matches[i].clone()];
                one.seed = Some(base.seed.unwrap_or(0).wrapping_add(i as u64));
                scene_from_args(&one)
            }),
            title,
        });
    }
    let base = a.clone();
    Ok(Frames {
        labels: vec!["0".into()],
        scene: Box::new(move |_| scene_from_args(&base)),
        title,
    })
}

/// Runs `filmsplat view`: prepares the first frame (a bad input fails here, exit 2), prints
/// the URL with its token and serves until Ctrl-C.
pub fn run(v: &ViewArgs, out: &mut dyn Write, err: &mut dyn Write) -> Result<()> {
    let a = &v.render;
    refuse_render_only(a)?;
    if let Some(bytes) = a.max_memory {
        crate::budget::set_allowance(bytes);
    }
    let frames = frames(a)?;
    let count = frames.labels.len();
    let addr = SocketAddr::new(v.bind, v.port);
    // Bind first: a port in use is reported before the minutes a big frame may take.
    let probe = std::net::TcpListener::bind(addr)
        .map_err(|e| Error::invalid(format!("view: cannot listen on {addr}: {e}")))?;
    drop(probe);
    let say = |out: &mut dyn Write, s: String| {
        let _ = writeln!(out, "{s}");
        let _ = out.flush();
    };
    // Progress, for a terminal only (a log gets the stages' lines and the error, if any).
    if !a.quiet && std::io::stderr().is_terminal() {
        say(
            err,
            format!(
                "filmsplat view: preparing {} ...",
                PathBuf::from(&frames.title).display()
            ),
        );
    }
    let budget = v
        .cache_memory
        .unwrap_or_else(|| crate::budget::allowance_bytes() / 2);
    let app = App::new(frames, Token::random()?, budget)?;
    let stop = Arc::new(AtomicBool::new(false));
    let server = Server::bind(addr, app, stop.clone())?;
    catch_interrupts();
    std::thread::spawn(move || {
        while !SIGNALLED.load(Ordering::Relaxed) {
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        stop.store(true, Ordering::Relaxed);
    });
    let local = server.local_addr();
    say(
        err,
        format!(
            "filmsplat view: {count} frame(s), {} particles in the first; Ctrl-C stops the server\n\
             from another machine, tunnel first: ssh -L {p}:localhost:{p} {host}\n\
             open the URL below in a browser (the token in it is the key):",
            server.app().particles,
            p = local.port(),
            host = hostname(),
        ),
    );
    // The URL is the command's data: alone on stdout, for scripts.
    say(out, server.url());
    server.run();
    say(err, "filmsplat view: stopped".into());
    Ok(())
}

/// This machine's name, for the tunnel hint.
fn hostname() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_string())
        .ok()
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "HOST".into())
}
