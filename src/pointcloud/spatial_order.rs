//! A spatial order of a cloud's particles (Morton, or Z-order, over their bounding box): work
//! done particle after particle in this order touches the k-d tree's leaves and the
//! neighbours' positions of one neighbourhood after another, where a file's own order (a
//! Fibonacci sphere's consecutive particles lie ~137° apart; simulator output in any order)
//! jumps across the cloud at every step. Results are written to each particle's own slot, so
//! the order changes no value, only the cache's hits.

use glam::Vec3;
use rayon::prelude::*;

/// Bits per axis of the Morton code (3 × 21 = 63 bits).
const BITS: u32 = 21;

/// Every particle index `0..positions.len()` once: the finite positions by their Morton code
/// over the finite positions' bounding box (ties by index), then the non-finite ones by index.
/// Cost: one parallel sort of n 128-bit keys (≈ 30 ms for 1M on 2 cores); 4 bytes a particle.
pub fn spatial_order(positions: &[Vec3]) -> Vec<u32> {
    let (lo, hi) = positions
        .par_iter()
        .filter(|p| p.is_finite())
        .fold(
            || (Vec3::INFINITY, Vec3::NEG_INFINITY),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
        .reduce(
            || (Vec3::INFINITY, Vec3::NEG_INFINITY),
            |a, b| (a.0.min(b.0), a.1.max(b.1)),
        );
    let span = (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE));
    let top = ((1u32 << BITS) - 1) as f32;
    let mut keyed: Vec<u128> = (0..positions.len() as u32)
        .into_par_iter()
        .map(|i| {
            let p = positions[i as usize];
            let code = if p.is_finite() {
                // In [0, 1] on every axis; the float-to-int cast saturates.
                let q = ((p - lo) / span * top).to_array().map(|c| c as u32 as u64);
                spread(q[0]) | (spread(q[1]) << 1) | (spread(q[2]) << 2)
            } else {
                u64::MAX
            };
            ((code as u128) << 32) | i as u128
        })
        .collect();
    keyed.par_sort_unstable();
    keyed.into_par_iter().map(|k| k as u32).collect()
}

/// The low 21 bits of `x` spread to every third bit (bit b to bit 3b).
fn spread(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | (x << 32)) & 0x001f_0000_0000_ffff;
    x = (x | (x << 16)) & 0x001f_0000_ff00_00ff;
    x = (x | (x << 8)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x << 4)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x << 2)) & 0x1249_2492_4924_9249;
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_puts_bit_b_at_3b() {
        for b in 0..BITS {
            assert_eq!(spread(1 << b), 1 << (3 * b), "bit {b}");
        }
        assert_eq!(spread(u64::MAX), 0x1249_2492_4924_9249);
    }

    #[test]
    fn every_particle_once_neighbours_close_and_non_finite_last() {
        // A 64 × 64 lattice in a shuffled order, with two NaN particles.
        let w = 64u32;
        let mut pos: Vec<Vec3> = (0..w * w)
            .map(|i| {
                let j = i.wrapping_mul(2_654_435_761) % (w * w); // odd multiplier: a bijection
                Vec3::new((j % w) as f32, (j / w) as f32, 0.0)
            })
            .collect();
        pos[5] = Vec3::NAN;
        pos[77] = Vec3::new(f32::INFINITY, 0.0, 0.0);
        let order = spatial_order(&pos);
        let mut seen = order.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..w * w).collect::<Vec<_>>());
        assert_eq!(&order[order.len() - 2..], &[5, 77]);
        // Consecutive particles of the order are near: on a Z-curve over a lattice the mean
        // step is a few spacings; in the file's shuffled order about w/2.
        let mean = |order: &[u32]| {
            let steps: f32 = order
                .windows(2)
                .map(|s| (pos[s[0] as usize] - pos[s[1] as usize]).length())
                .sum();
            steps / (order.len() - 1) as f32
        };
        let file: Vec<u32> = (0..w * w)
            .filter(|i| pos[*i as usize].is_finite())
            .collect();
        let (z, shuffled) = (mean(&order[..order.len() - 2]), mean(&file));
        assert!(
            z < 3.0 && shuffled > 15.0,
            "mean step {z}, shuffled {shuffled}"
        );
    }
}
