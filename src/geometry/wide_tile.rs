//! One walk of the 4-wide tree shared by a bundle of rays from one origin (a tile of pinhole
//! camera rays): each node is tested once for the whole bundle with an interval slab test, and
//! the caller tests its rays only against the leaves of the nodes the bundle enters.
//!
//! The interval test (Wald, Boulos and Shirley, "Ray tracing deformable scenes using dynamic
//! bounding volume hierarchies", 2007: the bundle's inverse directions as one interval per axis)
//! is conservative: a box any ray of the bundle enters within `[t_min, t_max]` passes it, since
//! each rounded product `(plane − origin) · inv` is monotonic in `inv` and the rays share the
//! origin, so the bundle's entry bound is at most each ray's entry and its exit bound at least
//! each ray's exit, both computed by the same operations as the single-ray test.

use glam::{Vec3, Vec4};

use super::Ray;
use super::aabb::{SLAB_ROBUST, safe_inv_dir};
use super::wide::{Node4, sort_lanes};

/// A bundle of rays with one origin prepared for 4-lane interval slab tests.
pub(super) struct Bundle {
    near: [usize; 3],
    far: [usize; 3],
    o: [Vec4; 3],
    inv_lo: [Vec4; 3],
    inv_hi: [Vec4; 3],
    /// Axes on which the rays' directions differ in sign: they do not bound the bundle.
    free: [bool; 3],
    t_min: Vec4,
}

impl Bundle {
    /// The bundle of `rays`, or `None` if there are none or their origins differ.
    pub(super) fn new(rays: &[Ray], t_min: f32) -> Option<Bundle> {
        let o = rays.first()?.origin;
        if rays.iter().any(|r| r.origin != o) {
            return None;
        }
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for r in rays {
            let inv = safe_inv_dir(r.dir);
            lo = lo.min(inv);
            hi = hi.max(inv);
        }
        // The near plane per axis as the single-ray test picks it (by the sign of `inv`).
        let near = [0, 1, 2].map(|a| if hi[a] < 0.0 { a + 3 } else { a });
        Some(Bundle {
            near,
            far: near.map(|k| (k + 3) % 6),
            o: [Vec4::splat(o.x), Vec4::splat(o.y), Vec4::splat(o.z)],
            inv_lo: [0, 1, 2].map(|a| Vec4::splat(lo[a])),
            inv_hi: [0, 1, 2].map(|a| Vec4::splat(hi[a])),
            free: [0, 1, 2].map(|a| lo[a] < 0.0 && hi[a] >= 0.0),
            t_min: Vec4::splat(t_min),
        })
    }

    /// The children of `n` some ray of the bundle may enter within `[t_min, t_max]`: a lane
    /// mask and a lower bound of the rays' entry distances per lane.
    #[inline(always)]
    fn test(&self, n: &Node4, t_max: f32) -> (u32, Vec4) {
        let b = &n.bounds;
        let mut tn = self.t_min;
        let mut tf = Vec4::splat(t_max);
        for a in 0..3 {
            if self.free[a] {
                continue;
            }
            let (lo, hi) = (self.inv_lo[a], self.inv_hi[a]);
            let dn = b[self.near[a]] - self.o[a];
            let df = b[self.far[a]] - self.o[a];
            tn = tn.max((dn * lo).min(dn * hi));
            tf = tf.min((df * lo).max(df * hi));
        }
        (tn.cmple(tf * SLAB_ROBUST).bitmask(), tn)
    }
}

/// The lanes of `n` that are leaves, as a mask.
#[inline(always)]
fn leaf_lanes(n: &Node4) -> u32 {
    (0..4).fold(0, |m, i| m | (((n.count[i] > 0) as u32) << i))
}

/// Walks the tree front to back (by the bundle's entry bounds) through every node some ray of
/// the bundle may enter within `[t_min, bound]`. For each node with leaf children the bundle
/// enters, `leaves(node, mask)` tests the rays against those leaves and returns the new `bound`
/// (the largest pruning distance over the rays); deferred nodes beyond it are skipped.
pub(super) fn walk<F: FnMut(&Node4, u32) -> f32>(
    nodes: &[Node4],
    stack_size: usize,
    bundle: &Bundle,
    mut bound: f32,
    mut leaves: F,
) {
    if nodes.is_empty() {
        return;
    }
    let mut stack: Vec<(u32, f32)> = Vec::with_capacity(stack_size + 4);
    stack.push((0, f32::NEG_INFINITY));
    while let Some((i, t)) = stack.pop() {
        if t > bound * SLAB_ROBUST {
            continue;
        }
        let n = &nodes[i as usize];
        let (mask, tn) = bundle.test(n, bound);
        let leafy = leaf_lanes(n);
        if mask & leafy != 0 {
            bound = leaves(n, mask & leafy);
        }
        let inner = mask & !leafy;
        if inner != 0 {
            // Nearest popped first.
            let sorted = sort_lanes(tn, inner);
            let nh = inner.count_ones() as usize;
            for &k in sorted[..nh].iter().rev() {
                let lane = (k & 3) as usize;
                stack.push((n.child[lane], tn[lane]));
            }
        }
    }
}
