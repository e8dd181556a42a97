//! `filmsplat._native._Scene`: geometry built once from clouds (or a scene file), rendered as
//! often as asked with the GIL released, stoppable with Ctrl-C.

use crate::cloud::Cloud;
use crate::errors::{invalid, to_py};
use crate::image::Image;
use filmsplat::pipeline::config::{check_image_size, check_spp};
use filmsplat::pipeline::memory::{MemoryEstimate, estimate_scene};
use filmsplat::pipeline::{Prepared, Shot, camera, camera_path, framing, prepare_with, render};
use filmsplat::pointcloud::PointCloud;
use filmsplat::render::{View, WorldRef, render_view_of};
use filmsplat::scene::{CameraDesc, SceneDesc};
use pyo3::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, mpsc};
use std::time::Duration;

/// How often a running render looks at Python: Ctrl-C and the progress callback.
const POLL: Duration = Duration::from_millis(100);

/// `desc`'s camera (the auto-framed one if it names no position; looking at the framing's
/// centre if it names no look-at) turned `deg` degrees about its up axis.
fn turned(desc: &SceneDesc, p: &Prepared, aspect: f32, deg: f64) -> PyResult<CameraDesc> {
    let mut start = framing::sequence_camera(desc, &p.framing, aspect)
        .map_err(to_py)?
        .unwrap_or_else(|| desc.camera.clone());
    start.look_at = start.look_at.or(Some(p.framing.centre.to_array()));
    camera_path::orbit(&start, deg).map_err(to_py)
}

