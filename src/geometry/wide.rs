//! The 4-wide traversal tree: the binary BVH collapsed into nodes of up to four children whose
//! bounds are stored structure-of-arrays, so one node visit is a single 4-lane slab test
//! (glam's `Vec4`, SSE on x86-64), followed by a front-to-back ordered descent.
//!
//! Collapse: a wide node takes its binary node's two children and keeps replacing the interior
//! child with the largest surface area by its two children until it has four (or only leaves
//! are left). Leaves keep the binary leaves' slot ranges, so slot order is unchanged.

use std::mem::MaybeUninit;

use glam::Vec4;

use super::aabb::{SLAB_ROBUST, safe_inv_dir};
use super::{BvhNode, Ray};
use crate::prefetch::prefetch_read;

/// One 4-wide node (128 bytes, two cache lines). Lane `i` is empty (its box is inverted, so
/// every slab test misses it), a leaf (`count[i] > 0`, slots `child[i] .. child[i] + count[i]`)
/// or an interior node (`count[i] == 0`, node index `child[i]`).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(crate) struct Node4 {
    /// `min_x, min_y, min_z, max_x, max_y, max_z`, one lane per child.
    bounds: [Vec4; 6],
    child: [u32; 4],
    count: [u32; 4],
}

const _: () = assert!(std::mem::size_of::<Node4>() == 128);

impl Node4 {
    const EMPTY: Node4 = Node4 {
        bounds: [
            Vec4::INFINITY,
            Vec4::INFINITY,
            Vec4::INFINITY,
            Vec4::NEG_INFINITY,
            Vec4::NEG_INFINITY,
            Vec4::NEG_INFINITY,
        ],
        child: [0; 4],
        count: [0; 4],
    };

    fn set(&mut self, lane: usize, n: &BvhNode, child: u32, count: u32) {
        for a in 0..3 {
            self.bounds[a][lane] = n.min[a];
            self.bounds[a + 3][lane] = n.max[a];
        }
        self.child[lane] = child;
        self.count[lane] = count;
    }
}

/// Collapses a binary tree (see [`BvhNode`]) into wide nodes, root first, and returns them with
/// the stack size their traversal needs. Cost: O(nodes).
pub(crate) fn collapse(nodes: &[BvhNode]) -> (Vec<Node4>, usize) {
    let Some(root) = nodes.first() else {
        return (Vec::new(), 0);
    };
    let mut out = Vec::with_capacity(nodes.len() / 3 + 1);
    out.push(Node4::EMPTY);
    if root.is_leaf() {
        out[0].set(0, root, root.offset, root.count);
        return (out, 1);
    }
    let area = |i: usize| nodes[i].bounds().surface_area();
    let mut todo = vec![(0usize, 0usize, 1usize)];
    let mut depth = 1;
    while let Some((b, w, d)) = todo.pop() {
        depth = depth.max(d);
        let mut kids = [b + 1, nodes[b].offset as usize, 0, 0];
        let mut nk = 2;
        while nk < 4 {
            let open = (0..nk)
                .filter(|&k| !nodes[kids[k]].is_leaf())
                .max_by(|&x, &y| area(kids[x]).total_cmp(&area(kids[y])));
            let Some(k) = open else { break };
            let i = kids[k];
            kids[k] = i + 1;
            kids[nk] = nodes[i].offset as usize;
            nk += 1;
        }
        for (lane, &k) in kids[..nk].iter().enumerate() {
            let n = &nodes[k];
            if n.is_leaf() {
                out[w].set(lane, n, n.offset, n.count);
            } else {
                let child = out.len();
                out.push(Node4::EMPTY);
                out[w].set(lane, n, child as u32, 0);
                todo.push((k, child, d + 1));
            }
        }
    }
    // Each node on the path defers at most three siblings.
    (out, 3 * depth + 1)
}

/// A copy of `nodes` whose leaves start at `first(slot)` instead of their first slot `slot`
/// (counts and interior lanes unchanged), for a caller that stores its primitives in another
/// layout than the slot order (the spheres' leaf-aligned packets). Cost: O(nodes).
pub(crate) fn remap_leaves(nodes: &[Node4], first: impl Fn(u32) -> u32) -> Vec<Node4> {
    let mut out = nodes.to_vec();
    for n in &mut out {
        for lane in 0..4 {
            if n.count[lane] > 0 {
                n.child[lane] = first(n.child[lane]);
            }
        }
    }
    out
}

