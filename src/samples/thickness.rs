//! The thin-film thickness field every sample generator paints its particles with: drainage
//! from top to bottom, thin "black film" patches, and swirls advected by drifting vortices.
//!
//! The field lives on the unit sphere (z up, gravity −z). A generator maps each particle to a
//! point q of the sphere with a smooth [`Chart`] (a bubble: its direction from the centre; a
//! flat film: a gently curved patch of the sphere facing the viewer) and reads h(q, time).
//!
//! # Model (nm)
//! 1. **Drainage.** With s = (top − q.z)/(top − bottom) ∈ [0, 1] the normalised depth below
//!    the film's top, h_d(s) = h_top + (h_bottom − h_top)·s^0.75: steepest near the top like
//!    Mysels' rigid-surface drainage law h ∝ √(x/t), softened so that the vivid low orders
//!    (< 400 nm) cover the upper part; slowly thinning as √(τ/(τ + time)) with τ = 60 s. Eight
//!    low-frequency waves (a few %, at most ±16 %) break the symmetry.
//! 2. **Black film.** A few seeded patches near the top (within `patch_tilt` of `patch_pole`)
//!    drop to [`H_BLACK_NM`] with a sharp rim, as in real draining films.
//! 3. **Swirls.** The field is advected by a divergence-free tangential flow: Gaussian vortices
//!    u(p) = Σ Ωᵥ·exp(−|p − cᵥ|²/2σᵥ²)·(cᵥ × p) on the unit sphere — the surface curl of the
//!    stream function Σ −Ωᵥσᵥ²·exp(−|p − cᵥ|²/2σᵥ²), so area (and thickness) is conserved.
//!    Point q shows h(X), X its position traced *back* along the flow (RK2, on the sphere)
//!    over a memory window of [`SWIRL_MEMORY`] s ending at `time`. The vortex centres drift
//!    about the chart's axis and wobble, so the bands twist into spirals that move smoothly as
//!    `time` advances. (The finite memory stands for gravity re-stratifying the film; it keeps
//!    the pattern from winding into noise and the cost per frame constant.)

use super::rng::SplitMix64;
use glam::{DQuat, DVec3};
use rayon::prelude::*;
use std::f64::consts::TAU;

/// Seconds of flow history that shape the swirls at any `time`.
pub const SWIRL_MEMORY: f64 = 2.5;
/// RK2 time step of the back-tracing, seconds (≤ 0.15 rad of rotation a step).
const SWIRL_DT: f64 = 0.05;
/// Default thickness at the film's top, before black-film patches (nm).
pub const H_TOP_NM: f32 = 60.0;
/// Default thickness at the film's bottom (nm).
pub const H_BOTTOM_NM: f32 = 1100.0;
/// Thickness of black-film patches (nm).
pub const H_BLACK_NM: f32 = 25.0;

/// Where a film lies on the field's unit sphere, and its thickness range.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    /// q.z of the film's top (thinnest) and bottom (thickest).
    pub top: f64,
    /// See `top`.
    pub bottom: f64,
    /// The film's image is within `angle` (rad) of `axis` (unit); vortices live there and
    /// drift about `axis`.
    pub axis: DVec3,
    /// See `axis`.
    pub angle: f64,
    /// Black patches are centred within `patch_tilt` (rad) of `patch_pole` (unit).
    pub patch_pole: DVec3,
    /// See `patch_pole`.
    pub patch_tilt: f64,
    /// Size of vortices, patches and waves relative to a whole bubble (1 = bubble).
    pub scale: f64,
    /// Number of vortices (a bubble has 6).
    pub vortices: usize,
    /// Thickness at the top and bottom, nm.
    pub h_top_nm: f64,
    /// See `h_top_nm`.
    pub h_bottom_nm: f64,
}

impl Chart {
    /// A whole sphere: top at the north pole, bottom at the south pole.
    pub fn sphere() -> Chart {
        Chart {
            top: 1.0,
            bottom: -1.0,
            axis: DVec3::Z,
            angle: std::f64::consts::PI,
            patch_pole: DVec3::Z,
            patch_tilt: 0.45, // ≈ 25° from the apex at most
            scale: 1.0,
            vortices: 6,
            h_top_nm: H_TOP_NM as f64,
            h_bottom_nm: H_BOTTOM_NM as f64,
        }
    }

