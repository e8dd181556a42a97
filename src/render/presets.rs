//! Render presets: named points on the measured speed/accuracy front (`benches/tradeoffs.rs`,
//! README "Choosing settings"). A preset fills every knob the scene or command line leaves
//! unset; `balanced` is the default.

use std::fmt;
use std::str::FromStr;

use super::shading::ShadingMode;
use crate::geometry::Primitive;
use crate::{Error, Result};

/// A named set of render settings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Preset {
    /// The fastest settings whose error stays near one just-noticeable difference: 1 sample per
    /// pixel, 4 film crossings deep, colour table, flat disks without first-order detail (mean
    /// ΔE00 ≈ 0.8 against a converged render of the bubble sample). For framing a shot and
    /// scrubbing a sequence.
    Preview,
    /// The default: 4 samples per pixel, 12 crossings, colour table (mean ΔE00 ≈ 0.4).
    #[default]
    Balanced,
    /// For figures: 16 samples per pixel, 16 crossings, branches followed down to 1e-4 of the
    /// camera ray's weight (mean ΔE00 ≈ 0.2).
    Final,
}

/// The settings a preset chooses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PresetValues {
    /// Camera samples per pixel.
    pub spp: u32,
    /// Most film crossings along a path.
    pub max_depth: u32,
    /// Branches below this weight escape to the environment.
    pub min_weight: f32,
    /// How films are shaded.
    pub shading: ShadingMode,
    /// Wavelengths per sample where the shading mode integrates spectra.
    pub wavelengths: usize,
}

impl Preset {
    /// Every preset, fastest first.
    pub const ALL: [Preset; 3] = [Preset::Preview, Preset::Balanced, Preset::Final];

    /// The settings this preset chooses.
    pub fn values(self) -> PresetValues {
        let (spp, max_depth, min_weight) = match self {
            Preset::Preview => (1, 4, 1e-2),
            Preset::Balanced => (4, 12, 1e-3),
            Preset::Final => (16, 16, 1e-4),
        };
        PresetValues {
            spp,
            max_depth,
            min_weight,
            shading: ShadingMode::Lut,
            wavelengths: 16,
        }
    }

    /// The Russian-roulette threshold this preset chooses for `primitive` (see
    /// `RenderSettings::roulette`): `balanced` and `final` take the primitive's own
    /// ([`Primitive::roulette`]); `preview` stops at depth 4 and needs none.
    pub fn roulette(self, primitive: Primitive) -> f32 {
        match self {
            Preset::Preview => 0.0,
            Preset::Balanced | Preset::Final => primitive.roulette(),
        }
    }

    /// Whether this preset gives disks their first-order detail (curvature and thickness
    /// gradient, see `DiskGeometry::set_curvature`) when the scene does not say. `preview`
    /// skips it: the neighbour search is 0.6 of the 1.4 s a 1M-particle preview at 960×540
    /// took, and at preview resolution the picture barely changes (mean ΔE00 against a `final`
    /// render 0.66 without, 0.62 with).
    pub fn first_order_detail(self) -> bool {
        self != Preset::Preview
    }
}

impl FromStr for Preset {
    type Err = Error;

    /// Parses `preview`, `balanced` or `final` (case-insensitive).
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "preview" => Ok(Preset::Preview),
            "balanced" => Ok(Preset::Balanced),
            "final" => Ok(Preset::Final),
            _ => Err(Error::invalid(format!(
                "unknown preset '{s}' (expected preview, balanced or final)"
            ))),
        }
    }
}

impl fmt::Display for Preset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Preset::Preview => "preview",
            Preset::Balanced => "balanced",
            Preset::Final => "final",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_parse_print_and_order_by_cost() {
        for p in Preset::ALL {
            assert_eq!(p.to_string().parse::<Preset>().unwrap(), p);
        }
        assert!("fast".parse::<Preset>().is_err());
        assert_eq!(Preset::default(), Preset::Balanced);
        // Each preset costs more than the one before: more samples, deeper, finer cut-off.
        for w in Preset::ALL.windows(2) {
            let (a, b) = (w[0].values(), w[1].values());
            assert!(a.spp < b.spp && a.max_depth <= b.max_depth && a.min_weight > b.min_weight);
        }
    }
}
