//! Which 3D particles are bulk liquid and which are droplets. The thin-film SPH code's 3D
//! particles (`tracker_points_3d`) are one SPH fluid (`sph_bubble/Fluid3DSPH.h`): each carries
//! the mass of a film particle, but the solver gives it the volume 1 / (its number density),
//! i.e. its share of the space its neighbours fill. Packed together (drops falling onto a film,
//! a dripping film, a bursting bubble's rim) they are bodies of liquid; alone, a droplet.
//!
//! * **Spacing** s: the median distance to the 12th neighbour over (3·12 / 4π)^⅓ = 1.42, the
//!   radius holding 12 particles of volume s³ each — for a cubic lattice of spacing s exactly s
//!   (its 12th neighbour is at √2 s), and, unlike the nearest-neighbour distance, robust to the
//!   close pairs an irregular SPH packing holds.
//! * **Bodies**: a particle with at least [`CORE_NEIGHBOURS`] others within 2 s lies inside a
//!   body (a particle in a cubic lattice has 32, on a face 22, on an edge 15, at a corner 10; one
//!   in a flat sheet 12, in a line 4, a pair 1); every particle within 2 s of such a core
//!   particle belongs to the body too (a body's edges and corners). The rest stay droplets.

use glam::Vec3;

use super::estimate::median_positive;
use super::knn::{KnnTable, NO_NEIGHBOUR};

/// Neighbours within [`NEIGHBOUR_SPACINGS`] spacings that make a particle a body's core.
pub const CORE_NEIGHBOURS: usize = 13;

/// The neighbour radius of the classification, liquid spacings.
pub const NEIGHBOUR_SPACINGS: f32 = 2.0;

/// The neighbour whose distance measures the spacing.
const SPACING_NEIGHBOUR: usize = 12;

/// Neighbours searched per particle (more than a core needs within 2 s in a packed body).
const SEARCHED: usize = 40;

/// The 3D particles split into liquid bodies and droplets.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LiquidSplit {
    /// Liquid spacing s, scene units (0 when there are too few particles to measure it).
    pub spacing: f32,
    /// Indices of the particles in liquid bodies.
    pub liquid: Vec<usize>,
    /// Indices of the particles that stay droplets.
    pub droplets: Vec<usize>,
    /// Number of separate bodies: the liquid particles joined through the core particles
    /// within [`NEIGHBOUR_SPACINGS`] spacings of each other or of them.
    pub bodies: usize,
}

/// The spacing s of `m`-th neighbour distances `d`: `d / (3m / 4π)^⅓`.
fn spacing_of(d: f32, m: usize) -> f32 {
    d / (3.0 * m as f32 / (4.0 * std::f32::consts::PI)).cbrt()
}

/// Splits `positions` (scene units) into liquid bodies and droplets (see the module docs).
/// Cost: one `SEARCHED`-neighbour search, O(n log n).
pub fn classify(positions: &[Vec3]) -> LiquidSplit {
    let n = positions.len();
    let all_droplets = || LiquidSplit {
        spacing: 0.0,
        liquid: Vec::new(),
        droplets: (0..n).collect(),
        bodies: 0,
    };
    if n <= CORE_NEIGHBOURS {
        return all_droplets();
    }
    let k = SEARCHED.min(n - 1);
    let table = KnnTable::build(positions, k);
    let m = SPACING_NEIGHBOUR.min(k);
    let Some(d) = median_positive((0..n).filter_map(|i| table.kth_distance(i, m))) else {
        return all_droplets();
    };
    let spacing = spacing_of(d, m);
    let reach = NEIGHBOUR_SPACINGS * spacing;
    let within = |i: usize| {
        table
            .row(i)
            .filter(move |&(j, dist)| j != NO_NEIGHBOUR && dist <= reach)
    };
    let core: Vec<bool> = (0..n)
        .map(|i| within(i).count() >= CORE_NEIGHBOURS)
        .collect();
    let (liquid, droplets): (Vec<usize>, Vec<usize>) =
        (0..n).partition(|&i| core[i] || within(i).any(|(j, _)| core[j as usize]));
    // Bodies: each core particle joined to every particle within reach (union-find).
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for i in (0..n).filter(|&i| core[i]) {
        for (j, _) in within(i) {
            let (a, b) = (root(&mut parent, i), root(&mut parent, j as usize));
            parent[a] = b;
        }
    }
    let bodies = liquid
        .iter()
        .filter(|&&i| root(&mut parent, i) == i)
        .count();
    LiquidSplit {
        spacing,
        liquid,
        droplets,
        bodies,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lattice(nx: i32, ny: i32, nz: i32, s: f32, origin: Vec3) -> Vec<Vec3> {
        let mut v = Vec::new();
        for i in 0..nx {
            for j in 0..ny {
                for k in 0..nz {
                    v.push(origin + s * Vec3::new(i as f32, j as f32, k as f32));
                }
            }
        }
        v
    }

    #[test]
    fn a_block_is_liquid_and_spray_stays_droplets() {
        let s = 0.005;
        let mut p = lattice(6, 6, 6, s, Vec3::ZERO);
        let block = p.len();
        // A flat sheet, a line and lone particles far away keep their droplets.
        p.extend(lattice(8, 1, 8, s, Vec3::new(1.0, 0.0, 0.0)));
        p.extend(lattice(10, 1, 1, s, Vec3::new(0.0, 1.0, 0.0)));
        p.extend([Vec3::new(-1.0, 0.0, 0.0), Vec3::new(-1.0, 0.5, 0.0)]);
        let split = classify(&p);
        assert!(
            (split.spacing - s).abs() < 0.05 * s,
            "spacing {}",
            split.spacing
        );
        assert_eq!(split.liquid, (0..block).collect::<Vec<_>>());
        assert_eq!(split.droplets.len(), p.len() - block);
        assert_eq!(split.bodies, 1);
        // A second block far away is a second body.
        p.extend(lattice(4, 4, 4, s, Vec3::new(0.0, 0.0, 2.0)));
        assert_eq!(classify(&p).bodies, 2);
    }

    #[test]
    fn too_few_particles_are_droplets() {
        let split = classify(&[Vec3::ZERO, Vec3::X]);
        assert!(split.liquid.is_empty() && split.droplets == vec![0, 1]);
    }
}
