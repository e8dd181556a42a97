//! Thin-film values (the CLI's `film`) and the interference chart (the CLI's `chart`).

use crate::arrays::f64s;
use crate::errors::{invalid, to_py};
use crate::image::Image;
use filmsplat::figure::{ChartParams, interference_chart};
use filmsplat::optics::{check_film_params, film_rt as airy};
use filmsplat::render::ViewImage;
use filmsplat::spectrum::{film_rgb_reference, reference_grid_nm};
use glam::Vec3;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;

/// Checks thicknesses and angles as `filmsplat film` does, with its messages.
fn check(ior: f64, thickness_nm: &[f64], angle_deg: &[f64]) -> PyResult<()> {
    for &h in thickness_nm {
        check_film_params(ior, h).map_err(|m| invalid(format!("film: {m}")))?;
    }
    if let Some(a) = angle_deg.iter().find(|a| !(0.0..=90.0).contains(*a)) {
        return Err(invalid(format!("film: angle {a} is outside 0..90 degrees")));
    }
    Ok(())
}

/// cos θ of an angle in degrees; 90° is exactly grazing (f64's cos(90°) is 6e-17).
fn cos_deg(a: f64) -> f64 {
    if a == 90.0 {
        0.0
    } else {
        a.to_radians().cos().max(0.0)
    }
}

/// Elementwise Airy reflectance of equal-length 1-D arrays: (R, T, Rs, Rp) as float64.
#[pyfunction]
pub fn film_rt<'py>(
    py: Python<'py>,
    thickness_nm: &Bound<'py, PyAny>,
    angle_deg: &Bound<'py, PyAny>,
    wavelength_nm: &Bound<'py, PyAny>,
    ior: f64,
) -> PyResult<[Bound<'py, PyArray1<f64>>; 4]> {
    let (h, a, l) = (
        f64s(thickness_nm, "thickness_nm")?,
        f64s(angle_deg, "angle_deg")?,
        f64s(wavelength_nm, "wavelength_nm")?,
    );
    if h.len() != a.len() || h.len() != l.len() {
        return Err(invalid("film: the arrays must have one length"));
    }
    check(ior, &h, &a)?;
    if let Some(l) = l.iter().find(|l| !(100.0..=10_000.0).contains(*l)) {
        return Err(invalid(format!(
            "film: wavelength {l} nm is outside 100..10000 nm"
        )));
    }
    let values = py.detach(|| {
        let rt: Vec<_> = (0..h.len())
            .map(|i| airy(cos_deg(a[i]), h[i], ior, l[i]))
            .collect();
        [
            rt.iter().map(|v| v.r()).collect::<Vec<f64>>(),
            rt.iter().map(|v| v.t()).collect(),
            rt.iter().map(|v| v.rs).collect(),
            rt.iter().map(|v| v.rp).collect(),
        ]
    });
    Ok(values.map(|v| PyArray1::from_vec(py, v)))
}

/// Elementwise colour (linear sRGB, D65 light, 1 nm spectral sum over 360..830 nm) of
/// equal-length 1-D arrays: float64 (N, 3).
#[pyfunction]
pub fn film_rgb<'py>(
    py: Python<'py>,
    thickness_nm: &Bound<'py, PyAny>,
    angle_deg: &Bound<'py, PyAny>,
    ior: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let (h, a) = (
        f64s(thickness_nm, "thickness_nm")?,
        f64s(angle_deg, "angle_deg")?,
    );
    if h.len() != a.len() {
        return Err(invalid("film: the arrays must have one length"));
    }
    check(ior, &h, &a)?;
    let rgb: Vec<f64> = py.detach(|| {
        let grid = reference_grid_nm();
        (0..h.len())
            .flat_map(|i| film_rgb_reference(cos_deg(a[i]), h[i], ior, &grid))
            .collect()
    });
    let n = h.len();
    Ok(PyArray1::from_vec(py, rgb).reshape([n, 3])?.into_any())
}

/// The interference colour chart (the CLI's `chart`) as an `Image`, with its checks.
#[pyfunction]
pub fn chart(
    py: Python<'_>,
    max_thickness_nm: f32,
    ior: f32,
    max_angle_deg: f32,
    width: usize,
    height: usize,
) -> PyResult<Image> {
    let params = ChartParams {
        max_thickness_nm,
        ior,
        max_angle_deg,
        width,
        height,
    };
    params.check().map_err(to_py)?;
    let img = py.detach(|| interference_chart(&params));
    let view = ViewImage {
        width: img.width,
        height: img.height,
        rgb: img.data.iter().map(|c| Vec3::from(*c)).collect(),
        legend: None,
    };
    Ok(Image::view(view, "chart"))
}
