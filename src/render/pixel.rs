//! One pixel's camera samples: where they fall in the pixel ([`SubPixel`]) and what they add
//! up to ([`Pixel`]).

use super::primary::FirstHits;
use super::sampler::Pcg32;
use glam::Vec3;

/// A pixel of the image and the image's aspect ratio.
pub(super) struct Px {
    pub x: usize,
    pub y: usize,
    pub aspect: f32,
}

#[derive(Default)]
pub(super) struct Pixel {
    pub rgb: Vec3,
    pub alpha: f32,
    pub depth: f32,
    pub normal: Vec3,
    pub thickness: f32,
    pub hits: f32,
    pub droplets: f32,
    /// Σ share of the samples that saw a film first.
    pub film: f32,
}

impl Pixel {
    /// Adds one camera sample's radiance `c` and what it met first.
    pub fn add(&mut self, c: Vec3, first: FirstHits) {
        if let Some((hit, w)) = first.film {
            self.film += w;
            self.depth += w * hit.t;
            self.normal += w * hit.normal;
            self.thickness += w * hit.thickness_nm;
            self.hits += w * hit.coverage as f32;
        }
        self.droplets += first.droplet;
        self.depth += first.droplet_depth;
        self.normal += first.droplet_normal;
        // Drop non-finite samples rather than poison the pixel (pbrt does the same).
        if c.is_finite() {
            self.rgb += c;
        }
    }

    /// Means over `spp` samples.
    pub fn finish(&mut self, spp: u32) {
        let inv = 1.0 / spp as f32;
        self.rgb *= inv;
        let seen = self.film + self.droplets;
        self.alpha = (seen * inv).min(1.0);
        self.droplets *= inv;
        if seen > 0.0 {
            self.depth /= seen;
            self.normal /= seen;
        }
        if self.film > 0.0 {
            self.thickness /= self.film;
            self.hits /= self.film;
        }
    }
}

/// Sub-pixel positions of a pixel's samples: the centre for 1 spp, jittered strata for square
/// counts, else the R2 low-discrepancy sequence (M. Roberts, "The unreasonable effectiveness
/// of quasirandom sequences", 2018) shifted by one random offset per pixel.
pub(super) struct SubPixel {
    spp: u32,
    strata: u32,
    square: bool,
    r2_offset: (f32, f32),
}

impl SubPixel {
    /// The pattern for `spp` samples (draws the R2 offset from `rng` when it is used).
    pub fn new(spp: u32, rng: &mut Pcg32) -> Self {
        let strata = (spp as f32).sqrt() as u32;
        let square = strata * strata == spp;
        let r2_offset = if spp > 1 && !square {
            (rng.next_f32(), rng.next_f32())
        } else {
            (0.0, 0.0)
        };
        SubPixel {
            spp,
            strata,
            square,
            r2_offset,
        }
    }

    /// Position in the pixel of sample `i`, each coordinate in [0, 1).
    pub fn at(&self, i: u32, rng: &mut Pcg32) -> (f32, f32) {
        let strata = self.strata;
        if self.spp == 1 {
            (0.5, 0.5)
        } else if self.square {
            let (a, b) = (i % strata, i / strata);
            (
                (a as f32 + rng.next_f32()) / strata as f32,
                (b as f32 + rng.next_f32()) / strata as f32,
            )
        } else {
            const R2: (f32, f32) = (0.754_877_7, 0.569_840_3);
            (
                (self.r2_offset.0 + i as f32 * R2.0).fract(),
                (self.r2_offset.1 + i as f32 * R2.1).fract(),
            )
        }
    }
}
