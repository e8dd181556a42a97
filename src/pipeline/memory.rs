//! Peak memory of a render, estimated before anything is loaded, so a render can refuse
//! (`--max-memory`) instead of being killed by the operating system.
//!
//! The per-particle and per-pixel figures are the sizes of the arrays the pipeline holds at its
//! peak, checked against measured peak resident memory (`/usr/bin/time -v`, bubble sample,
//! disks with curvature): 100 k → 1 M particles added 229 B/particle with normals and radii in
//! the file and 252 B/particle with positions only (normals and radii estimated); a 1920x1080
//! render added 66 B/pixel writing PNG and 123 B/pixel writing PNG and EXR.

use std::fmt;
use std::path::Path;

use crate::io::peek_count;
use crate::scene::SceneDesc;
use crate::{Error, Result};

/// Particle arrays of the cloud: position, normal (3 × f32 each), thickness, radius (f32),
/// and the copy of positions, normals and own radii the prepared scene keeps for the render
/// summary's pinhole figure (28 B, `pipeline::pinholes::FilmData`, up to its cap).
pub const CLOUD_BYTES_PER_PARTICLE: u64 = 32 + 28;
/// Neighbour search: the k-d tree (~24 B) plus the 12-nearest table (index u32 + distance f32
/// per neighbour), shared by the normal/radius estimate and the curvature detail.
pub const NEIGHBOUR_BYTES_PER_PARTICLE: u64 = 24 + 12 * 8;
/// Geometry: disk and BVH (~62 B, [`crate::geometry::DiskGeometry::memory_bytes`]), first-order
/// detail (curvature + thickness gradient, 16 B), scaled and sorted radii and the curvature and
/// gradient arrays before they are moved in (~28 B).
pub const GEOMETRY_BYTES_PER_PARTICLE: u64 = 62 + 16 + 28;
/// Render buffers per pixel: RGB, normal (3 × f32 each), alpha, depth, thickness, hit count,
/// droplet coverage (44 B), and the camera rays' raster of the disks at one sample a pixel
/// (16 B per disk–tile pair: measured 0.7 B/pixel at 800x600 with 2000 disks each covering
/// many tiles, `tests/memory_measured.rs`; 2 here).
pub const RENDER_BYTES_PER_PIXEL: u64 = 44 + 2;
/// Writing a PNG: the linear copy, the graded copy, the tone-mapped image and the encoder
/// (measured by `tests/memory_measured.rs` at 800x600, render and PNG together: 92.3 B/pixel
/// of heap once the process's one-time state is built, so 49 here with the render's 44).
pub const PNG_BYTES_PER_PIXEL: u64 = 49;
/// Writing an EXR: the layer copies and the encoder's buffers (measured, rounded up).
pub const EXR_BYTES_PER_PIXEL: u64 = 96;
/// Motion blur, per particle and time slice: each slice's disks and BVH, all alive while the
/// shot renders (measured by `tests/memory_measured.rs`: 8 slices of 10 000 disks added
/// 7.17 MB at the peak, ~80 B a particle and slice with the one-off part below; rounded up).
pub const MOTION_BYTES_PER_PARTICLE_SLICE: u64 = 90;
/// Motion blur, per particle once: the velocities (12 B), the disks' detail kept for the slices
/// (16 B) and one slice's moved copy of the cloud while it is built (32 B).
pub const MOTION_BYTES_PER_PARTICLE: u64 = 12 + 16 + 32;
/// Fixed cost: program, colour tables, thread stacks (measured ~4 MiB, rounded up).
pub const FIXED_BYTES: u64 = 8 << 20;

/// An estimate of a render's peak memory, split by what holds it. All sizes in bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemoryEstimate {
    /// Particles the estimate is for.
    pub particles: u64,
    /// True if the particle count is the file header's (or the sample's), false if estimated
    /// from the file size.
    pub exact_count: bool,
    /// The cloud's arrays.
    pub cloud: u64,
    /// The file's bytes held while a reader parses it (0 for streamed PLY).
    pub file: u64,
    /// Neighbour search for estimates and curvature.
    pub neighbours: u64,
    /// Disks or spheres, BVH, per-disk detail.
    pub geometry: u64,
    /// Image buffers: render output plus writing the outputs.
    pub image: u64,
    /// Motion blur: the time slices' geometries and the slices' sum of render buffers (0 with
    /// the shutter closed).
    pub motion: u64,
    /// Program and tables.
    pub fixed: u64,
}

