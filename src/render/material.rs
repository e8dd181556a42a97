//! Prop materials: Lambertian diffuse, glossy (diffuse under a dielectric GGX coat) and metal
//! (GGX with Schlick's Fresnel; roughness 0 is a perfect mirror).
//!
//! All functions take the shading normal `n` already turned toward the outgoing direction
//! `wo` (unit, pointing away from the surface); directions below the surface get no light.
//! Microfacets: GGX distribution `D`, separable Smith shadowing `G`, and sampling of `D·cos θ_h`
//! (Walter et al. 2007).

use super::radiance::{Lanes, Radiance};
use crate::geometry::frame;
use glam::Vec3;
use std::f32::consts::{FRAC_1_PI, PI, TAU};

/// Normal-incidence reflectance of the glossy coat (a dielectric of index 1.5).
const COAT_F0: f32 = 0.04;

/// A prop's surface. Colours are linear sRGB reflectances in [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    /// Matte: reflects `albedo` evenly in every direction.
    Diffuse {
        /// Reflectance.
        albedo: Vec3,
    },
    /// Plastic-like: a diffuse base under a clear coat with highlights of `roughness`.
    Glossy {
        /// Reflectance of the base.
        albedo: Vec3,
        /// Perceptual roughness in [0, 1] (GGX α = roughness²).
        roughness: f32,
    },
    /// Metal: coloured reflection, blurred by `roughness`; 0 is a mirror.
    Metal {
        /// Reflectance at normal incidence (Schlick's F0).
        colour: Vec3,
        /// Perceptual roughness in [0, 1] (GGX α = roughness²).
        roughness: f32,
    },
}

fn alpha(roughness: f32) -> f32 {
    (roughness * roughness).max(1e-3)
}

fn ggx_d(nh: f32, a: f32) -> f32 {
    let a2 = a * a;
    let d = nh * nh * (a2 - 1.0) + 1.0;
    a2 / (PI * d * d)
}

fn smith_g1(nv: f32, a: f32) -> f32 {
    let a2 = a * a;
    2.0 * nv / (nv + (a2 + (1.0 - a2) * nv * nv).sqrt())
}

fn schlick(c: f32) -> f32 {
    (1.0 - c).clamp(0.0, 1.0).powi(5)
}

/// GGX term without Fresnel: D·G / (4 cos θo cos θi).
fn ggx(n: Vec3, wo: Vec3, wi: Vec3, a: f32) -> (f32, f32) {
    let h = (wo + wi).normalize();
    let (no, ni) = (n.dot(wo), n.dot(wi));
    let v = ggx_d(n.dot(h).max(0.0), a) * smith_g1(no, a) * smith_g1(ni, a) / (4.0 * no * ni);
    (v, wo.dot(h).max(0.0))
}

fn ggx_pdf(n: Vec3, wo: Vec3, wi: Vec3, a: f32) -> f32 {
    let h = (wo + wi).normalize();
    let nh = n.dot(h).max(0.0);
    ggx_d(nh, a) * nh / (4.0 * wo.dot(h).abs().max(1e-8))
}

fn ggx_sample(n: Vec3, wo: Vec3, a: f32, u: (f32, f32)) -> Vec3 {
    let cos2 = (1.0 - u.0) / (1.0 + (a * a - 1.0) * u.0);
    let cos = cos2.sqrt();
    let sin = (1.0 - cos2).max(0.0).sqrt();
    let phi = TAU * u.1;
    let (t, b) = frame(n);
    let h = cos * n + sin * (phi.cos() * t + phi.sin() * b);
    2.0 * wo.dot(h) * h - wo
}

fn cosine_sample(n: Vec3, u: (f32, f32)) -> Vec3 {
    let r = u.0.sqrt();
    let phi = TAU * u.1;
    let (t, b) = frame(n);
    (r * phi.cos() * t + r * phi.sin() * b + (1.0 - u.0).max(0.0).sqrt() * n).normalize()
}

impl Material {
    /// True for a perfect mirror (followed as a specular branch, without light sampling).
    pub fn is_mirror(&self) -> bool {
        matches!(self, Material::Metal { roughness, .. } if *roughness <= 0.0)
    }

    /// A mirror's reflectance at `cos θ` (Schlick).
    pub fn mirror_reflectance<L: Lanes>(&self, lanes: &L, cos: f32) -> L::C {
        match self {
            Material::Metal { colour, .. } => {
                let f0 = lanes.input(*colour);
                f0 + (L::C::splat(1.0) - f0) * schlick(cos)
            }
            _ => L::C::splat(0.0),
        }
    }

