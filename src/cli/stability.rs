//! `filmsplat stability`: temporal stability of a rendered sequence — the mean per-pixel
//! CIEDE2000 change between adjacent frames, where the geometry moves little.

use super::parse::{self as frame_parse, FrameList};
use crate::image::stability::frame_change;
use crate::image::{RgbImage, read_exr, read_png};
use crate::pipeline::sequence;
use crate::{Error, Result};
use clap::Args;
use std::io::Write;
use std::path::Path;

/// Arguments of `filmsplat stability`.
#[derive(Debug, Args)]
pub struct StabilityArgs {
    /// Frame pattern of the rendered sequence, e.g. 'out/{:04}.exr' (EXR from `render --exr`
    /// carries the depth layer) or 'out/{:04}.png'.
    frames_pattern: String,
    /// Frames to compare, adjacent pairs (A..B, A..=B).
    #[arg(long, value_parser = frame_parse::frame_list)]
    frames: FrameList,
    /// Frame pattern of EXRs with the depth layer, for PNG frames (default: the frames
    /// themselves if they are EXR; PNG frames without it compare every pixel).
    #[arg(long)]
    depth: Option<String>,
    /// Pixels count only where the depth changes by at most this fraction between frames.
    #[arg(long, default_value_t = 0.01, value_parser = super::parse::finite_f32)]
    depth_tolerance: f32,
}

fn is_exr(p: &str) -> bool {
    p.to_ascii_lowercase().ends_with(".exr")
}

/// Colour (linear RGB) and depth of frame `f`.
fn load(a: &StabilityArgs, f: u64) -> Result<(RgbImage, Option<Vec<f32>>)> {
    let path = sequence::expand(&a.frames_pattern, f)?.expect("checked");
    let depth_of = |p: &str| -> Result<Vec<f32>> {
        read_exr(Path::new(p))?
            .depth
            .ok_or_else(|| Error::invalid(format!("{p}: the EXR has no depth layer (depth.Z)")))
    };
    let (img, depth) = if is_exr(&path) {
        let l = read_exr(Path::new(&path))?;
        let img = RgbImage {
            width: l.width,
            height: l.height,
            data: l.rgba.iter().map(|p| [p[0], p[1], p[2]]).collect(),
        };
        (img, l.depth)
    } else {
        (read_png(Path::new(&path))?, None)
    };
    let depth = match &a.depth {
        Some(pat) => Some(depth_of(&sequence::expand(pat, f)?.expect("checked"))?),
        None => depth,
    };
    Ok((img, depth))
}

/// Runs `filmsplat stability`.
pub fn run(a: &StabilityArgs, out: &mut dyn Write) -> Result<()> {
    for p in std::iter::once(&a.frames_pattern).chain(&a.depth) {
        if sequence::expand(p, 0)?.is_none() {
            return Err(Error::invalid(format!(
                "{p}: needs a frame pattern ({{}} or {{:04}})"
            )));
        }
    }
    if !(a.depth_tolerance >= 0.0 && a.depth_tolerance.is_finite()) {
        return Err(Error::invalid(
            "--depth-tolerance must be a finite fraction >= 0",
        ));
    }
    let frames = &a.frames.0;
    if frames.len() < 2 {
        return Err(Error::invalid("--frames must name at least two frames"));
    }
    let mut prev = load(a, frames[0])?;
    let (mut sum, mut covered, mut pairs) = (0.0f64, 0.0f64, 0usize);
    let mut worst = (0.0f64, frames[0]);
    for &f in &frames[1..] {
        let next = load(a, f)?;
        let depth = match (&prev.1, &next.1) {
            (Some(x), Some(y)) => Some((x.as_slice(), y.as_slice())),
            _ => None,
        };
        let c = frame_change(&prev.0, &next.0, depth, a.depth_tolerance)
            .map_err(|e| Error::invalid(format!("frame {f}: {e}")))?;
        let _ = writeln!(
            out,
            "frames {}-{f}: mean dE00 {:.3} over {:.1} % of the pixels",
            f - 1,
            c.mean_delta_e,
            100.0 * c.pixels as f64 / c.total as f64
        );
        sum += c.mean_delta_e;
        covered += c.pixels as f64 / c.total as f64;
        pairs += 1;
        if c.mean_delta_e > worst.0 {
            worst = (c.mean_delta_e, f);
        }
        prev = next;
    }
    let _ = writeln!(
        out,
        "{pairs} pairs: mean dE00 {:.3} (worst {:.3} at frame {}), {:.1} % of the pixels compared ({})",
        sum / pairs as f64,
        worst.0,
        worst.1,
        100.0 * covered / pairs as f64,
        if prev.1.is_some() {
            format!("depth change <= {} %", 100.0 * a.depth_tolerance)
        } else {
            "no depth: every pixel".to_string()
        }
    );
    Ok(())
}