/// Traversal stacks up to this size live in an array on the call stack; deeper trees (unusual
/// inputs) use a heap-allocated stack.
const INLINE_STACK: usize = 64;

/// A deferred child: node index or first slot, slot count (0 for a node), entry distance.
#[derive(Clone, Copy, Default)]
pub(crate) struct Entry {
    child: u32,
    count: u32,
    t: f32,
}

/// The ray prepared for 4-lane slab tests: origin and inverse direction splatted, and the
/// near and far bound planes per axis, chosen once by the direction's signs.
struct Slabs {
    near: [usize; 3],
    far: [usize; 3],
    o: [Vec4; 3],
    inv: [Vec4; 3],
    t_min: Vec4,
}

impl Slabs {
    #[inline(always)]
    fn new(ray: &Ray, t_min: f32) -> Slabs {
        let inv = safe_inv_dir(ray.dir);
        let near = |a: usize, neg: bool| if neg { a + 3 } else { a };
        let near = [
            near(0, inv.x < 0.0),
            near(1, inv.y < 0.0),
            near(2, inv.z < 0.0),
        ];
        let o = ray.origin;
        Slabs {
            near,
            far: near.map(|k| (k + 3) % 6),
            o: [Vec4::splat(o.x), Vec4::splat(o.y), Vec4::splat(o.z)],
            inv: [Vec4::splat(inv.x), Vec4::splat(inv.y), Vec4::splat(inv.z)],
            t_min: Vec4::splat(t_min),
        }
    }

    /// The children of `n` the ray enters within `[t_min, t_max]`: a lane mask and the entry
    /// distance per lane.
    #[inline(always)]
    fn test(&self, n: &Node4, t_max: f32) -> (u32, Vec4) {
        let b = &n.bounds;
        let ([nx, ny, nz], [fx, fy, fz]) = (self.near, self.far);
        let ([ox, oy, oz], [ix, iy, iz]) = (self.o, self.inv);
        let tn = ((b[nx] - ox) * ix)
            .max((b[ny] - oy) * iy)
            .max((b[nz] - oz) * iz)
            .max(self.t_min);
        let tf = ((b[fx] - ox) * ix)
            .min((b[fy] - oy) * iy)
            .min((b[fz] - oz) * iz)
            .min(Vec4::splat(t_max));
        (tn.cmple(tf * SLAB_ROBUST).bitmask(), tn)
    }
}

/// The sort key of lane `i` with entry distance `t`: the distance's bits made monotonic (as
/// unsigned integers) above the lane, so keys order by distance, then by lane.
#[inline(always)]
fn lane_key(t: f32, i: usize) -> u64 {
    let b = t.to_bits();
    let flip = ((b as i32) >> 31) as u32 | 0x8000_0000;
    (((b ^ flip) as u64) << 32) | i as u64
}

/// The hit lanes of `mask` sorted by entry distance `tn`: a branch-free sorting network on
/// [`lane_key`]s; the lane is `key & 3`, missed lanes sort last.
#[inline(always)]
fn sort_lanes(tn: Vec4, mask: u32) -> [u64; 4] {
    let key = |i: usize| {
        if mask & (1 << i) != 0 {
            lane_key(tn[i], i)
        } else {
            u64::MAX
        }
    };
    let (mut k0, mut k1, mut k2, mut k3) = (key(0), key(1), key(2), key(3));
    let cx = |a: &mut u64, b: &mut u64| {
        let (lo, hi) = ((*a).min(*b), (*a).max(*b));
        *a = lo;
        *b = hi;
    };
    cx(&mut k0, &mut k1);
    cx(&mut k2, &mut k3);
    cx(&mut k0, &mut k2);
    cx(&mut k1, &mut k3);
    cx(&mut k1, &mut k2);
    [k0, k1, k2, k3]
}

/// The two hit lanes of `mask` (exactly two bits set) nearest first, in the order
/// [`sort_lanes`] gives them, from two keys instead of four and five exchanges.
#[inline(always)]
fn two_lanes(tn: Vec4, mask: u32) -> [usize; 2] {
    let (i, j) = (
        mask.trailing_zeros() as usize,
        31 - mask.leading_zeros() as usize,
    );
    if lane_key(tn[j], j) < lane_key(tn[i], i) {
        [j, i]
    } else {
        [i, j]
    }
}

