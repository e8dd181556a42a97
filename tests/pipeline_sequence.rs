//! The sequence loop (`pipeline::sequence`) in-process, over a job that records what it was
//! asked: shards split the frames, the one camera is decided once and equally by every shard,
//! resume skips finished frames and cleans an interrupted run's temporaries, keep-going
//! reports every failure.

mod scratch;

use filmsplat::pipeline::camera_path::FrameCamera;
use filmsplat::pipeline::sequence::{
    FrameJob, SequenceOptions, at_frame, expand, frames, render_sequence, shard, sharded,
};
use filmsplat::pipeline::{Prepared, prepare};
use filmsplat::scene::SceneDesc;
use filmsplat::{Error, Result};
use std::cell::RefCell;
use std::io::Write;
use std::path::{Path, PathBuf};

/// A camera's position and look-at.
type Cam = ([f32; 3], [f32; 3]);

/// A sequence of tiny bubbles; frame `f`'s bubble is moved by `f` along x (so framing on all
/// frames differs from framing on the first), and the frames in `fail` fail to render.
struct Job {
    dir: PathBuf,
    fail: Vec<u64>,
    camera: Option<[f32; 3]>,
    /// More scene-file lines (camera keys, an orbit).
    extra: String,
    /// (frame, the camera it got (position, look-at), whether it came prepared).
    rendered: RefCell<Vec<(u64, Option<Cam>, bool)>>,
    prepared: RefCell<Vec<u64>>,
}

impl Job {
    fn new(name: &str) -> Job {
        let dir = scratch::dir("sequence").join(name);
        let _ = std::fs::remove_dir_all(&dir);
        Job {
            dir,
            fail: Vec::new(),
            camera: None,
            extra: String::new(),
            rendered: RefCell::new(Vec::new()),
            prepared: RefCell::new(Vec::new()),
        }
    }
}

impl FrameJob for Job {
    fn outputs(&self, f: u64) -> Result<Vec<PathBuf>> {
        Ok(vec![self.dir.join(format!("{f:03}.png"))])
    }

    fn scene(&self, _f: u64) -> Result<SceneDesc> {
        let mut d = SceneDesc::from_toml(
            &format!(
                "[input]\nsample = \"bubble\"\nparticles = 300\n[render]\nwidth = 16\nheight = \
                 12\n{}",
                self.extra
            ),
            "inline",
        )?;
        d.camera.position = self.camera;
        Ok(d)
    }

    fn prepare(&self, f: u64) -> Result<Prepared> {
        self.prepared.borrow_mut().push(f);
        let mut p = prepare(&self.scene(f)?, Path::new("."), false)?;
        let shift = glam::Vec3::new(f as f32, 0.0, 0.0);
        p.framing.min += shift;
        p.framing.max += shift;
        p.framing.centre += shift;
        Ok(p)
    }

    fn render(
        &self,
        f: u64,
        camera: Option<&FrameCamera>,
        ready: Option<Prepared>,
        _out: &mut dyn Write,
    ) -> Result<()> {
        let cam = camera.map(|c| (c.camera.position.unwrap(), c.camera.look_at.unwrap()));
        self.rendered.borrow_mut().push((f, cam, ready.is_some()));
        if self.fail.contains(&f) {
            return Err(Error::invalid("boom"));
        }
        std::fs::write(&self.outputs(f)?[0], b"png").map_err(|e| Error::io("out", e))
    }
}

fn opts(frames: &[u64]) -> SequenceOptions {
    SequenceOptions {
        frames: frames.to_vec(),
        quiet: true,
        ..SequenceOptions::default()
    }
}

fn run(job: &Job, o: &SequenceOptions) -> (Result<()>, String) {
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let r = render_sequence(job, o, &mut out, &mut err);
    (r, String::from_utf8(err).unwrap())
}

#[test]
fn shards_split_the_frames_and_agree_on_one_camera() {
    let all: Vec<u64> = (10..17).collect();
    let mut seen = Vec::new();
    let mut cameras = Vec::new();
    for k in 0..3 {
        let job = Job::new(&format!("shard{k}"));
        let o = SequenceOptions {
            shard: Some((k, 3)),
            ..opts(&all)
        };
        run(&job, &o).0.unwrap();
        let rendered = job.rendered.into_inner();
        // The camera is framed on the first frame of the whole sequence, by every shard, once.
        assert_eq!(job.prepared.into_inner(), vec![10]);
        for (f, camera, ready) in &rendered {
            seen.push(*f);
            cameras.push(camera.expect("an auto-framed camera"));
            // Only the frame that was prepared for framing comes prepared.
            assert_eq!(*ready, *f == 10, "frame {f}");
            assert!(job.dir.join(format!("{f:03}.png")).exists());
        }
    }
    seen.sort();
    assert_eq!(seen, all);
    assert!(cameras.windows(2).all(|w| w[0] == w[1]), "{cameras:?}");
}

