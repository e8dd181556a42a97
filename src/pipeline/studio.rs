//! Staging: the checked lights and props ([`super::lights_props`]) placed in the loaded scene.
//! A mesh prop's file is read ([`props`], before any particle); lights facing the scene's
//! centre by default are turned toward it and the props get the scene's epsilon
//! ([`staging`], after loading). Errors name the entry and its line.

use super::lights_props::{Facing, LightConfig, LightShapeConfig, PropConfig, PropShapeConfig};
use crate::Result;
use crate::geometry::{Mesh, Shape};
use crate::io::{ReadOptions, read_mesh};
use crate::render::{AreaLight, LightShape, Prop, Props, Staging};
use glam::Vec3;
use std::sync::Arc;

/// The props of `config`, their mesh files read (the one step of the props that reads a
/// file; it needs nothing of the loaded scene).
///
/// # Errors
/// [`crate::Error::Invalid`] naming the prop, its line and the mesh file's problem.
pub fn props(config: &[PropConfig]) -> Result<Vec<Prop>> {
    config
        .iter()
        .map(|p| {
            let shape = match &p.shape {
                PropShapeConfig::Shape(s) => s.clone(),
                PropShapeConfig::Mesh {
                    file,
                    scale,
                    position,
                } => mesh(p, file, *scale, *position)?,
            };
            Ok(Prop {
                shape,
                material: p.material,
            })
        })
        .collect()
}

/// A mesh prop: its OBJ or PLY file's triangles, scaled, then moved to `position`.
fn mesh(p: &PropConfig, file: &std::path::Path, scale: f32, position: Vec3) -> Result<Shape> {
    // OBJ or PLY (faces), through the same readers as meshes compared with splats.
    let mesh = read_mesh(file, &ReadOptions::default()).map_err(|x| p.entry.err(x))?;
    let vertices: Vec<Vec3> = mesh
        .vertices
        .positions
        .iter()
        .map(|v| *v * scale + position)
        .collect();
    Ok(Shape::Mesh(Arc::new(
        Mesh::new(&vertices, &mesh.triangles).map_err(|x| p.entry.err(x))?,
    )))
}

/// The lights and props placed in the loaded scene: `centre` is what lights face by default,
/// `eps` the scene's self-intersection distance.
///
/// # Errors
/// [`crate::Error::Invalid`] for a light left facing nowhere: one without `normal` or
/// `look_at` placed at the scene's centre.
pub fn staging(
    lights: &[LightConfig],
    props: Vec<Prop>,
    centre: Vec3,
    eps: f32,
) -> Result<Staging> {
    let lights = lights
        .iter()
        .map(|l| light(l, centre).map(Into::into))
        .collect::<Result<Vec<_>>>()?;
    Ok(Staging {
        lights,
        props: Props::new(props, eps),
        droplets: Default::default(),
        liquid: Default::default(),
    })
}

fn light(l: &LightConfig, centre: Vec3) -> Result<AreaLight> {
    Ok(AreaLight {
        shape: light_shape(l, centre)?,
        radiance: l.radiance,
        blackbody: l.blackbody,
    })
}

/// The unit direction a flat light at `position` emits toward.
fn facing(l: &LightConfig, facing: Facing, position: Vec3, centre: Vec3) -> Result<Vec3> {
    let target = match facing {
        Facing::Normal(n) => return Ok(n),
        Facing::Toward(t) => t,
        Facing::SceneCentre => centre,
    };
    (target - position)
        .try_normalize()
        .ok_or_else(|| l.entry.err("look_at must differ from position"))
}

/// A light's shape in the scene.
fn light_shape(l: &LightConfig, centre: Vec3) -> Result<LightShape> {
    Ok(match l.shape {
        LightShapeConfig::Rect {
            centre: position,
            facing: f,
            up,
            size: [w, h],
        } => {
            let n = facing(l, f, position, centre)?;
            let (right, _) = crate::render::lights::frame(n);
            let right = up.cross(n).try_normalize().unwrap_or(right);
            let v_dir = n.cross(right);
            // u × v must point along n: (right × (n × right)) = n.
            LightShape::Rect {
                centre: position,
                u: right * (0.5 * w),
                v: v_dir * (0.5 * h),
            }
        }
        LightShapeConfig::Disk {
            centre: position,
            facing: f,
            radius,
        } => LightShape::Disk {
            centre: position,
            normal: facing(l, f, position, centre)?,
            radius,
        },
        LightShapeConfig::Sphere {
            centre: position,
            radius,
        } => LightShape::Sphere {
            centre: position,
            radius,
        },
    })
}
