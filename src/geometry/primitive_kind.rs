//! [`Primitive`]: how particles are drawn, and every choice that depends on it. Each choice is
//! a method with an exhaustive `match` (no `_ =>`), so a new primitive is one enum arm and
//! the compiler points to each choice it must make.

use std::fmt;
use std::str::FromStr;

/// How particles are drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Primitive {
    /// An oriented disk (surfel) through the particle centre, perpendicular to its normal.
    #[default]
    Disk,
    /// A sphere around the particle centre (normals are not needed).
    Sphere,
    /// The smooth moving-least-squares surface the particles sample (see
    /// [`super::MlsSurface`]); needs normals.
    Mls,
}

impl Primitive {
    /// Every primitive, in the order the viewer and help texts list them.
    pub const ALL: [Primitive; 3] = [Primitive::Disk, Primitive::Sphere, Primitive::Mls];

    /// Its name in scene files, flags, the viewer and Python: `disk`, `sphere`, `mls`.
    pub const fn name(self) -> &'static str {
        match self {
            Primitive::Disk => "disk",
            Primitive::Sphere => "sphere",
            Primitive::Mls => "mls",
        }
    }

    /// Factor on radii estimated from the particle spacing. Estimated radii make disks (and
    /// MLS supports) overlap into a closed film; spheres drawn as particles get half of that,
    /// so each particle stays visible as its own ball. Radii given in the file are kept.
    pub fn estimated_radius_scale(self) -> f32 {
        match self {
            Primitive::Disk | Primitive::Mls => 1.0,
            Primitive::Sphere => 0.5,
        }
    }

    /// Whether radii are fitted to the sampling by default (grown over pinholes, cut at open
    /// edges): disks and MLS; a sphere keeps its size.
    pub fn fits_radii(self) -> bool {
        match self {
            Primitive::Disk | Primitive::Mls => true,
            Primitive::Sphere => false,
        }
    }

    /// Whether it takes first-order detail (curvature and thickness gradient across a splat):
    /// disks only (a sphere has no tangent plane to tilt; the MLS surface is curved itself).
    pub fn takes_first_order_detail(self) -> bool {
        match self {
            Primitive::Disk => true,
            Primitive::Sphere | Primitive::Mls => false,
        }
    }

    /// The Russian-roulette threshold of the presets that use roulette (`balanced`, `final`).
    /// Spheres: 0.1 — every sphere is its own film crossing, the ray tree of a sample grows to
    /// ~13 rays, and roulette cuts them 4× for a little noise (on the front: 16 spp with
    /// roulette beat 4 spp without, at equal time). Disks and MLS: 0 — their tree is short and
    /// noise-free, and roulette only added noise for the time it saved.
    pub fn roulette(self) -> f32 {
        match self {
            Primitive::Sphere => 0.1,
            Primitive::Disk | Primitive::Mls => 0.0,
        }
    }

    /// Distance past a film crossing before the next one is looked for, scene units, from the
    /// splats' median radius and the scene's self-intersection `epsilon`: half a radius for
    /// disks (one blended layer), `epsilon` for spheres (the far side is another crossing), a
    /// twentieth of a radius for MLS (a crossing is refined to 1e-3 radii).
    pub fn layer_skip(self, median_radius: f32, epsilon: f32) -> f32 {
        match self {
            Primitive::Disk => 0.5 * median_radius,
            Primitive::Sphere => epsilon,
            Primitive::Mls => 0.05 * median_radius,
        }
    }
}

impl FromStr for Primitive {
    type Err = crate::Error;

    /// Parses `"disk"`, `"sphere"` or `"mls"` (case-insensitive).
    fn from_str(s: &str) -> crate::Result<Self> {
        let name = s.trim().to_ascii_lowercase();
        Primitive::ALL
            .into_iter()
            .find(|p| p.name() == name)
            .ok_or_else(|| {
                crate::Error::invalid(format!(
                    "unknown primitive '{s}' (expected 'disk', 'sphere' or 'mls')"
                ))
            })
    }
}

impl fmt::Display for Primitive {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_primitive_round_trips_through_its_name() {
        for p in Primitive::ALL {
            assert_eq!(p.name().parse::<Primitive>().unwrap(), p);
            assert_eq!(p.to_string(), p.name());
        }
        let names: std::collections::BTreeSet<_> = Primitive::ALL.map(Primitive::name).into();
        assert_eq!(names.len(), Primitive::ALL.len(), "names are distinct");
        assert_eq!("Sphere".parse::<Primitive>().unwrap(), Primitive::Sphere);
        assert_eq!(" MLS ".parse::<Primitive>().unwrap(), Primitive::Mls);
        assert!("cube".parse::<Primitive>().is_err());
        assert_eq!(Primitive::default(), Primitive::Disk);
    }
}
