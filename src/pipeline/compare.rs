//! The pipeline behind `filmsplat compare`: one scene rendered with two geometries (splats,
//! a mesh from disk, or a mesh reconstructed from the cloud), with the same camera, lights,
//! shader and sampler, and the metrics between the two pictures.

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::time::{Duration, Instant};

use super::load::load_cloud;
use super::prepare;
use super::prepared::Prepared;
use crate::geometry::{MeshGeometry, MeshSides, Primitive};
use crate::image::RgbImage;
use crate::image::metrics::{DeltaEStats, delta_e_map, delta_e_stats, psnr, ssim};
use crate::io::{ReadOptions, read_mesh};
use crate::pointcloud::{PointCloud, Transfer, TriangleMesh, transfer_thickness};
use crate::render::RenderOutput;
use crate::scene::SceneDesc;
use crate::{Error, Result};

/// A geometry to compare.
#[derive(Clone, Debug, PartialEq)]
pub enum GeometryChoice {
    /// The particles drawn as a primitive (blended disks, spheres, the MLS surface).
    Particles(Primitive),
    /// A triangle mesh read from a PLY or OBJ file.
    Mesh(PathBuf),
    /// A mesh reconstructed from the cloud in-process (cargo feature `reconstruct`).
    Reconstructed,
}

impl FromStr for GeometryChoice {
    type Err = Error;

    /// `disk`, `sphere`, `mls`, `mesh:FILE` or `reconstructed`.
    fn from_str(s: &str) -> Result<Self> {
        if let Some(path) = s.strip_prefix("mesh:") {
            if path.is_empty() {
                return Err(Error::invalid("geometry 'mesh:' needs a file: mesh:FILE"));
            }
            return Ok(GeometryChoice::Mesh(PathBuf::from(path)));
        }
        let name = s.to_ascii_lowercase();
        if let Some(p) = Primitive::ALL.into_iter().find(|p| p.name() == name) {
            return Ok(GeometryChoice::Particles(p));
        }
        match name.as_str() {
            "reconstructed" => Ok(GeometryChoice::Reconstructed),
            _ => Err(Error::invalid(format!(
                "unknown geometry '{s}' (expected disk, sphere, mls, mesh:FILE or reconstructed)"
            ))),
        }
    }
}

impl fmt::Display for GeometryChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GeometryChoice::Particles(p) => f.write_str(p.name()),
            GeometryChoice::Mesh(p) => write!(
                f,
                "mesh {}",
                p.file_name().map_or(p.as_os_str(), |n| n).to_string_lossy()
            ),
            GeometryChoice::Reconstructed => f.write_str("reconstructed mesh"),
        }
    }
}

/// Which crossings of a mesh are films (see [`MeshSides`]).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum ShellOption {
    /// Every crossing, but warn if the mesh looks like a thin closed shell.
    #[default]
    Auto,
    /// Every crossing, no check.
    All,
    /// Merge the two walls of a thin shell: with the given distance, or the detected wall
    /// width × 1.5.
    Merge(Option<f32>),
}

impl FromStr for ShellOption {
    type Err = Error;

    /// `auto`, `all`, `merge` or `merge:DIST` (scene units).
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "auto" => Ok(ShellOption::Auto),
            "all" => Ok(ShellOption::All),
            "merge" => Ok(ShellOption::Merge(None)),
            _ => match s.strip_prefix("merge:").map(str::parse::<f32>) {
                Some(Ok(d)) if d.is_finite() && d > 0.0 => Ok(ShellOption::Merge(Some(d))),
                _ => Err(Error::invalid(format!(
                    "--shell: '{s}' is not auto, all, merge or merge:DIST (DIST > 0)"
                ))),
            },
        }
    }
}

/// How meshes are turned into films.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct MeshOptions {
    /// Shell handling.
    pub shell: ShellOption,
    /// How a mesh without thickness gets the cloud's.
    pub transfer: Transfer,
}

