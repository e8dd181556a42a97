//! Scene-file lights and props → the renderer's [`Staging`]. Errors name the entry, its
//! line and the key.

use crate::geometry::{Mesh, Shape};
use crate::io::{ReadOptions, read_mesh};
use crate::render::{AreaLight, LightShape, Material, Prop, Props, Staging};
use crate::scene::{LightDesc, PropDesc, SceneDesc};
use crate::spectrum::Blackbody;
use crate::{Error, Result};
use glam::Vec3;
use std::path::Path;
use std::sync::Arc;

/// Radiance of 1 in scene units corresponds to this luminance, cd/m² (a convention: display
/// white at 0 EV is 100 nits).
pub const NITS_PER_UNIT: f32 = 100.0;

fn err(what: &str, i: usize, line: usize, msg: impl std::fmt::Display) -> Error {
    Error::invalid(format!("{what} {} (line {line}): {msg}", i + 1))
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

/// Builds the lights and props of `desc`; `centre` is what lights face by default, `eps` the
/// scene's self-intersection distance.
pub fn staging(desc: &SceneDesc, base: &Path, centre: Vec3, eps: f32) -> Result<Staging> {
    let lights = desc
        .light
        .iter()
        .enumerate()
        .map(|(i, l)| light(i, l, centre).map(Into::into))
        .collect::<Result<Vec<_>>>()?;
    let props = desc
        .prop
        .iter()
        .enumerate()
        .map(|(i, p)| prop(i, p, base).map(|(shape, material)| Prop { shape, material }))
        .collect::<Result<Vec<_>>>()?;
    Ok(Staging {
        lights,
        props: Props::new(props, eps),
        droplets: Default::default(),
        liquid: Default::default(),
    })
}

fn light(i: usize, l: &LightDesc, centre: Vec3) -> Result<AreaLight> {
    let e = |msg: String| err("light", i, l.line, msg);
    let position = finite(l.position).ok_or_else(|| e("position must be finite".into()))?;
    let (radiance, blackbody) = light_radiance(l, &e)?;
    if radiance.min_element() < 0.0 {
        return Err(e(format!("radiance must be >= 0, got {radiance}")));
    }
    Ok(AreaLight {
        shape: light_shape(l, position, centre, &e)?,
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

/// A light's shape at `position`: a rect or disk facing its `normal` or `look_at` (default
/// `centre`), or a sphere.
fn light_shape(
    l: &LightDesc,
    position: Vec3,
    centre: Vec3,
    e: &dyn Fn(String) -> Error,
) -> Result<LightShape> {
    let facing = || -> Result<Vec3> {
        match (l.normal, l.look_at) {
            (Some(n), _) => unit(n).ok_or_else(|| e("normal must be a non-zero direction".into())),
            (None, target) => {
                let t = target.map(Vec3::from).unwrap_or(centre);
                (t - position)
                    .try_normalize()
                    .ok_or_else(|| e("look_at must differ from position".into()))
            }
        }
    };
    let radius = || positive(l.radius).ok_or_else(|| e("radius must be given and > 0".into()));
    match l.shape.get_ref().as_str() {
        "rect" | "rectangle" => {
            let n = facing()?;
            let [w, h] = l
                .size
                .ok_or_else(|| e("size = [width, height] is required".into()))?;
            if !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0) {
                return Err(e(format!("size must be > 0, got [{w}, {h}]")));
            }
            let up = finite(l.up.unwrap_or([0.0, 1.0, 0.0]))
                .ok_or_else(|| e("up must be finite".into()))?;
            let (right, _) = crate::render::lights::frame(n);
            let right = up.cross(n).try_normalize().unwrap_or(right);
            let v_dir = n.cross(right);
            // u × v must point along n: (right × (n × right)) = n.
            Ok(LightShape::Rect {
                centre: position,
                u: right * (0.5 * w),
                v: v_dir * (0.5 * h),
            })
        }
        "disk" => Ok(LightShape::Disk {
            centre: position,
            normal: facing()?,
            radius: radius()?,
        }),
        "sphere" => Ok(LightShape::Sphere {
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

fn prop(i: usize, p: &PropDesc, base: &Path) -> Result<(Shape, Material)> {
    let e = |msg: String| err("prop", i, p.line, msg);
    let position = finite(p.position).ok_or_else(|| e("position must be finite".into()))?;
    let shape = prop_shape(p, position, base, &e)?;
    Ok((shape, prop_material(p, &e)?))
}

/// A prop's shape at `position`.
fn prop_shape(
    p: &PropDesc,
    position: Vec3,
    base: &Path,
    e: &dyn Fn(String) -> Error,
) -> Result<Shape> {
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
        "mesh" => mesh(p, position, base, e)?,
        other => {
            return Err(e(format!(
                "shape: unknown '{other}' (expected plane, sphere, box, cylinder, torus or mesh)"
            )));
        }
    };
    Ok(shape)
}

/// A mesh prop: its OBJ or PLY file's triangles, scaled, then moved to `position`.
fn mesh(p: &PropDesc, position: Vec3, base: &Path, e: &dyn Fn(String) -> Error) -> Result<Shape> {
    let file = p
        .file
        .as_ref()
        .ok_or_else(|| e("file = \"mesh.obj\" (or a PLY mesh) is required".into()))?;
    let scale = p.scale.unwrap_or(1.0);
    if !(scale.is_finite() && scale > 0.0) {
        return Err(e(format!("scale must be > 0, got {scale}")));
    }
    // OBJ or PLY (faces), through the same readers as meshes compared with splats.
    let mesh =
        read_mesh(&base.join(file), &ReadOptions::default()).map_err(|x| e(x.to_string()))?;
    let vertices: Vec<Vec3> = mesh
        .vertices
        .positions
        .iter()
        .map(|v| *v * scale + position)
        .collect();
    Ok(Shape::Mesh(Arc::new(
        Mesh::new(&vertices, &mesh.triangles).map_err(|x| e(x.to_string()))?,
    )))
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