impl MemoryEstimate {
    /// The estimate for `particles` particles rendered at `width`×`height`, `exr` if an EXR is
    /// written, `file` bytes held while reading.
    pub fn new(particles: u64, width: usize, height: usize, exr: bool, file: u64) -> Self {
        let pixels = width as u64 * height as u64;
        let per_pixel = RENDER_BYTES_PER_PIXEL
            + PNG_BYTES_PER_PIXEL
            + if exr { EXR_BYTES_PER_PIXEL } else { 0 };
        MemoryEstimate {
            particles,
            exact_count: true,
            cloud: particles.saturating_mul(CLOUD_BYTES_PER_PARTICLE),
            file,
            neighbours: particles.saturating_mul(NEIGHBOUR_BYTES_PER_PARTICLE),
            geometry: particles.saturating_mul(GEOMETRY_BYTES_PER_PARTICLE),
            image: pixels.saturating_mul(per_pixel),
            motion: 0,
            fixed: FIXED_BYTES,
        }
    }

    /// The estimate with motion blur's `slices` time slices (0: none) at `pixels` pixels:
    /// [`MOTION_BYTES_PER_PARTICLE_SLICE`] a particle and slice, [`MOTION_BYTES_PER_PARTICLE`]
    /// a particle, and one more set of render buffers (the slices' sum).
    pub fn with_motion(mut self, slices: u64, pixels: u64) -> Self {
        self.motion = match slices {
            0 => 0,
            k => (self.particles)
                .saturating_mul(MOTION_BYTES_PER_PARTICLE_SLICE.saturating_mul(k))
                .saturating_add(self.particles.saturating_mul(MOTION_BYTES_PER_PARTICLE))
                .saturating_add(pixels.saturating_mul(RENDER_BYTES_PER_PIXEL)),
        };
        self
    }

    /// Estimated peak, bytes.
    pub fn total(&self) -> u64 {
        [
            self.cloud,
            self.file,
            self.neighbours,
            self.geometry,
            self.image,
            self.motion,
            self.fixed,
        ]
        .iter()
        .fold(0u64, |a, b| a.saturating_add(*b))
    }
}

impl fmt::Display for MemoryEstimate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} for {}{} particles (cloud {}, file {}, neighbours {}, geometry {}, image {}",
            human_bytes(self.total()),
            if self.exact_count { "" } else { "~" },
            self.particles,
            human_bytes(self.cloud),
            human_bytes(self.file),
            human_bytes(self.neighbours),
            human_bytes(self.geometry),
            human_bytes(self.image),
        )?;
        if self.motion > 0 {
            write!(f, ", motion-blur slices {}", human_bytes(self.motion))?;
        }
        write!(f, ")")
    }
}

pub use crate::budget::{human_bytes, parse_size};

/// Estimates the peak memory of rendering `desc` (paths relative to `base`) before loading
/// anything: the particle count comes from the sample's settings or the file's header
/// ([`peek_count`]); `exr` says an EXR output is written.
///
/// # Errors
/// As [`peek_count`] for an unreadable or unrecognised input file; [`Error::Invalid`] if the
/// scene names no particles.
pub fn estimate_scene(desc: &SceneDesc, base: &Path, exr: bool) -> Result<MemoryEstimate> {
    let (width, height) = super::image_size::image_size(desc);
    let slices = motion_slices(desc);
    let pixels = width as u64 * height as u64;
    estimate_particles(desc, base, exr, (width, height)).map(|e| e.with_motion(slices, pixels))
}

/// The time slices an open shutter renders (0 when closed): `render.shutter_slices` (default
/// 8), never more than the samples per pixel.
fn motion_slices(desc: &SceneDesc) -> u64 {
    let r = &desc.render;
    if r.shutter.unwrap_or(0.0) <= 0.0 {
        return 0;
    }
    let slices = r.shutter_slices.unwrap_or(super::shutter::DEFAULT_SLICES);
    u64::from(slices.min(r.spp.unwrap_or(u32::MAX)).max(1))
}

/// [`estimate_scene`] without motion blur.
fn estimate_particles(
    desc: &SceneDesc,
    base: &Path,
    exr: bool,
    (width, height): (usize, usize),
) -> Result<MemoryEstimate> {
    let paths = desc.input.paths();
    if !paths.is_empty() {
        let (mut particles, mut file, mut exact) = (0u64, 0u64, true);
        for path in paths {
            let hint = peek_count(&base.join(path))?;
            particles = particles.saturating_add(hint.particles);
            if hint.reads_whole_file {
                file = file.max(hint.file_bytes);
            }
            exact &= hint.exact;
        }
        let mut e = MemoryEstimate::new(particles, width, height, exr, file);
        e.exact_count = exact;
        return Ok(e);
    }
    match &desc.input.sample {
        Some(_) => {
            let n = desc
                .input
                .particles
                .unwrap_or(crate::samples::BubbleParams::default().particles);
            // A count the sample refuses is the pipeline's to report (with its line).
            let p = crate::samples::SampleParams {
                particles: n,
                ..Default::default()
            };
            super::sample_check::check_sample_params(&p, None, "input.")?;
            Ok(MemoryEstimate::new(n as u64, width, height, exr, 0))
        }
        None => Err(Error::invalid(
            "input: no particles given (set input.cloud, input.clouds or input.sample)",
        )),
    }
}