/// One side of a comparison, ready to render.
#[derive(Debug)]
pub struct Variant {
    /// What draws the films.
    pub choice: GeometryChoice,
    /// Scene, shader, settings.
    pub prepared: Prepared,
    /// Time spent reconstructing a mesh from the cloud (only for `reconstructed`).
    pub meshing_time: Option<Duration>,
    /// Time spent reading the mesh and giving it thickness (meshes only).
    pub mesh_time: Option<Duration>,
}

/// Prepares `desc` drawn with `choice`. Meshes take the camera, lights and settings the scene
/// gets with disks; the caller makes both sides share one camera (see [`prepare_pair`]).
pub fn prepare_variant(
    desc: &SceneDesc,
    base: &Path,
    choice: &GeometryChoice,
    mesh: &MeshOptions,
    progress: bool,
) -> Result<Variant> {
    let mut d = desc.clone();
    // A mesh takes the scene as it is prepared with disks.
    let primitive = match choice {
        GeometryChoice::Particles(p) => *p,
        GeometryChoice::Mesh(_) | GeometryChoice::Reconstructed => Primitive::Disk,
    };
    d.film.primitive = Some(primitive.name().to_string());
    let mut prepared = prepare(&d, base, progress)?;
    let (meshing_time, mesh_time) = match choice {
        GeometryChoice::Mesh(path) => {
            let t = Instant::now();
            let m = read_mesh(&base.join(path), &mesh_read_options(desc)?)?;
            let label = base.join(path).display().to_string();
            mesh_into(&mut prepared, desc, base, m, mesh, &label)?;
            (None, Some(t.elapsed()))
        }
        GeometryChoice::Reconstructed => {
            let (m, meshing, note) = reconstruct(desc, base)?;
            prepared.note(note);
            let t = Instant::now();
            mesh_into(&mut prepared, desc, base, m, mesh, "reconstructed mesh")?;
            (Some(meshing), Some(t.elapsed()))
        }
        _ => (None, None),
    };
    Ok(Variant {
        choice: choice.clone(),
        prepared,
        meshing_time,
        mesh_time,
    })
}

/// Prepares both sides; the second uses the first one's camera, so only the geometry differs.
pub fn prepare_pair(
    desc: &SceneDesc,
    base: &Path,
    choices: [&GeometryChoice; 2],
    mesh: &MeshOptions,
    progress: bool,
) -> Result<[Variant; 2]> {
    let a = prepare_variant(desc, base, choices[0], mesh, progress)?;
    let mut b = prepare_variant(desc, base, choices[1], mesh, progress)?;
    b.prepared.shot.camera = a.prepared.shot.camera;
    Ok([a, b])
}

/// Reader options for a mesh's vertex attributes, from the scene's input and film sections.
fn mesh_read_options(desc: &SceneDesc) -> Result<ReadOptions> {
    ReadOptions {
        thickness_attr: desc.input.thickness_attr.clone(),
        normal_attr: desc.input.normal_attr.clone(),
        ..ReadOptions::default()
    }
    .with_unit(desc.film.thickness_unit.as_deref())
}

