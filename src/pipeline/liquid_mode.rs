//! How bulk liquid is drawn (`[input] liquid`, `--liquid`): the typed choice, checked in
//! [`super::input_config`] and used by [`super::liquid`].

use crate::geometry::LiquidField;
use crate::scene::SceneDesc;
use crate::{Error, Result};
use std::str::FromStr;

/// How bulk liquid is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LiquidMode {
    /// As `Surface` for the 3D particles of a thin-film SPH run present since its frame 0 (or
    /// when there is no frame 0 to ask); every 3D particle a droplet when the run's frame 0
    /// holds none (spray shed by a rupture). The default.
    #[default]
    Auto,
    /// Particles in liquid bodies as a water surface; the rest droplets.
    Surface,
    /// Every 3D particle a droplet.
    Droplets,
}

impl FromStr for LiquidMode {
    type Err = Error;

    /// Parses `"auto"`, `"surface"` or `"droplets"` (case-insensitive).
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "auto" => Ok(LiquidMode::Auto),
            "surface" => Ok(LiquidMode::Surface),
            "droplets" => Ok(LiquidMode::Droplets),
            _ => Err(Error::invalid(format!(
                "input.liquid: unknown value '{s}' (expected 'auto', 'surface' or 'droplets')"
            ))),
        }
    }
}

impl FromStr for LiquidField {
    type Err = Error;

    /// Parses `"grid"` or `"exact"` (case-insensitive): `[input] liquid_field`,
    /// `--liquid-field`.
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "grid" => Ok(LiquidField::Grid),
            "exact" => Ok(LiquidField::Exact),
            _ => Err(Error::invalid(format!(
                "input.liquid_field: unknown value '{s}' (expected 'grid' or 'exact')"
            ))),
        }
    }
}

/// The scene's choice of how rays find a liquid body's surface (`[input] liquid_field`,
/// default grid).
///
/// # Errors
/// An unknown value.
pub(super) fn field(desc: &SceneDesc) -> Result<LiquidField> {
    desc.input
        .liquid_field
        .as_deref()
        .map_or(Ok(LiquidField::Grid), str::parse)
}

/// The scene's liquid mode (`[input] liquid`, default auto).
///
/// # Errors
/// An unknown value.
pub(super) fn mode(desc: &SceneDesc) -> Result<LiquidMode> {
    desc.input
        .liquid
        .as_deref()
        .map_or(Ok(LiquidMode::Auto), str::parse)
}
