//! `filmsplat.Image`: a rendered picture (or a view, or the chart) as numpy, PNG or EXR.

use crate::arrays::{to_numpy, vec3s_to_numpy};
use crate::errors::to_py;
use filmsplat::image::{Grade, RgbImage, ToneMap, to_srgb8};
use filmsplat::pipeline::{write_output, write_view};
use filmsplat::render::{RenderOutput, ViewImage};
use numpy::PyArray1;
use numpy::PyArrayMethods;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::path::PathBuf;

/// What an image holds.
enum Content {
    /// The shaded render with its buffers and the scene's display settings.
    Shaded {
        out: RenderOutput,
        grade: Grade,
        exposure: f32,
        tonemap: ToneMap,
    },
    /// A scientific view (or the chart): display-ready linear RGB, shown with a clamp.
    View(ViewImage),
}

/// A rendered image. `rgb` is linear (scene-referred) RGB; `to_srgb8()` and `save()` apply the
/// scene's grading, exposure and tone curve exactly as the CLI does.
#[pyclass(frozen, module = "filmsplat")]
pub struct Image {
    content: Content,
    /// Which view this is: "shaded", "thickness", ..., or "chart".
    #[pyo3(get)]
    view: String,
}

impl Image {
    /// A shaded render.
    pub fn shaded(out: RenderOutput, grade: Grade, exposure: f32, tonemap: ToneMap) -> Self {
        Image {
            content: Content::Shaded {
                out,
                grade,
                exposure,
                tonemap,
            },
            view: "shaded".into(),
        }
    }

    /// A view called `name`.
    pub fn view(v: ViewImage, name: &str) -> Self {
        Image {
            content: Content::View(v),
            view: name.into(),
        }
    }

    fn size(&self) -> (usize, usize) {
        match &self.content {
            Content::Shaded { out, .. } => (out.width, out.height),
            Content::View(v) => (v.width, v.height),
        }
    }
}

#[pymethods]
impl Image {
    /// Width, pixels.
    #[getter]
    fn width(&self) -> usize {
        self.size().0
    }

    /// Height, pixels.
    #[getter]
    fn height(&self) -> usize {
        self.size().1
    }

    /// Linear RGB, float32 (H, W, 3), top row first.
    #[getter]
    fn rgb<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let (w, h) = self.size();
        match &self.content {
            Content::Shaded { out, .. } => vec3s_to_numpy(py, &out.rgb, &[h, w]),
            Content::View(v) => vec3s_to_numpy(py, &v.rgb, &[h, w]),
        }
    }

    /// Coverage: the fraction of each pixel's camera samples that hit a film, float32 (H, W);
    /// None for views and the chart.
    #[getter]
    fn alpha<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let (w, h) = self.size();
        match &self.content {
            Content::Shaded { out, .. } => Ok(Some(to_numpy(py, out.alpha.clone(), &[h, w])?)),
            Content::View(_) => Ok(None),
        }
    }

    /// The first crossing's buffers (means over the samples that hit, 0 elsewhere):
    /// `depth` (scene units along the ray, film or droplet), `normal` (H, W, 3), `thickness`
    /// (nm) and `hits` (splats blended into the film crossing), and `droplets` (share of the
    /// pixel covered by droplets, 0..1), float32; empty for views and the chart.
    #[getter]
    fn layers<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let (w, h) = self.size();
        if let Content::Shaded { out, .. } = &self.content {
            d.set_item("depth", to_numpy(py, out.depth.clone(), &[h, w])?)?;
            d.set_item("normal", vec3s_to_numpy(py, &out.normal, &[h, w])?)?;
            d.set_item("thickness", to_numpy(py, out.thickness.clone(), &[h, w])?)?;
            d.set_item("hits", to_numpy(py, out.hits.clone(), &[h, w])?)?;
            d.set_item("droplets", to_numpy(py, out.droplets.clone(), &[h, w])?)?;
        }
        Ok(d)
    }

    /// Rays traced for this render (0 for views and the chart).
    #[getter]
    fn rays(&self) -> u64 {
        match &self.content {
            Content::Shaded { out, .. } => out.rays,
            Content::View(_) => 0,
        }
    }

    /// The displayed picture as sRGB-encoded uint8 (H, W, 3): grading, exposure and tone curve
    /// as in the CLI's PNG (views: clamp, without the colour bar).
    fn to_srgb8<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let (w, h) = self.size();
        let bytes = match &self.content {
            Content::Shaded {
                out,
                grade,
                exposure,
                tonemap,
            } => {
                let data = out.rgb.iter().map(|c| c.to_array()).collect();
                let img = RgbImage::from_data(w, h, data).map_err(to_py)?;
                to_srgb8(&grade.apply(&img), *exposure, *tonemap)
            }
            Content::View(v) => {
                let data = v.rgb.iter().map(|c| c.to_array()).collect();
                let img = RgbImage::from_data(w, h, data).map_err(to_py)?;
                to_srgb8(&img, 0.0, ToneMap::Clamp)
            }
        };
        Ok(PyArray1::from_vec(py, bytes).reshape([h, w, 3])?.into_any())
    }

    /// Writes the image with the CLI's writers, by extension: `.png` (graded, exposed, tone
    /// mapped sRGB; views with their colour bar) or `.exr` (linear RGBA plus the depth,
    /// normal, thickness and hit-count layers). Atomic: no half-written file on error.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        py.detach(|| match &self.content {
            Content::Shaded {
                out,
                grade,
                exposure,
                tonemap,
            } => write_output(out, grade, *exposure, *tonemap, &path),
            Content::View(v) => write_view(v, &path),
        })
        .map_err(to_py)
    }

    /// The PNG that `save` writes, as bytes (for notebooks).
    fn _repr_png_<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let dir = std::env::temp_dir();
        let path = dir.join(format!(
            "filmsplat-repr-{}-{:p}.png",
            std::process::id(),
            self as *const Image
        ));
        self.save(py, path.clone())?;
        let bytes = std::fs::read(&path);
        let _ = std::fs::remove_file(&path);
        let bytes = bytes.map_err(|e| to_py(filmsplat::Error::io(&path, e)))?;
        Ok(PyBytes::new(py, &bytes))
    }

    fn __repr__(&self) -> String {
        let (w, h) = self.size();
        format!("Image({w}x{h}, view '{}')", self.view)
    }
}
