//! `[[light]]` and `[[prop]]` entries, checked: part of [`super::RenderConfig`], so a bad entry
//! is refused before any particle is read. Pure (reads no file); what depends on the loaded
//! scene (a light facing the scene's centre, a mesh prop's triangles, the props' epsilon) is
//! filled in when the scene is staged (`pipeline/studio.rs`). Errors name the entry, its line and
//! the key.

use crate::geometry::Shape;
use crate::render::Material;
use crate::scene::{LightDesc, PropDesc, SceneDesc};
use crate::spectrum::Blackbody;
use crate::{Error, Result};
use glam::Vec3;
use std::path::{Path, PathBuf};

/// Radiance of 1 in scene units corresponds to this luminance, cd/m² (a convention: display
/// white at 0 EV is 100 nits).
pub const NITS_PER_UNIT: f32 = 100.0;

/// Where a checked entry came from: its kind, 0-based index and scene-file line (for errors
/// raised when it is staged).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Entry {
    /// "light" or "prop".
    pub what: &'static str,
    /// Index among the entries of its kind.
    pub index: usize,
    /// Line of its `shape` key (0 when built in code).
    pub line: usize,
}

impl Entry {
    /// An error about this entry: `light 2 (line 14): msg`.
    pub fn err(&self, msg: impl std::fmt::Display) -> Error {
        Error::invalid(format!(
            "{} {} (line {}): {msg}",
            self.what,
            self.index + 1,
            self.line
        ))
    }
}

/// Which way a flat light emits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Facing {
    /// Along this unit direction (`normal`).
    Normal(Vec3),
    /// Toward this point (`look_at`, checked to differ from the light's position).
    Toward(Vec3),
    /// Toward the loaded scene's centre (the default, filled in when staged).
    SceneCentre,
}

/// A light's shape, checked; scene units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightShapeConfig {
    /// A rectangle of `size` (width, height, > 0) at `centre`, its height along `up`'s side.
    Rect {
        /// Centre.
        centre: Vec3,
        /// Emitting side.
        facing: Facing,
        /// Up hint (finite).
        up: Vec3,
        /// Width and height, > 0.
        size: [f32; 2],
    },
    /// A disk.
    Disk {
        /// Centre.
        centre: Vec3,
        /// Emitting side.
        facing: Facing,
        /// Radius, > 0.
        radius: f32,
    },
    /// A sphere.
    Sphere {
        /// Centre.
        centre: Vec3,
        /// Radius, > 0.
        radius: f32,
    },
}

/// A `[[light]]`, checked.
#[derive(Debug, Clone, PartialEq)]
pub struct LightConfig {
    /// Where it came from.
    pub entry: Entry,
    /// Its shape.
    pub shape: LightShapeConfig,
    /// Emitted radiance, linear sRGB (>= 0).
    pub radiance: Vec3,
    /// Its black-body spectrum, for a `temperature` light.
    pub blackbody: Option<Blackbody>,
}

/// A prop's shape, checked.
#[derive(Debug, Clone)]
pub enum PropShapeConfig {
    /// An analytic shape, complete.
    Shape(Shape),
    /// A mesh file (read when the scene is staged), its vertices times `scale`, then moved by
    /// `position`.
    Mesh {
        /// The OBJ or PLY file, resolved against the scene's folder.
        file: PathBuf,
        /// Factor on the vertices, > 0.
        scale: f32,
        /// Offset, scene units.
        position: Vec3,
    },
}

/// A `[[prop]]`, checked.
#[derive(Debug, Clone)]
pub struct PropConfig {
    /// Where it came from.
    pub entry: Entry,
    /// Its shape.
    pub shape: PropShapeConfig,
    /// Its material.
    pub material: Material,
}

fn finite(v: [f32; 3]) -> Option<Vec3> {
    let v = Vec3::from(v);
    v.is_finite().then_some(v)
}

fn unit(v: [f32; 3]) -> Option<Vec3> {
    finite(v)?.try_normalize()
}

fn positive(v: Option<f32>) -> Option<f32> {
    v.filter(|r| r.is_finite() && *r > 0.0)
}

/// The scene's `[[light]]`s, checked.
///
/// # Errors
/// [`Error::Invalid`] for the first bad entry, naming it, its line and the key.
pub fn lights(desc: &SceneDesc) -> Result<Vec<LightConfig>> {
    desc.light
        .iter()
        .enumerate()
        .map(|(i, l)| light(i, l))
        .collect()
}

