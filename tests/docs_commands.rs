//! The docs work as written: every command of the ```sh blocks of README.md and docs/*.md runs
//! against the release binary on small data (how each is run: `tests/docs_support/table.rs`),
//! every link and repository path they mention exists in a clone, and nothing points outside it.

mod docs_support;
mod scratch;

use docs_support::table::{How, TABLE, small_args};
use docs_support::{blocks, commands, documents, exists, link_targets, repo_paths, root};
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_filmsplat");
/// A command that has not finished after this is killed and reported (not a timing test: a
/// hang guard; the commands take well under a second each on a quiet machine).
const HANG_GUARD: Duration = Duration::from_secs(600);

/// Every documented command, in document order: (document, command).
fn documented() -> Vec<(String, String)> {
    let mut out = Vec::new();
    for (doc, text) in documents() {
        for block in blocks(&text).iter().filter(|b| b.lang == "sh") {
            for command in commands(block) {
                out.push((doc.clone(), command));
            }
        }
    }
    out
}

fn how(command: &str) -> Option<&'static How> {
    TABLE.iter().find(|(c, _)| *c == command).map(|(_, h)| h)
}

#[test]
fn every_documented_command_has_a_row_and_every_row_a_command() {
    let documented = documented();
    assert!(
        documented.len() > 40,
        "too few commands found: {documented:?}"
    );
    let unknown: Vec<String> = documented
        .iter()
        .filter(|(_, c)| how(c).is_none())
        .map(|(d, c)| format!("{d}: {c}"))
        .collect();
    assert!(
        unknown.is_empty(),
        "commands the docs show but tests/docs_support/table.rs does not know (add a row):\n{}",
        unknown.join("\n")
    );
    let stale: Vec<&str> = TABLE
        .iter()
        .map(|(c, _)| *c)
        .filter(|c| !documented.iter().any(|(_, d)| d == c))
        .collect();
    assert!(stale.is_empty(), "rows no document shows: {stale:?}");
}

#[test]
fn every_code_block_says_its_language() {
    let mut bad = Vec::new();
    for (doc, text) in documents() {
        for b in blocks(&text) {
            if !["sh", "text", "toml", "python"].contains(&b.lang.as_str()) {
                bad.push(format!("{doc}:{}: ```{}", b.line, b.lang));
            }
        }
    }
    assert!(
        bad.is_empty(),
        "blocks must be ```sh (run by this test), ```python (run by the Python tests), \
         ```toml or ```text:\n{}",
        bad.join("\n")
    );
}

#[test]
fn every_link_and_repository_path_exists_and_nothing_points_outside_the_clone() {
    let mut missing = Vec::new();
    for (doc, text) in documents() {
        assert!(!text.contains("../shared"), "{doc} names ../shared");
        for target in link_targets(&text) {
            let external = ["http://", "https://", "mailto:"]
                .iter()
                .any(|p| target.starts_with(p));
            if !external && !exists(&doc, &target) {
                missing.push(format!("{doc}: link {target}"));
            }
        }
        for path in repo_paths(&text) {
            if !exists("", &path) {
                missing.push(format!("{doc}: path {path}"));
            }
        }
    }
    assert!(missing.is_empty(), "missing:\n{}", missing.join("\n"));
}

