//! Light transport, generic over what rays carry ([`Lanes`]): the films' specular ray tree,
//! area lights and the environment where rays escape, and prop shading by next-event
//! estimation with multiple importance sampling.
//!
//! Films stay purely specular (see [`super::integrator`]). At a prop, direct light is
//! estimated per sample with three strategies — a point on a light chosen uniformly, a
//! direction from the environment's importance distribution, and a direction from the
//! material — each weighted by the power heuristic against the material strategy (lights and
//! environment never cover the same direction, so each emitter sees two strategies). A
//! material sample that meets another prop continues as one indirect bounce per
//! `prop_bounces`. A perfect mirror prop is a specular branch of the tree instead.
//!
//! Light reaching a prop through films (shadow and material rays) passes straight through
//! each film, attenuated by its transmittance `T = 1 − R` at that crossing, and straight
//! through the bulk liquid, attenuated by the Fresnel transmittance `1 − F` of each crossing
//! of its surface: the light films and water reflect or focus onto props (their caustics) is
//! left out.

use super::env_sampling::EnvSampler;
use super::lights::nearest;
use super::material::Material;
use super::props::PropHit;
use super::radiance::{Lanes, Radiance};
use super::sampler::Pcg32;
use super::world::{RenderSettings, WorldRef};
use crate::geometry::{Ray, SurfaceHit};
use glam::Vec3;

/// The renderer's view of a scene for one render.
pub(crate) struct Tracer<'a> {
    pub scene: WorldRef<'a>,
    pub settings: &'a RenderSettings,
    /// Environment sampling for props (None when the scene has no props).
    pub env: Option<EnvSampler>,
}

/// A branch of the ray tree: its ray, the distance along it where the search starts, its
/// depth (film crossings and bounces so far) and its weight (what it contributes per unit
/// radiance).
#[derive(Clone, Copy)]
pub(crate) struct Branch<'r, C> {
    pub ray: &'r Ray,
    pub t_min: f32,
    pub depth: u32,
    pub weight: C,
}

impl<'r, C> Branch<'r, C> {
    /// A branch along `ray` from its origin on.
    #[inline]
    pub fn new(ray: &'r Ray, depth: u32, weight: C) -> Self {
        Branch {
            ray,
            t_min: 0.0,
            depth,
            weight,
        }
    }
}

/// A prop shading point: position `p` (already offset), normal `n` facing the incoming ray,
/// direction `wo` back along it, and the prop's material.
struct PropPoint<'m> {
    p: Vec3,
    n: Vec3,
    wo: Vec3,
    m: &'m Material,
}

/// Mutable per-path state.
pub(crate) struct PathState {
    pub rng: Pcg32,
    pub rays: u64,
}

/// The power heuristic (β = 2) weight of a strategy with density `a` against one with `b`.
#[inline]
fn power(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2.is_infinite() {
        1.0
    } else if a2 + b2 > 0.0 {
        a2 / (a2 + b2)
    } else {
        0.0
    }
}

impl<'a> Tracer<'a> {
    pub fn new(scene: WorldRef<'a>, settings: &'a RenderSettings) -> Self {
        let env = (settings.next_event && !scene.staging.props.is_empty())
            .then(|| EnvSampler::new(scene.environment));
        Tracer {
            scene,
            settings,
            env,
        }
    }

    /// Offset of rays leaving a prop, along its normal.
    fn offset(&self) -> f32 {
        4.0 * self.scene.epsilon
    }

    /// Radiance arriving along `ray` from beyond `t_min`.
    pub fn trace<L: Lanes>(&self, l: &L, b: Branch<'_, L::C>, st: &mut PathState) -> L::C {
        let Branch {
            ray,
            t_min,
            depth,
            weight,
        } = b;
        let w = weight.max_channel();
        if depth >= self.settings.max_depth || w < self.settings.min_weight {
            return self.escape(l, ray, t_min);
        }
        let roulette = self.settings.roulette;
        if w < roulette {
            // Russian roulette with the pruned branch's view as control variate: the branch is
            // followed with probability q = w / roulette (then at weight ≥ roulette) and its
            // difference from the escape radiance counts 1/q times. Unbiased, and it adds
            // little noise where the branch sees about what it would see escaping.
            let q = w / roulette;
            let esc = self.escape(l, ray, t_min);
            if st.rng.next_f32() >= q {
                return esc;
            }
            let boost = weight * (1.0 / q);
            let full = self.nearest(l, Branch { weight: boost, ..b }, st).0;
            return esc + (full - esc) * (1.0 / q);
        }
        self.nearest(l, b, st).0
    }