pub use crate::budget::{available_memory, parse_meminfo};

/// Where a memory limit comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Limit {
    /// Set by the user (`--max-memory`), bytes.
    Explicit(u64),
    /// The memory available to this process ([`available_memory`]: `MemAvailable`, lowered to
    /// its cgroups' limits), bytes.
    Available(u64),
}

impl Limit {
    /// The user's limit if given, else the machine's available memory, else none.
    pub fn new(explicit: Option<u64>) -> Option<Limit> {
        explicit
            .map(Limit::Explicit)
            .or_else(|| available_memory().map(Limit::Available))
    }

    /// The limit, bytes.
    pub fn bytes(self) -> u64 {
        match self {
            Limit::Explicit(b) | Limit::Available(b) => b,
        }
    }

    /// Refuses `estimate` if it exceeds the limit: a message saying by how much and what to do.
    pub fn check(self, estimate: &MemoryEstimate) -> std::result::Result<(), String> {
        if estimate.total() <= self.bytes() {
            return Ok(());
        }
        Err(match self {
            Limit::Explicit(b) => format!(
                "estimated peak memory {estimate} exceeds --max-memory {}",
                human_bytes(b)
            ),
            Limit::Available(b) => format!(
                "estimated peak memory {estimate} exceeds the machine's available memory {} \
                 (MemAvailable, lowered to the cgroup's memory limit if any); render fewer \
                 particles or pixels, or set --max-memory to try anyway",
                human_bytes(b)
            ),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse() {
        assert_eq!(parse_size("8G").unwrap(), 8 << 30);
        assert_eq!(parse_size("512M").unwrap(), 512 << 20);
        assert_eq!(parse_size("512mib").unwrap(), 512 << 20);
        assert_eq!(parse_size("1.5K").unwrap(), 1536);
        assert_eq!(parse_size("1000").unwrap(), 1000);
        for bad in ["", "G", "8X", "-1G", "0", "1e400"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
        assert_eq!(human_bytes(800), "800 B");
        assert_eq!(human_bytes(3 << 29), "1.5 GiB");
    }

    #[test]
    fn estimate_adds_up_and_matches_the_measured_rate() {
        let small = MemoryEstimate::new(100_000, 64, 48, false, 0);
        let big = MemoryEstimate::new(1_000_000, 64, 48, false, 0);
        let per_particle = (big.total() - small.total()) as f64 / 900_000.0;
        // Measured: 229..252 B/particle; the estimate must not be below the measurement.
        assert!((252.0..300.0).contains(&per_particle), "{per_particle}");
        let png = MemoryEstimate::new(0, 1920, 1080, false, 0).image as f64 / (1920.0 * 1080.0);
        let exr = MemoryEstimate::new(0, 1920, 1080, true, 0).image as f64 / (1920.0 * 1080.0);
        assert!(png >= 66.0 && exr >= 123.0, "{png} {exr}");
        let absurd = MemoryEstimate::new(u64::MAX, 32_768, 32_768, true, u64::MAX);
        assert_eq!(absurd.total(), u64::MAX);
    }

    #[test]
    fn meminfo_parses_and_limits_refuse_what_exceeds_them() {
        let e = MemoryEstimate::new(1_000_000, 64, 48, false, 0);
        assert!(Limit::Available(e.total()).check(&e).is_ok());
        let msg = Limit::Available(e.total() - 1).check(&e).unwrap_err();
        assert!(
            msg.contains("available memory") && msg.contains("--max-memory"),
            "{msg}"
        );
        let msg = Limit::Explicit(1 << 20).check(&e).unwrap_err();
        assert!(msg.contains("exceeds --max-memory 1.0 MiB"), "{msg}");
        assert_eq!(Limit::new(Some(7)), Some(Limit::Explicit(7)));
        // On Linux the default is the memory available to this process, the allowance's.
        if let Some(m) = available_memory() {
            assert!(m > 0);
            assert!(matches!(Limit::new(None), Some(Limit::Available(_))));
        }
    }
}