/// The folder the commands run in, with the small inputs the docs name.
fn fixtures() -> PathBuf {
    let dir = scratch::dir("docs");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("samples")).unwrap();
    std::os::unix::fs::symlink(root().join("tests"), dir.join("tests")).unwrap();
    for entry in std::fs::read_dir(root().join("samples")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let text = std::fs::read_to_string(&path).unwrap();
            let small = text.replace("particles = 200000", "particles = 3000");
            std::fs::write(dir.join("samples").join(path.file_name().unwrap()), small).unwrap();
        }
    }
    std::fs::write(dir.join("scene.toml"), docs_scene_file()).unwrap();
    for (name, text) in docs_toml_files() {
        std::fs::write(dir.join(name), text).unwrap();
    }
    std::fs::write(dir.join("frame_m.ply"), plane_in_metres()).unwrap();
    let frame = root().join("tests/data/thin-film-sph/bursting_bubble/60");
    for n in ["0", "1"] {
        copy_folder(&frame, &dir.join("out").join(n));
    }
    let make = [
        "sample bubble -o frame.ply --particles 2000",
        "sample bubble -o frames/frame_{:04}.ply --particles 1000 --frames 0..3",
        "sample bubble-mesh -o mesh_0000.ply --subdivisions 2",
        "sample bubble-mesh -o mesh_0001.ply --subdivisions 2",
    ];
    for args in make {
        let out = Command::new(BIN)
            .args(args.split(' '))
            .current_dir(&dir)
            .output()
            .unwrap();
        assert!(out.status.success(), "{args}: {out:?}");
    }
    dir
}

/// The scene file docs/scene-files.md shows (its ```toml block starting `# scene.toml`).
fn docs_scene_file() -> String {
    let text = std::fs::read_to_string(root().join("docs/scene-files.md")).unwrap();
    let block = blocks(&text)
        .into_iter()
        .find(|b| b.lang == "toml" && b.body[0].starts_with("# scene.toml"))
        .expect("docs/scene-files.md shows scene.toml");
    block.body.join("\n") + "\n"
}

/// The other scene files docs/sequences.md shows: its ```toml blocks starting `# NAME.toml:`,
/// as (NAME.toml, text).
fn docs_toml_files() -> Vec<(String, String)> {
    let text = std::fs::read_to_string(root().join("docs/sequences.md")).unwrap();
    blocks(&text)
        .into_iter()
        .filter(|b| b.lang == "toml")
        .filter_map(|b| {
            let name = b.body[0].strip_prefix("# ")?.split(':').next()?.to_string();
            name.ends_with(".toml")
                .then(|| (name, b.body.join("\n") + "\n"))
        })
        .collect()
}

/// A 20 × 20 film on a plane, thickness `rh` 300–700 nm stored in metres (ASCII PLY).
fn plane_in_metres() -> String {
    let mut s = String::from(
        "ply\nformat ascii 1.0\nelement vertex 400\nproperty float x\nproperty float y\n\
         property float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
         property float rh\nend_header\n",
    );
    for i in 0..400 {
        let (x, y) = ((i % 20) as f32 * 0.05, (i / 20) as f32 * 0.05);
        let rh_m = (300.0 + 20.0 * (i / 20) as f32) * 1e-9;
        s += &format!("{x} {y} 0 0 0 1 {rh_m:e}\n");
    }
    s
}

fn copy_folder(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        if entry.file_type().unwrap().is_file() {
            std::fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
        }
    }
}

/// `sh -c COMMAND` in `dir`, with the release binary first on PATH.
fn shell(dir: &Path, command: &str) -> Command {
    let bin_dir = Path::new(BIN).parent().unwrap();
    let path = format!("{}:{}", bin_dir.display(), std::env::var("PATH").unwrap());
    let mut c = Command::new("sh");
    c.arg("-c")
        .arg(command)
        .current_dir(dir)
        .env("PATH", path)
        .env("SLURM_ARRAY_TASK_ID", "0");
    c
}

/// Runs a command to its end: Ok if it exits 0, else what it printed.
fn run(dir: &Path, command: &str) -> Result<(), String> {
    let log = dir.join(".log");
    let mut child = shell(dir, command)
        .stdout(std::fs::File::create(log.with_extension("out")).unwrap())
        .stderr(std::fs::File::create(log.with_extension("err")).unwrap())
        .spawn()
        .unwrap();
    let status = wait_or_kill(&mut child)?;
    let err = std::fs::read_to_string(log.with_extension("err")).unwrap_or_default();
    if !status.success() {
        return Err(format!("{status}: {}", err.trim()));
    }
    written_outputs_exist(dir, command)
}

