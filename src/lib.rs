//! filmsplat: spectral thin-film rendering of SPH particle clouds, straight from the particles.
//!
//! A soap film's colours come from thin-film interference. filmsplat ray-traces the particles of a
//! thin-film simulation directly (as oriented disks, spheres or a moving-least-squares surface)
//! and shades each film crossing with the exact Airy reflectance of the particle's thickness.
//!
//! # Stages and who may import whom
//! Data flows one way; a module imports only modules listed before it:
//!
//! | module | what | imports |
//! |---|---|---|
//! | [`optics`] | thin-film Fresnel/Airy reflectance, plain numbers | — |
//! | [`scene`] | the scene-file description (TOML), pure data | — |
//! | [`image`] | pixel buffers, grading, tone mapping, PNG/EXR, text, metrics (PSNR, SSIM, ΔE) | — |
//! | [`spectrum`] | CIE tables, sampled wavelengths, colour, film colour | `optics` |
//! | [`pointcloud`] | the particle cloud (and triangle meshes) and its validation/estimation | — |
//! | [`io`] | readers (PLY, ...) filling a [`pointcloud::PointCloud`] | `pointcloud` |
//! | [`geometry`] | disks, spheres, MLS surfaces, triangle meshes, prop shapes, BVH, ray queries | — |
//! | [`samples`] | synthetic thin-film clouds: the scene gallery (bubble, catenoid, films, drip, ...) sharing one thickness field | `pointcloud` |
//! | [`figure`] | the interference chart and annotated figures | `spectrum`, `image` |
//! | [`render`] | camera, environment, area lights, materials, presets, the ray-tree integrator (RGB and spectral) | `geometry`, `spectrum`, `optics`, `image` |
//! | [`pipeline`] | scene description → particles → geometry → image files | all above |
//! | [`view`] | `filmsplat view`: the interactive preview in the browser (HTTP server, page, frame cache) | `pipeline` and all below it |
//! | [`cli`] | command-line front end | all |
//!
//! [`error`], [`atomic`] (all-or-nothing file output) and [`mix`] (the SplitMix64 mix) are shared
//! utilities any stage may use.
#![warn(missing_docs)]

pub mod atomic;
pub mod budget;
pub mod cli;
pub mod error;
pub mod figure;
pub mod geometry;
pub mod image;
pub mod io;
pub mod mix;
pub mod optics;
pub mod pipeline;
pub mod pointcloud;
pub mod prefetch;
pub mod render;
pub mod samples;
pub mod scene;
pub mod spectrum;
pub mod view;

pub use error::{Error, Result};
