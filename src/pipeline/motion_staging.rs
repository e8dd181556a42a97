//! Motion blur's staging: each time slice of an open shutter (see [`super::motion`]) gets the
//! scene's lights and props with its droplets and its liquid surface moved by velocity × the
//! slice's time, as the films are. A droplet set without a velocity stays where the frame holds
//! it, said in a note.
//!
//! Costs per slice: the droplets' sphere tree and the liquid surface's BVH, built again from
//! the moved centres (O(n log n) each; the liquid's spacing is the unmoved one's).

use super::build;
use super::motion::{MotionSlice, moved, stored_velocities};
use crate::Result;
use crate::geometry::LiquidSurface;
use crate::pointcloud::PointCloud;
use crate::render::Staging;
use glam::Vec3;

/// What moves besides the films.
pub(super) struct Moving<'a> {
    /// The clouds drawn as droplets (one per droplet part).
    pub kept: &'a [PointCloud],
    /// The droplet parts as read, before the liquid was split off.
    pub drops: &'a [PointCloud],
    /// The liquid surface's particles: indices into `drops`' particles taken in order.
    pub liquid: &'a [usize],
}

/// Gives each slice `staging` with the droplets of `moving.kept` and the liquid surface of
/// `moving.liquid` moved to the slice's time; slices stay without a staging of their own (the
/// scene's) when neither exists.
///
/// # Errors
/// [`crate::Error::Invalid`] for a non-finite droplet velocity (set and particle named); as
/// [`crate::geometry::Droplets::build`] and [`LiquidSurface::build`].
pub(super) fn move_staging(
    slices: &mut [MotionSlice],
    moving: &Moving,
    staging: &Staging,
    notes: &mut Vec<String>,
) -> Result<()> {
    if slices.is_empty() {
        return Ok(());
    }
    let droplet_v = part_velocities(moving.kept, "droplets", notes)?;
    let liquid = if staging.liquid.is_empty() {
        None
    } else {
        Some(liquid_particles(moving, notes)?)
    };
    if moving.kept.is_empty() && liquid.is_none() {
        return Ok(());
    }
    for slice in slices {
        let t = slice.time_s;
        let droplets = if moving.kept.is_empty() {
            staging.droplets.clone()
        } else {
            let clouds: Vec<PointCloud> = (moving.kept.iter().zip(&droplet_v))
                .map(|(cloud, v)| moved(cloud, v, t))
                .collect();
            build::droplets(&clouds)?
        };
        let liquid = match &liquid {
            Some((p, v)) => {
                let at: Vec<Vec3> = p.iter().zip(v).map(|(p, v)| *p + *v * t).collect();
                LiquidSurface::build_with(&at, staging.liquid.spacing(), staging.liquid.field())?
            }
            None => staging.liquid.clone(),
        };
        slice.staging = Some(Staging {
            lights: staging.lights.clone(),
            props: staging.props.clone(),
            droplets,
            liquid,
        });
    }
    Ok(())
}

/// Each part's velocities (zero for a part without one, said in a note naming `what`).
fn part_velocities(
    parts: &[PointCloud],
    what: &str,
    notes: &mut Vec<String>,
) -> Result<Vec<Vec<Vec3>>> {
    let mut all = Vec::with_capacity(parts.len());
    for (i, cloud) in parts.iter().enumerate() {
        let v = stored_velocities(cloud, &format!("droplet set {}", i + 1))?;
        if v.is_none() && !cloud.is_empty() {
            notes.push(format!(
                "--shutter: droplet set {} holds no velocity: its {} {what} are drawn where \
                 the frame holds them",
                i + 1,
                cloud.len()
            ));
        }
        all.push(v.unwrap_or_else(|| vec![Vec3::ZERO; cloud.len()]));
    }
    Ok(all)
}

