//! The support spheres a thread gathered for its last ray query, kept so that a query
//! continuing the same ray needs no new BVH traversal, and their order along the ray.

use std::cell::RefCell;

use super::field::Cand;
use crate::geometry::Ray;

thread_local! {
    /// The support spheres along the current ray (kept for a query continuing it).
    pub(super) static GATHERED: RefCell<Gathered> = const {
        RefCell::new(Gathered {
            cands: Vec::new(),
            key: None,
            from: 0.0,
            window: 0.0,
        })
    };
}

/// The support spheres gathered by the last query on this thread.
pub(super) struct Gathered {
    /// Spheres entered before `window`, clipped to `(from, t_max)`.
    pub cands: Vec<Cand>,
    /// The surface and ray they were gathered for.
    pub key: Option<QueryKey>,
    /// Start of the query they were gathered (or last clipped) for.
    pub from: f32,
    /// Every sphere the ray enters before this is in `cands`.
    pub window: f32,
}

/// A surface (by [`MlsSurface`](super::MlsSurface)'s id) and a ray and `t_max`, bit for bit.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) struct QueryKey {
    surface: u64,
    bits: [u32; 7],
}

impl QueryKey {
    pub(super) fn new(surface: u64, ray: &Ray, t_max: f32) -> QueryKey {
        let (o, d) = (ray.origin, ray.dir);
        let bits = [o.x, o.y, o.z, d.x, d.y, d.z, t_max].map(f32::to_bits);
        QueryKey { surface, bits }
    }
}

/// Sorts `cands` by entry `ta`. The near-first traversal gathers them nearly in order, and a
/// continued query keeps them in order, so an insertion sort is cheap (O(n + inversions));
/// long lists (a whole chord) take the general sort.
pub(super) fn sort_by_entry(cands: &mut [Cand]) {
    if cands.len() > 64 {
        cands.sort_unstable_by(|a, b| a.ta.total_cmp(&b.ta));
        return;
    }
    for i in 1..cands.len() {
        let x = cands[i];
        let mut j = i;
        while j > 0 && cands[j - 1].ta > x.ta {
            cands[j] = cands[j - 1];
            j -= 1;
        }
        cands[j] = x;
    }
}
