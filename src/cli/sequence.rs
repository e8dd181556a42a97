//! Frame sequences for `filmsplat render`: path patterns (`frame_{:04}.ply`), frame ranges,
//! shards for render farms, one camera per sequence, output folders checked first, resume,
//! keep-going.

use super::render::{RenderArgs, check_extension, prepare_frame, render_one, scene_from_args};
use crate::pipeline::Prepared;
use crate::pipeline::framing::{self, Framing};
use crate::scene::CameraDesc;
use crate::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Expands the first `{}` or `{:0N}` in `pattern` with `frame` (zero-padded to N digits).
/// Returns `None` if the pattern has no placeholder.
pub fn expand(pattern: &str, frame: u64) -> Result<Option<String>> {
    let Some(open) = pattern.find('{') else {
        return Ok(None);
    };
    let close = pattern[open..]
        .find('}')
        .map(|c| open + c)
        .ok_or_else(|| Error::invalid(format!("'{pattern}': unclosed '{{' in frame pattern")))?;
    let spec = &pattern[open + 1..close];
    let width = match spec {
        "" => 0,
        s if s.starts_with(":0") && s.len() > 2 => s[2..]
            .parse::<usize>()
            .ok()
            .filter(|w| *w <= 20)
            .ok_or_else(|| {
                Error::invalid(format!(
                    "'{pattern}': frame pattern must be {{}} or {{:0N}}"
                ))
            })?,
        _ => {
            return Err(Error::invalid(format!(
                "'{pattern}': frame pattern must be {{}} or {{:0N}}"
            )));
        }
    };
    Ok(Some(format!(
        "{}{frame:0width$}{}",
        &pattern[..open],
        &pattern[close + 1..]
    )))
}

/// A parsed list of frame numbers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FrameList(pub Vec<u64>);

/// clap value parser for [`FrameList`].
pub fn frame_list(s: &str) -> std::result::Result<FrameList, String> {
    frames(s).map(FrameList)
}

/// Parses a frame range `A..B` (B excluded) or `A..=B`, or a single frame `A`.
pub fn frames(s: &str) -> std::result::Result<Vec<u64>, String> {
    let bad = || format!("frames '{s}' must be A..B, A..=B or A (whole numbers)");
    let num = |v: &str| v.trim().parse::<u64>().map_err(|_| bad());
    let (a, b) = if let Some((a, b)) = s.split_once("..=") {
        (num(a)?, num(b)?.checked_add(1).ok_or_else(bad)?)
    } else if let Some((a, b)) = s.split_once("..") {
        (num(a)?, num(b)?)
    } else {
        let a = num(s)?;
        (a, a.checked_add(1).ok_or_else(bad)?)
    };
    if b <= a {
        return Err(format!("frames '{s}' is empty"));
    }
    if b - a > 10_000_000 {
        return Err(format!("frames '{s}' has more than 10 000 000 frames"));
    }
    Ok((a..b).collect())
}

/// Parses a shard `K/N` (0 <= K < N).
pub fn shard(s: &str) -> std::result::Result<(u64, u64), String> {
    let bad = || format!("shard '{s}' must be K/N with 0 <= K < N");
    let (k, n) = s.split_once('/').ok_or_else(bad)?;
    let (k, n) = (
        k.trim().parse::<u64>().map_err(|_| bad())?,
        n.trim().parse::<u64>().map_err(|_| bad())?,
    );
    if n == 0 || k >= n {
        return Err(bad());
    }
    Ok((k, n))
}

/// The frames this shard renders: every N-th of `frames`, starting at the K-th.
pub fn sharded(frames: &[u64], shard: Option<(u64, u64)>) -> Vec<u64> {
    match shard {
        None => frames.to_vec(),
        Some((k, n)) => frames
            .iter()
            .copied()
            .skip(k as usize)
            .step_by(n as usize)
            .collect(),
    }
}

