//! Scientific views: what the camera's first film crossing holds, drawn exactly and cheaply
//! (no spectra, no ray tree, one ray through each pixel centre).

use super::world::{World, WorldRef};
use crate::geometry::SurfaceHit;
use crate::image::{is_one_value, srgb_to_linear, viridis};
use crate::{Error, Result};
use glam::Vec3;
use rayon::prelude::*;
use std::fmt;
use std::str::FromStr;

/// What to show (`--view`).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum View {
    /// The photorealistic thin-film render.
    #[default]
    Shaded,
    /// Film thickness in false colour (viridis), with a labelled colour bar.
    Thickness,
    /// The film normal as RGB (x, y, z from −1..1 to 0..1).
    Normal,
    /// Distance to the first crossing, near = light, far = dark, with a colour bar.
    Depth,
    /// Each particle its own colour (the particle with the largest weight at the crossing).
    ParticleId,
    /// How many splats were blended into the crossing: shows sparse regions and holes.
    Coverage,
    /// A stored per-particle attribute (`attribute:NAME`; vectors by magnitude) of the particle
    /// that weighs most at the crossing, in false colour with a labelled colour bar. The values
    /// come with the render ([`AttributeValues`]). Holds NAME (not empty).
    Attribute(String),
}

/// The values an [`View::Attribute`] view shows: one per particle of the film geometry (in its
/// build order), a title for the bar, and the range the ramp spans (`None`: the visible
/// values' range).
#[derive(Debug, Clone, PartialEq)]
pub struct AttributeValues {
    /// Bar title, e.g. `vrt` or `|v|`.
    pub title: String,
    /// One value a particle.
    pub values: Vec<f32>,
    /// Values at the bottom and top of the bar; `None` for the range of what is visible.
    pub range: Option<(f32, f32)>,
}

impl FromStr for View {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "shaded" => Ok(View::Shaded),
            "thickness" => Ok(View::Thickness),
            "normal" => Ok(View::Normal),
            "depth" => Ok(View::Depth),
            "particle-id" => Ok(View::ParticleId),
            "coverage" => Ok(View::Coverage),
            _ => match s.strip_prefix("attribute:").filter(|n| !n.is_empty()) {
                Some(name) => Ok(View::Attribute(name.to_string())),
                None => Err(format!(
                    "unknown view '{s}' (expected shaded, thickness, normal, depth, particle-id, \
                 coverage or attribute:NAME)"
                )),
            },
        }
    }
}

impl View {
    /// True for the views drawn with a colour bar (thickness, depth, coverage).
    pub fn has_legend(&self) -> bool {
        matches!(
            self,
            View::Thickness | View::Depth | View::Coverage | View::Attribute(_)
        )
    }
}

impl fmt::Display for View {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            View::Shaded => "shaded",
            View::Thickness => "thickness",
            View::Normal => "normal",
            View::Depth => "depth",
            View::ParticleId => "particle-id",
            View::Coverage => "coverage",
            View::Attribute(_) => "attribute",
        })
    }
}

/// A colour bar for a view: the value range its colours span and how values map to colours.
/// The view paints each pixel with [`Legend::colour`] and the bar shows the same function, so
/// the two cannot disagree.
#[derive(Debug, Clone, PartialEq)]
pub struct Legend {
    /// Title, with unit.
    pub title: String,
    /// Value at the bottom of the bar.
    pub min: f32,
    /// Value at the top of the bar.
    pub max: f32,
    /// How values between `min` and `max` are coloured.
    pub ramp: Ramp,
}

/// A legend's colour ramp.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ramp {
    /// Viridis: dark purple at `min`, yellow at `max`.
    Viridis,
    /// Grey, light at `min`, dark at `max` (depth: near is light).
    GreyFalling,
}

impl Legend {
    /// Linear RGB of value `v` (clamped to `min..max`; mid-ramp if the range holds one value,
    /// [`crate::image::is_one_value`], as the colour bar then says `all V`).
    pub fn colour(&self, v: f32) -> Vec3 {
        let t = if is_one_value(self.min, self.max) {
            0.5
        } else {
            ((v - self.min) / (self.max - self.min)).clamp(0.0, 1.0)
        };
        match self.ramp {
            Ramp::Viridis => Vec3::from(viridis(t)),
            Ramp::GreyFalling => Vec3::splat(grey(1.0 - t)),
        }
    }
}

