//! Whether splat radii are fitted to the sampling (`[film] fit_radii`, `--fit-radii`,
//! `--raw-radii`): the typed choice, checked in [`super::config`] and used by [`super::load`].

use crate::scene::FitRadiiKey;
use crate::{Error, Result};
use std::str::FromStr;

/// When the radius fit (`pointcloud::gaps`) runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FitRadii {
    /// Only where it changes something: the fit run on a sample of the particles
    /// (`pointcloud::screen`) decides; the whole fit where any sampled radius, cut or edge
    /// would change. The default (`fit_radii = true`).
    #[default]
    Auto,
    /// Every cloud fitted whole.
    Always,
    /// Radii kept as read or estimated (`fit_radii = false`, `--raw-radii`).
    Never,
}

impl FitRadii {
    /// The radii may be fitted (not [`FitRadii::Never`]).
    pub fn may_fit(self) -> bool {
        self != FitRadii::Never
    }
}

impl FromStr for FitRadii {
    type Err = Error;

    /// Parses `"auto"`, `"always"` or `"never"` (case-insensitive).
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "auto" => Ok(FitRadii::Auto),
            "always" => Ok(FitRadii::Always),
            "never" => Ok(FitRadii::Never),
            _ => Err(Error::invalid(format!(
                "film.fit_radii: unknown value '{s}' (expected true, false, 'auto', 'always' or 'never')"
            ))),
        }
    }
}

/// The scene's `film.fit_radii`: `true` is `"auto"`, `false` is `"never"`; unset, auto.
///
/// # Errors
/// An unknown name.
pub(super) fn fit_mode(key: Option<&FitRadiiKey>) -> Result<FitRadii> {
    match key {
        None | Some(FitRadiiKey::Flag(true)) => Ok(FitRadii::Auto),
        Some(FitRadiiKey::Flag(false)) => Ok(FitRadii::Never),
        Some(FitRadiiKey::Name(s)) => s.parse(),
    }
}
