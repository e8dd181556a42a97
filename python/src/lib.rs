//! The native half of the `filmsplat` Python package (`filmsplat._native`): particle clouds
//! from numpy, scenes built once and rendered often, images as numpy, thin-film values.
//! The Python half (`python/filmsplat/__init__.py`) adds keyword arguments, broadcasting and
//! progress bars; users import `filmsplat`, never this module.

mod arrays;
mod cloud;
mod errors;
mod film;
mod image;
mod scene;

use pyo3::prelude::*;

/// Runs the `filmsplat` command line with `args` (without the program name) and returns what
/// it printed on stdout. Errors become the same exceptions as everywhere else.
#[pyfunction]
fn run_cli(py: Python<'_>, args: Vec<String>) -> PyResult<String> {
    let (result, out) = py.detach(move || {
        let mut out = Vec::new();
        let argv = std::iter::once("filmsplat".to_string()).chain(args);
        let result = filmsplat::cli::run(argv, &mut out);
        (result, out)
    });
    result.map_err(errors::to_py)?;
    Ok(String::from_utf8_lossy(&out).into_owned())
}

/// The text of a file (a scene file), with the CLI's message if it cannot be read.
#[pyfunction]
fn read_text(py: Python<'_>, path: std::path::PathBuf) -> PyResult<String> {
    py.detach(|| std::fs::read_to_string(&path).map_err(|e| filmsplat::Error::io(&path, e)))
        .map_err(errors::to_py)
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<cloud::Cloud>()?;
    m.add_class::<scene::NativeScene>()?;
    m.add_class::<image::Image>()?;
    m.add_function(wrap_pyfunction!(cloud::read, m)?)?;
    m.add_function(wrap_pyfunction!(film::film_rt, m)?)?;
    m.add_function(wrap_pyfunction!(film::film_rgb, m)?)?;
    m.add_function(wrap_pyfunction!(film::chart, m)?)?;
    m.add_function(wrap_pyfunction!(run_cli, m)?)?;
    m.add_function(wrap_pyfunction!(read_text, m)?)?;
    Ok(())
}
