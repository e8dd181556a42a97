//! Building: the loaded particles become the film geometry and the droplets, the scene's
//! distance heuristics are set from their size, the framing is measured, and the environment
//! is made (a map's file read).

use super::config::{AttributeView, EnvironmentConfig, FilmConfig};
use super::framing::{Framing, surface_box};
use crate::geometry::{
    Aabb, DiskGeometry, Droplets, FilmGeometry, LayerBlend, MlsSurface, Primitive, SphereGeometry,
};
use crate::pointcloud::PointCloud;
use crate::pointcloud::area::own_radii;
use crate::pointcloud::clip::EdgeClip;
use crate::pointcloud::curvature::{curvature_from_table, first_order_detail, gradient_from_table};
use crate::pointcloud::cut::{Cut, clips};
use crate::pointcloud::knn::KnnTable;
use crate::render::{AttributeValues, Environment, LatLongMap, Studio};
use crate::{Error, Result};
use glam::Vec3;

/// Neighbours used to estimate each disk's curvature and thickness gradient.
const DETAIL_NEIGHBOURS: usize = 12;

/// The droplet parts as one set of water spheres.
pub(super) fn droplets(parts: &[PointCloud]) -> Result<Droplets> {
    let centres: Vec<Vec3> = parts
        .iter()
        .flat_map(|p| p.positions.iter().copied())
        .collect();
    let radii: Vec<f32> = parts.iter().flat_map(radii_or_zero).collect();
    Droplets::build(&centres, &radii)
}

/// A cloud's radii, zero where it has none.
fn radii_or_zero(p: &PointCloud) -> Vec<f32> {
    p.radius.clone().unwrap_or_else(|| vec![0.0; p.len()])
}

/// The values of an `attribute:NAME` view from the film cloud: the extra attribute NAME, the
/// magnitude of the vector NAME_x/_y/_z, or `thickness` / `radius` themselves.
pub(super) fn attribute_values(
    view: &AttributeView,
    cloud: &PointCloud,
    radii: &[f32],
) -> Result<AttributeValues> {
    let name = view.name.as_str();
    let found = |title: String, values: Vec<f32>| AttributeValues {
        title,
        values,
        range: view.range,
    };
    if let Some(v) = cloud.extra(name) {
        return Ok(found(name.to_string(), v.to_vec()));
    }
    let comps: Option<Vec<&[f32]>> = ["x", "y", "z"]
        .iter()
        .map(|c| cloud.extra(&format!("{name}_{c}")))
        .collect();
    if let Some(c) = comps {
        let v = (0..cloud.len())
            .map(|i| Vec3::new(c[0][i], c[1][i], c[2][i]).length())
            .collect();
        return Ok(found(format!("|{name}|"), v));
    }
    match name {
        "thickness" => Ok(found(
            "thickness (nm)".into(),
            cloud.thickness_nm.clone().unwrap_or_default(),
        )),
        "radius" => Ok(found("splat radius".into(), radii.to_vec())),
        _ => {
            let mut names: Vec<&str> = cloud.extra.iter().map(|(k, _)| k.as_str()).collect();
            names.truncate(40);
            Err(Error::invalid(format!(
                "render.view: no attribute '{}' in the film particles (they have: {}; vectors \
                 by their name without _x/_y/_z; also thickness, radius)",
                crate::io::show_name(name),
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                }
            )))
        }
    }
}

/// First-order splat detail: each disk's curvature and thickness gradient (see [`detail`]).
pub(super) type Detail = (Vec<f32>, Vec<Vec3>);