/// Concatenates clouds. An array (normals, thickness, radius, an attribute) is kept only if
/// every cloud has it; normals and radii given by some clouds only are an error (estimating
/// them for the others would change those given), thickness too.
fn merge(clouds: &[PyRef<'_, Cloud>]) -> PyResult<PointCloud> {
    if let [one] = clouds {
        return Ok(one.cloud.clone());
    }
    let mut all = PointCloud::default();
    let count = |f: &dyn Fn(&PointCloud) -> bool| clouds.iter().filter(|c| f(&c.cloud)).count();
    let n = clouds.len();
    for (name, k) in [
        ("normals", count(&|c| c.normals.is_some())),
        ("thickness_nm", count(&|c| c.thickness_nm.is_some())),
        ("radius", count(&|c| c.radius.is_some())),
    ] {
        if k != 0 && k != n {
            return Err(invalid(format!(
                "Scene: {k} of {n} clouds have {name}; give it for all or none"
            )));
        }
    }
    for c in clouds {
        let c = &c.cloud;
        all.positions.extend(&c.positions);
        if let Some(v) = &c.normals {
            all.normals.get_or_insert_with(Vec::new).extend(v);
        }
        if let Some(v) = &c.thickness_nm {
            all.thickness_nm.get_or_insert_with(Vec::new).extend(v);
        }
        if let Some(v) = &c.radius {
            all.radius.get_or_insert_with(Vec::new).extend(v);
        }
    }
    let first = &clouds[0].cloud;
    for (name, _) in &first.extra {
        if clouds.iter().all(|c| c.cloud.extra(name).is_some()) {
            let v = clouds
                .iter()
                .flat_map(|c| c.cloud.extra(name).expect("checked").to_vec())
                .collect();
            all.extra.push((name.clone(), v));
        }
    }
    Ok(all)
}

/// Refuses a scene whose estimated peak memory (the CLI's estimate: particles of `clouds`, or
/// of the scene's inputs as their headers say, and the image) exceeds the allowance, before
/// the clouds are merged or anything is read. An input the estimate cannot read is left to
/// the reader, which names the problem better.
fn check_memory(
    desc: &SceneDesc,
    base: &Path,
    clouds: Option<&[PyRef<'_, Cloud>]>,
) -> PyResult<()> {
    let estimate = match clouds {
        Some(c) => {
            let n: usize = c.iter().map(|c| c.cloud.len()).sum();
            let (w, h) = filmsplat::pipeline::config::image_size(desc);
            MemoryEstimate::new(n as u64, w, h, false, 0)
        }
        None => match estimate_scene(desc, base, false) {
            Ok(e) => e,
            Err(_) => return Ok(()),
        },
    };
    filmsplat::budget::check(estimate.total(), || format!("Scene: {estimate}")).map_err(invalid)
}

/// A built scene: the geometry, the shader and the settings of one scene description. Read only
/// once built (each render takes its own shot), so threads may render it at once.
#[pyclass(frozen, name = "_Scene", module = "filmsplat._native")]
pub struct NativeScene {
    prepared: Prepared,
    desc: SceneDesc,
    #[pyo3(get)]
    particles: usize,
    #[pyo3(get)]
    notes: Vec<String>,
    /// Seconds spent loading, estimating and building.
    #[pyo3(get)]
    build_seconds: (f64, f64, f64),
    /// Image size of the scene description, (width, height) pixels.
    #[pyo3(get)]
    size: (usize, usize),
}

#[pymethods]
impl NativeScene {
    /// Builds a scene from TOML text (`name` for messages; paths relative to `base`) and, if
    /// given, in-memory clouds that replace its `[input]`.
    #[new]
    #[pyo3(signature = (toml, name, base, clouds=None))]
    fn new(
        py: Python<'_>,
        toml: &str,
        name: &str,
        base: PathBuf,
        clouds: Option<Vec<PyRef<'_, Cloud>>>,
    ) -> PyResult<Self> {
        let desc = SceneDesc::from_toml(toml, name).map_err(to_py)?;
        // The whole configuration before the memory estimate reads a header or clouds merge.
        desc.resolve_for(&base, clouds.is_some())
            .map_err(|e| to_py(desc.locate(e)))?;
        check_memory(&desc, &base, clouds.as_deref())?;
        let cloud = match clouds {
            Some(c) if c.is_empty() => return Err(invalid("Scene: no clouds given")),
            Some(c) => Some(merge(&c)?),
            None => None,
        };
        let p = py
            .detach(|| prepare_with(&desc, &base, false, cloud))
            .map_err(to_py)?;
        Ok(NativeScene {
            particles: p.particles,
            notes: p
                .notes
                .iter()
                .filter(|n| !n.text.is_empty())
                .map(|n| n.text.clone())
                .collect(),
            build_seconds: (
                p.load_time.as_secs_f64(),
                p.estimate_time.as_secs_f64(),
                p.build_time.as_secs_f64(),
            ),
            size: (p.shot.settings.width, p.shot.settings.height),
            prepared: p,
            desc,
        })
    }

    /// Renders. `camera_toml`: a `[camera]` table replacing the scene's; `None` arguments
    /// keep the scene's values; `progress(done, total)` is called about every 0.1 s with
    /// finished and total tiles; `orbit`: degrees that camera (auto-framed if it names no
    /// position) turns about its up axis around its look-at point, the studio with it, as
    /// `render --orbit` turns frame i of N by DEG·i/N.
    #[pyo3(signature = (camera_toml=None, size=None, spp=None, view=None, seed=None, progress=None, orbit=None))]
    #[allow(clippy::too_many_arguments)]
    fn render(
        &self,
        py: Python<'_>,
        camera_toml: Option<&str>,
        size: Option<(usize, usize)>,
        spp: Option<u32>,
        view: Option<&str>,
        seed: Option<u64>,
        progress: Option<Py<PyAny>>,
        orbit: Option<f64>,
    ) -> PyResult<Image> {
        let turn = orbit.unwrap_or(0.0);
        if !turn.is_finite() {
            return Err(invalid(format!(
                "orbit must be a finite number of degrees, got {turn}"
            )));
        }
        let cam_desc = match camera_toml {
            Some(t) => SceneDesc::from_toml(t, "camera").map_err(to_py)?.camera,
            None => self.desc.camera.clone(),
        };
        let view: Option<View> = view
            .map(|v| v.parse().map_err(|e| invalid(format!("view: {e}"))))
            .transpose()?;
        let p = &self.prepared;
        let mut settings = p.shot.settings.clone();
        // The same checks as a scene file's keys: the size against the memory allowance before
        // any buffer is allocated, spp within 1..=65536.
        if let Some((w, h)) = size {
            check_image_size(w, h).map_err(to_py)?;
            (settings.width, settings.height) = (w, h);
        }
        if let Some(s) = spp {
            check_spp(s).map_err(to_py)?;
            settings.spp = s;
        }
        if let Some(s) = seed {
            settings.seed = s;
        }
        let mut desc = SceneDesc {
            camera: cam_desc,
            ..SceneDesc::default()
        };
        let aspect = settings.width as f32 / settings.height as f32;
        if turn != 0.0 {
            desc.camera = turned(&desc, p, aspect, turn)?;
        }
        let mut shot = Shot {
            camera: camera(&desc, &p.framing, aspect).map_err(to_py)?,
            // The light turns with the camera (the environment as prepared without an orbit).
            turn_deg: turn as f32,
            view: view.unwrap_or_else(|| p.shot.view.clone()),
            settings,
            ..p.shot.clone()
        };
        if shot.view != View::Shaded {
            let (w, h, view) = (shot.settings.width, shot.settings.height, shot.view.clone());
            let world = WorldRef {
                camera: &shot.camera,
                ..(&p.scene).into()
            };
            let v = py
                .detach(|| render_view_of(world, view.clone(), w, h, None))
                .map_err(to_py)?;
            return Ok(Image::view(v, &view.to_string()));
        }
        let cancel = Arc::new(AtomicBool::new(false));
        let done = Arc::new(AtomicUsize::new(0));
        shot.settings.cancel = Some(cancel.clone());
        shot.settings.tiles_done = Some(done.clone());
        shot.settings.progress = false;
        let total = shot.settings.width.div_ceil(16) * shot.settings.height.div_ceil(16);
        let out = py.detach(|| {
            std::thread::scope(|s| {
                let (tx, rx) = mpsc::channel();
                let shot = &shot;
                s.spawn(move || {
                    let r = render(p, shot);
                    let _ = tx.send(r);
                });
                loop {
                    match rx.recv_timeout(POLL) {
                        Ok(r) => return r.map_err(to_py),
                        Err(mpsc::RecvTimeoutError::Disconnected) => {
                            return Err(invalid("render: the render thread stopped"));
                        }
                        Err(mpsc::RecvTimeoutError::Timeout) => {}
                    }
                    let polled = Python::attach(|py| -> PyResult<()> {
                        py.check_signals()?;
                        if let Some(cb) = &progress {
                            cb.call1(py, (done.load(Ordering::Relaxed), total))?;
                        }
                        Ok(())
                    });
                    if let Err(e) = polled {
                        cancel.store(true, Ordering::Relaxed);
                        let _ = rx.recv();
                        return Err(e);
                    }
                }
            })
        })?;
        if let Some(cb) = &progress {
            cb.call1(py, (total, total))?;
        }
        Ok(Image::shaded(out, shot.grade, shot.exposure, shot.tonemap))
    }
}