    /// True if unit point `q` lies in the chart's region.
    fn contains(&self, q: DVec3) -> bool {
        q.dot(self.axis).clamp(-1.0, 1.0).acos() <= self.angle
            && (self.bottom..=self.top).contains(&q.z)
    }

    /// Normalised depth below the top, s ∈ [0, 1].
    pub fn depth(&self, q: DVec3) -> f64 {
        ((self.top - q.z) / (self.top - self.bottom)).clamp(0.0, 1.0)
    }
}

/// A Gaussian surface vortex.
#[derive(Debug, Clone, Copy)]
struct Vortex {
    centre: DVec3,
    /// Peak angular velocity, rad/s (sign = sense of rotation).
    omega: f64,
    /// 1 / (2σ²), σ the core size on the unit sphere.
    inv_two_sigma2: f64,
    /// Drift about the chart's axis, rad/s.
    drift: f64,
    /// Oscillation across the drift: axis, amplitude (rad), angular frequency, phase.
    wobble_axis: DVec3,
    wobble_amp: f64,
    wobble_freq: f64,
    wobble_phase: f64,
}

/// The seeded, time-independent ingredients of a thickness field.
#[derive(Debug, Clone)]
pub struct ThicknessField {
    chart: Chart,
    vortices: Vec<Vortex>,
    /// Black patches: centre (unit), angular radius.
    patches: Vec<(DVec3, f64)>,
    /// Waves: direction, spatial frequency, phase, relative amplitude.
    waves: Vec<(DVec3, f64, f64, f64)>,
}