#[test]
fn frame_all_frames_on_every_frame_and_a_scene_camera_wins() {
    let job = Job::new("all");
    let first = Job::new("first");
    let o = opts(&[0, 4, 8]);
    run(&first, &o).0.unwrap();
    run(
        &job,
        &SequenceOptions {
            frame_all: true,
            ..o.clone()
        },
    )
    .0
    .unwrap();
    assert_eq!(job.prepared.into_inner(), vec![0, 4, 8]);
    let (a, b) = (job.rendered.into_inner(), first.rendered.into_inner());
    assert!(a.iter().all(|(_, _, ready)| !ready));
    // Framed on the union, the camera looks at its centre, 4 along x from the first frame's.
    let (ta, tb) = (a[0].1.unwrap().1, b[0].1.unwrap().1);
    assert!((ta[0] - tb[0] - 4.0).abs() < 1e-3, "{ta:?} {tb:?}");
    assert!(a.iter().chain(&b).all(|r| r.1.is_some()));

    let mut named = Job::new("named");
    named.camera = Some([0.0, 0.0, 5.0]);
    run(&named, &o).0.unwrap();
    assert!(named.prepared.into_inner().is_empty());
    assert!(named.rendered.into_inner().iter().all(|r| r.1.is_none()));
}

#[test]
fn resume_skips_finished_frames_and_removes_stale_temporaries() {
    let job = Job::new("resume");
    std::fs::create_dir_all(&job.dir).unwrap();
    std::fs::write(job.dir.join("001.png"), b"done").unwrap();
    // Left by a killed process (no such PID runs).
    let stale = job.dir.join(".002.png.tmp-4194304-0");
    std::fs::write(&stale, b"half").unwrap();
    let o = SequenceOptions {
        resume: true,
        ..opts(&[0, 1, 2])
    };
    run(&job, &o).0.unwrap();
    let rendered: Vec<u64> = job.rendered.into_inner().iter().map(|r| r.0).collect();
    assert_eq!(rendered, vec![0, 2]);
    assert!(!stale.exists());
    // Without resume every frame renders again.
    let again = Job::new("resume");
    run(&again, &opts(&[0, 1, 2])).0.unwrap();
    assert_eq!(again.rendered.into_inner().len(), 3);
}

#[test]
fn keep_going_reports_every_failure_and_otherwise_the_first_stops() {
    let mut job = Job::new("fail");
    job.fail = vec![1, 3];
    let (r, err) = run(&job, &opts(&[0, 1, 2, 3]));
    let m = r.unwrap_err().to_string();
    assert!(m.starts_with("frame 1: ") && m.contains("boom"), "{m}");
    assert_eq!(job.rendered.borrow().len(), 2);
    assert!(err.is_empty(), "{err}");

    let mut job = Job::new("fail-on");
    job.fail = vec![1, 3];
    let o = SequenceOptions {
        keep_going: true,
        ..opts(&[0, 1, 2, 3])
    };
    let (r, err) = run(&job, &o);
    assert_eq!(r.unwrap_err().to_string(), "2 of 4 frames failed: [1, 3]");
    assert_eq!(job.rendered.borrow().len(), 4);
    assert_eq!(err.lines().count(), 2, "{err}");
    assert!(err.contains("frame 3: boom"), "{err}");
}

#[test]
fn bad_outputs_fail_before_any_frame_renders() {
    struct Exr(Job);
    impl FrameJob for Exr {
        fn outputs(&self, f: u64) -> Result<Vec<PathBuf>> {
            Ok(vec![self.0.dir.join(format!("{f}.jpg"))])
        }
        fn scene(&self, f: u64) -> Result<SceneDesc> {
            self.0.scene(f)
        }
        fn prepare(&self, f: u64) -> Result<Prepared> {
            self.0.prepare(f)
        }
        fn render(
            &self,
            f: u64,
            c: Option<&FrameCamera>,
            r: Option<Prepared>,
            o: &mut dyn Write,
        ) -> Result<()> {
            self.0.render(f, c, r, o)
        }
    }
    let job = Exr(Job::new("jpg"));
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let e = render_sequence(&job, &opts(&[0, 1]), &mut out, &mut err).unwrap_err();
    assert!(e.to_string().contains("must end in .png or .exr"), "{e}");
    assert!(job.0.rendered.into_inner().is_empty());
    assert!(job.0.prepared.into_inner().is_empty());
}