    /// BSDF value f(wo, wi) (1/sr), without the cosine.
    pub fn eval<L: Lanes>(&self, lanes: &L, n: Vec3, wo: Vec3, wi: Vec3) -> L::C {
        if n.dot(wi) <= 0.0 || n.dot(wo) <= 0.0 {
            return L::C::splat(0.0);
        }
        match *self {
            Material::Diffuse { albedo } => lanes.input(albedo) * FRAC_1_PI,
            Material::Glossy { albedo, roughness } => {
                let (spec, c) = ggx(n, wo, wi, alpha(roughness));
                let f = COAT_F0 + (1.0 - COAT_F0) * schlick(c);
                lanes.input(albedo) * ((1.0 - COAT_F0) * FRAC_1_PI) + L::C::splat(spec * f)
            }
            Material::Metal { colour, roughness } => {
                let (spec, c) = ggx(n, wo, wi, alpha(roughness));
                let f0 = lanes.input(colour);
                (f0 + (L::C::splat(1.0) - f0) * schlick(c)) * spec
            }
        }
    }

    /// Solid-angle density of [`sample`](Self::sample) choosing `wi`.
    pub fn pdf(&self, n: Vec3, wo: Vec3, wi: Vec3) -> f32 {
        let ni = n.dot(wi);
        if ni <= 0.0 || n.dot(wo) <= 0.0 {
            return 0.0;
        }
        match *self {
            Material::Diffuse { .. } => ni * FRAC_1_PI,
            Material::Glossy { roughness, .. } => {
                0.5 * ni * FRAC_1_PI + 0.5 * ggx_pdf(n, wo, wi, alpha(roughness))
            }
            Material::Metal { roughness, .. } => ggx_pdf(n, wo, wi, alpha(roughness)),
        }
    }

    /// Samples an incoming direction with three random numbers; `None` below the surface.
    pub fn sample(&self, n: Vec3, wo: Vec3, u: (f32, f32, f32)) -> Option<Vec3> {
        let wi = match *self {
            Material::Diffuse { .. } => cosine_sample(n, (u.0, u.1)),
            Material::Glossy { roughness, .. } => {
                if u.2 < 0.5 {
                    cosine_sample(n, (u.0, u.1))
                } else {
                    ggx_sample(n, wo, alpha(roughness), (u.0, u.1))
                }
            }
            Material::Metal { roughness, .. } => ggx_sample(n, wo, alpha(roughness), (u.0, u.1)),
        };
        (n.dot(wi) > 0.0).then_some(wi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::sampler::Pcg32;

    struct Grey;
    impl Lanes for Grey {
        type C = Vec3;
        fn film_reflectance(&self, _: f32, _: f32) -> Vec3 {
            Vec3::ZERO
        }
        fn input(&self, c: Vec3) -> Vec3 {
            c
        }
        fn to_rgb(&self, c: Vec3) -> Vec3 {
            c
        }
    }

    /// Sampling is consistent with `pdf` (E[f cos / pdf] equals the albedo estimated with
    /// uniform hemisphere directions) and no material reflects more than it receives.
    #[test]
    fn sampling_matches_pdf_and_energy_is_bounded() {
        let n = Vec3::Y;
        let wo = Vec3::new(0.5, 0.8, 0.1).normalize();
        let mut rng = Pcg32::new(5, 5);
        for m in [
            Material::Diffuse {
                albedo: Vec3::splat(0.8),
            },
            Material::Glossy {
                albedo: Vec3::splat(0.5),
                roughness: 0.4,
            },
            Material::Metal {
                colour: Vec3::splat(0.9),
                roughness: 0.5,
            },
        ] {
            let k = 200_000;
            let (mut by_sample, mut uniform) = (0.0f64, 0.0f64);
            for _ in 0..k {
                if let Some(wi) = m.sample(n, wo, (rng.next_f32(), rng.next_f32(), rng.next_f32()))
                {
                    let pdf = m.pdf(n, wo, wi);
                    if pdf > 0.0 {
                        by_sample += (m.eval(&Grey, n, wo, wi).x * n.dot(wi) / pdf) as f64;
                    }
                }
                let z = rng.next_f32();
                let r = (1.0 - z * z).sqrt();
                let phi = TAU * rng.next_f32();
                let wi = Vec3::new(r * phi.cos(), z, r * phi.sin());
                uniform += (m.eval(&Grey, n, wo, wi).x * z * TAU) as f64;
            }
            let (a, b) = (by_sample / k as f64, uniform / k as f64);
            assert!((a - b).abs() < 0.02 * b.max(0.1), "{m:?}: {a} vs {b}");
            assert!(a <= 1.0 && a > 0.3, "{m:?}: albedo {a}");
        }
    }
}
