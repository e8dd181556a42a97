//! Binned-SAH construction of the flattened [`Bvh`](super::Bvh).
//!
//! Each node bins its primitives' centroids into `bins` buckets on all three axes in one pass,
//! sweeps the buckets for the cheapest surface-area-heuristic split, partitions in place and
//! recurses (the pieces are in `bvh_bins`); child bounds come from the bucket sums and child
//! centroid bounds from the partition pass, so every level costs one binning pass and one
//! partition pass. Nodes with many primitives recurse in parallel (`rayon::join`); the right
//! subtree is then built into its own vector and appended with its child offsets shifted, which
//! keeps the output depth-first. Deeper than [`MAX_SAH_DEPTH`] (pathological inputs) nodes fall
//! back to median splits, bounding the tree depth for the fixed traversal stack.

use glam::Vec3A;
use rayon::prelude::*;

use super::Aabb;
use super::bvh::{BvhNode, BvhParams, STACK_SIZE};
use super::bvh_bins::{Box3, Prims, best_binned_split, bin_coords, partition};

/// Depth after which nodes are split at the object median instead of by SAH.
pub(crate) const MAX_SAH_DEPTH: usize = 48;
const _: () = assert!(MAX_SAH_DEPTH + 34 < STACK_SIZE);

/// Nodes with at most this many primitives bin into 8 buckets instead of [`BvhParams::bins`].
const SMALL_NODE: usize = 64;

/// A chosen split: primitives `[..mid]` go left; (bounds, centroid bounds) of each side.
struct Split {
    mid: usize,
    left: (Box3, Box3),
    right: (Box3, Box3),
}

/// Builds nodes and the slot order for `n` primitives whose boxes are `bound(i)` (each called
/// once, in parallel).
pub(crate) fn build(
    n: usize,
    bound: impl Fn(usize) -> Aabb + Sync,
    params: BvhParams,
) -> (Vec<BvhNode>, Vec<u32>) {
    if n == 0 {
        return (Vec::new(), Vec::new());
    }
    let params = BvhParams {
        bins: params.bins.clamp(8, 32),
        max_leaf: params.max_leaf.clamp(1, 255),
        traversal_cost: params.traversal_cost.max(0.0),
        parallel_threshold: params.parallel_threshold.max(64),
    };
    let mut boxes: Vec<Box3> = (0..n)
        .into_par_iter()
        .map(|i| {
            let b = bound(i);
            Box3 {
                min: b.min.into(),
                max: b.max.into(),
            }
        })
        .collect();
    let mut ids: Vec<u32> = (0..n as u32).collect();
    let (bb, cb) = boxes.par_chunks(16 * 1024).map(summarize).reduce(
        || (Box3::EMPTY, Box3::EMPTY),
        |a, b| (a.0.union(b.0), a.1.union(b.1)),
    );
    let mut nodes = Vec::with_capacity(n);
    let prims = Prims {
        boxes: &mut boxes,
        ids: &mut ids,
    };
    build_node(&params, prims, 0, (bb, cb), 0, &mut nodes);
    nodes.shrink_to_fit();
    (nodes, ids)
}

/// Bounds and centroid (×2) bounds of a slice.
fn summarize(boxes: &[Box3]) -> (Box3, Box3) {
    let mut b = Box3::EMPTY;
    let mut c = Box3::EMPTY;
    for p in boxes {
        b = b.union(*p);
        c.grow(p.c2());
    }
    (b, c)
}

fn leaf(bounds: &Box3, first: u32, count: usize) -> BvhNode {
    BvhNode {
        min: bounds.min.to_array(),
        offset: first,
        max: bounds.max.to_array(),
        count: count as u32,
    }
}

