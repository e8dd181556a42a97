//! Whether the radius fit ([`super::gaps`]) would change anything, judged on a sample: the
//! same fit (same first look among [`FAN_NEIGHBOURS`], same second looks, same own sizes, same
//! adrift test) run on every [`SCREEN_STRIDE`]-th particle only, or on every particle of a
//! cloud of at most [`SCREEN_WHOLE`]. Where no sampled particle's radius, cut or edge would
//! change, the caller may keep the radii as they are and skip the whole fit.
//!
//! What it guarantees: each sampled particle's verdict is the whole fit's, bit for bit (a
//! test holds it to the fit); a cloud of at most [`SCREEN_WHOLE`] particles is judged exactly;
//! on a larger one, a change is found when one of the particles it touches is sampled. So a
//! film that needs the fit over a large part (sparser sampling than its radii cover, torn
//! rims, free edges, fragments) is always fitted; a defect touching m particles whose places
//! in the file are unrelated to the stride is missed with a chance of about (1 − 1/32)^m: a
//! small hole of a few missing particles (its rim 10–20 particles) more often than not.
//!
//! Cost: on a sample of n / 32, a k-nearest search, a fan and (where its first look is
//! bounded) a second look each, plus the fit's spacing estimate (65,536 searches) — about a
//! thirtieth of the whole fit, which also searches a 12-neighbour table for every particle.

use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};

use glam::Vec3;
use rayon::prelude::*;

use super::adrift::is_adrift;
use super::cut::Cut;
use super::fan::Fit;
use super::gaps::{FAN_NEIGHBOURS, apply, fit_row, scales};
use super::knn::PointIndex;
use super::looks::{Cloud, SecondLook, second_looks};

/// One particle in this many is sampled (evenly strided through the file's order).
pub const SCREEN_STRIDE: usize = 32;

/// Clouds of at most this many particles are judged whole (every particle sampled).
pub const SCREEN_WHOLE: usize = 32_768;

/// What the screen found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Screen {
    /// Particles judged.
    pub sampled: usize,
    /// One in how many particles was judged (1: all).
    pub stride: usize,
    /// Of those, how many the fit would change (radius, edge cut, on an edge, adrift), plus
    /// one if a neighbour of theirs is adrift.
    pub changed: usize,
}

impl Screen {
    /// The fit would change none of the sampled particles.
    pub fn keeps_radii(&self) -> bool {
        self.changed == 0
    }
}

impl std::fmt::Display for Screen {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let what = if self.stride == 1 {
            format!("the {} particles (each one checked)", self.sampled)
        } else {
            format!(
                "a sample of {} particles (1 in {}, strided through the file)",
                self.sampled, self.stride
            )
        };
        if self.keeps_radii() {
            write!(
                f,
                "radii kept as read: the radius fit would change none of {what} (--fit-radii always fits every particle)"
            )
        } else {
            write!(
                f,
                "radii fitted: the radius fit would change {} of {what}",
                self.changed
            )
        }
    }
}

/// Runs the radius fit ([`super::gaps::fit_radii_clipped`], default second look) on a sample
/// of the particles (see the module docs) with `index` over `positions`, unit `normals`, the
/// `radii` as they are and the particles' own sizes `own` (empty or 0: unknown), changing
/// nothing. Cost: see the module docs.
pub fn screen_fit(
    index: &PointIndex,
    positions: &[Vec3],
    normals: &[Vec3],
    radii: &[f32],
    own: &[f32],
) -> Screen {
    let n = positions.len();
    let stride = if n <= SCREEN_WHOLE { 1 } else { SCREEN_STRIDE };
    screen_fit_strided(index, (positions, normals), radii, own, stride)
}

/// [`screen_fit`] on every `stride`-th particle (1: all; 0 is taken as 1), whatever the
/// cloud's size.
pub fn screen_fit_strided(
    index: &PointIndex,
    (positions, normals): (&[Vec3], &[Vec3]),
    radii: &[f32],
    own: &[f32],
    stride: usize,
) -> Screen {
    let n = positions.len();
    let stride = stride.max(1);
    let ids: Vec<u32> = (0..n as u32).step_by(stride).collect();
    let mut screen = Screen {
        sampled: ids.len(),
        stride,
        changed: 0,
    };
    if n < 3 || normals.len() != n || radii.len() != n || index.len() > n {
        return screen;
    }
    let scales = scales(index, positions, radii);
    // The adrift test of every particle a sampled row holds, each once (0: not yet, 1: no,
    // 2: adrift), as the fit's from its FAN_NEIGHBOURS nearest.
    let areas = own.len() == n && own.iter().any(|o| *o > 0.0);
    let known: Vec<AtomicU8> = if areas {
        (0..n).map(|_| AtomicU8::new(0)).collect()
    } else {
        Vec::new()
    };
    let any_adrift = AtomicBool::new(false);
    let drifting = |j: usize| {
        let Some(state) = known.get(j) else {
            return false;
        };
        let adrift = match state.load(Ordering::Relaxed) {
            0 => {
                let row = index.nearest_excluding(positions[j], FAN_NEIGHBOURS, j as u32);
                let a = is_adrift(j, (positions, normals), own, row.into_iter());
                state.store(1 + u8::from(a), Ordering::Relaxed);
                a
            }
            s => s == 2,
        };
        if adrift {
            any_adrift.store(true, Ordering::Relaxed);
        }
        adrift
    };
    let fit = fit_row((positions, normals, radii), scales, &drifting);
    let mut looked: Vec<(Fit, Option<f32>)> = ids
        .par_iter()
        .with_min_len(512)
        .map_init(Default::default, |s, &i| {
            let i = i as usize;
            let row = index.nearest_excluding(positions[i], FAN_NEIGHBOURS, i as u32);
            let f = fit(s, i, &mut row.into_iter());
            (f, if drifting(i) { None } else { s.sixth() })
        })
        .collect();
    let cloud = Cloud {
        index,
        ids: Some(&ids),
        positions,
        normals,
        longest: scales.1,
        drifting: &drifting,
        fit: &fit,
    };
    second_looks(&cloud, &mut looked, SecondLook::default());
    let fits: Vec<Fit> = looked.into_iter().map(|(f, _)| f).collect();
    let own = if areas { own } else { &[] };
    let changed = changes(&ids, radii, own, &fits, scales.0);
    screen.changed = changed + usize::from(any_adrift.load(Ordering::Relaxed));
    screen
}

/// How many of the particles `ids` the fit's verdicts `fits` (one each) change: radius
/// (growth capped at `cap`; `own`, every particle's own size, or empty), edge cut, or on an
/// edge.
fn changes(ids: &[u32], radii: &[f32], own: &[f32], fits: &[Fit], cap: f32) -> usize {
    let mut kept: Vec<f32> = ids.iter().map(|&i| radii[i as usize]).collect();
    let own: Vec<f32> = match own.is_empty() {
        true => Vec::new(),
        false => ids.iter().map(|&i| own[i as usize]).collect(),
    };
    let before = kept.clone();
    let (_, verdicts) = apply(&mut kept, fits.iter().copied(), cap, &own);
    let on_edge = |f: &Fit| matches!(f, Fit::Sheet { edge: true, .. });
    (kept.iter().zip(&before).zip(verdicts.iter().zip(fits)))
        .filter(|((a, b), (c, f))| a.to_bits() != b.to_bits() || **c != Cut::None || on_edge(f))
        .count()
}