/// The first-order detail of `cloud`'s disks with `radii`, when `film` draws disks with it;
/// `neighbours` is the estimate's neighbour table, if it built one (dropped here, used or not,
/// so it is gone before a tree's build allocates).
pub(super) fn film_detail(
    film: &FilmConfig,
    cloud: &PointCloud,
    radii: &[f32],
    neighbours: Option<KnnTable>,
) -> Option<Detail> {
    let wanted = film.primitive == Primitive::Disk && film.first_order_detail && !cloud.is_empty();
    wanted.then(|| {
        let normals = cloud.normals.as_deref().unwrap_or_default();
        let thickness = cloud.thickness_nm.as_deref().unwrap_or_default();
        detail(&cloud.positions, normals, thickness, radii, neighbours)
    })
}

/// The film geometry of `cloud` drawn as `film.primitive` with `radii`; `detail`, the disks'
/// first-order detail ([`film_detail`]; `None`: flat disks of uniform thickness; motion blur's
/// slices share their unmoved frame's); `cuts`, the fit's verdicts (empty: none);
/// `sheets`, each particle's film part, blended on its own by the MLS surface (empty: one).
pub(super) fn film_geometry(
    film: &FilmConfig,
    cloud: &PointCloud,
    radii: &[f32],
    detail: Option<&Detail>,
    (cuts, sheets): (&[Cut], &[u32]),
) -> Result<FilmGeometry> {
    let normals = cloud.normals.as_deref().unwrap_or_default();
    let thickness = cloud.thickness_nm.as_deref().unwrap_or_default();
    if cloud.is_empty() {
        return Ok(SphereGeometry::build(&[], &[], &[], &[])?.into());
    }
    let (positions, n) = (&cloud.positions, normals);
    match film.primitive {
        Primitive::Disk => {
            let mut disks = DiskGeometry::build(positions, n, radii, thickness)?;
            if let Some((curvature, gradient)) = detail {
                disks.set_curvature(curvature)?;
                disks.set_thickness_gradient(gradient)?;
            }
            if !film.blend {
                disks.set_layer_blend(LayerBlend::NONE);
            }
            if !cuts.is_empty() {
                disks.set_edge_clips(&clips(cuts))?;
            }
            Ok(disks.into())
        }
        Primitive::Sphere => Ok(SphereGeometry::build(positions, n, radii, thickness)?.into()),
        Primitive::Mls => {
            let own = own_radii(cloud);
            let fitted = radii;
            let cut: Vec<f32>;
            let radii = if cuts.is_empty() {
                radii
            } else {
                cut = mls_radii(radii, cuts, &own);
                &cut
            };
            let mut surface = MlsSurface::build(positions, n, radii, thickness)?;
            if !sheets.is_empty() {
                surface.set_sheets(sheets)?;
            }
            // The film the particles' own areas hold is drawn, as their fitted and cut disks,
            // where the surface leaves it bare.
            if own.len() == positions.len() {
                let clips: Vec<_> = cuts.iter().map(Cut::clip).collect();
                surface.set_own_disks(&own, Some((fitted, &clips)))?;
            }
            Ok(surface.into())
        }
    }
}

/// The MLS surface's particle radii (its supports are [`crate::geometry::MlsParams::support`]
/// times these) from the fitted `radii`, the fit's verdicts `cuts` and the particles' own radii √(A/π)
/// `own` (0 or missing: unknown). The surface has no cut, so:
///
/// - an edge particle (an edge cut, on its neighbours' hull) stays within its cut's offset,
///   half a spacing past the hull, instead of the radius that covers its cell up to the cut;
///   where its own area is known, within the cut's reach without the corner's shortening
///   ([`support_reach`]), so a torn fragment's corner particles still reach each other
///   (without areas, on the MELP foam with its walls merged into one sheet, the larger corner
///   supports left pixels whose field holds a crossing the march skips: `tests/pinholes_real.rs`);
/// - a particle one row in ([`Cut::Inner`]) keeps the plain disk's radius, its cut's nearer
///   offset, as a particle the fit did not cut keeps its radius; so does a disk grown past its
///   cell for its neighbours' tilted planes ([`Cut::Grown`]);
/// - neither is ever smaller than its own area: the fit trims a rolled rim's or a torn
///   fragment's particles well below it, and the supports of so sparse a sampling then weigh
///   less than the intact film's threshold where the particles' areas hold film
///   (single-pixel pinholes at fragments' edges, bursting frames 83–113).
fn mls_radii(radii: &[f32], cuts: &[Cut], own: &[f32]) -> Vec<f32> {
    radii
        .iter()
        .enumerate()
        .map(|(i, &r)| {
            let own = own.get(i).copied().unwrap_or(0.0);
            match cuts.get(i) {
                Some(Cut::Inner(c)) => r.min(c[0].w).min(c[1].w).max(own),
                Some(Cut::Grown { flat }) => r.min(*flat).max(own),
                Some(Cut::Edge(c)) if own > 0.0 => r.min(support_reach(c)),
                Some(Cut::Edge(c)) => r.min(c[0].w).min(c[1].w),
                Some(Cut::None) | None => r.max(own),
            }
        })
        .collect()
}

