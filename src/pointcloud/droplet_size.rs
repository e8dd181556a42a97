//! Droplet size: the radius of the water spheres a rupturing film sheds, from what the
//! simulator stored about their mass or volume.
//!
//! The thin-film SPH code turns a film particle into a 3D droplet of the same mass
//! (`FluidSPHBubble::Transform_3D_Particles` passes `particles.M(i)` to `Add_Particle`), and a
//! film particle's volume is `Vol = SA·H` (`Update_Particle_Heights`: `SA = Vol / density`,
//! `H = Vol / SA`), its mass over ρ = 1000 kg/m³. So a droplet is a sphere of volume
//! `m / ρ` — its own stored mass (a snapshot's `3d/m.bin`) where there is one, else a film
//! particle's `SA·H` (or `m / ρ`) of the same run. This file holds the arithmetic; which
//! frame of the run it is taken from is [`crate::pipeline`]'s business.

use super::PointCloud;
use glam::Vec3;

/// Density of water in kg/m³: the simulator's `rho` for films and droplets.
pub const WATER_DENSITY_KG_M3: f64 = 1000.0;

/// Radius (m) of a sphere of volume `v_m3` (m³).
pub fn volume_radius(v_m3: f64) -> f64 {
    (3.0 * v_m3 / (4.0 * std::f64::consts::PI)).cbrt()
}

/// The droplet radius when nothing stored gives a volume: half the droplets' median spacing
/// (1e-4 scene units if they have none). A guess, to be said so.
pub fn spacing_radius(droplets: &[Vec3]) -> f32 {
    let r = 0.5 * super::estimate::median_spacing(droplets);
    if r.is_finite() && r > 0.0 { r } else { 1e-4 }
}

/// Median of the finite positive values, if any.
fn median_positive(values: impl Iterator<Item = f64>) -> Option<f64> {
    let mut v: Vec<f64> = values.filter(|v| v.is_finite() && *v > 0.0).collect();
    if v.is_empty() {
        return None;
    }
    let mid = v.len() / 2;
    Some(*v.select_nth_unstable_by(mid, f64::total_cmp).1)
}

/// Where a particle volume was read from, for the user.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VolumeSource {
    /// The film particles' area times height, `SA·H` (`sa`, `h`).
    AreaTimesHeight,
    /// The particles' mass over water's density (`m`).
    Mass,
    /// The 3D (droplet) particles' own stored mass over water's density, where a run has
    /// no film to take a volume from.
    DropletMass,
}

impl std::fmt::Display for VolumeSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            VolumeSource::AreaTimesHeight => "SA·H",
            VolumeSource::Mass => "mass m / 1000 kg/m³",
            VolumeSource::DropletMass => "3D particles' median mass m / 1000 kg/m³",
        })
    }
}

/// The median particle volume (m³) of a film `cloud`: `SA·H` over the particles with both
/// attributes (`sa`, m²; `h`, m) and a positive finite product, else `m / ρ` (`m`, kg). `None`
/// if it stores neither (or no particle has a usable value). Cost: O(n).
pub fn film_particle_volume(cloud: &PointCloud) -> Option<(f64, VolumeSource)> {
    if let (Some(sa), Some(h)) = (cloud.extra("sa"), cloud.extra("h"))
        && let Some(v) =
            median_positive(sa.iter().zip(h).map(|(a, h)| f64::from(*a) * f64::from(*h)))
    {
        return Some((v, VolumeSource::AreaTimesHeight));
    }
    median_mass_volume(cloud).map(|v| (v, VolumeSource::Mass))
}

/// The median of the particles' stored mass `m` (kg) over water's density (m³); `None`
/// without masses or none positive.
fn median_mass_volume(cloud: &PointCloud) -> Option<f64> {
    let m = cloud.extra("m")?;
    median_positive(m.iter().map(|m| f64::from(*m) / WATER_DENSITY_KG_M3))
}

/// The median volume (m³) of droplets that store their own mass `m` (kg): m / ρ of water.
/// `None` without masses.
pub fn stored_droplet_volume(droplets: &PointCloud) -> Option<(f64, VolumeSource)> {
    median_mass_volume(droplets).map(|v| (v, VolumeSource::DropletMass))
}

/// Each droplet's radius (m) from its own stored mass `m` (kg), if the droplet cloud stores
/// one. The readers refuse masses that are not finite and positive; any left give `None`.
pub fn radii_from_mass(droplets: &PointCloud) -> Option<Vec<f32>> {
    let m = droplets.extra("m")?;
    m.iter()
        .map(|m| {
            let r = volume_radius(f64::from(*m) / WATER_DENSITY_KG_M3) as f32;
            (r.is_finite() && r > 0.0).then_some(r)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cloud(extra: &[(&str, Vec<f32>)]) -> PointCloud {
        PointCloud {
            positions: vec![Vec3::ZERO; extra[0].1.len()],
            extra: extra
                .iter()
                .map(|(k, v)| (k.to_string(), v.clone()))
                .collect(),
            ..PointCloud::default()
        }
    }

    #[test]
    fn a_sphere_of_the_stored_volume() {
        // 4/3 π r³ = v.
        let r = volume_radius(4.0 / 3.0 * std::f64::consts::PI * 8.0);
        assert!((r - 2.0).abs() < 1e-12);
        // The bursting bubble's film particles: SA·H = 1.0845e-11 m³ = m / ρ with m = 1.0845e-8 kg.
        let film = cloud(&[
            ("sa", vec![1.0845e-5, 0.0, 2.0]),
            ("h", vec![1e-6, 1e-6, -1.0]),
        ]);
        let (v, src) = film_particle_volume(&film).unwrap();
        assert!((v - 1.0845e-11).abs() < 1e-16, "{v}");
        assert_eq!(src, VolumeSource::AreaTimesHeight);
        let massed = cloud(&[("m", vec![1.0845e-8; 3])]);
        let (v2, src) = film_particle_volume(&massed).unwrap();
        assert!((v2 - v).abs() < 1e-16 && src == VolumeSource::Mass);
        let r = radii_from_mass(&massed).unwrap();
        assert!((f64::from(r[0]) - 1.373e-4).abs() < 1e-7, "{r:?}");
        assert!(film_particle_volume(&cloud(&[("rh", vec![1.0])])).is_none());
        assert!(radii_from_mass(&cloud(&[("m", vec![1.0, -1.0])])).is_none());
    }
}
