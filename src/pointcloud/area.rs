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

/// How far a particle's nearest neighbour lies, as a multiple of the sum of the two
/// particles' own area radii, before the particle counts as detached from the film (a torn
/// film's last particle past its rupture). On the writers' intact films the nearest neighbour
/// lies at most 1.25 × that sum (99.9th percentile 0.94–1.07: the thin-film SPH bubble's frames
/// 0 and 10, catenoid, Rayleigh–Taylor, drops on a film, a blown bubble, MELP's bubble); the
/// bursting bubble's detached particles lie 1.5–2.8 × away.
pub const DETACHED: f32 = 1.5;

/// Draws every detached particle (see [`DETACHED`]) at its own size, √(A/π): no growth
/// reaches across a rupture towards the film it has left. `nearest(i)` gives particle `i`'s
/// nearest neighbour; `own` as from [`area_radii`] (0: unknown, never detached). Returns how
/// many radii were trimmed.
pub fn detached_at_own_size(
    radii: &mut [f32],
    own: &[f32],
    nearest: impl Fn(usize) -> Option<(u32, f32)>,
) -> usize {
    let mut trimmed = 0;
    for i in 0..radii.len().min(own.len()) {
        let Some((j, d)) = nearest(i) else { continue };
        let (a, b) = (own[i], own.get(j as usize).copied().unwrap_or(0.0));
        if a > 0.0 && b > 0.0 && d > DETACHED * (a + b) && radii[i] > a {
            radii[i] = a;
            trimmed += 1;
        }
    }
    trimmed
}

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_detached_particle_keeps_its_own_size_and_the_film_its_fit() {
        // Own radius 1 each; particle 2 lies 4 from its nearest (> 1.5 × 2); 0 and 1 touch.
        let own = [1.0, 1.0, 1.0];
        let nearest = |i: usize| {
            Some(match i {
                0 => (1, 1.9),
                1 => (0, 1.9),
                _ => (1, 4.0),
            })
        };
        let mut radii = [1.8, 1.8, 3.5];
        assert_eq!(detached_at_own_size(&mut radii, &own, nearest), 1);
        assert_eq!(radii, [1.8, 1.8, 1.0]);
        // Unknown area (0): never detached.
        let mut radii = [3.5, 3.5, 3.5];
        assert_eq!(detached_at_own_size(&mut radii, &[0.0; 3], nearest), 0);
    }
}