/// How far an edge particle's MLS support may reach past the film's hull, from its disk's cut
/// `clip`: the cut's offset w without its corner factor cos(φ/2) (φ the angle between the two
/// hull edges' normals; `pointcloud::clip::edge_cut`). That factor keeps the point where a
/// disk's two cut lines meet within half a spacing of the hull; a round support reaches no
/// farther past the hull than its radius, and must reach the particle's neighbours along both
/// edges (at a torn fragment's sharp corners w fell to a quarter of the edge's length, and the
/// supports of its corner particles no longer met).
fn support_reach(clip: &EdgeClip) -> f32 {
    let [a, b] = clip;
    let corner = (0.5 * (1.0 + a.truncate().dot(b.truncate())))
        .max(0.0)
        .sqrt();
    let w = a.w.min(b.w);
    if corner > 0.0 { (w / corner).max(w) } else { w }
}

/// First-order splats: normals tilt with the curvature, thickness follows its gradient (limited
/// so that across each disk of `radii` it stays within its neighbours' values). Reuses
/// the estimate's neighbour table when it has enough neighbours per particle; otherwise finds
/// the neighbours a slice at a time, so no whole table is ever held (96 bytes a particle for
/// 12 neighbours).
fn detail(
    positions: &[Vec3],
    normals: &[Vec3],
    thickness: &[f32],
    radii: &[f32],
    neighbours: Option<KnnTable>,
) -> (Vec<f32>, Vec<Vec3>) {
    match neighbours {
        Some(t) if t.k >= DETAIL_NEIGHBOURS => (
            curvature_from_table(positions, normals, &t),
            gradient_from_table(positions, normals, thickness, radii, &t),
        ),
        _ => first_order_detail(positions, normals, thickness, radii, DETAIL_NEIGHBOURS),
    }
}

/// The scene's distances, from its size and its splats.
#[derive(Debug, Clone, Copy)]
pub(super) struct Tolerances {
    /// Self-intersection offset, scene units.
    pub epsilon: f32,
    /// Distance past a film crossing before the next one is looked for, scene units.
    pub layer_skip: f32,
}

impl Tolerances {
    /// The tolerances of films and droplets within `bounds` drawn as `primitive` with `radii`.
    pub fn of(bounds: Aabb, primitive: Primitive, radii: &[f32]) -> Self {
        let diag = (bounds.max - bounds.min).length().max(1e-12);
        let epsilon = 1e-5 * diag.max(bounds.max.abs().max_element());
        let mut sorted = radii.to_vec();
        let mid = sorted.len() / 2;
        let median_radius = if sorted.is_empty() {
            0.0
        } else {
            *sorted.select_nth_unstable_by(mid, f32::total_cmp).1
        };
        let layer_skip = primitive.layer_skip(median_radius, epsilon);
        Tolerances {
            epsilon,
            layer_skip,
        }
    }
}

