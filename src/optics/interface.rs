//! A single smooth interface between two dielectrics (a water droplet's surface): the
//! unpolarised Fresnel reflectance, and Snell's law for the refracted direction's cosine.
//! Plain numbers in, as everywhere in `optics`.

/// Unpolarised reflectance of light arriving with `cos_i` (cosine to the normal, 0..1) from a
/// medium of index `n1` at one of index `n2`: the mean of |r_s|² and |r_p|² (Fresnel
/// equations). Total internal reflection (n1 > n2 past the critical angle) gives 1.
///
/// ```
/// use filmsplat::optics::interface::dielectric_reflectance;
/// // Air to water head-on: ((1.33 - 1) / (1.33 + 1))² ≈ 0.0201.
/// assert!((dielectric_reflectance(1.0, 1.0, 1.33) - 0.020059).abs() < 1e-5);
/// assert_eq!(dielectric_reflectance(0.1, 1.33, 1.0), 1.0);
/// ```
pub fn dielectric_reflectance(cos_i: f32, n1: f32, n2: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let Some(cos_t) = refracted_cos(cos_i, n1, n2) else {
        return 1.0;
    };
    let rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
    let rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
    (0.5 * (rs * rs + rp * rp)).clamp(0.0, 1.0)
}

/// Cosine of the refracted ray's angle to the normal (Snell: n1 sin θi = n2 sin θt), or
/// `None` under total internal reflection.
pub fn refracted_cos(cos_i: f32, n1: f32, n2: f32) -> Option<f32> {
    let eta = n1 / n2;
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    (sin2_t < 1.0).then(|| (1.0 - sin2_t).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_limits_and_reciprocity() {
        // Grazing incidence reflects everything; equal indices nothing.
        assert!((dielectric_reflectance(0.0, 1.0, 1.33) - 1.0).abs() < 1e-6);
        assert!(dielectric_reflectance(0.7, 1.33, 1.33).abs() < 1e-7);
        // Brewster's angle: tan θB = n2/n1, r_p = 0, so R = r_s²/2.
        let tb = 1.33f32.atan();
        let (ci, ct) = (tb.cos(), refracted_cos(tb.cos(), 1.0, 1.33).unwrap());
        let rs = (ci - 1.33 * ct) / (ci + 1.33 * ct);
        assert!((dielectric_reflectance(ci, 1.0, 1.33) - 0.5 * rs * rs).abs() < 1e-6);
        // Reflectance is the same from either side along the same path (Stokes).
        for ci in [0.2f32, 0.5, 0.9] {
            let ct = refracted_cos(ci, 1.0, 1.33).unwrap();
            let a = dielectric_reflectance(ci, 1.0, 1.33);
            let b = dielectric_reflectance(ct, 1.33, 1.0);
            assert!((a - b).abs() < 1e-5, "{a} {b}");
        }
        // Critical angle of water: sin θc = 1/1.33.
        let cc = (1.0f32 - (1.0 / 1.33f32).powi(2)).sqrt();
        assert_eq!(dielectric_reflectance(cc - 1e-3, 1.33, 1.0), 1.0);
        assert!(dielectric_reflectance(cc + 1e-3, 1.33, 1.0) < 1.0);
    }
}
