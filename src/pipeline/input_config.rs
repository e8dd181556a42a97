//! `[input]` (and `film.thickness_unit`), checked without reading a particle: part of
//! [`super::RenderConfig`], so a bad input key is refused before any file is read. The files
//! themselves are read (and their contents checked) when the particles are loaded
//! (`pipeline/load.rs`).

use super::liquid_mode::{self, LiquidMode};
use super::melp_sets::MelpSet;
use super::sample_check::check_sample_params;
use crate::geometry::LiquidField;
use crate::io::ReadOptions;
use crate::samples::{SampleKind, SampleParams};
use crate::scene::{InputDesc, SceneDesc};
use crate::{Error, Result};

/// `[input]`, checked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputConfig {
    /// How 3D particles packed into bodies of liquid are drawn.
    pub liquid: LiquidMode,
    /// How rays find a liquid body's surface.
    pub liquid_field: LiquidField,
    /// Particles come from the scene's `[input]` (`false`: a cloud given in memory replaces
    /// it, and only `input.liquid` and `input.repair` apply).
    pub from_input: bool,
}

/// Checks `desc`'s `[input]` as the loader will read it: one of a file or a sample, a known
/// sample with sound parameters, a known thickness unit and MELP set, a known liquid mode.
/// With `given_cloud` (the Python API's cloud in memory) only the liquid mode is checked.
///
/// # Errors
/// [`Error::Invalid`] naming the key, with the loader's own message.
pub fn input(desc: &SceneDesc, given_cloud: bool) -> Result<InputConfig> {
    let liquid = liquid_mode::mode(desc)?;
    let liquid_field = liquid_mode::field(desc)?;
    if !given_cloud {
        particles(desc)?;
    }
    Ok(InputConfig {
        liquid,
        liquid_field,
        from_input: !given_cloud,
    })
}

/// What the loader checks before it reads: the same conditions, the same messages.
fn particles(desc: &SceneDesc) -> Result<()> {
    let input = &desc.input;
    match (&input.cloud, &input.sample) {
        (Some(_), Some(_)) => {
            return Err(Error::invalid(
                "input: give either cloud or sample, not both",
            ));
        }
        (None, Some(_)) if input.clouds.is_some() => {
            return Err(Error::invalid(
                "input: give either clouds or sample, not both",
            ));
        }
        (_, Some(name)) => {
            sample_kind(name)?;
            return check_sample_params(&sample_params(input), input.sparse, "input.");
        }
        (None, None) if input.paths().is_empty() => {
            return Err(Error::invalid(
                "input: no particles given (set input.cloud or input.sample)",
            ));
        }
        _ => {}
    }
    read_options(desc)?;
    MelpSet::parse(input.melp_set.as_deref())?;
    Ok(())
}

/// The sample `input.sample` names.
pub(super) fn sample_kind(name: &str) -> Result<SampleKind> {
    SampleKind::from_name(name).map_err(|e| Error::invalid(format!("input.sample: {e}")))
}

/// A sample's parameters: `[input]`'s, the defaults where unset (checked by
/// [`check_sample_params`]).
pub(super) fn sample_params(input: &InputDesc) -> SampleParams {
    let mut p = SampleParams::default();
    if let Some(n) = input.particles {
        p.particles = n;
    }
    if let Some(s) = input.sample_seed {
        p.seed = s;
    }
    if let Some(t) = input.time {
        p.time = t;
    }
    p
}

/// How the scene's input files are read: attribute names and the thickness unit (without an
/// explicit unit each format's own applies: m for the simulators' files, nm else).
pub(super) fn read_options(desc: &SceneDesc) -> Result<ReadOptions> {
    let input = &desc.input;
    ReadOptions {
        thickness_attr: input.thickness_attr.clone(),
        normal_attr: input.normal_attr.clone(),
        radius_attr: input.radius_attr.clone(),
        ..ReadOptions::default()
    }
    .with_unit(desc.film.thickness_unit.as_deref())
}