#[test]
fn patterns_ranges_shards_and_frame_scenes() {
    assert_eq!(expand("f_{:04}.ply", 7).unwrap().unwrap(), "f_0007.ply");
    assert_eq!(expand("f_{}.ply", 12).unwrap().unwrap(), "f_12.ply");
    assert_eq!(expand("plain.ply", 1).unwrap(), None);
    assert!(expand("f_{:x}.ply", 1).is_err());
    assert!(expand("f_{.ply", 1).is_err());
    assert_eq!(frames("3..6").unwrap(), vec![3, 4, 5]);
    assert_eq!(frames("3..=5").unwrap(), vec![3, 4, 5]);
    assert_eq!(frames("9").unwrap(), vec![9]);
    for bad in ["5..5", "a..3", "", "1..x"] {
        assert!(frames(bad).is_err(), "{bad}");
    }
    assert_eq!(shard("1/3").unwrap(), (1, 3));
    assert!(shard("3/3").is_err() && shard("1/0").is_err() && shard("x").is_err());
    let all: Vec<u64> = (0..10).collect();
    let mut union: Vec<u64> = (0..3).flat_map(|k| sharded(&all, Some((k, 3)))).collect();
    union.sort();
    assert_eq!(union, all);
    assert_eq!(sharded(&all, Some((1, 3))), vec![1, 4, 7]);

    let mut d = SceneDesc::default();
    d.input.cloud = Some("f_{:03}.ply".into());
    d.input.clouds = Some(vec!["d_{}.ply".into(), "static.ply".into()]);
    at_frame(&mut d, 42, 24.0).unwrap();
    assert_eq!(d.input.cloud.unwrap(), PathBuf::from("f_042.ply"));
    assert_eq!(
        d.input.clouds.unwrap(),
        vec![PathBuf::from("d_42.ply"), PathBuf::from("static.ply")]
    );
    let mut s = SceneDesc::default();
    s.input.sample = Some("bubble".into());
    s.input.time = Some(1.0);
    at_frame(&mut s, 12, 24.0).unwrap();
    assert_eq!(s.input.time, Some(1.5));
}

/// Every frame's camera (position, look-at) of `job` rendered in `shards` jobs.
fn cameras(name: &str, extra: &str, frames: &[u64], shards: u64) -> Vec<(u64, Cam)> {
    let mut all = Vec::new();
    for k in 0..shards {
        let mut job = Job::new(&format!("{name}{k}"));
        job.extra = extra.into();
        let o = SequenceOptions {
            shard: Some((k, shards)),
            ..opts(frames)
        };
        run(&job, &o).0.unwrap();
        all.extend(
            job.rendered
                .into_inner()
                .into_iter()
                .map(|(f, c, _)| (f, c.unwrap())),
        );
    }
    all.sort_by_key(|(f, _)| *f);
    all
}

#[test]
fn keys_and_orbits_give_each_frame_its_camera_alike_in_every_shard() {
    let keys = "[[camera.key]]\nframe = 2\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n\
                [[camera.key]]\nframe = 6\nposition = [4, 0, 3]\nlook_at = [0, 1, 0]\n";
    let frames: Vec<u64> = (0..9).collect();
    let one = cameras("keys", keys, &frames, 1);
    assert_eq!(one, cameras("keys-sharded", keys, &frames, 3));
    for (f, (p, t)) in &one {
        match f {
            // Held before the first key and after the last.
            0..=2 => assert_eq!((*p, *t), ([0.0, 0.0, 5.0], [0.0, 0.0, 0.0]), "frame {f}"),
            6.. => assert_eq!((*p, *t), ([4.0, 0.0, 3.0], [0.0, 1.0, 0.0]), "frame {f}"),
            // Two keys: a straight line, halfway at frame 4.
            _ => assert!(*f != 4 || (p[0] - 2.0).abs() < 1e-5 && (t[1] - 0.5).abs() < 1e-5),
        }
    }
    // An orbit turns the auto-framed start a quarter per frame of four, in every shard alike.
    let frames: Vec<u64> = (10..14).collect();
    let orbit = cameras("orbit", "[camera]\norbit = 360\n", &frames, 1);
    assert_eq!(
        orbit,
        cameras("orbit-sharded", "[camera]\norbit = 360\n", &frames, 2)
    );
    let (p0, t) = orbit[0].1;
    let (p2, t2) = orbit[2].1;
    assert_eq!(t, t2);
    // Half a turn: the start mirrored through the vertical axis at the look-at point.
    for i in [0, 2] {
        assert!(
            (p2[i] - (2.0 * t[i] - p0[i])).abs() < 1e-4,
            "{p0:?} -> {p2:?}"
        );
    }
    assert!((p2[1] - p0[1]).abs() < 1e-5);
}
