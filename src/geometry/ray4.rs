//! A ray splatted into four SSE lanes (glam's `Vec4`), shared by the four-wide disk test
//! (`disk4`) and sphere test (`sphere4`), and the padding the disks' slot array carries so a
//! packet of four can start at any slot (the spheres are stored in leaf-aligned packets and
//! need none).

use glam::Vec4;

use super::Ray;

/// Number of padding primitives after the last disk of a slot array.
pub(super) const PAD: usize = 3;

/// A ray splatted into lanes.
pub(super) struct Ray4 {
    pub(super) ox: Vec4,
    pub(super) oy: Vec4,
    pub(super) oz: Vec4,
    pub(super) dx: Vec4,
    pub(super) dy: Vec4,
    pub(super) dz: Vec4,
}

impl Ray4 {
    /// Splats `ray` into lanes.
    #[inline(always)]
    pub fn new(ray: &Ray) -> Ray4 {
        let (o, d) = (ray.origin, ray.dir);
        Ray4 {
            ox: Vec4::splat(o.x),
            oy: Vec4::splat(o.y),
            oz: Vec4::splat(o.z),
            dx: Vec4::splat(d.x),
            dy: Vec4::splat(d.y),
            dz: Vec4::splat(d.z),
        }
    }
}

/// The bit mask of the first `lanes` lanes.
#[inline(always)]
pub(super) fn lane_mask(lanes: usize) -> u32 {
    (1u32 << lanes) - 1
}

/// A xorshift generator of uniform values in [-1, 1] for the lane tests.
#[cfg(test)]
pub(super) fn test_rng(mut s: u32) -> impl FnMut() -> f32 {
    move || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        s as f32 / u32::MAX as f32 * 2.0 - 1.0
    }
}

/// A test packet for case `k`: `make()` in the first four lanes (two for every seventh case),
/// `pad` in the rest.
#[cfg(test)]
pub(super) fn test_packet<P: Copy>(k: usize, pad: P, mut make: impl FnMut() -> P) -> [P; 4] {
    let mut packet = [pad; 4];
    for p in packet
        .iter_mut()
        .take(if k.is_multiple_of(7) { 2 } else { 4 })
    {
        *p = make();
    }
    packet
}

/// Checks one packet's lane results against the scalar test, bit for bit: `got(i)` is lane
/// `i`'s result if its mask bit is set, `want(i)` the scalar result (masked-off lanes must
/// miss). Returns the number of hits.
#[cfg(test)]
pub(super) fn assert_lanes_match<T: PartialEq + std::fmt::Debug>(
    case: usize,
    lanes: usize,
    got: impl Fn(usize) -> Option<T>,
    want: impl Fn(usize) -> Option<T>,
) -> usize {
    let mut hits = 0;
    for i in 0..4 {
        let want = want(i).filter(|_| i < lanes);
        let got = got(i);
        assert_eq!(got, want, "case {case} lane {i}");
        hits += got.is_some() as usize;
    }
    hits
}
