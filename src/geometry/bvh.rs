//! The flattened BVH's node format and build parameters, shared by the builder (`bvh_build`),
//! the 4-wide collapse (`wide`) and the tree with its queries ([`Bvh`](super::Bvh), `tree`), so
//! none of them imports another's tree.

use glam::Vec3;

use super::Aabb;

/// One flattened node (32 bytes). Interior: `count == 0`, left child at `index + 1`, right child
/// at `offset`. Leaf: slots `offset .. offset + count`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
pub struct BvhNode {
    /// Lower corner of the node's bounds.
    pub min: [f32; 3],
    /// Right child index (interior) or first slot (leaf).
    pub offset: u32,
    /// Upper corner of the node's bounds.
    pub max: [f32; 3],
    /// Number of slots (leaf) or 0 (interior).
    pub count: u32,
}

const _: () = assert!(std::mem::size_of::<BvhNode>() == 32);

impl BvhNode {
    /// The node's bounds.
    #[inline(always)]
    pub fn bounds(&self) -> Aabb {
        Aabb::new(Vec3::from_array(self.min), Vec3::from_array(self.max))
    }

    /// True for a leaf.
    #[inline(always)]
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// Build parameters. The defaults suit cheap primitives (disks, spheres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhParams {
    /// SAH bins per axis: 8, 16 or 32 (other values round down into that set; nodes of at most
    /// 64 primitives always use 8).
    pub bins: usize,
    /// Largest leaf the SAH may choose; larger nodes are always split (clamped to 1..=255).
    pub max_leaf: usize,
    /// Cost of a node visit relative to one primitive test. The default 4 gives about 6
    /// primitives per leaf (disks are tested four at a time); on a 1M-disk shell it used 20% less
    /// memory than 2 and traced slightly faster.
    pub traversal_cost: f32,
    /// Nodes with at least this many primitives build their children in parallel.
    pub parallel_threshold: usize,
}

impl Default for BvhParams {
    fn default() -> Self {
        BvhParams {
            bins: 16,
            max_leaf: 8,
            traversal_cost: 4.0,
            parallel_threshold: 4096,
        }
    }
}

/// Bound on the binary tree's depth. The builder switches to median splits below depth
/// `bvh_build::MAX_SAH_DEPTH`, so trees stay shallower than this for any 32-bit primitive count.
pub(crate) const STACK_SIZE: usize = 96;
