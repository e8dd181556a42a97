//! Movies: `render --frames … -o movie.mp4` and `encode` write H.264 MP4s (and VP9 WebMs)
//! through the system's ffmpeg. The movies are decoded back with ffprobe/ffmpeg: codec, pixel
//! format, size, frame count and rate, and the first frame against the PNG of the same frame.
//! Bad input is refused in one line, exit 2, before any frame renders; a failure leaves no
//! movie. These tests need ffmpeg and ffprobe on PATH (`.ci/run` installs them): without them
//! they fail, naming the fix.

mod cli_support;
use cli_support::{filmsplat, tmp};

use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_filmsplat");

/// Fails the test, naming the fix, if ffmpeg or ffprobe cannot run.
fn need_ffmpeg() {
    for program in ["ffmpeg", "ffprobe"] {
        let ok = Command::new(program)
            .arg("-version")
            .output()
            .is_ok_and(|o| o.status.success());
        assert!(
            ok,
            "{program} not found on PATH: these tests encode and decode movies; install it \
             (apt-get install ffmpeg, or run .ci/run, which installs it)"
        );
    }
}

/// A fresh folder holding `osc.toml`: the oscillating-bubble sample, small.
fn scene(name: &str) -> PathBuf {
    let dir = tmp(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("osc.toml"),
        "[input]\nsample = \"oscillating-bubble\"\nparticles = 4000\n",
    )
    .unwrap();
    dir
}

/// Runs filmsplat in `dir` with `PATH` set to `path` when given; (code, stdout, stderr).
fn run_in(dir: &Path, args: &[&str], path: Option<&Path>) -> (i32, String, String) {
    let mut c = Command::new(BIN);
    c.args(args).current_dir(dir);
    if let Some(p) = path {
        c.env("PATH", p);
    }
    let out = c.output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The small render every movie here is made with.
const SMALL: [&str; 4] = ["--size", "64x48", "--preset", "preview"];

/// ffprobe's `key=value` lines of the first video stream, frames counted by decoding.
fn probe(movie: &Path) -> String {
    let out = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args(["-show_entries"])
        .arg("stream=codec_name,pix_fmt,width,height,nb_read_frames,r_frame_rate")
        .args(["-of", "default=noprint_wrappers=1"])
        .arg(movie)
        .output()
        .unwrap();
    assert!(out.status.success(), "ffprobe {}", movie.display());
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The movie's first frame decoded to 8-bit RGB (BT.709 studio range back to RGB, as the
/// movie is tagged).
fn first_frame(movie: &Path) -> Vec<u8> {
    let out = Command::new("ffmpeg")
        .args(["-v", "error", "-i"])
        .arg(movie)
        .args([
            "-frames:v",
            "1",
            "-vf",
            "scale=in_color_matrix=bt709:in_range=tv",
        ])
        .args(["-f", "rawvideo", "-pix_fmt", "rgb24", "-"])
        .output()
        .unwrap();
    assert!(out.status.success(), "ffmpeg decoding {}", movie.display());
    out.stdout
}

/// Mean absolute difference per channel (0..255) between two RGB8 pictures.
fn mean_abs_error(a: &[u8], b: &[u8]) -> [f64; 3] {
    assert_eq!(a.len(), b.len());
    let mut sum = [0.0; 3];
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        sum[i % 3] += (*x as f64 - *y as f64).abs();
    }
    sum.map(|s| s / (a.len() / 3) as f64)
}

/// The RGB8 bytes of a PNG.
fn png_bytes(p: &Path) -> Vec<u8> {
    image::open(p).unwrap().to_rgb8().into_raw()
}

/// `png` through yuv420p and back with no codec (ffmpeg's own conversion, as the movie's):
/// the error the pixel format alone makes, the reference for the codec's.
fn subsampled(png: &Path) -> Vec<u8> {
    let out = Command::new("ffmpeg")
        .args(["-v", "error", "-i"])
        .arg(png)
        .arg("-vf")
        .arg(
            "scale=out_color_matrix=bt709:out_range=tv,format=yuv420p,\
             scale=in_color_matrix=bt709:in_range=tv",
        )
        .args(["-f", "rawvideo", "-pix_fmt", "rgb24", "-"])
        .output()
        .unwrap();
    assert!(out.status.success(), "ffmpeg converting {}", png.display());
    out.stdout
}

/// Mean abs error per channel (0..255) H.264 at CRF 18 may add to what yuv420p alone makes
/// ([`subsampled`]). On this 64×48 preview bubble yuv420p alone measures 8.3/3.6/7.7 (R/G/B:
/// the picture is mostly coloured rims and 1-spp noise, where halving the chroma both ways
/// costs most) and the movie 8.8/4.0/8.5, so the codec adds 0.4-0.8; the next frame's PNG is
/// 11.4/7.5/10.4 away.
const CODEC_ERROR: f64 = 1.5;

/// Checks that `movie`'s first frame is `png` within codec error, and nearer to it than to
/// `other` (another frame's PNG).
fn first_frame_is(movie: &Path, png: &Path, other: &Path) {
    let decoded = first_frame(movie);
    let err = mean_abs_error(&decoded, &png_bytes(png));
    let base = mean_abs_error(&subsampled(png), &png_bytes(png));
    let off = mean_abs_error(&decoded, &png_bytes(other));
    eprintln!(
        "{}: first frame: error {err:?}, yuv420p alone {base:?}, other {off:?}",
        movie.display()
    );
    for c in 0..3 {
        assert!(err[c] <= base[c] + CODEC_ERROR, "{err:?} against {base:?}");
        assert!(err[c] < off[c], "{err:?} against another frame's {off:?}");
    }
}

#[test]
fn a_sequence_becomes_an_h264_movie_whose_first_frame_is_its_png() {
    need_ffmpeg();
    let dir = scene("video-movie");
    let args = |o: &'static str| {
        let mut v = vec!["render", "osc.toml", "--frames", "0..4", "-o", o];
        v.extend(SMALL);
        v
    };
    let (code, stdout, stderr) = run_in(&dir, &args("movie.mp4"), None);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.is_empty(), "stdout carries data only: {stdout}");
    assert!(
        stderr.contains("wrote 4 frames (64x48, 24 fps, H.264"),
        "{stderr}"
    );
    let info = probe(&dir.join("movie.mp4"));
    for want in [
        "codec_name=h264",
        "pix_fmt=yuv420p",
        "width=64",
        "height=48",
        "nb_read_frames=4",
        "r_frame_rate=24/1",
    ] {
        assert!(info.contains(want), "{want} in {info}");
    }
    // The same frames as images: the movie's first frame is frame 0's PNG within codec error.
    let (code, _, stderr) = run_in(&dir, &args("png/{:04}.png"), None);
    assert_eq!(code, 0, "{stderr}");
    let png = |f: &str| dir.join(format!("png/{f}.png"));
    first_frame_is(&dir.join("movie.mp4"), &png("0000"), &png("0003"));
    // No temporary left beside the movie.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(!names.iter().any(|n| n.contains(".tmp-")), "{names:?}");
}

