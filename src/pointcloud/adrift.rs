//! Particles adrift past a rupture: where a film tears, particles are left behind the
//! retreating rim, alone or hovering a spacing or two off the film they came from. The radius
//! fit ([`super::gaps`]) must not take such a particle for film: drawn at its fitted size its
//! flat disk stands off the film (an ellipse past the rupture at the silhouette), and taken as
//! a neighbour it holds up the hull of the film's last row, which is then not cut as an edge.
//!
//! A particle is **adrift** when its nearest neighbour, or its nearest neighbour on its own
//! sheet (normals within 60°, off its tangent plane by at most [`SHEET_SLOPE`] × the distance
//! along it), lies farther than [`DETACHED`] × the sum of
//! the two particles' own area radii √(A/π) — or it has no neighbour on its sheet at all. It is
//! then drawn at its own size and left out of every other particle's fan. Only where the
//! simulator stores the areas (unknown areas: never adrift).
//!
//! Measured on the writers' intact films (thin-film SPH bubble frames 0 and 10, catenoid 45,
//! Rayleigh–Taylor 100, drops on a film 105, MELP bubble 100 and 104): no particle is adrift,
//! at a slope of 0.35 as at 1. Bursting bubble frame 30: particles 2017 and 1966 hover 3–7 mm
//! (1–2 spacings) off the film beside them (the film's neighbours 1–2 spacings away lie at
//! 40–70° off their tangent planes) and were grown to 4 and 3.6 × their own radius as if that
//! film were theirs; 209 lies 1.8 × the sum away from its nearest and held up 1966's hull.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::area::DETACHED;
use super::cell::off_sheet;
use super::knn::{KnnTable, PointIndex};

/// Most a neighbour on a particle's sheet lies off its tangent plane, as a multiple of its
/// distance along it (26.6°): a film curved to radius R keeps its neighbours at distance d
/// within d / 2R of the plane, so only a neighbour farther along than the radius of curvature
/// is taken off the sheet.
pub const SHEET_SLOPE: f32 = 0.5;

/// Whether particle `i` is adrift (see the module docs): `own`, the particles' own radii
/// √(A/π) (0: unknown); `row`, its neighbours `(index, distance)`, nearest first.
pub fn is_adrift(
    i: usize,
    (positions, normals): (&[Vec3], &[Vec3]),
    own: &[f32],
    row: impl Iterator<Item = (u32, f32)>,
) -> bool {
    let a = own.get(i).copied().unwrap_or(0.0);
    let (p, n) = (positions[i], normals[i]);
    if !(a > 0.0 && a.is_finite() && p.is_finite() && n.is_finite()) || n.length_squared() < 0.5 {
        return false;
    }
    let (u, v) = n.any_orthonormal_pair();
    for (k, (j, d)) in row.enumerate() {
        let b = own.get(j as usize).copied().unwrap_or(0.0);
        if !(b > 0.0 && b.is_finite()) {
            return false;
        }
        let far = d > DETACHED * (a + b);
        let off = positions[j as usize] - p;
        let flat = Vec2::new(off.dot(u), off.dot(v)).length();
        let on_sheet = !off_sheet(n, normals[j as usize], off, flat, SHEET_SLOPE);
        if on_sheet || k == 0 && far {
            return far;
        }
    }
    true
}

/// [`is_adrift`] for every particle, from `table`'s rows, else `k` neighbours searched in
/// `index`; empty when no own radius is known. Cost: one pass over the rows (a k-nearest
/// search a particle without a table), parallel.
pub fn adrift_flags(
    index: &PointIndex,
    (positions, normals): (&[Vec3], &[Vec3]),
    own: &[f32],
    table: Option<&KnnTable>,
    k: usize,
) -> Vec<bool> {
    if own.len() != positions.len() || !own.iter().any(|o| *o > 0.0) {
        return Vec::new();
    }
    (0..positions.len())
        .into_par_iter()
        .with_min_len(512)
        .map(|i| match table {
            Some(t) => is_adrift(i, (positions, normals), own, t.row(i)),
            None => {
                let row = index.nearest_excluding(positions[i], k, i as u32);
                is_adrift(i, (positions, normals), own, row.into_iter())
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_particle_off_the_film_or_alone_is_adrift_and_the_film_is_not() {
        // A 6×6 grid of spacing 1 in z = 0, own radius 0.6 each (neighbours at 0.83 × the sum),
        // one particle hovering 1.5 above the middle and one alone 5 beyond the edge.
        let mut pos: Vec<Vec3> = (0..36)
            .map(|i| Vec3::new((i % 6) as f32, (i / 6) as f32, 0.0))
            .collect();
        pos.push(Vec3::new(2.5, 2.5, 1.5));
        pos.push(Vec3::new(10.0, 2.5, 0.0));
        let normals = vec![Vec3::Z; pos.len()];
        let own = vec![0.6; pos.len()];
        let index = PointIndex::build(&pos);
        let flags = adrift_flags(&index, (&pos, &normals), &own, None, 12);
        assert_eq!(flags.iter().filter(|f| **f).count(), 2, "{flags:?}");
        assert!(flags[36] && flags[37]);
        // The same with areas unknown: nothing is judged.
        assert!(adrift_flags(&index, (&pos, &normals), &[0.0; 38], None, 12).is_empty());
        // Hovering only half a spacing above: still on the film (its second ring, 1.66 away at
        // 0.69 × the sum, lies 1.58 along the plane and 0.5 off it).
        pos[36].z = 0.5;
        let index = PointIndex::build(&pos);
        let flags = adrift_flags(&index, (&pos, &normals), &own, None, 12);
        assert!(!flags[36] && flags[37]);
    }
}
