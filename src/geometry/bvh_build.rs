//! Binned-SAH construction of the flattened [`Bvh`](super::Bvh).
//!
//! Each node bins its primitives' centroids into `bins` buckets on all three axes in one pass,
//! sweeps the buckets for the cheapest surface-area-heuristic split, partitions in place and
//! recurses; child bounds come from the bucket sums, so every level costs one binning pass and one
//! partition pass. Nodes with many primitives recurse in parallel (`rayon::join`); the right
//! subtree is then built into its own vector and appended with its child offsets shifted, which
//! keeps the output depth-first. Deeper than [`MAX_SAH_DEPTH`] (pathological inputs) nodes fall
//! back to median splits, bounding the tree depth for the fixed traversal stack.

use glam::Vec3;
use rayon::prelude::*;

use super::Aabb;
use super::bvh::{BvhNode, BvhParams, STACK_SIZE};

/// Depth after which nodes are split at the object median instead of by SAH.
pub(crate) const MAX_SAH_DEPTH: usize = 48;
const MAX_BINS: usize = 64;
const _: () = assert!(MAX_SAH_DEPTH + 34 < STACK_SIZE);

/// A primitive during the build: its box and original index (32 bytes, swapped by partitions).
#[derive(Clone, Copy)]
#[repr(C)]
struct BuildPrim {
    min: Vec3,
    index: u32,
    max: Vec3,
    _pad: u32,
}

impl BuildPrim {
    /// Twice the centroid (binning only needs an affine image of it).
    #[inline(always)]
    fn c2(&self) -> Vec3 {
        self.min + self.max
    }
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    cbounds: Aabb,
    count: u32,
}

const EMPTY_BIN: Bin = Bin {
    bounds: Aabb::EMPTY,
    cbounds: Aabb::EMPTY,
    count: 0,
};

/// A chosen split: primitives `[..mid]` go left.
struct Split {
    mid: usize,
    left: (Aabb, Aabb),
    right: (Aabb, Aabb),
}

/// Builds nodes and the slot order for `bounds`.
pub(crate) fn build(bounds: &[Aabb], params: BvhParams) -> (Vec<BvhNode>, Vec<u32>) {
    let n = bounds.len();
    if n == 0 {
        return (Vec::new(), Vec::new());
    }
    let params = BvhParams {
        bins: params.bins.clamp(2, MAX_BINS),
        max_leaf: params.max_leaf.clamp(1, 255),
        traversal_cost: params.traversal_cost.max(0.0),
        parallel_threshold: params.parallel_threshold.max(64),
    };
    let mut prims: Vec<BuildPrim> = bounds
        .par_iter()
        .enumerate()
        .map(|(i, b)| BuildPrim {
            min: b.min,
            index: i as u32,
            max: b.max,
            _pad: 0,
        })
        .collect();
    let (bb, cb) = summarize_par(&prims);
    let mut nodes = Vec::with_capacity(n);
    build_node(&params, &mut prims, 0, bb, cb, 0, &mut nodes);
    nodes.shrink_to_fit();
    let order = prims.par_iter().map(|p| p.index).collect();
    (nodes, order)
}

/// Bounds and centroid (×2) bounds of a slice, in parallel.
fn summarize_par(prims: &[BuildPrim]) -> (Aabb, Aabb) {
    prims.par_chunks(16 * 1024).map(summarize).reduce(
        || (Aabb::EMPTY, Aabb::EMPTY),
        |a, b| (a.0.union(&b.0), a.1.union(&b.1)),
    )
}

fn summarize(prims: &[BuildPrim]) -> (Aabb, Aabb) {
    let mut b = Aabb::EMPTY;
    let mut c = Aabb::EMPTY;
    for p in prims {
        b = b.union(&Aabb::new(p.min, p.max));
        c.grow(p.c2());
    }
    (b, c)
}

fn leaf(bounds: &Aabb, first: u32, count: usize) -> BvhNode {
    BvhNode {
        min: bounds.min.to_array(),
        offset: first,
        max: bounds.max.to_array(),
        count: count as u32,
    }
}