#[test]
fn webm_is_vp9_at_the_given_rate() {
    need_ffmpeg();
    let dir = scene("video-webm");
    let mut args = vec!["render", "osc.toml", "--frames", "0..2", "-o", "m.webm"];
    args.extend(SMALL);
    args.extend(["--fps", "12", "-q"]);
    let (code, _, stderr) = run_in(&dir, &args, None);
    assert_eq!(code, 0, "{stderr}");
    let info = probe(&dir.join("m.webm"));
    for want in ["codec_name=vp9", "nb_read_frames=2", "r_frame_rate=12/1"] {
        assert!(info.contains(want), "{want} in {info}");
    }
}

#[test]
fn encode_joins_images_and_names_a_missing_frame() {
    need_ffmpeg();
    let dir = scene("video-encode");
    let mut args = vec![
        "render",
        "osc.toml",
        "--frames",
        "0..3",
        "-o",
        "out/{:04}.png",
    ];
    args.extend(SMALL);
    args.push("-q");
    let (code, _, stderr) = run_in(&dir, &args, None);
    assert_eq!(code, 0, "{stderr}");
    let enc = ["encode", "out/{:04}.png", "-o", "j.mp4", "--fps", "30"];
    let (code, stdout, stderr) = run_in(&dir, &enc, None);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.is_empty(), "{stdout}");
    let info = probe(&dir.join("j.mp4"));
    for want in ["codec_name=h264", "nb_read_frames=3", "r_frame_rate=30/1"] {
        assert!(info.contains(want), "{want} in {info}");
    }
    let png = |f: &str| dir.join(format!("out/{f}.png"));
    first_frame_is(&dir.join("j.mp4"), &png("0000"), &png("0002"));

    // A frame of another size is refused, naming it; no movie is left.
    image::RgbImage::new(66, 48)
        .save(dir.join("out/0001.png"))
        .unwrap();
    let (code, _, stderr) = run_in(&dir, &["encode", "out/{:04}.png", "-o", "k.mp4"], None);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("out/0001.png: is 66x48"), "{stderr}");
    assert!(!dir.join("k.mp4").exists());
    // A missing frame in the range is an error naming it, never skipped.
    std::fs::remove_file(dir.join("out/0001.png")).unwrap();
    let (code, _, stderr) = run_in(&dir, &["encode", "out/{:04}.png", "-o", "k.mp4"], None);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("out/0001.png: frame 1 is missing"),
        "{stderr}"
    );
    let with_frames = ["encode", "out/{:04}.png", "-o", "k.mp4", "--frames", "0..5"];
    let (code, _, stderr) = run_in(&dir, &with_frames, None);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("frame 1 is missing"), "{stderr}");
    assert!(!dir.join("k.mp4").exists());
    // --frames without the missing one joins the rest.
    let skip = [
        "encode",
        "out/{:04}.png",
        "-o",
        "k.mp4",
        "--frames",
        "2",
        "-q",
    ];
    let (code, _, stderr) = run_in(&dir, &skip, None);
    assert_eq!(code, 0, "{stderr}");
    assert!(probe(&dir.join("k.mp4")).contains("nb_read_frames=1"));
}