/// What auto-framing frames: the films (`geometry` of `cloud` with `radii`) and the droplets
/// together; `bounds` (of both) when there is neither.
pub(super) fn framing(
    geometry: &FilmGeometry,
    cloud: &PointCloud,
    radii: &[f32],
    drops: &[PointCloud],
    bounds: Aabb,
) -> Framing {
    let mut parts = Vec::new();
    if !cloud.is_empty() {
        let fb = geometry.bounds();
        let (min, max) = match geometry {
            // Its box holds the support spheres, not the surface (see `surface_box`).
            FilmGeometry::Mls(_) => surface_box(fb.min, fb.max, &cloud.positions, radii),
            _ => (fb.min, fb.max),
        };
        parts.push(Framing::of_splats(min, max, &cloud.positions, radii));
    }
    for d in drops.iter().filter(|d| !d.is_empty()) {
        let (lo, hi) = d
            .positions
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(*p), hi.max(*p))
            });
        parts.push(Framing::of_splats(lo, hi, &d.positions, &radii_or_zero(d)));
    }
    Framing::union_all(&parts)
        .unwrap_or_else(|| Framing::of_splats(bounds.min, bounds.max, &[], &[]))
}

/// The environment of the configuration (a studio with its dark ground facing `view`, the
/// camera's viewing direction); a map's EXR file is read here.
///
/// # Errors
/// As [`crate::image::read_exr_rgba`] for the map.
pub(super) fn environment(e: &EnvironmentConfig, view: Vec3) -> Result<Environment> {
    match e {
        // The studio's dark ground faces the camera, as a photographer sets it up.
        EnvironmentConfig::Studio { intensity } => Ok(Environment::Studio(Studio {
            intensity: *intensity,
            ..Studio::facing(view)
        })),
        EnvironmentConfig::Uniform(radiance) => Ok(Environment::Uniform(*radiance)),
        EnvironmentConfig::Map {
            path,
            rotation_deg,
            intensity,
        } => {
            let (w, h, rgba) = crate::image::read_exr_rgba(path)?;
            let texels = rgba
                .into_iter()
                .map(|p| Vec3::new(p[0], p[1], p[2]))
                .collect();
            Ok(Environment::Map(LatLongMap::new(
                w,
                h,
                texels,
                *rotation_deg,
                *intensity,
            )))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    /// Each verdict's MLS radius: a whole or grown disk keeps its plain radius (never below its
    /// own area), an inner cut its nearer offset (never below its own area), an edge particle
    /// its cut's reach (its offset where its area is unknown).
    #[test]
    fn each_verdict_gives_its_support_radius() {
        let edge = [
            Vec4::new(0.0, -1.0, 0.0, 0.4),
            Vec4::new(-1.0, 0.0, 0.0, 0.4),
        ];
        let inner = [
            Vec4::new(0.0, -1.0, 0.0, 0.7),
            Vec4::new(-1.0, 0.0, 0.0, 0.9),
        ];
        let cuts = [
            Cut::None,
            Cut::Grown { flat: 0.8 },
            Cut::Inner(inner),
            Cut::Edge(edge),
            Cut::Edge(edge),
            Cut::Grown { flat: 0.3 },
        ];
        let radii = [1.0, 1.2, 1.0, 1.0, 1.0, 1.2];
        let own = [1.1, 0.5, 0.5, 0.5, 0.0, 0.5];
        let got = mls_radii(&radii, &cuts, &own);
        // An edge cut at a right-angled corner: the reach is its offset over cos 45°.
        let reach = 0.4 / std::f32::consts::FRAC_1_SQRT_2;
        let want = [1.1, 0.8, 0.7, reach, 0.4, 0.5];
        for (k, (g, w)) in got.iter().zip(want).enumerate() {
            assert!((g - w).abs() < 1e-6, "verdict {k}: {g} against {w}");
        }
        assert_eq!(
            mls_radii(&[1.0], &[], &[2.0]),
            vec![2.0],
            "no verdict: a whole disk"
        );
    }
}