/// Starts fetching lane `i`'s child of `n`, deferred on the stack, so that it is in the cache
/// when popped: an interior node's two cache lines, or a leaf through `leaf(first, count)`.
#[inline(always)]
fn prefetch_child(nodes: &[Node4], n: &Node4, i: usize, leaf: &impl Fn(u32, u32)) {
    if n.count[i] > 0 {
        leaf(n.child[i], n.count[i]);
    } else if let Some(c) = nodes.get(n.child[i] as usize) {
        prefetch_read(&c.bounds[0]);
        prefetch_read(&c.bounds[4]);
    }
}

/// Ordered front-to-back traversal. `leaf(first, count, &mut t_max)` is called for every leaf
/// whose box the ray enters within `[t_min, t_max]` (the closure may lower `t_max`, which culls
/// later boxes); it returns `true` to stop, and the traversal then returns `true`.
#[inline(always)]
pub(crate) fn traverse<L: FnMut(u32, u32, &mut f32) -> bool>(
    nodes: &[Node4],
    stack_size: usize,
    ray: &Ray,
    t_min: f32,
    t_max: &mut f32,
    leaf: L,
) -> bool {
    traverse_prefetching(nodes, stack_size, ray, t_min, t_max, leaf, |_, _| {})
}

/// [`traverse`], calling `prefetch(first, count)` for each leaf deferred on the stack, so the
/// caller can start fetching its primitives (deferred interior nodes are prefetched here).
#[inline(always)]
pub(crate) fn traverse_prefetching<L, P>(
    nodes: &[Node4],
    stack_size: usize,
    ray: &Ray,
    t_min: f32,
    t_max: &mut f32,
    mut leaf: L,
    prefetch: P,
) -> bool
where
    L: FnMut(u32, u32, &mut f32) -> bool,
    P: Fn(u32, u32),
{
    if nodes.is_empty() {
        return false;
    }
    let slabs = Slabs::new(ray, t_min);
    // The inline stack is not zeroed (768 bytes per ray showed up as 3% memset in profiles):
    // entries are written before they are read, and only the `sp` written ones are read.
    let mut inline = [MaybeUninit::<Entry>::uninit(); INLINE_STACK];
    let mut heap;
    let stack: &mut [MaybeUninit<Entry>] = if stack_size <= INLINE_STACK {
        &mut inline
    } else {
        heap = vec![MaybeUninit::new(Entry::default()); stack_size];
        &mut heap
    };
    let mut sp = 0usize;
    let mut cur = Entry::default();
    loop {
        if cur.count > 0 {
            if leaf(cur.child, cur.count, t_max) {
                return true;
            }
        } else {
            let n = &nodes[cur.child as usize];
            let (mask, tn) = slabs.test(n, *t_max);
            if mask != 0 {
                let lane = |i: usize| Entry {
                    child: n.child[i],
                    count: n.count[i],
                    t: tn[i],
                };
                if mask & (mask - 1) == 0 {
                    cur = lane(mask.trailing_zeros() as usize);
                    continue;
                }
                // Two hits (the most common case of several on a film): the same order as
                // `sort_lanes`, from two keys.
                if mask.count_ones() == 2 {
                    let [near, far] = two_lanes(tn, mask);
                    prefetch_child(nodes, n, far, &prefetch);
                    stack[sp] = MaybeUninit::new(lane(far));
                    sp += 1;
                    cur = lane(near);
                    continue;
                }
                // Three or four hits: descend into the nearest and push the others farthest
                // first.
                let sorted = sort_lanes(tn, mask);
                let nh = mask.count_ones() as usize;
                for &k in sorted[1..nh].iter().rev() {
                    prefetch_child(nodes, n, (k & 3) as usize, &prefetch);
                    stack[sp] = MaybeUninit::new(lane((k & 3) as usize));
                    sp += 1;
                }
                cur = lane((sorted[0] & 3) as usize);
                continue;
            }
        }
        match pop_in_range(stack, &mut sp, *t_max) {
            Some(e) => cur = e,
            None => return false,
        }
    }
}

