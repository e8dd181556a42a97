//! Scene files: the serde description of a render (TOML). Pure data; [`crate::pipeline`] turns
//! it into a rendered image. Every key is optional except the input; unknown keys are errors.
//! Paths are relative to the scene file. The keys are documented in `samples/README.md`.

use serde::Deserialize;
use std::path::PathBuf;

/// A whole scene file.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    /// Where the particles come from.
    #[serde(default)]
    pub input: InputDesc,
    /// The film's optics and the splats.
    #[serde(default)]
    pub film: FilmDesc,
    /// The camera (auto-framed when absent).
    #[serde(default)]
    pub camera: CameraDesc,
    /// The lighting.
    #[serde(default)]
    pub environment: EnvironmentDesc,
    /// Sampling and shading.
    #[serde(default)]
    pub render: RenderDesc,
    /// Output files and tone mapping.
    #[serde(default)]
    pub output: OutputDesc,
}

/// `[input]`: a particle file, or a built-in sample generator.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputDesc {
    /// Particle file (PLY), relative to the scene file.
    pub cloud: Option<PathBuf>,
    /// Built-in sample instead of a file: "bubble", "irregular-bubble", "catenoid",
    /// "half-bubble", "square-film", "circle-film", "drip" or "oscillating-bubble".
    pub sample: Option<String>,
    /// Particle count for a sample.
    pub particles: Option<usize>,
    /// Seed of a sample's random jitter.
    pub sample_seed: Option<u64>,
    /// Time of a sample's thickness animation, seconds.
    pub time: Option<f32>,
    /// Keep only this random fraction (0, 1] of a sample's particles (sparse-data tests).
    pub sparse: Option<f64>,
    /// Name of the thickness attribute in the file (default: rh, thickness, h).
    pub thickness_attr: Option<String>,
    /// Prefix of the normal attributes (default: n, normal, normals, N).
    pub normal_attr: Option<String>,
    /// Name of the radius attribute (default: radius, pscale).
    pub radius_attr: Option<String>,
    /// Drop particles with non-finite positions or bad thickness and re-estimate bad normals
    /// and radii, instead of refusing the file (default false).
    pub repair: Option<bool>,
}

/// `[film]`: optics and splat geometry.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FilmDesc {
    /// Film index of refraction (default 1.33).
    pub ior: Option<f32>,
    /// Unit of the file's thickness values: "nm", "um" or "m" (default "nm").
    pub thickness_unit: Option<String>,
    /// Extra factor on thickness after the unit conversion (default 1).
    pub thickness_scale: Option<f32>,
    /// Thickness for particles without one, nm (default 500).
    pub default_thickness_nm: Option<f32>,
    /// "disk" or "sphere" (default "disk").
    pub primitive: Option<String>,
    /// Factor on every splat radius (estimated or from the file), default 1.
    pub radius_scale: Option<f32>,
    /// Curvature-aware disks: each disk's normal tilts across it with the film's local curvature
    /// (estimated from neighbours), so curved films have no faceted, orange-peel reflections
    /// (default true; costs one neighbour search, ~1–2 s per million particles).
    pub curvature: Option<bool>,
    /// Blend overlapping disks of one film layer into one crossing (default true). Off shows
    /// what unblended splats look like: the film applied once per disk, colours jumping at rims.
    pub blend: Option<bool>,
}

/// `[camera]`: either explicit (`position` and `look_at`) or auto-framed from `from`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    /// Eye position, scene units.
    pub position: Option<[f32; 3]>,
    /// Point looked at (default: the cloud's centre).
    pub look_at: Option<[f32; 3]>,
    /// Up direction (default +y).
    pub up: Option<[f32; 3]>,
    /// Vertical field of view, degrees (default 40).
    pub fov: Option<f32>,
    /// Direction from the cloud toward the camera for auto-framing (default [0.35, 0.3, 1]).
    pub from: Option<[f32; 3]>,
}

/// `[environment]`: the light.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentDesc {
    /// "studio" (default), "uniform" or "map".
    pub kind: Option<String>,
    /// Radiance of a uniform environment (linear RGB, default [1, 1, 1]).
    pub colour: Option<[f32; 3]>,
    /// Lat-long EXR file for "map", relative to the scene file.
    pub map: Option<PathBuf>,
    /// Rotation of the map about +y, degrees.
    pub rotation: Option<f32>,
    /// Multiplier on the environment's radiance (default 1).
    pub intensity: Option<f32>,
}

/// `[render]`: sampling and shading.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RenderDesc {
    /// Image width, pixels (default 960).
    pub width: Option<usize>,
    /// Image height, pixels (default 540).
    pub height: Option<usize>,
    /// Samples per pixel (default 4).
    pub spp: Option<u32>,
    /// Most film crossings along a path (default 12).
    pub max_depth: Option<u32>,
    /// Branch weight below which a path escapes to the environment (default 1e-3).
    pub min_weight: Option<f32>,
    /// Random seed (default 0).
    pub seed: Option<u64>,
    /// "lut" (default) or "rgb".
    pub shading: Option<String>,
    /// Wavelengths per sample for "rgb" shading (default 16).
    pub wavelengths: Option<usize>,
    /// "jittered" (default), "stratified" or "hero".
    pub strategy: Option<String>,
    /// What to show: "shaded" (default), "thickness", "normal", "depth", "particle-id",
    /// "coverage".
    pub view: Option<String>,
}

/// `[output]`: files and tone mapping.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputDesc {
    /// Output image (.png or .exr), relative to the scene file.
    pub path: Option<PathBuf>,
    /// Exposure, EV (default 0).
    pub exposure: Option<f32>,
    /// "filmic" (default) or "clamp".
    pub tonemap: Option<String>,
}

impl SceneDesc {
    /// Parses TOML text; `name` (the file) is used in error messages, which name the key and
    /// line.
    pub fn from_toml(text: &str, name: &str) -> crate::Result<Self> {
        toml::from_str(text).map_err(|e| {
            let msg = e.message().to_string();
            let line = e
                .span()
                .map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1);
            crate::Error::Format {
                path: name.into(),
                format: "scene TOML",
                message: match line {
                    Some(l) => format!("line {l}: {msg}"),
                    None => msg,
                },
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_a_full_scene_and_rejects_unknown_keys_with_their_line() {
        let s = SceneDesc::from_toml(
            "[input]\nsample = \"bubble\"\n[film]\nior = 1.4\n[render]\nspp = 2\n",
            "a.toml",
        )
        .unwrap();
        assert_eq!(s.film.ior, Some(1.4));
        assert_eq!(s.render.spp, Some(2));
        let e = SceneDesc::from_toml(
            "[input]\nsample = \"bubble\"\n\n[render]\nspps = 2\n",
            "b.toml",
        )
        .unwrap_err();
        let m = e.to_string();
        assert!(
            m.contains("b.toml") && m.contains("line 5") && m.contains("spps"),
            "{m}"
        );
        let e = SceneDesc::from_toml("[film]\nior = \"x\"\n", "c.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 2"), "{e}");
    }
}
