//! Scene files: the serde description of a render (TOML). Pure data; [`crate::pipeline`] turns
//! it into a rendered image. Every key is optional except the input; unknown keys are errors.
//! Paths are relative to the scene file. The keys are documented in `samples/README.md`.

mod check;
mod keys;

pub use check::key_line;
pub use keys::{CameraKey, check_keys};

use serde::Deserialize;
use std::path::PathBuf;
use toml::Spanned;

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
    /// `[[light]]`: area lights.
    #[serde(default)]
    pub light: Vec<LightDesc>,
    /// `[[prop]]`: opaque props.
    #[serde(default)]
    pub prop: Vec<PropDesc>,
    /// The file this description was parsed from (its name and text), so later errors about a
    /// key can name the file and line ([`SceneDesc::locate`]); `None` when built in code.
    #[serde(skip)]
    pub source: Option<(String, String)>,
}

/// `[[light]]`: one area light. Which keys apply depends on `shape`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightDesc {
    /// "rect", "disk" or "sphere" ("point" and "directional" are refused: a film cannot show
    /// them).
    pub shape: Spanned<String>,
    /// Centre, scene units.
    pub position: [f32; 3],
    /// Point the rect/disk faces (default: the scene's centre); or give `normal`.
    pub look_at: Option<[f32; 3]>,
    /// Direction the rect/disk emits toward (instead of `look_at`).
    pub normal: Option<[f32; 3]>,
    /// Rect width and height, scene units.
    pub size: Option<[f32; 2]>,
    /// Up hint orienting a rect's height (default +y).
    pub up: Option<[f32; 3]>,
    /// Disk or sphere radius, scene units.
    pub radius: Option<f32>,
    /// Emitted radiance, linear sRGB per channel (W·sr⁻¹·m⁻² in scene units).
    pub radiance: Option<[f32; 3]>,
    /// Luminance in cd/m² (nits), instead of `radiance`: 100 nits = radiance 1.
    pub luminance: Option<f32>,
    /// Colour of a `luminance` light (scaled to luminance 1; default white).
    pub colour: Option<[f32; 3]>,
    /// Black-body colour temperature, kelvin, for a `luminance` light instead of `colour`:
    /// spectral shading then carries the Planck spectrum itself.
    pub temperature: Option<f32>,
    /// Line of the `shape` key (filled in by the parser).
    #[serde(skip)]
    pub line: usize,
}

/// `[[prop]]`: one opaque prop. Which keys apply depends on `shape`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PropDesc {
    /// "plane", "sphere", "box", "cylinder", "torus" or "mesh".
    pub shape: Spanned<String>,
    /// Plane: a point on it; sphere, box, torus: centre; cylinder: centre of its base; mesh:
    /// offset added to its vertices.
    pub position: [f32; 3],
    /// Mesh: Wavefront OBJ file, relative to the scene file.
    pub file: Option<PathBuf>,
    /// Mesh: factor on its vertices (before the offset), default 1.
    pub scale: Option<f32>,
    /// Plane normal (default +y).
    pub normal: Option<[f32; 3]>,
    /// Sphere and cylinder radius; torus ring radius.
    pub radius: Option<f32>,
    /// Torus tube radius.
    pub minor_radius: Option<f32>,
    /// Box edge lengths (axis-aligned).
    pub size: Option<[f32; 3]>,
    /// Cylinder and torus axis (default +y).
    pub axis: Option<[f32; 3]>,
    /// Cylinder length along its axis.
    pub height: Option<f32>,
    /// "diffuse" (default), "glossy" or "metal".
    pub material: Option<String>,
    /// Albedo (diffuse, glossy) or normal-incidence reflectance (metal), linear sRGB 0..1
    /// (default 0.8 grey).
    pub colour: Option<[f32; 3]>,
    /// Roughness 0..1 of glossy and metal (default 0.3; metal 0 is a mirror).
    pub roughness: Option<f32>,
    /// Line of the `shape` key (filled in by the parser).
    #[serde(skip)]
    pub line: usize,
}