fn random_unit(g: &mut SplitMix64) -> DVec3 {
    let z = g.range(-1.0, 1.0);
    let phi = g.range(0.0, TAU);
    let r = (1.0 - z * z).sqrt();
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

impl ThicknessField {
    /// The field of `seed` over `chart`. Deterministic for a seed.
    pub fn new(seed: u64, chart: Chart) -> ThicknessField {
        let mut g = SplitMix64::new(seed ^ 0x0B0B_B1E5);
        let axis = chart.axis;
        let vortices = (0..chart.vortices)
            .map(|_| {
                let mut centre = random_unit(&mut g);
                for _ in 0..1000 {
                    if chart.contains(centre) {
                        break;
                    }
                    centre = random_unit(&mut g);
                }
                let sigma = g.range(0.25, 0.45) * chart.scale;
                let sign = if g.next_f64() < 0.5 { -1.0 } else { 1.0 };
                let wobble_axis = centre
                    .cross(axis)
                    .normalize_or(axis.any_orthonormal_vector());
                Vortex {
                    centre,
                    omega: sign * g.range(1.2, 2.5),
                    inv_two_sigma2: 1.0 / (2.0 * sigma * sigma),
                    drift: g.range(-0.3, 0.3),
                    wobble_axis,
                    wobble_amp: g.range(0.1, 0.35) * chart.scale,
                    wobble_freq: g.range(0.2, 0.6),
                    wobble_phase: g.range(0.0, TAU),
                }
            })
            .collect();
        let to_pole = DQuat::from_rotation_arc(DVec3::Z, chart.patch_pole);
        let patches = (0..g.range(3.0, 6.0) as usize)
            .map(|_| {
                let tilt = g.range(0.0, chart.patch_tilt);
                let az = g.range(0.0, TAU);
                let c = DVec3::new(tilt.sin() * az.cos(), tilt.sin() * az.sin(), tilt.cos());
                (to_pole * c, g.range(0.06, 0.16) * chart.scale)
            })
            .collect();
        let waves = (0..8)
            .map(|_| {
                (
                    random_unit(&mut g),
                    g.range(2.0, 7.0) / chart.scale,
                    g.range(0.0, TAU),
                    g.range(0.01, 0.02),
                )
            })
            .collect();
        ThicknessField {
            chart,
            vortices,
            patches,
            waves,
        }
    }

    /// The chart the field was built for.
    pub fn chart(&self) -> &Chart {
        &self.chart
    }

    fn centres(&self, t: f64) -> Vec<DVec3> {
        self.vortices
            .iter()
            .map(|v| {
                let wobble = DQuat::from_axis_angle(
                    v.wobble_axis,
                    v.wobble_amp * (v.wobble_freq * t + v.wobble_phase).sin(),
                );
                DQuat::from_axis_angle(self.chart.axis, v.drift * t) * (wobble * v.centre)
            })
            .collect()
    }

    /// Flow velocity at unit-sphere point `p`, vortex centres `centres` (1/s).
    fn velocity(&self, p: DVec3, centres: &[DVec3]) -> DVec3 {
        let mut u = DVec3::ZERO;
        for (v, c) in self.vortices.iter().zip(centres) {
            let w = v.omega * (-(p - *c).length_squared() * v.inv_two_sigma2).exp();
            u += c.cross(p) * w;
        }
        u
    }

    /// Unadvected thickness at unit-sphere point `p`, nm.
    fn base_thickness(&self, p: DVec3, thinning: f64) -> f64 {
        let c = &self.chart;
        let s = c.depth(p);
        let drained = c.h_top_nm + (c.h_bottom_nm - c.h_top_nm) * s.powf(0.75);
        let wave: f64 = self
            .waves
            .iter()
            .map(|(d, f, ph, a)| a * (f * d.dot(p) + ph).sin())
            .sum();
        let h = drained * thinning * (1.0 + wave);
        // Black film: sharp-rimmed patches.
        let mut black = 0.0f64;
        for (c, r) in &self.patches {
            let ang = p.dot(*c).clamp(-1.0, 1.0).acos();
            let x = ((r - ang) / (0.15 * r)).clamp(0.0, 1.0); // rim width 15 % of the radius
            black = black.max(x * x * (3.0 - 2.0 * x));
        }
        h + (H_BLACK_NM as f64 - h) * black
    }

    /// The field frozen at `time` (s): the flow history precomputed for [`FieldAt::thickness`].
    pub fn at(&self, time: f64) -> FieldAt<'_> {
        let nsteps = (SWIRL_MEMORY / SWIRL_DT).round() as usize;
        let dt = SWIRL_MEMORY / nsteps as f64;
        let steps = (0..nsteps)
            .map(|k| {
                let t = time - k as f64 * dt;
                (dt, self.centres(t), self.centres(t - 0.5 * dt))
            })
            .collect();
        FieldAt {
            field: self,
            steps,
            thinning: (60.0 / (60.0 + time.max(0.0))).sqrt(),
        }
    }

    /// Thickness (nm) at each unit point of `qs` at `time`, in parallel; deterministic.
    pub fn thickness_of(&self, qs: &[DVec3], time: f64) -> Vec<f32> {
        let at = self.at(time);
        qs.par_iter().map(|q| at.thickness(*q) as f32).collect()
    }
}

/// A [`ThicknessField`] at one time.
pub struct FieldAt<'a> {
    field: &'a ThicknessField,
    /// RK2 steps backwards in time: dt, vortex centres at the step's start and middle.
    steps: Vec<(f64, Vec<DVec3>, Vec<DVec3>)>,
    thinning: f64,
}

impl FieldAt<'_> {
    /// Thickness at unit-sphere point `p`, nm: the base field at the back-traced position.
    pub fn thickness(&self, p: DVec3) -> f64 {
        let f = self.field;
        let mut x = p;
        // Trace backwards from `time` to `time − SWIRL_MEMORY` (RK2 midpoint, re-projected).
        for (dt, c0, cmid) in &self.steps {
            let k1 = f.velocity(x, c0);
            let xm = (x - k1 * (0.5 * dt)).normalize();
            let k2 = f.velocity(xm, cmid);
            x = (x - k2 * *dt).normalize();
        }
        f.base_thickness(x, self.thinning)
    }
}