/// The liquid surface's particles: positions and velocities, in the surface's build order. A
/// droplet set of the liquid without a velocity stays, said in a note.
fn liquid_particles(moving: &Moving, notes: &mut Vec<String>) -> Result<(Vec<Vec3>, Vec<Vec3>)> {
    let (mut p, mut v) = (Vec::new(), Vec::new());
    let mut start = 0;
    for (i, d) in moving.drops.iter().enumerate() {
        let range = start..start + d.len();
        start = range.end;
        let held = moving.liquid.iter().filter(|i| range.contains(i)).count();
        let stored = match held {
            0 => None,
            _ => stored_velocities(d, &format!("droplet set {}", i + 1))?,
        };
        if held > 0 && stored.is_none() {
            notes.push(format!(
                "--shutter: droplet set {} holds no velocity: its {held} particles of the \
                 liquid surface are drawn where the frame holds them",
                i + 1
            ));
        }
        p.extend_from_slice(&d.positions);
        v.extend(stored.unwrap_or_else(|| vec![Vec3::ZERO; d.len()]));
    }
    Ok((
        moving.liquid.iter().map(|&i| p[i]).collect(),
        moving.liquid.iter().map(|&i| v[i]).collect(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cloud(x: &[f32], vx: Option<&[f32]>) -> PointCloud {
        let n = x.len();
        let mut extra = Vec::new();
        if let Some(vx) = vx {
            extra.push(("v_x".to_string(), vx.to_vec()));
            extra.push(("v_y".to_string(), vec![0.0; n]));
            extra.push(("v_z".to_string(), vec![0.5; n]));
        }
        PointCloud {
            positions: x.iter().map(|x| Vec3::new(*x, 0.0, 0.0)).collect(),
            normals: None,
            thickness_nm: None,
            radius: Some(vec![0.01; n]),
            extra,
        }
    }

    fn slice(time_s: f32) -> MotionSlice {
        let none = crate::geometry::SphereGeometry::build(&[], &[], &[], &[]).unwrap();
        MotionSlice {
            time_s,
            geometry: none.into(),
            staging: None,
        }
    }

    fn droplets_only(kept: &[PointCloud]) -> Moving<'_> {
        Moving {
            kept,
            drops: kept,
            liquid: &[],
        }
    }

    #[test]
    fn droplets_move_along_their_velocity_and_those_without_one_stay() {
        let kept = [cloud(&[0.0, 1.0], Some(&[2.0, -4.0])), cloud(&[5.0], None)];
        let mut slices = [slice(-0.25), slice(0.5)];
        let mut notes = Vec::new();
        let moving = droplets_only(&kept);
        move_staging(&mut slices, &moving, &Staging::default(), &mut notes).unwrap();
        for s in &slices {
            let d = &s.staging.as_ref().unwrap().droplets;
            let t = s.time_s;
            let want = [
                Vec3::new(2.0 * t, 0.0, 0.5 * t),
                Vec3::new(1.0 - 4.0 * t, 0.0, 0.5 * t),
                Vec3::new(5.0, 0.0, 0.0),
            ];
            for (i, w) in want.iter().enumerate() {
                let (c, r) = d.sphere(i as u32);
                assert!(
                    (c - *w).length() < 1e-6 && r == 0.01,
                    "t {t}: {i}: {c} not {w}"
                );
            }
        }
        assert!(
            notes
                .iter()
                .any(|n| n.contains("droplet set 2 holds no velocity"))
        );
        // A non-finite velocity is refused, naming the particle.
        let bad = [cloud(&[0.0, 1.0], Some(&[0.0, f32::NAN]))];
        let moving = droplets_only(&bad);
        let e = move_staging(&mut slices, &moving, &Staging::default(), &mut notes).unwrap_err();
        assert!(e.to_string().contains("particle 1"), "{e}");
    }

    #[test]
    fn the_liquid_surface_moves_with_its_particles() {
        // Set 1: one droplet; set 2: a 4 × 4 × 4 block of spacing 0.1 moving at v_x = 2,
        // v_z = 0.5, drawn as the liquid surface.
        let block: Vec<f32> = (0..64).map(|i| 0.1 * (i % 4) as f32).collect();
        let mut liquid_cloud = cloud(&block, Some(&[2.0; 64]));
        for (i, p) in liquid_cloud.positions.iter_mut().enumerate() {
            *p += Vec3::new(0.0, 0.1 * ((i / 4) % 4) as f32, 0.1 * (i / 16) as f32);
        }
        let drops = [cloud(&[9.0], None), liquid_cloud.clone()];
        let kept = [drops[0].clone(), PointCloud::default()];
        let index: Vec<usize> = (1..65).collect();
        let staging = Staging {
            liquid: LiquidSurface::build(&liquid_cloud.positions, 0.1).unwrap(),
            ..Staging::default()
        };
        let still = staging.liquid.bounds();
        let mut slices = [slice(-0.25), slice(0.5)];
        let mut notes = Vec::new();
        let moving = Moving {
            kept: &kept,
            drops: &drops,
            liquid: &index,
        };
        move_staging(&mut slices, &moving, &staging, &mut notes).unwrap();
        for s in &slices {
            let st = s.staging.as_ref().unwrap();
            let b = st.liquid.bounds();
            let shift = Vec3::new(2.0, 0.0, 0.5) * s.time_s;
            assert!(
                (b.min - still.min - shift).length() < 1e-5
                    && (b.max - still.max - shift).length() < 1e-5,
                "t {}: {b:?} not {still:?} + {shift}",
                s.time_s
            );
            assert_eq!(st.liquid.len(), 64);
            assert!((st.liquid.spacing() - 0.1).abs() < 1e-9);
            // The droplet set without a velocity stays.
            assert!((st.droplets.sphere(0).0 - Vec3::new(9.0, 0.0, 0.0)).length() < 1e-6);
        }
        // The droplet set stays, said once; the liquid's set has its velocity: no note for it.
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(notes[0].contains("droplet set 1"), "{notes:?}");
    }
}
