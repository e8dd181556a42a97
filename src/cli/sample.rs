//! `filmsplat sample`: write a built-in thin-film particle cloud.

use crate::io::{write_mesh_ply, write_ply};
use crate::samples::{BubbleParams, bubble, icosphere};
use crate::{Error, Result};
use clap::{Args, ValueEnum};
use std::io::Write;
use std::path::PathBuf;

/// The sample generators.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum SampleName {
    /// A soap bubble: a sphere of particles with a draining, swirling thickness field.
    Bubble,
    /// The bubble's analytic surface as a triangle mesh (subdivided icosahedron about the
    /// origin, radius --radius, outward normals, no thickness), to compare against with
    /// `compare ... mesh:FILE`.
    BubbleMesh,
}

/// Arguments of `filmsplat sample`.
#[derive(Debug, Args)]
pub struct SampleArgs {
    /// Which sample.
    name: SampleName,
    /// Output PLY (binary little-endian, with x y z nx ny nz rh radius; rh in nm).
    #[arg(short, long)]
    output: PathBuf,
    /// Number of particles.
    #[arg(long, default_value_t = 200_000)]
    particles: usize,
    /// Seed of the particle jitter.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Radius of bubble-mesh, scene units (the bubble sample's is 1).
    #[arg(long, default_value_t = 1.0)]
    radius: f32,
    /// Subdivisions of the icosahedron for bubble-mesh (20·4^N triangles, 0..=9).
    #[arg(long, default_value_t = 5)]
    subdivisions: u32,
    /// Time of the thickness animation, seconds.
    #[arg(long, default_value_t = 0.0)]
    time: f32,
}

/// Runs `filmsplat sample`.
pub fn run(a: &SampleArgs, out: &mut dyn Write) -> Result<()> {
    if a.particles == 0 || a.particles > 50_000_000 {
        return Err(Error::invalid(format!(
            "sample: --particles must be 1..=50000000, got {}",
            a.particles
        )));
    }
    if !a.time.is_finite() {
        return Err(Error::invalid("sample: --time must be finite"));
    }
    let cloud = match a.name {
        SampleName::Bubble => bubble(&BubbleParams {
            particles: a.particles,
            seed: a.seed,
            time: a.time,
            ..BubbleParams::default()
        }),
        SampleName::BubbleMesh => {
            if a.subdivisions > 9 {
                return Err(Error::invalid(format!(
                    "sample: --subdivisions must be 0..=9, got {}",
                    a.subdivisions
                )));
            }
            if !(a.radius > 0.0 && a.radius.is_finite()) {
                return Err(Error::invalid(format!(
                    "sample: --radius must be > 0, got {}",
                    a.radius
                )));
            }
            let mesh = icosphere(a.radius, a.subdivisions);
            write_mesh_ply(&a.output, &mesh)?;
            let _ = writeln!(
                out,
                "wrote {} triangles to {}",
                mesh.len(),
                a.output.display()
            );
            return Ok(());
        }
    };
    write_ply(&a.output, &cloud)?;
    let _ = writeln!(
        out,
        "wrote {} particles to {}",
        cloud.len(),
        a.output.display()
    );
    Ok(())
}