/// Replaces the prepared geometry by `mesh`, giving it the cloud's thickness if it has none.
fn mesh_into(
    p: &mut Prepared,
    desc: &SceneDesc,
    base: &Path,
    mesh: TriangleMesh,
    opts: &MeshOptions,
    label: &str,
) -> Result<()> {
    let TriangleMesh {
        mut vertices,
        triangles,
    } = mesh;
    if triangles.is_empty() {
        return Err(Error::invalid(format!(
            "{label}: the mesh has no triangles"
        )));
    }
    let thickness = mesh_thickness(p, desc, base, &mut vertices, opts.transfer, label)?;
    let normals = vertices.normals.unwrap_or_default();
    let mut g = MeshGeometry::build(&vertices.positions, &triangles, &normals, &thickness)
        .map_err(|e| Error::invalid(format!("{label}: {e}")))?;
    let shell = match opts.shell {
        ShellOption::All => None,
        _ => g.shell_width(2000),
    };
    match (opts.shell, shell) {
        (ShellOption::Merge(Some(d)), _) => g.set_sides(MeshSides::Merge(d)),
        (ShellOption::Merge(None), Some(w)) => {
            g.set_sides(MeshSides::Merge(1.5 * w));
            p.note(format!(
                "{label}: thin closed shell (walls {w:.4} apart); merging hits within {:.4}",
                1.5 * w
            ));
        }
        (ShellOption::Merge(None), None) => p.note(format!(
            "{label}: not a thin closed shell; every crossing is a film"
        )),
        (ShellOption::Auto, Some(w)) => p.note(format!(
            "warning: {label} looks like a thin closed shell (walls {w:.4} apart): every film \
             crossing is drawn twice; --shell merge draws one film per crossing"
        )),
        _ => {}
    }
    p.particles = triangles.len();
    p.scene.layer_skip = p.scene.epsilon;
    p.scene.geometry = g.into();
    Ok(())
}

/// A mesh's thickness, nm: its vertices' own (scaled), else transferred from the scene's
/// particles, else the default; says which in a note.
fn mesh_thickness(
    p: &mut Prepared,
    desc: &SceneDesc,
    base: &Path,
    vertices: &mut PointCloud,
    transfer: Transfer,
    label: &str,
) -> Result<Vec<f32>> {
    let scale = desc.film.thickness_scale.unwrap_or(1.0);
    let default = desc.film.default_thickness_nm.unwrap_or(500.0);
    if let Some(mut t) = vertices.thickness_nm.take() {
        t.iter_mut().for_each(|v| *v *= scale);
        p.note(format!("{label}: thickness from the mesh's vertices"));
        return Ok(t);
    }
    let cloud = load_cloud(desc, base)?;
    let Some(ct) = cloud.thickness_nm else {
        p.note(format!(
            "{label}: neither the mesh nor the cloud has thickness; {default} nm"
        ));
        return Ok(vec![default; vertices.positions.len()]);
    };
    let ct: Vec<f32> = ct.iter().map(|v| v * scale).collect();
    p.note(format!(
        "{label}: no thickness; transferred from the {} particles ({})",
        cloud.positions.len(),
        match transfer {
            Transfer::Nearest => "nearest particle".to_string(),
            Transfer::Kernel { k } => format!("SPH kernel over {k} neighbours"),
        }
    ));
    Ok(transfer_thickness(
        &cloud.positions,
        &ct,
        &vertices.positions,
        transfer,
        default,
    ))
}

/// Reconstructs a mesh around the scene's cloud (cargo feature `reconstruct`); returns it with
/// the time the meshing took and a note on the parameters.
#[cfg(not(feature = "reconstruct"))]
fn reconstruct(_desc: &SceneDesc, _base: &Path) -> Result<(TriangleMesh, Duration, String)> {
    Err(Error::invalid(
        "geometry 'reconstructed' needs filmsplat built with `--features reconstruct`; \
         or mesh the cloud elsewhere (e.g. splashsurf) and use mesh:FILE",
    ))
}

#[cfg(feature = "reconstruct")]
fn reconstruct(desc: &SceneDesc, base: &Path) -> Result<(TriangleMesh, Duration, String)> {
    let cloud = load_cloud(desc, base)?;
    let t = Instant::now();
    let (m, note) = super::reconstruct::reconstruct(&cloud)?;
    Ok((m, t.elapsed(), note))
}

/// The picture as displayed (a render of `p`'s default shot): exposure and tone curve applied, linear RGB in `[0, 1]` (what the
/// metrics compare).
pub fn display_image(p: &Prepared, out: &RenderOutput) -> Result<RgbImage> {
    let gain = p.shot.exposure.exp2();
    let data = out
        .rgb
        .iter()
        .map(|c| c.to_array().map(|v| p.shot.tonemap.apply(v * gain)))
        .collect();
    RgbImage::from_data(out.width, out.height, data)
}

