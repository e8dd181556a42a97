//! The k-d tree behind [`super::knn::PointIndex`] (kiddo 6, immutable, parallel build) for
//! clouds a uniform grid does not suit (see [`super::grid`]).
//!
//! Non-finite positions are left out of the tree: they have no neighbours and are nobody's
//! neighbour.

use glam::Vec3;
use kiddo::SquaredEuclidean;
use kiddo::kd_tree::KdTree;
use kiddo::leaf_strategies::FlatVec;
use kiddo::stem_strategies::Eytzinger;
use rayon::prelude::*;
use std::num::NonZeroUsize;

/// The tree layout: immutable, Eytzinger stems, flat leaves of 32 points. Measured on 1M
/// Fibonacci-sphere points (13-NN, one thread): ≈ 1.45 µs a query against ≈ 1.6 µs for
/// kiddo's `ImmutableKdTree` default (arena leaves); build ≈ 0.2 s either way.
type Tree = KdTree<f32, u32, Eytzinger, FlatVec<f32, u32, 3, 32>, 3, 32>;

/// A k-d tree over the finite positions of a cloud, indexed by particle index: the fallback of
/// [`super::knn::PointIndex`] where a uniform grid does not suit the cloud.
///
/// Coincident points (SPH output does contain exact duplicates) enter the tree once: a k-d
/// tree cannot split equal points, so thousands of copies of one position would make one leaf
/// that every query scans (quadratic). Copies are grouped instead, and a query expands the
/// groups it finds into their particles, so the cost stays O(k log n) per query however many
/// points coincide.
pub(crate) struct TreeIndex {
    tree: Tree,
    finite: usize,
    /// `None` when every finite position is distinct (the tree's items are particle indices);
    /// else the tree's items are group ids and group `g` holds the particles
    /// `members[starts[g]..starts[g + 1]]`, in ascending index order.
    groups: Option<Groups>,
}

/// Particles sharing one position (see [`TreeIndex`]).
struct Groups {
    starts: Vec<u32>,
    members: Vec<u32>,
}

/// A position's bits with -0.0 folded into +0.0, so equal positions get equal keys.
fn key(p: Vec3) -> [u32; 3] {
    [
        (p.x + 0.0).to_bits(),
        (p.y + 0.0).to_bits(),
        (p.z + 0.0).to_bits(),
    ]
}

/// `(key(p), i)` as one number with the same order.
fn sort_key(p: Vec3, i: u32) -> u128 {
    let [x, y, z] = key(p);
    ((x as u128) << 96) | ((y as u128) << 64) | ((z as u128) << 32) | i as u128
}

impl TreeIndex {
    /// Builds the tree over all finite positions. Cost: O(n log n): a parallel sort of the
    /// positions' bits (which finds copies) and kiddo's parallel construction, which gives
    /// the serial construction's tree exactly; ≈ 0.15 s for 1M points on 2 cores.
    pub(crate) fn build(positions: &[Vec3]) -> Self {
        // One 128-bit number per particle orders exactly as (key, index) and compares in one
        // instruction pair, instead of recomputing three keys per comparison.
        let mut keyed: Vec<u128> = (0..positions.len() as u32)
            .into_par_iter()
            .filter(|&i| positions[i as usize].is_finite())
            .map(|i| sort_key(positions[i as usize], i))
            .collect();
        keyed.par_sort_unstable();
        let order: Vec<u32> = keyed.par_iter().map(|&v| v as u32).collect();
        let finite = order.len();
        let distinct = !keyed.par_windows(2).any(|w| w[0] >> 32 == w[1] >> 32);
        drop(keyed);
        // Construction only fails on index overflow (u32) for mutable-bucket splits; neither
        // applies to an immutable tree built from explicit u32 entries.
        if distinct {
            let entries: Vec<(u32, [f32; 3])> = order
                .iter()
                .map(|&i| (i, positions[i as usize].to_array()))
                .collect();
            let tree = Tree::new_from_entries_parallel(&entries).unwrap_or_default();
            return TreeIndex {
                tree,
                finite,
                groups: None,
            };
        }
        let mut starts = Vec::new();
        let mut entries = Vec::new();
        for (n, &i) in order.iter().enumerate() {
            let p = positions[i as usize];
            if n == 0 || key(positions[order[n - 1] as usize]) != key(p) {
                entries.push((starts.len() as u32, p.to_array()));
                starts.push(n as u32);
            }
        }
        starts.push(order.len() as u32);
        let tree = Tree::new_from_entries_parallel(&entries).unwrap_or_default();
        TreeIndex {
            tree,
            finite,
            groups: Some(Groups {
                starts,
                members: order,
            }),
        }
    }