/// Pops the nearest deferred child still in range (entry distance within `t_max`), dropping
/// those beyond it; None when the stack runs empty. `stack[..sp]` must have been written.
#[inline(always)]
fn pop_in_range(stack: &[MaybeUninit<Entry>], sp: &mut usize, t_max: f32) -> Option<Entry> {
    while *sp > 0 {
        *sp -= 1;
        // SAFETY: slots below the old `sp` were written by the traversal's pushes.
        let e = unsafe { stack[*sp].assume_init() };
        if e.t <= t_max * SLAB_ROBUST {
            return Some(e);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use crate::geometry::{Aabb, Bvh, Ray};
    use glam::{Vec3, Vec4};

    /// The two-hit shortcut orders its lanes exactly as the sorting network, ties (equal
    /// distances, +0 against -0, infinities) included.
    #[test]
    fn two_lanes_order_as_the_sorting_network() {
        let values = [
            -1.0,
            -0.0,
            0.0,
            0.5,
            0.5000001,
            2.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        let mut cases = 0;
        for mask in [0b0011u32, 0b0101, 0b1001, 0b0110, 0b1010, 0b1100] {
            for &a in &values {
                for &b in &values {
                    let mut tn = Vec4::splat(7.0);
                    let (i, j) = (
                        mask.trailing_zeros() as usize,
                        31 - mask.leading_zeros() as usize,
                    );
                    tn[i] = a;
                    tn[j] = b;
                    let sorted = super::sort_lanes(tn, mask);
                    let want = [(sorted[0] & 3) as usize, (sorted[1] & 3) as usize];
                    assert_eq!(super::two_lanes(tn, mask), want, "mask {mask:#b} tn {tn}");
                    cases += 1;
                }
            }
        }
        assert_eq!(cases, 6 * 64);
    }

    /// Closest box entry through the wide traversal (with the inline and the heap stack) agrees
    /// with brute force over the boxes, and the collapse keeps every slot in exactly one leaf.
    #[test]
    fn wide_queries_match_brute_force() {
        // A geometric line of boxes (unbalanced tree) and a grid (balanced).
        let line: Vec<Aabb> = (0..600)
            .map(|i| {
                let x = (1.03f32).powi(i) - 1.0;
                Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 0.01, 1.0, 1.0))
            })
            .collect();
        let grid: Vec<Aabb> = (0..4096)
            .map(|i| {
                let c = Vec3::new((i % 16) as f32, (i / 16 % 16) as f32, (i / 256) as f32);
                Aabb::new(c, c + Vec3::splat(0.7))
            })
            .collect();
        for boxes in [line, grid] {
            let bvh = Bvh::build(&boxes);
            assert!(bvh.wide_stack <= super::INLINE_STACK);
            let mut seen = vec![0u32; boxes.len()];
            for n in &bvh.wide {
                for lane in 0..4 {
                    for s in n.child[lane]..n.child[lane] + n.count[lane] {
                        seen[s as usize] += 1;
                    }
                }
            }
            assert!(seen.iter().all(|&c| c == 1), "each slot in one wide leaf");
            let hi = boxes.iter().fold(Aabb::EMPTY, |a, b| a.union(b)).max;
            let mut hits = 0;
            for k in 0..300 {
                let f = k as f32 / 300.0;
                let o = Vec3::new(-1.0, 0.5 + 0.4 * f, hi.z * f);
                let ray = Ray::new(o, Vec3::new(1.0, 0.3 * f - 0.1, 0.2 - 0.5 * f));
                let want = boxes
                    .iter()
                    .filter_map(|b| b.intersect_ray(&ray, 0.0, f32::INFINITY))
                    .map(|(tn, _)| tn)
                    .fold(f32::INFINITY, f32::min);
                hits += want.is_finite() as usize;
                for stack in [bvh.wide_stack, super::INLINE_STACK + 1] {
                    let mut got = f32::INFINITY;
                    let mut t_max = f32::INFINITY;
                    super::traverse(&bvh.wide, stack, &ray, 0.0, &mut t_max, |f, c, lim| {
                        for s in f..f + c {
                            let b = boxes[bvh.order()[s as usize] as usize];
                            if let Some((tn, _)) = b.intersect_ray(&ray, 0.0, *lim) {
                                got = got.min(tn);
                                *lim = lim.min(tn);
                            }
                        }
                        false
                    });
                    assert_eq!(got, want, "ray {k}, stack {stack}");
                }
            }
            assert!(hits > 100, "only {hits} hits");
        }
    }
}
