//! Deterministic per-pixel random numbers: a PCG32 stream seeded from (seed, pixel, pass), so a
//! render is the same for a given seed whatever the thread count or tile order.

/// PCG32 (O'Neill 2014, XSH-RR output), a small fast generator with good statistics.
#[derive(Debug, Clone)]
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

impl Pcg32 {
    /// A generator for stream `stream` of `seed`.
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut rng = Pcg32 {
            state: 0,
            inc: (stream << 1) | 1,
        };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(mix64(seed));
        rng.next_u32();
        rng
    }

    /// Next 32 random bits.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// Uniform float in [0, 1).
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
    }
}

pub use crate::mix::mix64;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_and_deterministic() {
        let mut a = Pcg32::new(42, 7);
        let mut b = Pcg32::new(42, 7);
        let mut c = Pcg32::new(42, 8);
        let n = 100_000;
        let mut sum = 0.0f64;
        let mut same_as_other_stream = 0;
        for _ in 0..n {
            let x = a.next_f32();
            assert_eq!(x, b.next_f32());
            assert!((0.0..1.0).contains(&x));
            if x == c.next_f32() {
                same_as_other_stream += 1;
            }
            sum += x as f64;
        }
        assert!((sum / n as f64 - 0.5).abs() < 0.005);
        assert!(same_as_other_stream < 10);
    }
}