    /// What a pruned branch along `ray` sees from its origin on (see `escape`).
    pub(super) fn escape_view<L: Lanes>(&self, l: &L, ray: &Ray) -> L::C {
        self.escape(l, ray, 0.0)
    }

    /// What a pruned branch sees: lights first, then the environment.
    fn escape<L: Lanes>(&self, l: &L, ray: &Ray, t_min: f32) -> L::C {
        let lights = &self.scene.staging.lights;
        if !lights.is_empty()
            && let Some((i, _, front)) = nearest(lights, ray, t_min, f32::INFINITY)
        {
            return lights[i].le(l, front);
        }
        l.input(self.scene.environment.radiance(ray.dir))
    }

    /// Radiance along `ray` from its nearest film, prop or light (the environment if none),
    /// and the film crossing when a film was nearest.
    pub fn nearest<L: Lanes>(
        &self,
        l: &L,
        b: Branch<'_, L::C>,
        st: &mut PathState,
    ) -> (L::C, Option<SurfaceHit>) {
        self.nearest_with(l, b, st, None)
    }

    /// As [`nearest`](Self::nearest), with the film crossing already known when `film` is
    /// `Some` (what `geometry.intersect(ray, t_min, ∞)` answers, e.g. from the camera rays'
    /// raster).
    pub fn nearest_with<L: Lanes>(
        &self,
        l: &L,
        b: Branch<'_, L::C>,
        st: &mut PathState,
        film: Option<Option<SurfaceHit>>,
    ) -> (L::C, Option<SurfaceHit>) {
        let Branch {
            ray,
            t_min,
            depth,
            weight,
        } = b;
        st.rays += 1;
        let staging = &self.scene.staging;
        let film = film.unwrap_or_else(|| self.scene.geometry.intersect(ray, t_min, f32::INFINITY));
        let mut t_max = film.as_ref().map_or(f32::INFINITY, |h| h.t);
        let droplet = if staging.droplets.is_empty() {
            None
        } else {
            staging.droplets.intersect(ray, t_min, t_max)
        };
        if let Some(d) = &droplet {
            t_max = d.t;
        }
        let liquid = if staging.liquid.is_empty() {
            None
        } else {
            staging.liquid.intersect(ray, t_min, t_max)
        };
        if let Some(h) = &liquid {
            t_max = h.t;
        }
        let prop = if staging.props.is_empty() {
            None
        } else {
            staging.props.intersect(ray, t_min, t_max)
        };
        if let Some(p) = &prop {
            t_max = p.t;
        }
        if !staging.lights.is_empty()
            && let Some((i, _, front)) = nearest(&staging.lights, ray, t_min, t_max)
        {
            return (staging.lights[i].le(l, front), None);
        }
        if let Some(p) = prop {
            let c = self.shade_prop(l, ray, &p, depth, self.settings.prop_bounces, st);
            return (c, None);
        }
        if let Some(h) = liquid {
            let c = self.shade_liquid(l, ray, &h, depth, weight, st);
            return (c, Some(self.liquid_first_hit(ray, &h)));
        }
        if let Some(d) = droplet {
            return (self.shade_droplet(l, ray, &d, depth, weight, st), None);
        }
        match film {
            Some(hit) => {
                let c = self.shade_film(l, ray, &hit, depth, weight, st);
                (c, Some(hit))
            }
            None => (l.input(self.scene.environment.radiance(ray.dir)), None),
        }
    }

