//! Thin-film optics: reflectance and transmittance of one lossless film between two half-spaces
//! of air, for s, p and unpolarised light.
//!
//! This layer takes plain numbers (cosines, indices, thicknesses in nm, wavelengths in nm) and
//! never sees rays or spectra.
//!
//! Two paths compute the same physics:
//! * [`airy`]: the f64 reference — complex Fresnel amplitude coefficients at both faces and the
//!   Airy sum of all internal reflections. Exact; used by `filmsplat film` and by tests.
//! * [`fast`]: the renderer's path — f32, the Fresnel terms computed once per hit
//!   ([`FilmFresnel`]), then any number of wavelengths evaluated by a branch-free loop that the
//!   compiler vectorises. Agrees with the reference to 2e-4 in R away from grazing
//!   (cos θ ≥ 0.05) and to 2e-4 in integrated colour at every angle: near grazing, Airy
//!   resonances become narrower than the f32 phase resolves.
//!
//! [`interface`] is one smooth air–water surface (the droplets of a ruptured film): the
//! unpolarised Fresnel reflectance and Snell's law.
//!
//! A film is symmetric (air on both sides), so a hit from the back face has the same R and T as
//! from the front: callers pass `|cos θ|`.

pub mod airy;
pub mod fast;
pub mod interface;
mod validate;

pub use airy::{FilmRT, film_rt};
pub use fast::FilmFresnel;
pub use validate::{MAX_THICKNESS_NM, check_film_params};
