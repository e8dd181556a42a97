//! `filmsplat.Cloud` and `filmsplat.read`.

use crate::arrays::{leading_len, scalars, to_numpy, vec3s, vec3s_to_numpy};
use crate::errors::{invalid, to_py};
use filmsplat::io::{ReadOptions, read_cloud};
use filmsplat::pipeline::memory::MemoryEstimate;
use filmsplat::pointcloud::{PointCloud, validate};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// A thin-film particle cloud: positions (scene units), and optionally normals, film
/// thickness (nm), splat radius (scene units) and any other per-particle attributes.
///
/// `Cloud(positions, normals=None, thickness_nm=None, radius=None, attributes=None)`: arrays
/// of float32 or float64, any strides; each is copied once, into the cloud. `positions` and
/// `normals` are (N, 3), the others (N,); `attributes` maps names to (N,) arrays. What is
/// missing is estimated when a `Scene` is built (normals and radii from the neighbours,
/// thickness 500 nm).
#[pyclass(frozen, module = "filmsplat")]
pub struct Cloud {
    pub cloud: PointCloud,
}

#[pymethods]
impl Cloud {
    #[new]
    #[pyo3(signature = (positions, normals=None, thickness_nm=None, radius=None, attributes=None))]
    fn new(
        positions: &Bound<'_, PyAny>,
        normals: Option<&Bound<'_, PyAny>>,
        thickness_nm: Option<&Bound<'_, PyAny>>,
        radius: Option<&Bound<'_, PyAny>>,
        attributes: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        // What the caller's arrays would make us hold, checked before any copy: a broadcast
        // view of a billion rows is 24 bytes to numpy and a refusal here.
        check_particles(leading_len(positions, "positions")?, "Cloud")?;
        let positions = vec3s(positions, "positions")?;
        let n = positions.len();
        let normals = normals.map(|a| vec3s(a, "normals")).transpose()?;
        if let Some(v) = &normals
            && v.len() != n
        {
            return Err(crate::errors::invalid(format!(
                "normals must have shape ({n}, 3), got ({}, 3)",
                v.len()
            )));
        }
        let thickness_nm = thickness_nm
            .map(|a| scalars(a, "thickness_nm", Some(n)))
            .transpose()?;
        let radius = radius.map(|a| scalars(a, "radius", Some(n))).transpose()?;
        let mut extra = Vec::new();
        for (k, v) in attributes.into_iter().flat_map(|d| d.iter()) {
            let name: String = k.extract()?;
            let values = scalars(&v, &format!("attributes['{name}']"), Some(n))?;
            extra.push((name, values));
        }
        let cloud = PointCloud {
            positions,
            normals,
            thickness_nm,
            radius,
            extra,
        };
        // Bad values are refused where they enter, not at the first render.
        validate(&cloud).map_err(|e| invalid(format!("Cloud: {e}")))?;
        Ok(Cloud { cloud })
    }

    /// Particle centres, scene units: float32 array (N, 3) (a new copy each call).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        vec3s_to_numpy(py, &self.cloud.positions, &[self.cloud.len()])
    }

    /// Film normals: float32 array (N, 3), or None if the cloud has none.
    #[getter]
    fn normals<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let n = self.cloud.len();
        self.cloud
            .normals
            .as_ref()
            .map(|v| vec3s_to_numpy(py, v, &[n]))
            .transpose()
    }

    /// Film thickness, nanometres: float32 array (N,), or None.
    #[getter]
    fn thickness_nm<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let n = self.cloud.len();
        let t = self.cloud.thickness_nm.clone();
        t.map(|v| to_numpy(py, v, &[n])).transpose()
    }

    /// Splat radius, scene units: float32 array (N,), or None.
    #[getter]
    fn radius<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let n = self.cloud.len();
        let r = self.cloud.radius.clone();
        r.map(|v| to_numpy(py, v, &[n])).transpose()
    }

    /// Every other per-particle attribute: dict of name → float32 array (N,).
    #[getter]
    fn attributes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let n = self.cloud.len();
        for (k, v) in &self.cloud.extra {
            d.set_item(k, to_numpy(py, v.clone(), &[n])?)?;
        }
        Ok(d)
    }

    fn __len__(&self) -> usize {
        self.cloud.len()
    }

    fn __repr__(&self) -> String {
        let c = &self.cloud;
        let has = |b: bool| if b { "yes" } else { "no" };
        format!(
            "Cloud({} particles, normals: {}, thickness: {}, radius: {}, attributes: [{}])",
            c.len(),
            has(c.normals.is_some()),
            has(c.thickness_nm.is_some()),
            has(c.radius.is_some()),
            c.extra
                .iter()
                .map(|(k, _)| k.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )
    }
}

/// Refuses `n` particles whose render would not fit in the memory allowance: the same
/// per-particle estimate (cloud, neighbour search, geometry) and allowance as the CLI's
/// (`filmsplat::budget`), before anything is copied. `what` starts the message.
pub fn check_particles(n: usize, what: &str) -> PyResult<()> {
    let estimate = MemoryEstimate::new(n as u64, 0, 0, false, 0);
    filmsplat::budget::check(estimate.total(), || format!("{what}: {n} particles")).map_err(invalid)
}

/// Reads a particle file or frame folder (every format the CLI reads) into a `Cloud`, with
/// thickness converted to nm (`thickness_unit`: "nm", "um", "mm" or "m"; default: the format's
/// own unit, m for frame folders, nm otherwise). The attribute names choose the thickness
/// attribute, the normal prefix and the radius attribute (default: the usual aliases).
#[pyfunction]
#[pyo3(signature = (path, thickness_attr=None, thickness_unit=None, normal_attr=None, radius_attr=None))]
pub fn read(
    py: Python<'_>,
    path: PathBuf,
    thickness_attr: Option<String>,
    thickness_unit: Option<String>,
    normal_attr: Option<String>,
    radius_attr: Option<String>,
) -> PyResult<Cloud> {
    let opts = ReadOptions {
        thickness_attr,
        normal_attr,
        radius_attr,
        ..ReadOptions::default()
    }
    .with_unit(thickness_unit.as_deref())
    .map_err(to_py)?;
    let cloud = py.detach(|| read_cloud(&path, &opts)).map_err(to_py)?;
    Ok(Cloud { cloud })
}