    /// Radiance leaving a film crossing `hit` back along `ray`: the reflected and the
    /// transmitted branch, weighted by R and T = 1 − R.
    fn shade_film<L: Lanes>(
        &self,
        l: &L,
        ray: &Ray,
        hit: &SurfaceHit,
        depth: u32,
        weight: L::C,
        st: &mut PathState,
    ) -> L::C {
        let cos_signed = ray.dir.dot(hit.normal);
        let cos_i = cos_signed.abs().min(1.0);
        // Reflected: mirror about the normal that faces the incoming ray. Its environment
        // texels are fetched while the transmitted branch is traced (most reflected rays off a
        // convex film escape), and the transmitted ray's while the reflectance is computed.
        let n = if cos_signed < 0.0 {
            hit.normal
        } else {
            -hit.normal
        };
        let dir = (ray.dir - 2.0 * ray.dir.dot(n) * n).normalize();
        let env = &self.scene.environment;
        env.prefetch(ray.dir);
        env.prefetch(dir);
        let r = l.film_reflectance(cos_i, hit.thickness_nm);
        let t = L::C::splat(1.0) - r;
        // Transmitted: the same line, beyond the film layer.
        let transmitted = Branch {
            ray,
            t_min: hit.t_exit + self.scene.epsilon,
            depth: depth + 1,
            weight: weight * t,
        };
        let lt = self.trace(l, transmitted, st);
        let skip = (self.scene.layer_skip / cos_i.max(0.1)).max(self.scene.epsilon);
        let reflected = Ray {
            origin: hit.position,
            dir,
        };
        let reflected = Branch {
            ray: &reflected,
            t_min: skip,
            depth: depth + 1,
            weight: weight * r,
        };
        let lr = self.trace(l, reflected, st);
        r * lr + t * lt
    }

    /// Radiance leaving prop hit `hit` back along `ray`; `bounces` indirect bounces remain.
    fn shade_prop<L: Lanes>(
        &self,
        l: &L,
        ray: &Ray,
        hit: &PropHit,
        depth: u32,
        bounces: u32,
        st: &mut PathState,
    ) -> L::C {
        let m = self.scene.staging.props.material(hit.index);
        let n = if hit.normal.dot(ray.dir) > 0.0 {
            -hit.normal
        } else {
            hit.normal
        };
        let p = ray.at(hit.t) + n * self.offset();
        let wo = -ray.dir;
        if m.is_mirror() {
            let f = m.mirror_reflectance(l, n.dot(wo));
            let dir = (ray.dir - 2.0 * ray.dir.dot(n) * n).normalize();
            let reflected = Ray { origin: p, dir };
            return f * self.trace(l, Branch::new(&reflected, depth + 1, f), st);
        }
        let at = PropPoint { p, n, wo, m };
        let k = self.settings.light_samples.max(1);
        let mut sum = L::C::splat(0.0);
        for _ in 0..k {
            sum = sum + self.prop_sample(l, &at, depth, bounces, st);
        }
        sum * (1.0 / k as f32)
    }

    /// One sample of each strategy at the prop point `at`.
    fn prop_sample<L: Lanes>(
        &self,
        l: &L,
        at: &PropPoint,
        depth: u32,
        bounces: u32,
        st: &mut PathState,
    ) -> L::C {
        let mut sum = L::C::splat(0.0);
        if let Some(c) = self.light_strategy(l, at, st) {
            sum = sum + c;
        }
        if let Some(c) = self.env_strategy(l, at, st) {
            sum = sum + c;
        }
        match self.material_strategy(l, at, depth, bounces, st) {
            Some(c) => sum + c,
            None => sum,
        }
    }

    /// Light sampling: a point on a light chosen uniformly, MIS-weighted against the material.
    fn light_strategy<L: Lanes>(&self, l: &L, at: &PropPoint, st: &mut PathState) -> Option<L::C> {
        let lights = &self.scene.staging.lights;
        if !self.settings.next_event || lights.is_empty() {
            return None;
        }
        let (p, n, wo, m) = (at.p, at.n, at.wo, at.m);
        let nl = lights.len() as f32;
        let i = ((st.rng.next_f32() * nl) as usize).min(lights.len() - 1);
        let u = (st.rng.next_f32(), st.rng.next_f32());
        let s = lights[i].sample_li(p, u)?;
        let cos = Some(n.dot(s.dir)).filter(|&c| c > 0.0)?;
        let pdf = s.pdf / nl;
        let t_max = s.dist * (1.0 - 1e-4);
        let tr = self.transmittance(l, p, s.dir, t_max, st)?;
        let w = power(pdf, m.pdf(n, wo, s.dir));
        let le = lights[i].le(l, true);
        Some(m.eval(l, n, wo, s.dir) * tr * le * (cos * w / pdf))
    }

    /// Environment sampling by its importance distribution, MIS-weighted against the material.
    fn env_strategy<L: Lanes>(&self, l: &L, at: &PropPoint, st: &mut PathState) -> Option<L::C> {
        let es = self.env.as_ref()?;
        let (p, n, wo, m) = (at.p, at.n, at.wo, at.m);
        let (d, pdf) = es.sample((st.rng.next_f32(), st.rng.next_f32()));
        let cos = Some(n.dot(d)).filter(|&c| c > 0.0)?;
        let tr = self.transmittance(l, p, d, f32::INFINITY, st)?;
        let w = power(pdf, m.pdf(n, wo, d));
        let le = l.input(self.scene.environment.radiance(d));
        Some(m.eval(l, n, wo, d) * tr * le * (cos * w / pdf))
    }

