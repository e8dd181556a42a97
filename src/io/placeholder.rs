//! The film a thin-film SPH run of bulk liquid alone stores in place of a film.
//!
//! The sph-thin-film code always carries a film solver; its liquid-only cases (in its
//! `FluidSPHBubbleDriver.cpp`, the rod that merges into droplets and the 3D surface-tension
//! test) give it one film particle far out of the scene, at (0, 10⁴, 0) with thickness 1 m,
//! and write it in every frame beside the 3D liquid. It is not a film: drawn, it would be a
//! 1 m-thick disk 10 km away that the camera frames and whose volume sizes the droplets.
//!
//! Told by its shape, not its numbers: the film part is a single particle and lies farther
//! from the 3D particles than [`FAR`] times their extent. Such a part is emptied and a note
//! says what was there, so nothing is dropped without a word.

use super::{CloudPart, PartKind};
use crate::pointcloud::PointCloud;
use glam::Vec3;

/// How many times the 3D particles' bounding-box diagonal a lone film particle lies from
/// their box before it is taken for the placeholder (the simulator's lies 10⁴ m from a
/// liquid a few centimetres wide: 10⁵ times).
pub const FAR: f32 = 100.0;

/// Empties a film part of `parts` that is the placeholder described in the module docs,
/// with a note naming the particle. Returns whether one was found.
pub fn drop_placeholder_film(parts: &mut [CloudPart]) -> bool {
    let Some(liquid) = liquid_box(parts) else {
        return false;
    };
    let mut found = false;
    for part in parts.iter_mut().filter(|p| p.kind == PartKind::Film) {
        let [p] = part.cloud.positions[..] else {
            continue;
        };
        if !liquid.is_far(p) {
            continue;
        }
        let thickness = part
            .cloud
            .thickness_nm
            .as_ref()
            .and_then(|t| t.first())
            .map(|t| format!(", stored thickness {:.3e} nm", t))
            .unwrap_or_default();
        part.notes.push(format!(
            "{}: its one particle, at ({}, {}, {}){thickness}, lies {:.0} m from the 3D liquid \
             (more than {FAR} times its size): the stand-in film the thin-film SPH code keeps \
             in a run of bulk liquid alone; no film is drawn",
            part.label,
            p.x,
            p.y,
            p.z,
            liquid.distance(p)
        ));
        part.cloud = PointCloud::default();
        found = true;
    }
    found
}

/// The bounding box of every droplet (3D) particle of `parts`, if there are any.
fn liquid_box(parts: &[CloudPart]) -> Option<Box3> {
    let mut points = parts
        .iter()
        .filter(|p| p.kind == PartKind::Droplets)
        .flat_map(|p| p.cloud.positions.iter().copied())
        .peekable();
    let first = *points.peek()?;
    let (lo, hi) = points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
    Some(Box3 { lo, hi })
}

/// An axis-aligned box.
struct Box3 {
    lo: Vec3,
    hi: Vec3,
}

impl Box3 {
    /// Distance from `p` to the box (0 inside).
    fn distance(&self, p: Vec3) -> f32 {
        (self.lo - p).max(p - self.hi).max(Vec3::ZERO).length()
    }

    /// Whether `p` lies farther than [`FAR`] times the box's diagonal from it (a box of one
    /// point counts as 1 mm wide).
    fn is_far(&self, p: Vec3) -> bool {
        let size = (self.hi - self.lo).length().max(1e-3);
        self.distance(p) > FAR * size
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn part(kind: PartKind, positions: Vec<Vec3>) -> CloudPart {
        CloudPart {
            label: format!("{kind}"),
            kind,
            cloud: PointCloud {
                positions,
                ..PointCloud::default()
            },
            stored: Vec::new(),
            notes: Vec::new(),
        }
    }

    fn liquid() -> CloudPart {
        let block = (0..27)
            .map(|i| Vec3::new((i % 3) as f32, (i / 3 % 3) as f32, (i / 9) as f32) * 0.005)
            .collect();
        part(PartKind::Droplets, block)
    }

    #[test]
    fn the_simulators_stand_in_is_emptied_with_a_note() {
        let mut parts = vec![
            part(PartKind::Film, vec![Vec3::new(0.0, 1e4, 0.0)]),
            liquid(),
        ];
        assert!(drop_placeholder_film(&mut parts));
        assert!(parts[0].cloud.is_empty());
        assert!(
            parts[0].notes[0].contains("(0, 10000, 0)"),
            "{:?}",
            parts[0].notes
        );
        assert_eq!(parts[1].cloud.len(), 27);
    }

    #[test]
    fn a_real_film_or_a_near_particle_stays() {
        // A lone film particle near the liquid (a burst film's last fragment) is film.
        let mut near = vec![
            part(PartKind::Film, vec![Vec3::new(0.0, 0.5, 0.0)]),
            liquid(),
        ];
        assert!(!drop_placeholder_film(&mut near));
        assert_eq!(near[0].cloud.len(), 1);
        // Two far particles are not the stand-in.
        let far = Vec3::new(0.0, 1e4, 0.0);
        let mut two = vec![part(PartKind::Film, vec![far, far + Vec3::X]), liquid()];
        assert!(!drop_placeholder_film(&mut two));
        // Without 3D particles there is nothing to be far from.
        let mut alone = vec![part(PartKind::Film, vec![far])];
        assert!(!drop_placeholder_film(&mut alone));
        assert_eq!(alone[0].cloud.len(), 1);
    }
}