/// Renders the sequence `frames` of `render --frames`: checks the patterns and every output
/// folder of this job first, decides the one camera ([`sequence_camera`]) before the first
/// frame it renders, then renders its shard's frames (resume, keep-going).
pub(super) fn render_sequence(a: &RenderArgs, frames: &[u64], out: &mut dyn Write) -> Result<()> {
    let output = a.output.as_ref().ok_or_else(|| {
        Error::invalid("--frames needs -o with a frame pattern, e.g. -o 'out/{:04}.png'")
    })?;
    let out_pattern = output.to_string_lossy().into_owned();
    let is_toml = a.scene_file()?.is_some();
    if expand(&out_pattern, 0)?.is_none() {
        return Err(Error::invalid(format!(
            "{out_pattern}: --frames needs a frame pattern ({{}} or {{:04}}) in -o"
        )));
    }
    if !is_toml {
        let mut patterned = false;
        for i in &a.inputs {
            patterned |= expand(&i.to_string_lossy(), 0)?.is_some();
        }
        if !patterned {
            return Err(Error::invalid(format!(
                "{}: --frames needs a frame pattern ({{}} or {{:04}}) in an input",
                a.first_input()
            )));
        }
    }
    // The arguments of one frame of the sequence.
    let frame_args = |f: u64| -> Result<RenderArgs> {
        let mut one = a.clone();
        one.frames = None;
        one.frame_all = false;
        one.frame = Some(f);
        one.output = Some(PathBuf::from(expand(&out_pattern, f)?.expect("checked")));
        if let Some(exr) = &a.exr {
            one.exr = expand(&exr.to_string_lossy(), f)?
                .map(PathBuf::from)
                .or(Some(exr.clone()));
        }
        // Each input's pattern is expanded for `one.frame` by scene_from_args.
        one.seed = Some(a.seed.unwrap_or(0).wrapping_add(f));
        Ok(one)
    };
    let mine = sharded(frames, a.shard);
    // Fail before the work: every folder this job writes in exists and takes files.
    let mut ready = std::collections::BTreeSet::new();
    for &f in &mine {
        let one = frame_args(f)?;
        for p in one.output.iter().chain(one.exr.as_ref()) {
            check_extension(p)?;
            if ready.insert(p.parent().map(Path::to_path_buf)) {
                crate::atomic::prepare_output(p)?;
            }
        }
    }
    // Decided before the first frame this job renders (not at all if it renders none).
    let mut camera: Option<Option<CameraDesc>> = None;
    let mut failed = Vec::new();
    for (n, &f) in mine.iter().enumerate() {
        let mut one = frame_args(f)?;
        let target = one.output.clone().expect("set");
        if a.resume {
            // A run killed mid-write leaves a hidden `.NAME.tmp-PID-N`; this shard owns frame f.
            let mut removed = 0;
            for t in std::iter::once(&target).chain(one.exr.as_ref()) {
                removed += crate::atomic::remove_stale_temps(t)?;
            }
            if removed > 0 && !a.quiet {
                let _ = writeln!(
                    out,
                    "frame {f}: removed {removed} unfinished temporary file(s) of an interrupted run"
                );
            }
        }
        let finished = std::iter::once(&target)
            .chain(one.exr.as_ref())
            .all(|p| p.exists());
        if a.resume && finished {
            if !a.quiet {
                let _ = writeln!(out, "frame {f}: {} exists, skipped", target.display());
            }
            continue;
        }
        let mut first = None;
        if camera.is_none() {
            let decided = sequence_camera(a, frames, &frame_args, out)?;
            camera = Some(decided.camera);
            first = decided.first.filter(|(g, _)| *g == f).map(|(_, p)| p);
        }
        if let Some(Some(c)) = &camera {
            one.camera = c.position;
            one.look_at = c.look_at;
        }
        if !a.quiet {
            let _ = writeln!(out, "frame {f} ({}/{}):", n + 1, mine.len());
        }
        match render_one(&one, out, first) {
            Ok(()) => {}
            Err(e) if a.keep_going => {
                eprintln!("filmsplat: error: frame {f}: {e}");
                failed.push(f);
            }
            Err(e) => return Err(Error::invalid(format!("frame {f}: {e}"))),
        }
    }
    if !failed.is_empty() {
        return Err(Error::invalid(format!(
            "{} of {} frames failed: {:?}",
            failed.len(),
            mine.len(),
            failed
        )));
    }
    Ok(())
}

/// The camera every frame of a sequence is rendered from: `None` if the scene or the flags
/// name a camera position (it wins); else auto-framed once, on the first frame of the whole
/// `frames` list, or with --frame-all on the union of every frame's bounds, so every job of a
/// farm picks the same camera. Prints it as `[camera]` lines (unless -q). Also returns the
/// first frame's prepared scene when it was prepared whole (not with --frame-all), for the
/// caller to render instead of preparing it again.
fn sequence_camera(
    a: &RenderArgs,
    frames: &[u64],
    frame_args: &dyn Fn(u64) -> Result<RenderArgs>,
    out: &mut dyn Write,
) -> Result<SequenceCamera> {
    let first = frames[0];
    let (desc, _) = scene_from_args(&frame_args(first)?)?;
    if desc.camera.position.is_some() {
        return Ok(SequenceCamera {
            camera: None,
            first: None,
        });
    }
    let measured: &[u64] = if a.frame_all { frames } else { &frames[..1] };
    let mut framings = Vec::with_capacity(measured.len());
    let mut aspect = 1.0;
    let mut kept = None;
    for &f in measured {
        let p = prepare_frame(&frame_args(f)?, false).map_err(|e| {
            Error::invalid(format!(
                "frame {f} (the sequence's camera is framed on it): {e}"
            ))
        })?;
        framings.push(p.framing);
        aspect = p.aspect;
        if !a.frame_all {
            kept = Some((f, p));
        }
    }
    let framing = Framing::union_all(&framings).expect("at least one frame");
    let camera = framing::sequence_camera(&desc, &framing, aspect)?;
    if let Some(c) = &camera
        && !a.quiet
    {
        let on = if a.frame_all {
            format!(
                "the bounds of all {} frames ({}..={}, --frame-all)",
                frames.len(),
                first,
                frames[frames.len() - 1]
            )
        } else {
            format!("frame {first}, the first of the sequence")
        };
        let _ = writeln!(
            out,
            "camera for every frame, auto-framed on {on} (paste into a scene file to keep it):\n{}",
            framing::camera_toml(c).trim_end()
        );
    }
    Ok(SequenceCamera {
        camera,
        first: kept,
    })
}

/// What [`sequence_camera`] decided.
struct SequenceCamera {
    /// The camera every frame is rendered from; `None` if the scene names one.
    camera: Option<CameraDesc>,
    /// The first frame's number and its prepared scene, if it was prepared whole.
    first: Option<(u64, Prepared)>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_ranges_and_shards() {
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
    }
}