/// A rendered view: display-ready linear RGB (write it with the clamp tone curve at 0 EV) and
/// its legend, if it has one.
#[derive(Debug, Clone)]
pub struct ViewImage {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Linear RGB.
    pub rgb: Vec<Vec3>,
    /// The view's colour bar, if it has one.
    pub legend: Option<Legend>,
}

/// How a view colours one crossing.
type Colouring = Box<dyn Fn(&SurfaceHit) -> Vec3 + Sync>;

/// Background of pixels whose ray meets no film.
const BACKGROUND: Vec3 = Vec3::splat(0.012);

/// Renders `view` (not [`View::Shaded`]) at `width × height`.
pub fn render_view(scene: &World, view: View, width: usize, height: usize) -> Result<ViewImage> {
    render_view_of(scene, view, width, height, None)
}

/// [`render_view`] with the values of an [`View::Attribute`] view.
///
/// # Errors
/// As [`render_view`]; an attribute view without values, or with a count that is not the
/// geometry's, is refused.
pub fn render_view_of<'a>(
    scene: impl Into<WorldRef<'a>>,
    view: View,
    width: usize,
    height: usize,
    attribute: Option<&AttributeValues>,
) -> Result<ViewImage> {
    let scene = scene.into();
    if matches!(view, View::Attribute(_))
        && attribute.is_none_or(|a| a.values.len() != scene.geometry.len())
    {
        return Err(Error::invalid(format!(
            "the attribute view needs one value per particle ({} particles)",
            scene.geometry.len()
        )));
    }
    if width == 0 || height == 0 {
        return Err(Error::invalid(format!(
            "image size must be at least 1x1, got {width}x{height}"
        )));
    }
    if view == View::Shaded {
        return Err(Error::Internal(
            "render_view: the shaded view is the integrator's".into(),
        ));
    }
    let hits = primary_hits(scene, width, height);
    let (colour, legend) = colouring(view, &hits, attribute);
    let rgb = hits
        .par_iter()
        .map(|h| h.as_ref().map_or(BACKGROUND, &colour))
        .collect();
    Ok(ViewImage {
        width,
        height,
        rgb,
        legend,
    })
}

/// The first film crossing of each pixel's centre ray, row-major.
fn primary_hits(scene: WorldRef<'_>, width: usize, height: usize) -> Vec<Option<SurfaceHit>> {
    let aspect = width as f32 / height as f32;
    (0..width * height)
        .into_par_iter()
        .with_min_len(256)
        .map(|k| {
            let (x, y) = (k % width, k / width);
            let ray = scene.camera.ray(
                (x as f32 + 0.5) / width as f32,
                (y as f32 + 0.5) / height as f32,
                aspect,
            );
            scene.geometry.intersect(&ray, 0.0, f32::INFINITY)
        })
        .collect()
}

/// How `view` colours a crossing, and its colour bar: value views span the range of the
/// values in `hits` (unless the attribute gives one).
fn colouring(
    view: View,
    hits: &[Option<SurfaceHit>],
    attribute: Option<&AttributeValues>,
) -> (Colouring, Option<Legend>) {
    let range = |f: &dyn Fn(&SurfaceHit) -> f32| {
        hits.iter()
            .flatten()
            .map(f)
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            })
    };
    // A value view: the legend's ramp applied to `value` of the crossing.
    let ramp = |title: &str,
                (min, max): (f32, f32),
                ramp,
                value: Box<dyn Fn(&SurfaceHit) -> f32 + Sync>|
     -> (Colouring, Option<Legend>) {
        let l = Legend {
            title: title.into(),
            min,
            max,
            ramp,
        };
        let paint = l.clone();
        (Box::new(move |h| paint.colour(value(h))), Some(l))
    };
    match view {
        View::Thickness => ramp(
            "thickness (nm)",
            range(&|h| h.thickness_nm),
            Ramp::Viridis,
            Box::new(|h| h.thickness_nm),
        ),
        View::Depth => ramp(
            "distance (scene units)",
            range(&|h| h.t),
            Ramp::GreyFalling,
            Box::new(|h| h.t),
        ),
        View::Coverage => {
            let r = (1.0, range(&|h| h.coverage as f32).1.max(2.0));
            ramp(
                "splats blended",
                r,
                Ramp::Viridis,
                Box::new(|h| h.coverage as f32),
            )
        }
        View::Normal => (
            Box::new(|h| (h.normal * 0.5 + Vec3::splat(0.5)).map(srgb_to_linear)),
            None,
        ),
        View::ParticleId => (Box::new(|h| id_colour(h.particle)), None),
        View::Attribute(_) => {
            let a = attribute.expect("checked by render_view_of");
            let values = a.values.clone();
            let value =
                move |h: &SurfaceHit| values.get(h.particle as usize).copied().unwrap_or(0.0);
            let r = a.range.unwrap_or_else(|| range(&value));
            ramp(&a.title, r, Ramp::Viridis, Box::new(value))
        }
        View::Shaded => unreachable!("rejected by render_view_of"),
    }
}

