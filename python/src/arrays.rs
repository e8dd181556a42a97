//! numpy ↔ Rust: float32/float64 arrays of any strides in (one copy), float32 arrays out.

use crate::errors::invalid;
use glam::Vec3;
use numpy::ndarray::{ArrayViewD, Axis};
use numpy::{PyArrayDyn, PyArrayMethods};
use pyo3::prelude::*;

/// Calls `f` with a view of `ob` as f32 or f64 values. Float32 and float64 arrays are viewed in
/// place (any strides); anything else goes through `numpy.asarray(ob, dtype=float64)` first.
fn with_view<R>(
    ob: &Bound<'_, PyAny>,
    name: &str,
    f32s: impl FnOnce(ArrayViewD<'_, f32>) -> PyResult<R>,
    f64s: impl FnOnce(ArrayViewD<'_, f64>) -> PyResult<R>,
) -> PyResult<R> {
    if let Ok(a) = ob.cast::<PyArrayDyn<f32>>() {
        return f32s(a.readonly().as_array());
    }
    if let Ok(a) = ob.cast::<PyArrayDyn<f64>>() {
        return f64s(a.readonly().as_array());
    }
    let np = ob.py().import("numpy")?;
    let converted = np
        .call_method1("asarray", (ob, "float64"))
        .map_err(|e| invalid(format!("{name}: not an array of numbers ({e})")))?;
    let a = converted
        .cast::<PyArrayDyn<f64>>()
        .map_err(|_| invalid(format!("{name}: not an array of numbers")))?;
    f64s(a.readonly().as_array())
}

fn shape_error(name: &str, want: &str, shape: &[usize]) -> PyErr {
    invalid(format!("{name} must have shape {want}, got {shape:?}"))
}

/// The length of `ob`'s first axis, read from its shape without copying an array (`0` for a
/// scalar). Sizes a caller chooses are checked with it before anything is allocated.
pub fn leading_len(ob: &Bound<'_, PyAny>, name: &str) -> PyResult<usize> {
    let np = ob.py().import("numpy")?;
    let shape: Vec<usize> = np
        .call_method1("shape", (ob,))
        .and_then(|s| s.extract())
        .map_err(|e| invalid(format!("{name}: not an array of numbers ({e})")))?;
    Ok(shape.first().copied().unwrap_or(0))
}

/// A `Vec` for `n` values of `name`, allocated through the memory allowance
/// (`filmsplat::budget`): refused with a `ValueError` instead of aborting the interpreter.
fn reserve<T>(n: usize, name: &str) -> PyResult<Vec<T>> {
    filmsplat::budget::vec_with_capacity(n, || format!("{name}: {n} values")).map_err(invalid)
}

/// An (N, 3) array as N points or vectors (f32).
pub fn vec3s(ob: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<Vec3>> {
    fn rows<T: Copy + Into<f64>>(a: ArrayViewD<'_, T>, name: &str) -> PyResult<Vec<Vec3>> {
        if a.ndim() != 2 || a.shape()[1] != 3 {
            return Err(shape_error(name, "(N, 3)", a.shape()));
        }
        let mut out = reserve(a.shape()[0], name)?;
        out.extend(a.axis_iter(Axis(0)).map(|r| {
            let c = |i: usize| r[[i]].into() as f32;
            Vec3::new(c(0), c(1), c(2))
        }));
        Ok(out)
    }
    with_view(ob, name, |a| rows(a, name), |a| rows(a, name))
}

/// A 1-D array of `n` values (f32); `n = None` accepts any length.
pub fn scalars(ob: &Bound<'_, PyAny>, name: &str, n: Option<usize>) -> PyResult<Vec<f32>> {
    fn flat<T: Copy + Into<f64>>(
        a: ArrayViewD<'_, T>,
        name: &str,
        n: Option<usize>,
    ) -> PyResult<Vec<f32>> {
        if a.ndim() != 1 || n.is_some_and(|n| a.len() != n) {
            let want = n.map_or("(N,)".to_string(), |n| format!("({n},)"));
            return Err(shape_error(name, &want, a.shape()));
        }
        let mut out = reserve(a.len(), name)?;
        out.extend(a.iter().map(|v| (*v).into() as f32));
        Ok(out)
    }
    with_view(ob, name, |a| flat(a, name, n), |a| flat(a, name, n))
}

/// A 1-D array as f64 values (for the optics, which compute in f64).
pub fn f64s(ob: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    fn flat<T: Copy + Into<f64>>(a: ArrayViewD<'_, T>, name: &str) -> PyResult<Vec<f64>> {
        if a.ndim() != 1 {
            return Err(shape_error(name, "(N,)", a.shape()));
        }
        Ok(a.iter().map(|v| (*v).into()).collect())
    }
    with_view(ob, name, |a| flat(a, name), |a| flat(a, name))
}

/// `values` as a float32 numpy array of `shape`.
pub fn to_numpy<'py>(
    py: Python<'py>,
    values: Vec<f32>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    let a = numpy::PyArray1::from_vec(py, values);
    Ok(a.reshape(shape.to_vec())?.into_any())
}

/// Points or vectors as an (N, 3) float32 array; `rows` is the number of leading dimensions'
/// shape (e.g. `[h, w]` for an image).
pub fn vec3s_to_numpy<'py>(
    py: Python<'py>,
    v: &[Vec3],
    rows: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f32> = v.iter().flat_map(|p| p.to_array()).collect();
    let mut shape = rows.to_vec();
    shape.push(3);
    to_numpy(py, flat, &shape)
}