fn wait_or_kill(child: &mut Child) -> Result<std::process::ExitStatus, String> {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return Ok(status);
        }
        if start.elapsed() > HANG_GUARD {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("still running after {HANG_GUARD:?}: killed"));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The file after `-o` exists and is not empty (unless it is `-` or a pattern).
fn written_outputs_exist(dir: &Path, command: &str) -> Result<(), String> {
    let words: Vec<&str> = command.split_whitespace().collect();
    for w in words.windows(2).filter(|w| w[0] == "-o") {
        let name = w[1].trim_matches('\'');
        if name == "-" || name.contains(['{', '*']) {
            continue;
        }
        let len = std::fs::metadata(dir.join(name)).map(|m| m.len());
        if !matches!(len, Ok(n) if n > 0) {
            return Err(format!("exit 0 but {name} was not written"));
        }
    }
    Ok(())
}

/// Starts `filmsplat view`, fetches its page with the printed token, stops it with Ctrl-C.
fn view(dir: &Path, command: &str) -> Result<(), String> {
    let mut child = shell(dir, &format!("exec {command} --port 0"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let (send, lines) = mpsc::channel();
    for stream in [
        Box::new(child.stdout.take().unwrap()) as Box<dyn Read + Send>,
        Box::new(child.stderr.take().unwrap()),
    ] {
        let send = send.clone();
        std::thread::spawn(move || {
            for line in BufReader::new(stream).lines().map_while(Result::ok) {
                let _ = send.send(line);
            }
        });
    }
    drop(send);
    let page = match find_url(&lines) {
        Some(url) => fetch(&url),
        None => Err("no URL printed".to_string()),
    };
    let _ = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status();
    let status = wait_or_kill(&mut child)?;
    page?;
    match status.code() {
        Some(0) => Ok(()),
        _ => Err(format!("Ctrl-C did not stop it cleanly: {status}")),
    }
}

/// The URL with its token, from the first printed line that holds one.
fn find_url(lines: &mpsc::Receiver<String>) -> Option<String> {
    let deadline = Instant::now() + HANG_GUARD;
    loop {
        let left = deadline.checked_duration_since(Instant::now())?;
        let line = lines.recv_timeout(left).ok()?;
        if let Some(i) = line.find("http://") {
            let url = line[i..].split_whitespace().next()?;
            if url.contains("token=") {
                return Some(url.to_string());
            }
        }
    }
}

/// GET of the page at `url` (http://HOST:PORT/?token=T): Ok if it answers 200 with HTML.
fn fetch(url: &str) -> Result<(), String> {
    let rest = url.strip_prefix("http://").ok_or("not http")?;
    let (host, path) = rest.split_once('/').ok_or("no path")?;
    let mut s = std::net::TcpStream::connect(host).map_err(|e| e.to_string())?;
    s.set_read_timeout(Some(HANG_GUARD)).unwrap();
    write!(
        s,
        "GET /{path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut answer = String::new();
    let _ = s.read_to_string(&mut answer);
    if answer.starts_with("HTTP/1.1 200") && answer.to_lowercase().contains("<html") {
        Ok(())
    } else {
        Err(format!("the page: {}", answer.lines().next().unwrap_or("")))
    }
}

#[test]
fn every_documented_command_runs_on_small_data() {
    let dir = fixtures();
    let mut failed = Vec::new();
    let mut ran = 0;
    for (doc, command) in documented() {
        let Some(how) = how(&command) else { continue };
        let root = root().display().to_string();
        let result = match how {
            How::AsIs => run(&dir, &command),
            How::Small => run(&dir, &format!("{command} {}", small_args())),
            How::Instead(c) => run(&dir, &c.replace("{root}", &root)),
            How::View(c) => view(&dir, c),
            How::NotRun(_) => continue,
        };
        ran += 1;
        if let Err(e) = result {
            failed.push(format!("{doc}: {command}\n    {e}"));
        }
    }
    assert!(ran > 40, "only {ran} commands ran");
    assert!(failed.is_empty(), "failed:\n{}", failed.join("\n"));
    let _ = std::fs::remove_dir_all(&dir);
}
