//! Sample scene generators: synthetic thin-film particle clouds (bubbles, films), all painted
//! by the shared [`thickness`] field and laid out by the shared [`surface`] samplers.

pub mod bubble;
pub mod catenoid;
pub mod drip;
pub mod fibonacci;
pub mod flat_film;
pub mod half_bubble;
pub mod icosphere;
pub mod irregular_bubble;
pub mod oscillating_bubble;
pub mod rng;
pub mod surface;
pub mod thickness;

use crate::pointcloud::PointCloud;
pub use bubble::{BubbleParams, bubble};
pub use fibonacci::{fibonacci_spacing, fibonacci_sphere};
pub use icosphere::icosphere;
pub use surface::{SampleParams, sparse};

/// The built-in sample generators (the gallery).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SampleKind {
    /// A soap bubble (unit sphere).
    Bubble,
    /// A wobbling, non-spherical bubble.
    IrregularBubble,
    /// A film between two rings being pulled apart.
    Catenoid,
    /// A hemisphere standing on a surface.
    HalfBubble,
    /// A flat film in a square wire frame.
    SquareFilm,
    /// A flat film in a circular wire frame.
    CircleFilm,
    /// A bubble with a drop forming and separating at its bottom.
    Drip,
    /// A bubble ringing in its l = 2 shape mode.
    OscillatingBubble,
}

impl SampleKind {
    /// Every generator, in gallery order.
    pub const ALL: [SampleKind; 8] = [
        SampleKind::Bubble,
        SampleKind::IrregularBubble,
        SampleKind::Catenoid,
        SampleKind::HalfBubble,
        SampleKind::SquareFilm,
        SampleKind::CircleFilm,
        SampleKind::Drip,
        SampleKind::OscillatingBubble,
    ];

    /// The generator's name on the command line and in scene files.
    pub fn name(self) -> &'static str {
        match self {
            SampleKind::Bubble => "bubble",
            SampleKind::IrregularBubble => "irregular-bubble",
            SampleKind::Catenoid => "catenoid",
            SampleKind::HalfBubble => "half-bubble",
            SampleKind::SquareFilm => "square-film",
            SampleKind::CircleFilm => "circle-film",
            SampleKind::Drip => "drip",
            SampleKind::OscillatingBubble => "oscillating-bubble",
        }
    }

    /// The generator called `name`, or an error listing the names.
    pub fn from_name(name: &str) -> crate::Result<SampleKind> {
        SampleKind::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| {
                crate::Error::invalid(format!(
                    "unknown sample '{name}' (available: {})",
                    SampleKind::names()
                ))
            })
    }

    /// All names, comma-separated.
    pub fn names() -> String {
        SampleKind::ALL.map(|k| k.name()).join(", ")
    }

    /// Generates the cloud (y up, thickness in nm, unit normals, splat radii). Every shape is
    /// about 2 scene units across; deterministic for `p.seed`.
    pub fn generate(self, p: &SampleParams) -> PointCloud {
        match self {
            SampleKind::Bubble => bubble(&BubbleParams {
                particles: p.particles,
                time: p.time,
                seed: p.seed,
                ..BubbleParams::default()
            }),
            SampleKind::IrregularBubble => irregular_bubble::irregular_bubble(p),
            SampleKind::Catenoid => catenoid::catenoid(p),
            SampleKind::HalfBubble => half_bubble::half_bubble(p),
            SampleKind::SquareFilm => flat_film::square_film(p),
            SampleKind::CircleFilm => flat_film::circle_film(p),
            SampleKind::Drip => drip::drip(p),
            SampleKind::OscillatingBubble => oscillating_bubble::oscillating_bubble(p),
        }
    }
}