/// The scene's `[[prop]]`s, checked; mesh files resolved against `base` (not read).
///
/// # Errors
/// [`Error::Invalid`] for the first bad entry, naming it, its line and the key.
pub fn props(desc: &SceneDesc, base: &Path) -> Result<Vec<PropConfig>> {
    desc.prop
        .iter()
        .enumerate()
        .map(|(i, p)| prop(i, p, base))
        .collect()
}

fn light(index: usize, l: &LightDesc) -> Result<LightConfig> {
    let entry = Entry {
        what: "light",
        index,
        line: l.line,
    };
    let e = |msg: String| entry.err(msg);
    let position = finite(l.position).ok_or_else(|| e("position must be finite".into()))?;
    let (radiance, blackbody) = light_radiance(l, &e)?;
    if radiance.min_element() < 0.0 {
        return Err(e(format!("radiance must be >= 0, got {radiance}")));
    }
    Ok(LightConfig {
        entry,
        shape: light_shape(l, position, &e)?,
        radiance,
        blackbody,
    })
}

/// A light's radiance (linear sRGB), from `radiance`, or from `luminance` with a `colour` or a
/// black-body `temperature` (then also its spectrum).
fn light_radiance(l: &LightDesc, e: &dyn Fn(String) -> Error) -> Result<(Vec3, Option<Blackbody>)> {
    if l.temperature.is_some() && (l.colour.is_some() || l.luminance.is_none()) {
        return Err(e(
            "temperature goes with luminance (nits) and replaces colour".into(),
        ));
    }
    match (l.radiance, l.luminance) {
        (Some(_), Some(_)) => Err(e("give radiance or luminance, not both".into())),
        (Some(r), None) => Ok((
            finite(r).ok_or_else(|| e("radiance must be finite".into()))?,
            None,
        )),
        (None, Some(nits)) if l.temperature.is_some() => {
            let k = l.temperature.unwrap_or_default();
            if !(k.is_finite() && (500.0..=50_000.0).contains(&k)) {
                return Err(e(format!("temperature must be 500..50000 K, got {k}")));
            }
            if !(nits.is_finite() && nits >= 0.0) {
                return Err(e(format!("luminance must be >= 0, got {nits}")));
            }
            let mut b = Blackbody::new(k);
            let y = nits / NITS_PER_UNIT;
            b.scale *= y;
            Ok((Vec3::from(b.rgb).max(Vec3::ZERO) * y, Some(b)))
        }
        (None, Some(nits)) => {
            let c = finite(l.colour.unwrap_or([1.0; 3]))
                .ok_or_else(|| e("colour must be finite".into()))?;
            let y = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
            if y <= 0.0 {
                return Err(e("colour must have a positive luminance".into()));
            }
            Ok((c / y * (nits / NITS_PER_UNIT), None))
        }
        (None, None) => Err(e("needs radiance = [r, g, b] or luminance (nits)".into())),
    }
}

/// A light's shape at `position`: a rect or disk facing its `normal` or `look_at` (default:
/// the scene's centre), or a sphere.
fn light_shape(
    l: &LightDesc,
    position: Vec3,
    e: &dyn Fn(String) -> Error,
) -> Result<LightShapeConfig> {
    let facing = || -> Result<Facing> {
        match (l.normal, l.look_at) {
            (Some(n), _) => unit(n)
                .map(Facing::Normal)
                .ok_or_else(|| e("normal must be a non-zero direction".into())),
            (None, Some(t)) => {
                let t = Vec3::from(t);
                (t - position)
                    .try_normalize()
                    .map(|_| Facing::Toward(t))
                    .ok_or_else(|| e("look_at must differ from position".into()))
            }
            (None, None) => Ok(Facing::SceneCentre),
        }
    };
    let radius = || positive(l.radius).ok_or_else(|| e("radius must be given and > 0".into()));
    match l.shape.get_ref().as_str() {
        "rect" | "rectangle" => {
            let facing = facing()?;
            let [w, h] = l
                .size
                .ok_or_else(|| e("size = [width, height] is required".into()))?;
            if !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0) {
                return Err(e(format!("size must be > 0, got [{w}, {h}]")));
            }
            let up = finite(l.up.unwrap_or([0.0, 1.0, 0.0]))
                .ok_or_else(|| e("up must be finite".into()))?;
            Ok(LightShapeConfig::Rect {
                centre: position,
                facing,
                up,
                size: [w, h],
            })
        }
        "disk" => Ok(LightShapeConfig::Disk {
            centre: position,
            facing: facing()?,
            radius: radius()?,
        }),
        "sphere" => Ok(LightShapeConfig::Sphere {
            centre: position,
            radius: radius()?,
        }),
        "point" | "directional" => Err(e(format!(
            "shape = \"{}\": a film is a perfect mirror and would never show a light without \
             area; use a small \"sphere\" (or \"disk\") instead",
            l.shape.get_ref()
        ))),
        other => Err(e(format!(
            "shape: unknown '{other}' (expected rect, disk or sphere)"
        ))),
    }
}