/// `[input]`: a particle file, or a built-in sample generator.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputDesc {
    /// Particle file (any readable format, or a simulator's frame folder), relative to the
    /// scene file.
    pub cloud: Option<PathBuf>,
    /// Several particle inputs rendered together in one scene (a foam's bubbles, a film and
    /// its droplets), each read with its own attributes; with or instead of `cloud`. Frame
    /// patterns (`{:04}`) work in every entry.
    pub clouds: Option<Vec<PathBuf>>,
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
    /// How 3D particles packed into bodies of liquid are drawn: "auto" (the default: where
    /// they came from decides), "surface" (a water surface through them) or "droplets" (every
    /// 3D particle a droplet).
    pub liquid: Option<String>,
    /// How rays find a liquid body's surface: "grid" (the default: the field sampled once on a
    /// grid of 3 cells a spacing, within 0.03 spacings of the exact surface) or "exact" (the
    /// field summed over the particles at every step: slower).
    pub liquid_field: Option<String>,
    /// Which set of a MELP frame is drawn when its Eulerian (`e_`) and Lagrangian (`l_`) files
    /// are both given: "lagrangian" (default), "eulerian" or "both".
    pub melp_set: Option<String>,
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
    /// "disk", "sphere" or "mls" (default "disk"; see `geometry::Primitive`).
    pub primitive: Option<String>,
    /// Factor on every splat radius (estimated or from the file), default 1.
    pub radius_scale: Option<f32>,
    /// Curvature-aware disks: each disk's normal tilts across it with the film's local curvature
    /// (estimated from neighbours), so curved films have no faceted, orange-peel reflections
    /// (default: true, except with the `preview` preset; costs one neighbour search, ~0.6 s per
    /// million particles on two cores).
    pub curvature: Option<bool>,
    /// Fit disk and MLS radii to the sampling: grow them where disks would leave a pinhole
    /// between neighbouring particles, trim them at open edges (rims, holes, rupture fronts) so
    /// they end about half a spacing past the last particles. Spheres keep their size. `true`
    /// or "auto" (the default): only where the fit run on a sample of the particles changes
    /// something; "always": every cloud; `false` or "never": radii as read or estimated. Costs
    /// one 12-neighbour search (shared with the disks' first-order detail) and a fan a particle.
    pub fit_radii: Option<FitRadiiKey>,
    /// Blend overlapping disks of one film layer into one crossing (default true). Off shows
    /// what unblended splats look like: the film applied once per disk, colours jumping at rims.
    pub blend: Option<bool>,
}

/// `film.fit_radii`: a flag (`true`: "auto", `false`: "never") or a name.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize)]
#[serde(untagged)]
pub enum FitRadiiKey {
    /// `true` or `false`.
    Flag(bool),
    /// "auto", "always" or "never".
    Name(String),
}

/// `[camera]`: either explicit (`position` and `look_at`) or auto-framed from `from`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
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
    /// Thin-lens aperture radius, scene units (default 0: pinhole, all sharp).
    pub aperture: Option<f32>,
    /// Distance in focus, scene units (default: the distance to `look_at` or the cloud's
    /// centre).
    pub focus_distance: Option<f32>,
    /// Degrees the camera turns about `up` over a sequence, around its look-at point: frame i
    /// of N is turned by orbit·i/N (so 360 loops without a repeated frame). Default 0.
    pub orbit: Option<f32>,
    /// `[[camera.key]]`: a sequence's camera path, in increasing frame order (see
    /// [`CameraKey`]).
    #[serde(default)]
    pub key: Vec<CameraKey>,
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
    /// Degrees the light is turned about +y with an orbiting camera (a turntable's frame: see
    /// [`crate::render::Environment::turn`]); set by a sequence, not a scene-file key.
    #[serde(skip)]
    pub turn_deg: f32,
}