fn build_node(
    params: &BvhParams,
    prims: &mut [BuildPrim],
    base: u32,
    bounds: Aabb,
    cbounds: Aabb,
    depth: usize,
    out: &mut Vec<BvhNode>,
) {
    let me = out.len();
    let n = prims.len();
    out.push(leaf(&bounds, base, n));
    if n <= 1 {
        return;
    }
    let Some(split) = choose_split(params, prims, &bounds, &cbounds, depth) else {
        return;
    };
    let (lp, rp) = prims.split_at_mut(split.mid);
    let right_base = base + split.mid as u32;
    out[me].count = 0;
    if n >= params.parallel_threshold {
        let ((), right_nodes) = rayon::join(
            || build_node(params, lp, base, split.left.0, split.left.1, depth + 1, out),
            || {
                let mut v = Vec::with_capacity(rp.len());
                build_node(
                    params,
                    rp,
                    right_base,
                    split.right.0,
                    split.right.1,
                    depth + 1,
                    &mut v,
                );
                v
            },
        );
        let shift = out.len() as u32;
        out[me].offset = shift;
        out.extend(right_nodes.into_iter().map(|mut nd| {
            if nd.count == 0 {
                nd.offset += shift;
            }
            nd
        }));
    } else {
        build_node(params, lp, base, split.left.0, split.left.1, depth + 1, out);
        out[me].offset = out.len() as u32;
        build_node(
            params,
            rp,
            right_base,
            split.right.0,
            split.right.1,
            depth + 1,
            out,
        );
    }
}

/// Picks a split for a node, or `None` to make it a leaf. Kept out of line so the bin arrays do
/// not live in the recursive frames.
#[inline(never)]
fn choose_split(
    params: &BvhParams,
    prims: &mut [BuildPrim],
    bounds: &Aabb,
    cbounds: &Aabb,
    depth: usize,
) -> Option<Split> {
    let n = prims.len();
    let ext = cbounds.max - cbounds.min;
    let degenerate = !(ext.max_element() > 0.0);
    if degenerate || depth >= MAX_SAH_DEPTH {
        if n <= params.max_leaf {
            return None;
        }
        return Some(median_split(prims, cbounds, degenerate));
    }

    let nb = params.bins;
    let scale = Vec3::select(ext.cmpgt(Vec3::ZERO), nb as f32 / ext, Vec3::ZERO);
    let cmin = cbounds.min;
    let mut bins = [[EMPTY_BIN; MAX_BINS]; 3];
    for p in prims.iter() {
        let c = p.c2();
        let b = Aabb::new(p.min, p.max);
        for (axis, axis_bins) in bins.iter_mut().enumerate() {
            let k = bin_index(c[axis], cmin[axis], scale[axis], nb);
            let bin = &mut axis_bins[k];
            bin.bounds = bin.bounds.union(&b);
            bin.cbounds.grow(c);
            bin.count += 1;
        }
    }

    // Sweep: cost of splitting before bin k on each axis.
    let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, k)
    for axis in 0..3 {
        if !(ext[axis] > 0.0) {
            continue;
        }
        let bins = &bins[axis][..nb];
        let mut right_cost = [0f32; MAX_BINS];
        let mut acc = Aabb::EMPTY;
        let mut cnt = 0u32;
        for k in (1..nb).rev() {
            acc = acc.union(&bins[k].bounds);
            cnt += bins[k].count;
            right_cost[k] = acc.surface_area() * cnt as f32;
        }
        let mut acc = Aabb::EMPTY;
        let mut cnt = 0u32;
        for k in 1..nb {
            acc = acc.union(&bins[k - 1].bounds);
            cnt += bins[k - 1].count;
            if cnt == 0 || cnt as usize == n {
                continue;
            }
            let cost = acc.surface_area() * cnt as f32 + right_cost[k];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, k));
            }
        }
    }
    let Some((cost, axis, k)) = best else {
        return (n > params.max_leaf).then(|| median_split(prims, cbounds, false));
    };
    let area = bounds.surface_area();
    let split_cost = if area > 0.0 {
        params.traversal_cost + cost / area
    } else {
        params.traversal_cost + n as f32 * 0.5
    };
    if n <= params.max_leaf && n as f32 <= split_cost {
        return None;
    }

    let sum = |bins: &[Bin]| {
        bins.iter().fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), x| {
            (b.union(&x.bounds), c.union(&x.cbounds))
        })
    };
    let left = sum(&bins[axis][..k]);
    let right = sum(&bins[axis][k..nb]);
    let (c0, s) = (cmin[axis], scale[axis]);
    let mid = partition(prims, |p| bin_index(p.c2()[axis], c0, s, nb) < k);
    Some(Split { mid, left, right })
}

