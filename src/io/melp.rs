//! MELP's VTK XML PolyData (wang-mengdi/melp-thin-film, `melp/VTKIOFunc.cpp`), recognised by
//! their arrays, so they render as written with no flags:
//!
//! - `OutputPointCloudDataAsVTP` (`l_particles_NNNN.vtp`, `e_particles_NNNN.vtp`): points
//!   with float32 `H` (film thickness, **metres**), `SA` (area a particle, m²), `V`, (Eulerian
//!   also `NDEN`, `BH_LV`, `F`); no normals. `H` is the thickness in metres, and the splat
//!   radius is the disk of the particle's area, r = √(SA/π), as the writer's own glyphs use.
//! - `OutputCircleDisksAsVTP` (`l_circles_NNNN.vtp`): the particles as `vtkGlyph3D` disks,
//!   [`GLYPH_POINTS`] points each, every point carrying its particle's `GlyphVector` (the
//!   normal), `radius` and `height` (= H, metres). Each glyph is collapsed back to its
//!   particle: centre (the mean of its points), normal, radius, thickness.

use glam::Vec3;

use super::columns::{Aliases, Columns};
use super::{NORMAL_ALIASES, RADIUS_ALIASES};

/// Points of one `vtkDiskSource` glyph (radial resolution 1, circumferential 20: two rings).
pub const GLYPH_POINTS: usize = 40;

/// Which MELP writer made a PolyData file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Writer {
    /// `OutputPointCloudDataAsVTP`.
    Particles,
    /// `OutputCircleDisksAsVTP`.
    Glyphs,
}

/// Point-cloud aliases: thickness `H` in metres.
pub(crate) const PARTICLE_ALIASES: Aliases = Aliases {
    thickness: &["H"],
    normal: NORMAL_ALIASES,
    radius: RADIUS_ALIASES,
    default_scale_to_nm: 1e9,
};

/// Glyph aliases: thickness `height` in metres, normal `GlyphVector`.
pub(crate) const GLYPH_ALIASES: Aliases = Aliases {
    thickness: &["height"],
    normal: &["GlyphVector"],
    radius: &["radius"],
    default_scale_to_nm: 1e9,
};

/// The MELP writer of `cols`, if its arrays are exactly one writer's.
pub(crate) fn writer(cols: &Columns) -> Option<Writer> {
    let has = |n: &str| cols.scalars.iter().any(|(k, _)| k == n);
    if has("H") && has("SA") && !has("rh") && !has("thickness") {
        Some(Writer::Particles)
    } else if has("GlyphVector_x") && has("radius") && has("height") {
        Some(Writer::Glyphs)
    } else {
        None
    }
}

/// Collapses a glyph file's points to one per glyph (see the module docs).
///
/// # Errors
/// A one-line message if the points are not whole glyphs of equal attributes.
pub(crate) fn collapse_glyphs(mut cols: Columns) -> Result<Columns, String> {
    let n = cols.positions.len();
    if !n.is_multiple_of(GLYPH_POINTS) {
        return Err(format!(
            "{n} points are not whole MELP disk glyphs of {GLYPH_POINTS} points"
        ));
    }
    let m = n / GLYPH_POINTS;
    for (name, v) in &cols.scalars {
        if let Some(g) = (0..m).find(|g| {
            let b = &v[g * GLYPH_POINTS..(g + 1) * GLYPH_POINTS];
            b.iter().any(|x| x.to_bits() != b[0].to_bits())
        }) {
            return Err(format!(
                "'{name}' varies within glyph {g}: not MELP disk glyphs (read the matching \
                 l_particles file instead)"
            ));
        }
    }
    cols.positions = cols
        .positions
        .chunks_exact(GLYPH_POINTS)
        .map(|b| b.iter().copied().sum::<Vec3>() / GLYPH_POINTS as f32)
        .collect();
    for (_, v) in &mut cols.scalars {
        *v = v.iter().step_by(GLYPH_POINTS).copied().collect();
    }
    Ok(cols)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glyphs_collapse_to_their_centres() {
        let mut cols = Columns::default();
        let ring: Vec<Vec3> = (0..GLYPH_POINTS)
            .map(|i| {
                let a = i as f32 / 20.0 * std::f32::consts::TAU;
                let r = if i < 20 { 0.0 } else { 2.0 };
                Vec3::new(5.0 + r * a.cos(), 1.0, r * a.sin())
            })
            .collect();
        cols.positions = ring.iter().chain(&ring).copied().collect();
        let mut rad = vec![2.0f32; GLYPH_POINTS];
        rad.extend(vec![3.0f32; GLYPH_POINTS]);
        cols.scalars.push(("radius".into(), rad));
        let c = collapse_glyphs(cols).unwrap();
        assert_eq!(c.positions.len(), 2);
        assert!((c.positions[0] - Vec3::new(5.0, 1.0, 0.0)).length() < 1e-5);
        assert_eq!(c.scalars[0].1, [2.0, 3.0]);
    }

    #[test]
    fn glyph_errors() {
        let cols = Columns {
            positions: vec![Vec3::ZERO; GLYPH_POINTS + 1],
            ..Columns::default()
        };
        assert!(collapse_glyphs(cols).unwrap_err().contains("whole"));
        let mut cols = Columns {
            positions: vec![Vec3::ZERO; GLYPH_POINTS],
            ..Columns::default()
        };
        let mut r = vec![1.0f32; GLYPH_POINTS];
        r[7] = 2.0;
        cols.scalars.push(("radius".into(), r));
        assert!(collapse_glyphs(cols).unwrap_err().contains("varies"));
    }
}