    /// Material sampling: the emitters the sampled direction meets (MIS-weighted against light
    /// and environment sampling), or one indirect bounce off another prop.
    fn material_strategy<L: Lanes>(
        &self,
        l: &L,
        at: &PropPoint,
        depth: u32,
        bounces: u32,
        st: &mut PathState,
    ) -> Option<L::C> {
        let (p, n, wo, m) = (at.p, at.n, at.wo, at.m);
        let lights = &self.scene.staging.lights;
        let u = (st.rng.next_f32(), st.rng.next_f32(), st.rng.next_f32());
        let wi = m.sample(n, wo, u)?;
        let pdf = m.pdf(n, wo, wi);
        if pdf <= 0.0 {
            return None;
        }
        let ray = Ray { origin: p, dir: wi };
        let props = &self.scene.staging.props;
        st.rays += 1;
        let prop = if props.is_empty() {
            None
        } else {
            props.intersect(&ray, 0.0, f32::INFINITY)
        };
        let t_prop = prop.as_ref().map_or(f32::INFINITY, |h| h.t);
        let light = if lights.is_empty() {
            None
        } else {
            nearest(lights, &ray, 0.0, t_prop)
        };
        let t_end = light.map_or(t_prop, |x| x.1);
        let tr = self.film_transmittance(l, &ray, t_end, st)?;
        let incoming = match (light, prop) {
            (Some((i, t, front)), _) => {
                let w = if self.settings.next_event {
                    power(pdf, lights[i].pdf_li(p, wi, t) / lights.len() as f32)
                } else {
                    1.0
                };
                lights[i].le(l, front) * w
            }
            (None, Some(h)) if bounces > 0 => {
                self.shade_prop(l, &ray, &h, depth + 1, bounces - 1, st)
            }
            (None, Some(_)) => L::C::splat(0.0),
            (None, None) => {
                let w = self.env.as_ref().map_or(1.0, |es| power(pdf, es.pdf(wi)));
                l.input(self.scene.environment.radiance(wi)) * w
            }
        };
        Some(m.eval(l, n, wo, wi) * tr * incoming * (n.dot(wi) / pdf))
    }

    /// What passes from `p` along `dir` up to `t_max`: `None` if a prop or light blocks it,
    /// else the product of the crossed films' transmittances.
    fn transmittance<L: Lanes>(
        &self,
        l: &L,
        p: Vec3,
        dir: Vec3,
        t_max: f32,
        st: &mut PathState,
    ) -> Option<L::C> {
        let ray = Ray { origin: p, dir };
        let staging = &self.scene.staging;
        st.rays += 1;
        if staging.props.occluded(&ray, 0.0, t_max)
            || nearest(&staging.lights, &ray, 0.0, t_max).is_some()
        {
            return None;
        }
        self.film_transmittance(l, &ray, t_max, st)
    }

    /// Product of `T = 1 − R` over the film crossings along `ray` before `t_max`, times the
    /// liquid's Fresnel transmittance there ([`Tracer::liquid_transmittance`]); `None` once it
    /// falls below the branch threshold.
    fn film_transmittance<L: Lanes>(
        &self,
        l: &L,
        ray: &Ray,
        t_max: f32,
        st: &mut PathState,
    ) -> Option<L::C> {
        st.rays += u64::from(!self.scene.staging.liquid.is_empty());
        let mut tr = L::C::splat(self.liquid_transmittance(ray, t_max)?);
        let mut t = 0.0;
        for _ in 0..self.settings.max_depth {
            st.rays += 1;
            match self.scene.geometry.intersect(ray, t, t_max) {
                None => return Some(tr),
                Some(h) => {
                    let cos = ray.dir.dot(h.normal).abs().min(1.0);
                    tr = tr * (L::C::splat(1.0) - l.film_reflectance(cos, h.thickness_nm));
                    if tr.max_channel() < self.settings.min_weight {
                        return None;
                    }
                    t = h.t_exit + self.scene.epsilon;
                }
            }
        }
        Some(tr)
    }
}
