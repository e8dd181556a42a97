//! The generated samples' parameters, checked where they enter (scene file or command line).

use crate::samples::SampleParams;
use crate::{Error, Result};

/// Checks a sample's parameters (`prefix` names where they came from: "input." in scene
/// files, "--" on the command line): particles in 1..=50 000 000, a finite time, a sparse
/// fraction in (0, 1].
pub fn check_sample_params(p: &SampleParams, sparse: Option<f64>, prefix: &str) -> Result<()> {
    if p.particles == 0 || p.particles > 50_000_000 {
        return Err(Error::invalid(format!(
            "{prefix}particles must be 1..=50000000, got {}",
            p.particles
        )));
    }
    // The generated cloud's arrays (positions, normals, thickness, radius) and the generator's
    // scratch: ~64 bytes a particle.
    crate::budget::check(p.particles as u64 * 64, || {
        format!("{prefix}particles = {}", p.particles)
    })
    .map_err(Error::invalid)?;
    if !p.time.is_finite() {
        return Err(Error::invalid(format!("{prefix}time must be finite")));
    }
    if let Some(f) = sparse
        && !(f > 0.0 && f <= 1.0)
    {
        return Err(Error::invalid(format!(
            "{prefix}sparse must be a fraction in (0, 1], got {f}"
        )));
    }
    Ok(())
}
