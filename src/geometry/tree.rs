//! [`Bvh`]: a bounding volume hierarchy over an arbitrary set of primitive boxes.
//!
//! Built with binned SAH (parallel recursion with `rayon::join`, see `bvh_build`), flattened
//! depth-first into 32-byte [`BvhNode`]s (the `bvh` module): the left child of an interior node directly follows it,
//! the right child is at `offset`. Leaves hold a contiguous range of *slots*; slot `s` stands for
//! the caller's primitive `order()[s]`, so callers store their primitive data in slot order
//! for locality and pass slot indices around.
//!
//! Queries take closures and are independent of the primitive type:
//! [`Bvh::closest`] (closest hit, the closure shrinks `t_max`), [`Bvh::any`] (stops at the first
//! `true`) and [`Bvh::visit_segment`] (every slot whose box overlaps a ray segment). Queries run
//! on a 4-wide copy of the tree (see the `wide` module: one SIMD slab test per node, children
//! visited nearest first, deferred nodes culled once their entry distance is beyond `t_max`).

use glam::Vec3;

use super::bvh::{BvhNode, BvhParams, STACK_SIZE};
use super::wide::Node4;
use super::{Aabb, Ray};

/// A flattened BVH (see the module docs). Memory: 32 bytes per binary node (about
/// `2n / leaf size` nodes), 128 bytes per 4-wide node (about a third as many) and 4 bytes per
/// primitive for the slot order: ~30 bytes per primitive at 6 primitives per leaf.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    pub(crate) nodes: Vec<BvhNode>,
    pub(crate) order: Vec<u32>,
    /// The same tree collapsed to 4-wide nodes; all queries traverse this.
    pub(crate) wide: Vec<Node4>,
    /// Traversal stack entries the wide tree needs.
    pub(crate) wide_stack: usize,
}

impl Bvh {
    /// Builds a BVH over `bounds` (one box per primitive, fewer than `u32::MAX`; boxes should be
    /// finite and non-empty — others do not panic but may make queries miss them) with default
    /// parameters. Cost: O(n log n), parallel over the rayon pool.
    pub fn build(bounds: &[Aabb]) -> Bvh {
        Self::build_with(bounds, BvhParams::default())
    }

    /// Builds with explicit parameters (see [`Bvh::build`]).
    pub fn build_with(bounds: &[Aabb], params: BvhParams) -> Bvh {
        Self::build_by(bounds.len(), |i| bounds[i], params)
    }

    /// Builds over `n` primitives whose boxes are `bound(i)` (called once each, in parallel),
    /// without a slice of boxes in between (see [`Bvh::build`]).
    pub(crate) fn build_by(
        n: usize,
        bound: impl Fn(usize) -> Aabb + Sync,
        params: BvhParams,
    ) -> Bvh {
        let (nodes, order) = super::bvh_build::build(n, bound, params);
        let (wide, wide_stack) = super::wide::collapse(&nodes);
        Bvh {
            nodes,
            order,
            wide,
            wide_stack,
        }
    }

    /// `order()[slot]` is the index (into the `bounds` given to the build) of the primitive in
    /// `slot`. Store primitive data in this order.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// The flattened nodes (root first; empty for zero primitives).
    pub fn nodes(&self) -> &[BvhNode] {
        &self.nodes
    }

    /// Number of primitives.
    pub fn len(&self) -> usize {
        self.order.len()
    }

    /// True if the BVH holds no primitive.
    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// Bounds of everything (empty box for zero primitives).
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, BvhNode::bounds)
    }

    /// Heap bytes used by nodes (binary and 4-wide) and slot order.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.capacity() * std::mem::size_of::<BvhNode>()
            + self.wide.capacity() * std::mem::size_of::<Node4>()
            + self.order.capacity() * 4
    }

    /// Closest-hit query. `hit(slot, &mut t_max)` must test the primitive in `slot` and, if it
    /// finds a hit closer than `*t_max`, record it and lower `*t_max` (boxes entered beyond
    /// `*t_max` are then skipped). The closure applies `t_min` itself.
    #[inline]
    pub fn closest<F: FnMut(u32, &mut f32)>(&self, ray: &Ray, t_min: f32, t_max: f32, mut hit: F) {
        let mut t_max = t_max;
        self.traverse(ray, t_min, &mut t_max, |first, count, t_max| {
            for s in first..first + count {
                hit(s, t_max);
            }
            false
        });
    }

    /// Any-hit query: calls `hit(slot)` for primitives whose boxes the ray meets within
    /// `[t_min, t_max]` until one returns `true`; returns whether one did.
    #[inline]
    pub fn any<F: FnMut(u32) -> bool>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        mut hit: F,
    ) -> bool {
        let mut t_max = t_max;
        self.traverse(ray, t_min, &mut t_max, |first, count, _| {
            (first..first + count).any(&mut hit)
        })
    }

    /// Calls `visit(slot)` for every primitive whose box the segment `[t0, t1]` of the ray
    /// overlaps (a superset of the primitives hit in that range).
    #[inline]
    pub fn visit_segment<F: FnMut(u32)>(&self, ray: &Ray, t0: f32, t1: f32, mut visit: F) {
        let mut t_max = t1;
        self.traverse(ray, t0, &mut t_max, |first, count, _| {
            (first..first + count).for_each(&mut visit);
            false
        });
    }

    /// Calls `visit(slot)` for every primitive whose box contains the point `p` (boundary
    /// included). Walks the binary tree; cost O(log n) plus the boxes that contain `p`.
    pub fn visit_point<F: FnMut(u32)>(&self, p: Vec3, mut visit: F) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = [0u32; STACK_SIZE];
        let mut sp = 0;
        let mut i = 0usize;
        loop {
            let node = &self.nodes[i];
            if node.bounds().contains(p) {
                if !node.is_leaf() {
                    stack[sp] = node.offset;
                    sp += 1;
                    i += 1;
                    continue;
                }
                (node.offset..node.offset + node.count).for_each(&mut visit);
            }
            if sp == 0 {
                return;
            }
            sp -= 1;
            i = stack[sp] as usize;
        }
    }

    /// The traversal loop (over the 4-wide tree, see the `wide` module). `leaf(first, count,
    /// &mut t_max)` returns `true` to stop; the loop then returns `true`.
    #[inline(always)]
    fn traverse<L: FnMut(u32, u32, &mut f32) -> bool>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: &mut f32,
        leaf: L,
    ) -> bool {
        super::wide::traverse(&self.wide, self.wide_stack, ray, t_min, t_max, leaf)
    }

    /// Closest-hit query by leaves: `hit(first, count, &mut t_max)` tests slots
    /// `first .. first + count` (near leaves first) and may lower `t_max` (see [`Bvh::closest`]).
    #[inline]
    pub(crate) fn closest_leaves<F: FnMut(u32, u32, &mut f32)>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        mut hit: F,
    ) {
        let mut t_max = t_max;
        self.traverse(ray, t_min, &mut t_max, |first, count, t_max| {
            hit(first, count, t_max);
            false
        });
    }

    /// Tie-break between two hits at the same distance: true if slot `a` holds the lower
    /// particle index. Only evaluated on exact ties, so the slot order is rarely touched during
    /// traversal.
    #[inline]
    pub(crate) fn lower_particle(&self, a: u32, b: u32) -> bool {
        self.order[a as usize] < self.order[b as usize]
    }
}