/// `[render]`: sampling and shading.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RenderDesc {
    /// "preview", "balanced" (default) or "final": fills spp, max_depth, min_weight, roulette,
    /// shading and wavelengths where they are not set.
    pub preset: Option<String>,
    /// Image width, pixels (default 960).
    pub width: Option<usize>,
    /// Image height, pixels (default 540).
    pub height: Option<usize>,
    /// Samples per pixel (default: from the preset, 4 for balanced).
    pub spp: Option<u32>,
    /// Most film crossings along a path (default: from the preset, 12 for balanced).
    pub max_depth: Option<u32>,
    /// Branch weight below which a path escapes to the environment (default: from the preset,
    /// 1e-3 for balanced).
    pub min_weight: Option<f32>,
    /// Russian roulette below this branch weight, 0..1 (default from the preset: 0.1 for
    /// spheres at balanced and final, otherwise 0 = off, every branch above `min_weight` is
    /// followed). Fewer rays, some noise; pays for spheres.
    pub roulette: Option<f32>,
    /// Random seed (default 0).
    pub seed: Option<u64>,
    /// "lut" (default), "rgb" or "spectral".
    pub shading: Option<String>,
    /// Light samples per prop hit (default 1).
    pub light_samples: Option<u32>,
    /// Indirect bounces between props (default 1).
    pub prop_bounces: Option<u32>,
    /// Wavelengths per sample for "rgb" shading (default 16).
    pub wavelengths: Option<usize>,
    /// "jittered" (default), "stratified" or "hero".
    pub strategy: Option<String>,
    /// What to show: "shaded" (default), "thickness", "normal", "depth", "particle-id",
    /// "coverage", or "attribute:NAME" (a stored per-particle attribute; vectors by magnitude).
    pub view: Option<String>,
    /// Values at the ends of the colour bar of an `attribute:NAME` view (default: the range of
    /// what is visible).
    pub view_range: Option<[f32; 2]>,
    /// Motion blur: the fraction of a frame the shutter is open, 0..=1 (default 0, off),
    /// centred on the frame's time; particles move along their stored velocity.
    pub shutter: Option<f32>,
    /// Simulation seconds between two frames (the simulators do not store it); required with
    /// a shutter.
    pub frame_time: Option<f32>,
    /// Time slices the open shutter is rendered as (1..=256, default 8; never more than the
    /// samples per pixel).
    pub shutter_slices: Option<u32>,
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
    /// White balance: colour temperature of the light to neutralise, kelvin (6504 = none).
    pub white_balance: Option<f32>,
    /// White balance as per-channel gains (instead of or after the temperature).
    pub gains: Option<[f32; 3]>,
    /// Contrast around middle grey (1 = unchanged).
    pub contrast: Option<f32>,
    /// Saturation (1 = unchanged, 0 = grey).
    pub saturation: Option<f32>,
}

impl SceneDesc {
    /// Uses the settings preset `name` (checked where the description is resolved): it
    /// replaces the sampling keys it fills (spp, max_depth, min_weight, roulette, shading,
    /// wavelengths), as `render --preset` does; keys set after this still win.
    pub fn set_preset(&mut self, name: &str) {
        let r = &mut self.render;
        (r.spp, r.max_depth, r.min_weight, r.shading, r.wavelengths) =
            (None, None, None, None, None);
        r.roulette = None;
        r.preset = Some(name.to_string());
    }

