//! The SplitMix64 mix (G. L. Steele, D. Lea and C. H. Flood, "Fast splittable pseudorandom
//! number generators", OOPSLA 2014), shared by the renderer's seed derivation and the sample
//! generators' PRNG. A utility like [`crate::error`]: any stage may use it.

/// The Weyl-sequence increment of SplitMix64 (2⁶⁴ / φ, odd).
pub const GOLDEN_GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// SplitMix64's output for state `z`: `z + γ`, then two multiply-xorshift rounds. A strong
/// 64-bit mix (every input bit affects every output bit), for deriving seeds. Cost: ~2 ns.
#[inline]
pub fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(GOLDEN_GAMMA);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
