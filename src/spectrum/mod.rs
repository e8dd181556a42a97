//! Spectra and colour: CIE tables, sampled wavelengths and the spectrum carried at them, RGB →
//! spectrum (Smits), spectrum → XYZ → sRGB, and the colour of a film under white light.

pub mod blackbody;
pub mod cie;
pub mod colour;
pub mod film_colour;
pub mod sampled;
pub mod smits;
pub mod wavelengths;

pub use blackbody::{Blackbody, planck};
pub use colour::{XYZ_TO_LINEAR_SRGB, linear_to_srgb, srgb_to_linear, xyz_to_linear_srgb};
pub use film_colour::{FilmLut, SpectralWeights, film_rgb_reference, reference_grid_nm};
pub use sampled::{SPECTRAL_LANES, Spectrum};
pub use smits::SmitsBasis;
pub use wavelengths::{SampledWavelengths, WavelengthRange, WavelengthStrategy};