fn build_node(
    params: &BvhParams,
    prims: Prims<'_>,
    base: u32,
    (bounds, cbounds): (Box3, Box3),
    depth: usize,
    out: &mut Vec<BvhNode>,
) {
    let me = out.len();
    let n = prims.len();
    out.push(leaf(&bounds, base, n));
    if n <= 1 {
        return;
    }
    let mut prims = prims;
    let Some(split) = choose_split(params, &mut prims, &bounds, &cbounds, depth) else {
        // A leaf lists its primitives in input order, so what a query meets (and the order in
        // which blended layers sum) depends on the tree's shape, not on how the partitions
        // happened to shuffle the leaf.
        prims.ids.sort_unstable();
        return;
    };
    let (lp, rp) = prims.split_at(split.mid);
    let right_base = base + split.mid as u32;
    out[me].count = 0;
    if n >= params.parallel_threshold {
        let ((), right_nodes) = rayon::join(
            || build_node(params, lp, base, split.left, depth + 1, out),
            || {
                let mut v = Vec::with_capacity(rp.len());
                build_node(params, rp, right_base, split.right, depth + 1, &mut v);
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
        build_node(params, lp, base, split.left, depth + 1, out);
        out[me].offset = out.len() as u32;
        build_node(params, rp, right_base, split.right, depth + 1, out);
    }
}

/// Picks a split for a node and partitions it, or returns `None` to make it a leaf. Kept out of
/// line so the bin arrays do not live in the recursive frames.
#[inline(never)]
fn choose_split(
    params: &BvhParams,
    prims: &mut Prims<'_>,
    bounds: &Box3,
    cbounds: &Box3,
    depth: usize,
) -> Option<Split> {
    let n = prims.len();
    if n as f32 <= params.traversal_cost && n <= params.max_leaf {
        return None; // a split costs at least the traversal: no binning needed
    }
    let ext = cbounds.max - cbounds.min;
    let spread = ext.max_element() > 0.0;
    let degenerate = !spread;
    if degenerate || depth >= MAX_SAH_DEPTH {
        if n <= params.max_leaf {
            return None;
        }
        return Some(median_split(prims, cbounds, degenerate));
    }
    let best = if n <= SMALL_NODE {
        best_binned_split::<8>(prims.boxes, cbounds)
    } else {
        match params.bins {
            8..=15 => best_binned_split::<8>(prims.boxes, cbounds),
            16..=31 => best_binned_split::<16>(prims.boxes, cbounds),
            _ => best_binned_split::<32>(prims.boxes, cbounds),
        }
    };
    let Some(best) = best else {
        return (n > params.max_leaf).then(|| median_split(prims, cbounds, false));
    };
    let area = bounds.area();
    let split_cost = if area > 0.0 {
        params.traversal_cost + best.cost / area
    } else {
        params.traversal_cost + n as f32 * 0.5
    };
    if n <= params.max_leaf && n as f32 <= split_cost {
        return None;
    }
    let (axis, c0, s, top) = (best.axis, cbounds.min, best.scale, best.top);
    let k = Vec3A::splat(best.k as f32);
    // The binning's own test: floor(x) < k exactly when x < k (x ≥ 0, k whole).
    let (mid, lc, rc) = partition(prims, |c| {
        (bin_coords(c, c0, s, top).cmplt(k).bitmask() >> axis) & 1 == 1
    });
    debug_assert_eq!(mid, best.left_count);
    Some(Split {
        mid,
        left: (best.left, lc),
        right: (best.right, rc),
    })
}

/// Object-median split along the widest centroid axis (any halving if all centroids coincide).
fn median_split(prims: &mut Prims<'_>, cbounds: &Box3, degenerate: bool) -> Split {
    let n = prims.len();
    let mid = n / 2;
    if !degenerate {
        let ext = cbounds.max - cbounds.min;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        // Sort a permutation, then apply it to both arrays (rare path: pathological inputs).
        let mut perm: Vec<usize> = (0..n).collect();
        perm.select_nth_unstable_by(mid, |&a, &b| {
            prims.boxes[a].c2()[axis].total_cmp(&prims.boxes[b].c2()[axis])
        });
        let boxes: Vec<Box3> = perm.iter().map(|&i| prims.boxes[i]).collect();
        let ids: Vec<u32> = perm.iter().map(|&i| prims.ids[i]).collect();
        prims.boxes.copy_from_slice(&boxes);
        prims.ids.copy_from_slice(&ids);
    }
    Split {
        mid,
        left: summarize(&prims.boxes[..mid]),
        right: summarize(&prims.boxes[mid..]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Bvh;
    use glam::Vec3;

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