/// Asserts a refusal: exit 2, one line naming `want`, nothing rendered, no movie.
fn refused(dir: &Path, args: &[&str], path: Option<&Path>, want: &str) {
    let (code, stdout, stderr) = run_in(dir, args, path);
    assert_eq!(code, 2, "{args:?}: {stderr}");
    assert!(stdout.is_empty(), "{args:?}: {stdout}");
    assert_eq!(
        stderr.trim().lines().count(),
        1,
        "{args:?}: one line: {stderr}"
    );
    assert!(stderr.contains(want), "{args:?}: {want} in {stderr}");
    assert!(
        !stderr.contains("particles"),
        "{args:?}: rendered first: {stderr}"
    );
    for m in ["m.mp4", "m.avi", "m.webm"] {
        assert!(!dir.join(m).exists(), "{args:?} left {m}");
    }
}

#[test]
fn bad_input_is_refused_in_one_line_before_any_frame() {
    let dir = scene("video-refused");
    let empty = tmp("video-empty-path");
    std::fs::create_dir_all(&empty).unwrap();
    let seq = |extra: &[&'static str]| {
        let mut v = vec!["render", "osc.toml", "--frames", "0..2", "-o", "m.mp4"];
        v.extend(SMALL);
        v.extend(extra);
        v
    };
    let install = "ffmpeg: not found on PATH; writing a movie needs it (Debian/Ubuntu: apt-get \
                   install ffmpeg)";
    refused(&dir, &seq(&[]), Some(&empty), install);
    let enc = ["encode", "out/{:04}.png", "-o", "m.mp4"];
    refused(&dir, &enc, Some(&empty), install);
    let mut avi = seq(&[]);
    avi[5] = "m.avi";
    refused(&dir, &avi, None, "m.avi: -o must be images");
    refused(
        &dir,
        &["encode", "o/{}.png", "-o", "m.avi"],
        None,
        "m.avi: a movie must end in .mp4",
    );
    for fps in ["0", "nan", "-1", "inf"] {
        let want = format!("'{fps}': frames per second must be a number in (0, 1000]");
        refused(&dir, &seq(&["--fps", fps]), None, &want);
    }
    let odd = [
        "render", "osc.toml", "--frames", "0..2", "-o", "m.mp4", "--size", "65x48",
    ];
    refused(&dir, &odd, None, "render at --size 66x48");
    refused(&dir, &seq(&["--crf", "52"]), None, "--crf 52 is above 51");
    for flag in ["--resume", "--keep-going"] {
        refused(
            &dir,
            &seq(&[flag]),
            None,
            "then join them with `filmsplat encode",
        );
    }
    refused(
        &dir,
        &seq(&["--shard", "0/2"]),
        None,
        "--shard needs image files",
    );
    refused(
        &dir,
        &seq(&["--exr", "d/{}.exr"]),
        None,
        "--exr needs image files",
    );
    let still = ["render", "osc.toml", "-o", "m.png", "--crf", "20"];
    refused(
        &dir,
        &still,
        None,
        "--crf is a flag of sequences and movies",
    );
    let still = ["render", "osc.toml", "-o", "m.png", "--fps", "30"];
    refused(
        &dir,
        &still,
        None,
        "--fps is a flag of sequences and movies",
    );
    let mut images = seq(&["--crf", "20"]);
    images[5] = "o/{}.png";
    refused(&dir, &images, None, "--crf sets a movie's quality");
    let single = ["render", "osc.toml", "-o", "m.mp4"];
    refused(
        &dir,
        &single,
        None,
        "a movie is made of a sequence: give --frames",
    );
    refused(
        &dir,
        &["encode", "o/{}.png", "-o", "-"],
        None,
        "not to standard output",
    );
    let (code, _, stderr) = filmsplat(&["encode", "nopattern.png", "-o", "x.mp4"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("needs a frame pattern"), "{stderr}");
}

/// A frame that fails, or an ffmpeg that dies, leaves no movie (nor its temporary), and
/// ffmpeg's own words are in the one-line error.
#[test]
fn failures_leave_no_movie() {
    need_ffmpeg();
    let dir = scene("video-fails");
    let (code, _, stderr) = filmsplat(&[
        "sample",
        "bubble",
        "-o",
        &dir.join("f/{:04}.ply").to_string_lossy(),
        "--frames",
        "0..2",
        "--particles",
        "2000",
    ]);
    assert_eq!(code, 0, "{stderr}");
    std::fs::write(dir.join("f/0002.ply"), "ply\nnot a ply\n").unwrap();
    let mut args = vec!["render", "f/{:04}.ply", "--frames", "0..3", "-o", "m.mp4"];
    args.extend(SMALL);
    let (code, _, stderr) = run_in(&dir, &args, None);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("frame 2"), "{stderr}");
    let left: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains("m.mp4"))
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");

    // An ffmpeg that fails: its message is shown, no movie is left.
    let fake = tmp("video-fake-ffmpeg");
    std::fs::create_dir_all(&fake).unwrap();
    let script = fake.join("ffmpeg");
    std::fs::write(
        &script,
        "#!/bin/sh\necho 'Unknown encoder libx264' >&2\nexit 1\n",
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    args[3] = "0..2";
    let (code, _, stderr) = run_in(&dir, &args, Some(&fake));
    assert_eq!(code, 2, "{stderr}");
    let last = stderr.trim().lines().last().unwrap_or("");
    assert!(
        last.contains("m.mp4: ffmpeg failed (exit status: 1); it said: Unknown encoder libx264"),
        "{stderr}"
    );
    assert!(!dir.join("m.mp4").exists());
}

