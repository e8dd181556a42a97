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
            crossed: f32::NAN,
        })
    };
}

thread_local! {
    /// A second [`Gathered`], swapped in by [`aside`].
    static ASIDE: RefCell<Gathered> = const {
        RefCell::new(Gathered {
            cands: Vec::new(),
            key: None,
            from: 0.0,
            crossed: f32::NAN,
        })
    };
}

/// Runs `query` with a second set of kept spheres in place of this thread's, and puts them
/// back after: a query on another stretch of the ray (the band around a disk, the `fallback`
/// module) leaves the ray's kept spheres for its continuation.
pub(super) fn aside<R>(query: impl FnOnce() -> R) -> R {
    let swap = || GATHERED.with(|g| ASIDE.with(|a| g.swap(a)));
    swap();
    let r = query();
    swap();
    r
}

/// The support spheres gathered by the last query on this thread.
pub(super) struct Gathered {
    /// Every sphere the ray is inside somewhere in `(from, t_max)`, clipped to it.
    pub cands: Vec<Cand>,
    /// The surface and ray they were gathered for.
    pub key: Option<QueryKey>,
    /// Start of the query they were gathered (or last clipped) for.
    pub from: f32,
    /// The last surface crossing found on this ray (NaN: none), so a disk of the film just
    /// crossed is known to be drawn without a query of its own (the `fallback` module).
    pub crossed: f32,
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

thread_local! {
    /// Scratch of [`sort_by_entry`]: the sort keys and the candidates in their new order.
    static SORT_SCRATCH: RefCell<(Vec<u64>, Vec<Cand>)> = const {
        RefCell::new((Vec::new(), Vec::new()))
    };
}

/// Sorts `cands` by entry `ta`, stably. A continued query keeps them in order (one pass checks
/// that); otherwise the keys (`ta`'s bits in total order above the index, 8 bytes each) are
/// sorted and each 64-byte candidate is moved once, where sorting the records themselves moved
/// each as often as it was out of order (the near-first traversal gathers the spheres only
/// roughly in order: a leaf's spheres are in slot order and the boxes overlap).
pub(super) fn sort_by_entry(cands: &mut [Cand]) {
    if cands.is_sorted_by(|a, b| a.ta.total_cmp(&b.ta).is_le()) {
        return;
    }
    SORT_SCRATCH.with_borrow_mut(|(keys, moved)| {
        keys.clear();
        keys.extend(
            cands
                .iter()
                .enumerate()
                .map(|(i, c)| (u64::from(order_bits(c.ta)) << 32) | i as u64),
        );
        keys.sort_unstable();
        moved.clear();
        moved.extend(keys.iter().map(|&k| cands[(k & 0xffff_ffff) as usize]));
        cands.copy_from_slice(moved);
    });
}

/// The bits of `x` as an unsigned integer in [`f32::total_cmp`]'s order.
#[inline(always)]
fn order_bits(x: f32) -> u32 {
    let b = x.to_bits();
    if b >> 31 == 1 { !b } else { b | 1 << 31 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// Entries with ties, negative values and long runs come out as a stable sort by
    /// `total_cmp` leaves them.
    #[test]
    fn sort_by_entry_is_a_stable_sort_by_entry() {
        let mut s = 0x2545_f491u32;
        for n in [0usize, 1, 2, 7, 40, 65, 300] {
            let cands: Vec<Cand> = (0..n)
                .map(|i| {
                    s ^= s << 13;
                    s ^= s >> 17;
                    s ^= s << 5;
                    let ta =
                        [(s % 9) as f32 - 3.0, -0.0, 0.0, 1e-30, -1e-30][(s >> 8) as usize % 5];
                    Cand {
                        p: Vec3::ZERO,
                        inv_h2: 1.0,
                        n: Vec3::Z,
                        thickness: 0.0,
                        ta,
                        tb: ta + 1.0,
                        slot: i as u32,
                        r: 1.0,
                        g0: 0.0,
                        g1: 0.0,
                        b: 0.0,
                        k2: 0.0,
                    }
                })
                .collect();
            let mut want = cands.clone();
            want.sort_by(|a, b| a.ta.total_cmp(&b.ta));
            let mut got = cands;
            sort_by_entry(&mut got);
            let slots = |v: &[Cand]| v.iter().map(|c| c.slot).collect::<Vec<_>>();
            assert_eq!(slots(&got), slots(&want), "n = {n}");
        }
    }
}