/// Linear value of an sRGB-encoded grey level, so ramps look even on screen.
fn grey(encoded: f32) -> f32 {
    srgb_to_linear(0.08 + 0.92 * encoded)
}

/// A stable, well-spread colour for a particle index.
fn id_colour(id: u32) -> Vec3 {
    let h = super::sampler::mix64(id as u64);
    let c = |shift: u32| srgb_to_linear(0.25 + 0.75 * ((h >> shift) & 0xff) as f32 / 255.0);
    Vec3::new(c(0), c(8), c(16))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::DiskGeometry;
    use crate::render::{Camera, Environment};

    /// Two disks side by side at x = ∓1 of thicknesses `t` (nm), seen face-on from +z.
    fn two_disks(t: [f32; 2]) -> World {
        let p = [Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0)];
        let geometry = DiskGeometry::build(&p, &[Vec3::Z; 2], &[0.9; 2], &t).unwrap();
        World {
            geometry: geometry.into(),
            camera: Camera::look_at(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO, Vec3::Y, 20.0),
            environment: Environment::Uniform(Vec3::ONE),
            layer_skip: 0.1,
            epsilon: 1e-5,
            staging: Default::default(),
        }
    }

    #[test]
    fn thickness_view_maps_the_range_and_leaves_background() {
        // Two disks side by side, 100 and 500 nm.
        let scene = two_disks([100.0, 500.0]);
        let v = render_view(&scene, View::Thickness, 40, 20).unwrap();
        let legend = v.legend.unwrap();
        assert!(
            (legend.min - 100.0).abs() < 1e-3 && (legend.max - 500.0).abs() < 1e-3,
            "{legend:?}"
        );
        let left = v.rgb[10 * 40 + 11];
        let right = v.rgb[10 * 40 + 28];
        assert!((left - Vec3::from(viridis(0.0))).length() < 1e-4, "{left}");
        assert!(
            (right - Vec3::from(viridis(1.0))).length() < 1e-4,
            "{right}"
        );
        assert_eq!(v.rgb[0], BACKGROUND);
        let c = render_view(&scene, View::Coverage, 40, 20).unwrap();
        assert_eq!(c.rgb[10 * 40 + 11], Vec3::from(viridis(0.0)), "one splat");
        let ids = render_view(&scene, View::ParticleId, 40, 20).unwrap();
        assert_ne!(ids.rgb[10 * 40 + 11], ids.rgb[10 * 40 + 28]);
    }

    #[test]
    fn a_constant_field_is_one_colour_whatever_its_round_off() {
        // sph_bubble -test 52 starts at 1938.3 nm everywhere; blended crossings differ in the
        // last f32 bits, and the view stretched those over the whole ramp (a speckle of five
        // colours under a bar saying `all 1938.32`).
        let h = 1938.32f32;
        let scene = two_disks([h, f32::from_bits(h.to_bits() + 1)]);
        let v = render_view(&scene, View::Thickness, 40, 20).unwrap();
        let legend = v.legend.unwrap();
        assert!(legend.max > legend.min, "{legend:?}");
        assert!(is_one_value(legend.min, legend.max));
        let mid = Vec3::from(viridis(0.5));
        assert_eq!(v.rgb[10 * 40 + 11], mid);
        assert_eq!(v.rgb[10 * 40 + 28], mid);
    }
}