/// Ctrl-C (SIGINT to filmsplat alone; ffmpeg then sees its input end) or SIGKILL mid-movie
/// leaves no movie under the name, and the next run removes the killed run's temporary.
#[test]
fn an_interrupted_movie_leaves_no_movie_and_the_next_run_cleans_up() {
    need_ffmpeg();
    let dir = scene("video-interrupted");
    let mut args = vec!["render", "osc.toml", "--frames", "0..400", "-o", "m.mp4"];
    args.extend(["--size", "32x24", "--spp", "1"]);
    for signal in ["-INT", "-KILL"] {
        let mut child = Command::new(BIN)
            .args(&args)
            .current_dir(&dir)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        // Wait for the third frame to start: ffmpeg is running and has frames.
        let stderr = child.stderr.take().unwrap();
        let mut lines = std::io::BufRead::lines(std::io::BufReader::new(stderr));
        assert!(
            lines.any(|l| l.is_ok_and(|l| l.starts_with("frame 2 (3/400)"))),
            "the movie never reached frame 2"
        );
        let ok = Command::new("kill")
            .args([signal, &child.id().to_string()])
            .status()
            .unwrap();
        assert!(ok.success());
        let status = child.wait().unwrap();
        assert!(!status.success(), "{signal}: {status}");
        // ffmpeg finishes its temporary when its input ends; give it a moment.
        std::thread::sleep(std::time::Duration::from_millis(500));
        assert!(!dir.join("m.mp4").exists(), "{signal} left the movie");
    }
    let temps = || {
        std::fs::read_dir(&dir)
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .file_name()
                    .to_string_lossy()
                    .contains("m.mp4.tmp-")
            })
            .count()
    };
    eprintln!("temporaries after the interrupted runs: {}", temps());
    let mut short = args.clone();
    short[3] = "0..2";
    short.push("-q");
    let (code, _, stderr) = run_in(&dir, &short, None);
    assert_eq!(code, 0, "{stderr}");
    assert!(dir.join("m.mp4").exists());
    assert_eq!(temps(), 0, "the killed runs' temporaries are removed");
}

#[test]
fn a_turntable_goes_into_a_movie_prepared_once() {
    need_ffmpeg();
    let dir = scene("video-turntable");
    let frame = cli_support::data("thin-film-sph/bursting_bubble/60");
    let args = |o: &'static str| {
        let mut v = vec![
            "render",
            frame.as_str(),
            "--frames",
            "0..4",
            "--orbit",
            "360",
            "-o",
            o,
        ];
        v.extend(SMALL);
        v
    };
    let (code, _, stderr) = run_in(&dir, &args("turn.mp4"), None);
    assert_eq!(code, 0, "{stderr}");
    // The cloud is read once; the other three frames re-aim it.
    assert_eq!(stderr.matches("load ").count(), 1, "{stderr}");
    assert_eq!(stderr.matches("camera re-aimed").count(), 3, "{stderr}");
    assert!(probe(&dir.join("turn.mp4")).contains("nb_read_frames=4"));
    // The same turntable as images: the movie's first frame is its first view.
    let (code, _, stderr) = run_in(&dir, &args("png/{:04}.png"), None);
    assert_eq!(code, 0, "{stderr}");
    let png = |f: &str| dir.join(format!("png/{f}.png"));
    first_frame_is(&dir.join("turn.mp4"), &png("0000"), &png("0002"));
}
