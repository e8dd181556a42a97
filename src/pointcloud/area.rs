//! The particles' own size: the radius of the disk of the area a simulator stores for each
//! particle (the thin-film SPH code's `sa_bin`, MELP's `SA`), and the bounds it puts on splat
//! radii (see [`super::gaps`]).

/// Largest radius, as a multiple of the radius of the particle's own area √(A/π) (where the
/// simulator stores the area), that a splat keeps without a measured gap to close: the radius
/// as read or estimated from the spacing. On a hexagonal sampling a disk must reach
/// 1.10 × √(A/π) to cover its cell, 1.27 × with the blending margin [`super::gaps::GAP_MARGIN`]; on the
/// writers' own intact films the fit's need is a median 1.4–1.6 × √(A/π) (thin-film SPH bubble
/// frame 0, catenoid, Rayleigh–Taylor and drops-on-film frames, MELP's bubble), and the
/// spacing-based estimate a median 1.8 ×. Twice the area's radius keeps the films closed and
/// stops a spacing-based radius from drawing a particle far larger than its area.
pub const AREA_OVERLAP: f32 = 2.0;

/// Largest radius, as a multiple of √(A/π), a splat grows to close a gap its cell leaves
/// between its neighbours: the fit's need reaches at most 3.8 × √(A/π) on the intact films
/// named at [`AREA_OVERLAP`] (99.9th percentile 2.2–3.4 ×), so no film closed there opens here.
pub const AREA_GROWTH: f32 = 4.0;

/// The radius of the disk of each area (scene units², e.g. the simulators' `SA` in m²),
/// √(A/π); 0 for a non-finite or negative area.
pub fn area_radii(areas: &[f32]) -> Vec<f32> {
    areas
        .iter()
        .map(|a| {
            if a.is_finite() && *a > 0.0 {
                (a / std::f32::consts::PI).sqrt()
            } else {
                0.0
            }
        })
        .collect()
}

/// Names of the per-particle area attribute (scene units²) the simulators write: the thin-film
/// SPH code's `sa_bin` (read as `sa`), MELP's `SA`.
pub const AREA_ATTRIBUTES: &[&str] = &["sa", "SA"];

/// The radius of each particle's own area ([`area_radii`] of the first of
/// [`AREA_ATTRIBUTES`] the cloud holds); empty when it holds none.
pub fn own_radii(cloud: &super::PointCloud) -> Vec<f32> {
    AREA_ATTRIBUTES
        .iter()
        .find_map(|name| cloud.extra(name))
        .map(area_radii)
        .unwrap_or_default()
}

/// Bounds every radius by [`AREA_OVERLAP`] × its particle's area radius `own` (from
/// [`area_radii`]; 0 means unknown and bounds nothing). Returns how many were trimmed.
pub fn bound_by_area(radii: &mut [f32], own: &[f32]) -> usize {
    let mut trimmed = 0;
    for (r, o) in radii.iter_mut().zip(own) {
        if *o > 0.0 && *r > AREA_OVERLAP * o {
            *r = AREA_OVERLAP * o;
            trimmed += 1;
        }
    }
    trimmed
}