fn prop(index: usize, p: &PropDesc, base: &Path) -> Result<PropConfig> {
    let entry = Entry {
        what: "prop",
        index,
        line: p.line,
    };
    let e = |msg: String| entry.err(msg);
    let position = finite(p.position).ok_or_else(|| e("position must be finite".into()))?;
    let shape = prop_shape(p, position, base, &e)?;
    Ok(PropConfig {
        entry,
        shape,
        material: prop_material(p, &e)?,
    })
}

/// A prop's shape at `position`.
fn prop_shape(
    p: &PropDesc,
    position: Vec3,
    base: &Path,
    e: &dyn Fn(String) -> Error,
) -> Result<PropShapeConfig> {
    let axis = || {
        unit(p.axis.unwrap_or([0.0, 1.0, 0.0]))
            .ok_or_else(|| e("axis must be a non-zero direction".into()))
    };
    let radius = || positive(p.radius).ok_or_else(|| e("radius must be given and > 0".into()));
    let shape = match p.shape.get_ref().as_str() {
        "plane" => Shape::Plane {
            point: position,
            normal: unit(p.normal.unwrap_or([0.0, 1.0, 0.0]))
                .ok_or_else(|| e("normal must be a non-zero direction".into()))?,
        },
        "sphere" => Shape::Sphere {
            centre: position,
            radius: radius()?,
        },
        "box" => {
            let size = p
                .size
                .and_then(finite)
                .filter(|s| s.min_element() > 0.0)
                .ok_or_else(|| e("size = [x, y, z] must be given and > 0".into()))?;
            Shape::Box {
                centre: position,
                half: 0.5 * size,
            }
        }
        "cylinder" => Shape::Cylinder {
            base: position,
            axis: axis()?,
            height: positive(p.height).ok_or_else(|| e("height must be given and > 0".into()))?,
            radius: radius()?,
        },
        "torus" => {
            let major = radius()?;
            let minor = positive(p.minor_radius)
                .filter(|r| *r < major)
                .ok_or_else(|| e("minor_radius must be given, > 0 and < radius".into()))?;
            Shape::Torus {
                centre: position,
                axis: axis()?,
                major,
                minor,
            }
        }
        "mesh" => return mesh(p, position, base, e),
        other => {
            return Err(e(format!(
                "shape: unknown '{other}' (expected plane, sphere, box, cylinder, torus or mesh)"
            )));
        }
    };
    Ok(PropShapeConfig::Shape(shape))
}

/// A mesh prop: its file (not read here) and scale.
fn mesh(
    p: &PropDesc,
    position: Vec3,
    base: &Path,
    e: &dyn Fn(String) -> Error,
) -> Result<PropShapeConfig> {
    let file = p
        .file
        .as_ref()
        .ok_or_else(|| e("file = \"mesh.obj\" (or a PLY mesh) is required".into()))?;
    let scale = p.scale.unwrap_or(1.0);
    if !(scale.is_finite() && scale > 0.0) {
        return Err(e(format!("scale must be > 0, got {scale}")));
    }
    Ok(PropShapeConfig::Mesh {
        file: base.join(file),
        scale,
        position,
    })
}

/// A prop's material and its colour and roughness.
fn prop_material(p: &PropDesc, e: &dyn Fn(String) -> Error) -> Result<Material> {
    let colour = finite(p.colour.unwrap_or([0.8; 3]))
        .filter(|c| c.min_element() >= 0.0 && c.max_element() <= 1.0)
        .ok_or_else(|| e("colour must be in 0..1".into()))?;
    let roughness = p.roughness.unwrap_or(0.3);
    if !(0.0..=1.0).contains(&roughness) {
        return Err(e(format!("roughness must be in 0..1, got {roughness}")));
    }
    let material = match p.material.as_deref().unwrap_or("diffuse") {
        "diffuse" => Material::Diffuse { albedo: colour },
        "glossy" => Material::Glossy {
            albedo: colour,
            roughness,
        },
        "metal" => Material::Metal { colour, roughness },
        other => {
            return Err(e(format!(
                "material: unknown '{other}' (expected diffuse, glossy or metal)"
            )));
        }
    };
    Ok(material)
}
