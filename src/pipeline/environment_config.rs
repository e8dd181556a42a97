//! `[environment]`, checked: the light around the scene (a map's file is read when the scene
//! is built).

use crate::scene::EnvironmentDesc;
use crate::{Error, Result};
use glam::Vec3;
use std::path::{Path, PathBuf};

/// `[environment]`, checked (a map's file is read when the scene is built).
#[derive(Debug, Clone, PartialEq)]
pub enum EnvironmentConfig {
    /// The built-in studio, its radiance times `intensity`.
    Studio {
        /// Multiplier on the studio's radiance.
        intensity: f32,
    },
    /// One radiance (linear RGB, intensity applied) from every direction.
    Uniform(Vec3),
    /// A lat-long EXR panorama.
    Map {
        /// The EXR file, resolved against the scene's folder.
        path: PathBuf,
        /// Rotation about +y, degrees.
        rotation_deg: f32,
        /// Multiplier on the map's radiance.
        intensity: f32,
    },
}

/// `v` as a vector, if finite; else an error naming `key`.
pub(crate) fn vec3(v: [f32; 3], key: &str) -> Result<Vec3> {
    let v = Vec3::from(v);
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Error::invalid(format!("{key} must be finite")))
    }
}

/// `[environment]`: studio (default), uniform, or a map (the default when one is named).
pub(super) fn environment(e: &EnvironmentDesc, base: &Path) -> Result<EnvironmentConfig> {
    let intensity = e.intensity.unwrap_or(1.0);
    if !(intensity.is_finite() && intensity >= 0.0) {
        return Err(Error::invalid(format!(
            "environment.intensity must be >= 0, got {intensity}"
        )));
    }
    let default = if e.map.is_some() { "map" } else { "studio" };
    match e.kind.as_deref().unwrap_or(default) {
        "studio" => Ok(EnvironmentConfig::Studio { intensity }),
        "uniform" => Ok(EnvironmentConfig::Uniform(
            vec3(e.colour.unwrap_or([1.0; 3]), "environment.colour")? * intensity,
        )),
        "map" => {
            let path = e.map.as_ref().ok_or_else(|| {
                Error::invalid("environment.kind = \"map\" needs environment.map")
            })?;
            Ok(EnvironmentConfig::Map {
                path: base.join(path),
                rotation_deg: e.rotation.unwrap_or(0.0),
                intensity,
            })
        }
        other => Err(Error::invalid(format!(
            "environment.kind: unknown '{other}' (expected studio, uniform or map)"
        ))),
    }
}