/// The differences between two displayed pictures.
#[derive(Clone, Debug)]
pub struct Metrics {
    /// PSNR of the sRGB-encoded pictures, dB (infinite for identical pictures).
    pub psnr_db: f64,
    /// Mean SSIM of the luma.
    pub ssim: f64,
    /// CIEDE2000 summary.
    pub delta_e: DeltaEStats,
    /// Per-pixel CIEDE2000, row-major.
    pub delta_e_map: Vec<f32>,
}

/// PSNR, SSIM and CIEDE2000 between two displayed pictures of the same size.
pub fn metrics(a: &RgbImage, b: &RgbImage) -> Result<Metrics> {
    Ok(Metrics {
        psnr_db: psnr(a, b)?,
        ssim: ssim(a, b)?,
        delta_e: delta_e_stats(a, b)?,
        delta_e_map: delta_e_map(a, b)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::linear_to_srgb;
    use crate::image::metrics::{delta_e2000, linear_srgb_to_lab};

    #[test]
    fn choices_and_shell_options_parse() {
        assert_eq!(
            "Disk".parse::<GeometryChoice>().unwrap(),
            GeometryChoice::Particles(Primitive::Disk)
        );
        for p in Primitive::ALL {
            let choice = GeometryChoice::Particles(p);
            assert_eq!(
                choice.to_string().parse::<GeometryChoice>().unwrap(),
                choice
            );
        }
        assert_eq!(
            "mesh:a/b.obj".parse::<GeometryChoice>().unwrap(),
            GeometryChoice::Mesh("a/b.obj".into())
        );
        assert_eq!(
            GeometryChoice::Mesh("a/b.obj".into()).to_string(),
            "mesh b.obj"
        );
        assert!("mesh:".parse::<GeometryChoice>().is_err());
        assert!("cube".parse::<GeometryChoice>().is_err());
        assert_eq!(
            "merge:0.5".parse::<ShellOption>().unwrap(),
            ShellOption::Merge(Some(0.5))
        );
        for bad in ["merge:-1", "merge:x", "both"] {
            assert!(bad.parse::<ShellOption>().is_err(), "{bad}");
        }
    }

    #[test]
    fn a_uniform_shift_gives_the_analytic_metrics() {
        // Two flat grey pictures: every sRGB value differs by δ, so PSNR = −20 log10 δ; SSIM
        // reduces to its luminance term (2 μa μb + C1) / (μa² + μb² + C1); ΔE is the pair's.
        let (x, y) = (0.2f32, 0.25f32);
        let a = RgbImage::filled(32, 24, [x; 3]);
        let b = RgbImage::filled(32, 24, [y; 3]);
        let m = metrics(&a, &b).unwrap();
        let (ea, eb) = (linear_to_srgb(x) as f64, linear_to_srgb(y) as f64);
        let want_psnr = -20.0 * (eb - ea).abs().log10();
        assert!(
            (m.psnr_db - want_psnr).abs() < 1e-4,
            "{} {want_psnr}",
            m.psnr_db
        );
        let c1 = 0.01f64.powi(2);
        let want_ssim = (2.0 * ea * eb + c1) / (ea * ea + eb * eb + c1);
        assert!((m.ssim - want_ssim).abs() < 1e-6, "{} {want_ssim}", m.ssim);
        let de = delta_e2000(linear_srgb_to_lab([x; 3]), linear_srgb_to_lab([y; 3]));
        assert!((m.delta_e.mean - de).abs() < 1e-4 && (m.delta_e.p95 - de).abs() < 1e-4);
        assert!(m.delta_e_map.iter().all(|&v| (v as f64 - de).abs() < 1e-4));
        let same = metrics(&a, &a).unwrap();
        assert!(same.psnr_db.is_infinite() && same.ssim == 1.0 && same.delta_e.max == 0.0);
    }
}