    /// Parses TOML text; `name` (the file) is used in error messages, which name the key and
    /// line.
    pub fn from_toml(text: &str, name: &str) -> crate::Result<Self> {
        // Line of a byte offset by binary search over the newlines: O(log n) per key, so a file
        // with many [[light]]s or [[prop]]s stays linear.
        let newlines: Vec<usize> = text.match_indices('\n').map(|(i, _)| i).collect();
        let line_of = |start: usize| newlines.partition_point(|&i| i < start) + 1;
        let mut desc: SceneDesc = toml::from_str(text).map_err(|e| {
            let msg = e.message().to_string();
            let line = e.span().map(|s| line_of(s.start));
            crate::Error::Format {
                path: name.into(),
                format: "scene TOML",
                message: match line {
                    Some(l) => format!("line {l}: {msg}"),
                    None => msg,
                },
            }
        })?;
        let table: toml::Table =
            text.parse()
                .map_err(|e: toml::de::Error| crate::Error::Format {
                    path: name.into(),
                    format: "scene TOML",
                    message: e.message().to_string(),
                })?;
        if let Some((key, v)) = check::bad_float(&table) {
            let keys: Vec<&str> = key.iter().map(String::as_str).collect();
            let at = key_line(text, &keys).map_or(String::new(), |l| format!("line {l}: "));
            return Err(crate::Error::Format {
                path: name.into(),
                format: "scene TOML",
                message: format!(
                    "{at}{} = {v} must be a finite number within the 32-bit float range",
                    key.join(".")
                ),
            });
        }
        desc.source = Some((name.to_string(), text.to_string()));
        for l in &mut desc.light {
            l.line = line_of(l.shape.span().start);
        }
        for p in &mut desc.prop {
            p.line = line_of(p.shape.span().start);
        }
        keys::number_lines(&mut desc.camera.key, text);
        check_keys(&desc.camera.key).map_err(|m| crate::Error::Format {
            path: name.into(),
            format: "scene TOML",
            message: m,
        })?;
        Ok(desc)
    }
}

impl SceneDesc {
    /// Names the scene file (and the line of the key the message starts with, e.g.
    /// `camera.fov must be ...`) in an [`crate::Error::Invalid`] about this description; other
    /// errors, and descriptions not parsed from a file, pass through unchanged.
    pub fn locate(&self, e: crate::Error) -> crate::Error {
        let (Some((name, text)), crate::Error::Invalid(msg)) = (&self.source, &e) else {
            return e;
        };
        let first = msg
            .split(|c: char| c.is_whitespace() || c == ':' || c == ',')
            .next()
            .unwrap_or("");
        // A message that starts with a path is about another file (the particles), named already.
        if first.contains(['/', '\\']) || std::path::Path::new(first).exists() {
            return e;
        }
        const SECTIONS: [&str; 8] = [
            "input",
            "film",
            "camera",
            "environment",
            "render",
            "output",
            "light",
            "prop",
        ];
        let keys: Vec<&str> = first.split('.').collect();
        let at = (keys.len() >= 2 && SECTIONS.contains(&keys[0]))
            .then(|| key_line(text, &keys))
            .flatten()
            .map_or(String::new(), |l| format!("line {l}: "));
        crate::Error::Format {
            path: name.into(),
            format: "scene TOML",
            message: format!("{at}{msg}"),
        }
    }
}

impl InputDesc {
    /// Every particle input: `cloud`, then the `clouds` list.
    pub fn paths(&self) -> Vec<&PathBuf> {
        self.cloud
            .iter()
            .chain(self.clouds.iter().flatten())
            .collect()
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
        let s = SceneDesc::from_toml(
            "[input]\nsample = \"bubble\"\n\n[[light]]\nshape = \"disk\"\nposition = [0, 1, 0]\n\n[[prop]]\nshape = \"plane\"\nposition = [0, 0, 0]\n",
            "d.toml",
        )
        .unwrap();
        assert_eq!((s.light[0].line, s.prop[0].line), (5, 9));
        let e = SceneDesc::from_toml(
            "[[prop]]\nshape = \"box\"\nposition = [0, 0, 0]\nsizes = [1, 1, 1]\n",
            "e.toml",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("line 4") && e.contains("sizes"), "{e}");
    }
}
