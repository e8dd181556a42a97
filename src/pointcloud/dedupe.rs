//! Coincident particles: SPH output does contain exact duplicates, and a pile of copies at one
//! position is drawn as a pile of identical disks that no tree can split (every ray through it
//! would test every copy). The pipeline keeps one particle per position.

use glam::Vec3;
use rayon::prelude::*;

use super::PointCloud;
use super::validate::keep_particles;

/// Removes every particle whose position (bit for bit, -0 = +0) equals an earlier particle's,
/// keeping the first in file order with its attributes. Returns how many were removed.
/// Non-finite positions are left alone (validation reports them).
///
/// Cost: one O(n log n) sort of a 128-bit number a particle (its position's bits and its
/// index, so a comparison reads no position); the arrays are compacted only if something is
/// removed.
pub fn drop_coincident(cloud: &mut PointCloud) -> usize {
    // The position's three coordinates (-0 as +0) above the index: equal positions sort
    // together, the first in file order first.
    let key = |p: Vec3, i: u32| {
        let bits = |v: f32| u128::from((v + 0.0).to_bits());
        bits(p.x) << 96 | bits(p.y) << 64 | bits(p.z) << 32 | u128::from(i)
    };
    let pos = &cloud.positions;
    let mut order: Vec<u128> = (0..pos.len() as u32)
        .into_par_iter()
        .filter(|&i| pos[i as usize].is_finite())
        .map(|i| key(pos[i as usize], i))
        .collect();
    order.par_sort_unstable();
    let mut keep = vec![true; pos.len()];
    let mut removed = 0;
    for w in order.windows(2) {
        if w[0] >> 32 == w[1] >> 32 {
            keep[(w[1] as u32) as usize] = false;
            removed += 1;
        }
    }
    if removed > 0 {
        keep_particles(cloud, &keep);
    }
    removed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_the_first_of_each_position_with_its_attributes() {
        let mut c = PointCloud {
            positions: vec![
                Vec3::ONE,
                Vec3::ZERO,
                Vec3::ONE,
                Vec3::new(-0.0, 0.0, 0.0),
                Vec3::X,
            ],
            thickness_nm: Some(vec![1.0, 2.0, 3.0, 4.0, 5.0]),
            extra: vec![("a".into(), vec![10.0, 20.0, 30.0, 40.0, 50.0])],
            ..PointCloud::default()
        };
        assert_eq!(drop_coincident(&mut c), 2);
        assert_eq!(c.positions, vec![Vec3::ONE, Vec3::ZERO, Vec3::X]);
        assert_eq!(c.thickness_nm, Some(vec![1.0, 2.0, 5.0]));
        assert_eq!(c.extra[0].1, vec![10.0, 20.0, 50.0]);
        assert_eq!(drop_coincident(&mut c), 0);
    }
}
