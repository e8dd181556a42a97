//! Checks applied before numbers reach the optics kernels.

/// Largest film thickness accepted, in nanometres (1 mm). Far thicker than any soap film; beyond
/// it the interference phase no longer fits f32 and the film is plainly incoherent anyway.
pub const MAX_THICKNESS_NM: f64 = 1.0e6;

/// Checks film parameters: `ior` finite and in [1, 10] (a film denser than the surrounding air),
/// `thickness_nm` finite and in [0, [`MAX_THICKNESS_NM`]]. Returns a message naming the problem.
pub fn check_film_params(ior: f64, thickness_nm: f64) -> Result<(), String> {
    if !ior.is_finite() || !(1.0..=10.0).contains(&ior) {
        return Err(format!(
            "film index of refraction must be between 1 and 10, got {ior}"
        ));
    }
    if !thickness_nm.is_finite() || thickness_nm < 0.0 {
        return Err(format!(
            "film thickness must be a finite number >= 0 nm, got {thickness_nm}"
        ));
    }
    if thickness_nm > MAX_THICKNESS_NM {
        return Err(format!(
            "film thickness {thickness_nm} nm is above the supported maximum of {MAX_THICKNESS_NM} nm"
        ));
    }
    Ok(())
}