    /// Number of finite points in the tree.
    pub(crate) fn len(&self) -> usize {
        self.finite
    }

    /// Up to `k` nearest particles to `q` other than `exclude`, nearest first (equal distances
    /// in ascending index), as `(index, distance)` with distances in scene units. Cost:
    /// O(k log n), also when many points coincide. Which of several particles tied at the
    /// `k`-th distance make the cut follows the tree's layout.
    pub(crate) fn nearest_excluding(&self, q: Vec3, k: usize, exclude: u32) -> Vec<(u32, f32)> {
        if self.finite == 0 || k == 0 {
            return Vec::new();
        }
        let entries = self
            .groups
            .as_ref()
            .map_or(self.finite, |g| g.starts.len() - 1);
        // k + 1 entries hold at least k + 1 particles, so k remain after excluding one.
        let want = (k + 1).min(entries);
        let Some(n) = NonZeroUsize::new(want) else {
            return Vec::new();
        };
        let found = self
            .tree
            .query(&q.to_array())
            .nearest_n::<SquaredEuclidean<f32>>(n)
            .execute();
        let mut out: Vec<(f32, u32)> = match &self.groups {
            None => found
                .into_iter()
                .filter(|r| r.item != exclude)
                .take(k)
                .map(|r| (r.distance, r.item))
                .collect(),
            Some(g) => {
                let mut out = Vec::with_capacity(k);
                'groups: for r in found {
                    let (a, b) = (g.starts[r.item as usize], g.starts[r.item as usize + 1]);
                    for &j in &g.members[a as usize..b as usize] {
                        if out.len() == k {
                            break 'groups;
                        }
                        if j != exclude {
                            out.push((r.distance, j));
                        }
                    }
                }
                out
            }
        };
        // kiddo orders equal distances by its layout: put them in index order, as the grid does.
        out.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        out.into_iter()
            .map(|(d2, j)| (j, d2.max(0.0).sqrt()))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The index as it was built before: serial construction, entries sorted by a per-compare
    /// key. Its answers are the reference for the parallel build.
    fn serial_rows(positions: &[Vec3], k: usize) -> Vec<Vec<(u32, f32)>> {
        let mut order: Vec<u32> = (0..positions.len() as u32)
            .filter(|&i| positions[i as usize].is_finite())
            .collect();
        order.sort_unstable_by_key(|&i| (key(positions[i as usize]), i));
        let entries: Vec<(u32, [f32; 3])> = order
            .iter()
            .map(|&i| (i, positions[i as usize].to_array()))
            .collect();
        let index = TreeIndex {
            tree: Tree::new_from_entries(&entries).unwrap_or_default(),
            finite: order.len(),
            groups: None,
        };
        (0..positions.len())
            .map(|i| index.nearest_excluding(positions[i], k, i as u32))
            .collect()
    }

    #[test]
    fn parallel_build_answers_as_the_serial_one_ties_included() {
        let mut s = 11u32;
        let mut rnd = move || {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            s as f32 / u32::MAX as f32
        };
        // Above kiddo's parallel threshold (262 144): a random shell, and a square lattice
        // whose distances tie four ways (tie order comes from the tree's layout).
        let shell: Vec<Vec3> = (0..300_000)
            .map(|_| Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize())
            .collect();
        let lattice: Vec<Vec3> = (0..300_000)
            .map(|i| Vec3::new((i % 600) as f32 * 0.25, (i / 600) as f32 * 0.25, 0.0))
            .collect();
        for pos in [shell, lattice] {
            let index = TreeIndex::build(&pos);
            let want = serial_rows(&pos, 12);
            for i in (0..pos.len()).step_by(37) {
                assert_eq!(
                    index.nearest_excluding(pos[i], 12, i as u32),
                    want[i],
                    "{i}"
                );
            }
        }
    }
}