#[inline(always)]
fn bin_index(v: f32, min: f32, scale: f32, nb: usize) -> usize {
    (((v - min) * scale) as usize).min(nb - 1)
}

/// In-place partition; returns the number of elements satisfying `pred` (now at the front).
fn partition(prims: &mut [BuildPrim], pred: impl Fn(&BuildPrim) -> bool) -> usize {
    let (mut i, mut j) = (0, prims.len());
    while i < j {
        if pred(&prims[i]) {
            i += 1;
        } else {
            j -= 1;
            prims.swap(i, j);
        }
    }
    i
}

/// Object-median split along the widest centroid axis (any halving if all centroids coincide).
fn median_split(prims: &mut [BuildPrim], cbounds: &Aabb, degenerate: bool) -> Split {
    let mid = prims.len() / 2;
    if !degenerate {
        let axis = cbounds.largest_axis();
        prims.select_nth_unstable_by(mid, |a, b| a.c2()[axis].total_cmp(&b.c2()[axis]));
    }
    Split {
        mid,
        left: summarize(&prims[..mid]),
        right: summarize(&prims[mid..]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Bvh;

    /// Every slot appears once, every leaf's bounds hold its primitives, every interior node's
    /// bounds hold its children, and the depth stays within the stack.
    fn check(bvh: &Bvh, bounds: &[Aabb]) {
        let mut seen = vec![false; bounds.len()];
        for &i in bvh.order() {
            assert!(!seen[i as usize]);
            seen[i as usize] = true;
        }
        assert!(seen.iter().all(|&s| s));
        let mut slots = vec![0u32; bounds.len()];
        let mut stack = vec![(0usize, 1usize)];
        let mut max_depth = 0;
        while let Some((i, d)) = stack.pop() {
            max_depth = max_depth.max(d);
            let nd = bvh.nodes()[i];
            let nb = nd.bounds();
            if nd.is_leaf() {
                for s in nd.offset..nd.offset + nd.count {
                    slots[s as usize] += 1;
                    let b = bounds[bvh.order()[s as usize] as usize];
                    assert!(nb.contains(b.min) && nb.contains(b.max));
                }
            } else {
                for c in [i + 1, nd.offset as usize] {
                    let cb = bvh.nodes()[c].bounds();
                    assert!(nb.contains(cb.min) && nb.contains(cb.max));
                    stack.push((c, d + 1));
                }
            }
        }
        assert!(
            slots.iter().all(|&c| c == 1),
            "each slot in exactly one leaf"
        );
        assert!(max_depth < STACK_SIZE);
    }

    #[test]
    fn structure_is_valid_random_and_degenerate() {
        let mut s = 12345u32;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            s as f32 / u32::MAX as f32
        };
        let random: Vec<Aabb> = (0..20_000)
            .map(|_| {
                let c = Vec3::new(rnd(), rnd(), rnd()) * 10.0;
                Aabb::new(c, c + Vec3::splat(0.05 * rnd()))
            })
            .collect();
        let same = vec![Aabb::new(Vec3::ONE, Vec3::splat(1.5)); 5000];
        // A line of centroids: SAH degenerates to many unbalanced splits; depth must stay bounded.
        let line: Vec<Aabb> = (0..5000)
            .map(|i| {
                let x = (1.0001f32).powi(i) - 1.0;
                Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x, 1.0, 1.0))
            })
            .collect();
        for bounds in [random, same, line, vec![Aabb::from_point(Vec3::ONE)]] {
            let bvh = Bvh::build(&bounds);
            check(&bvh, &bounds);
        }
        assert!(Bvh::build(&[]).nodes().is_empty());
    }
}
