//! Readers: particle files in, [`PointCloud`](crate::pointcloud::PointCloud) out.
//!
//! [`read_cloud`] picks the reader ([`detect_format`]) from the file's first bytes (magic),
//! else its extension, or for a directory its content, and every reader fills the same
//! [`PointCloud`](crate::pointcloud::PointCloud). What each format is (extensions, magic,
//! reader, size estimate, help) is one row of [`formats::FORMATS`].
//!
//! Each reader's docs give the thickness unit its writers use (nm for the generic file
//! formats, m for the thin-film SPH folders).
//!
//! Attribute names: positions are the format's positions (`x y z`, `POINTS`, `P`, `x_bin`).
//! Vector attributes become the scalar attributes `name_x name_y name_z` (other component
//! counts `name_0 ..`). Normals, thickness and radius are found by the first present name in
//! the format's alias lists ([`NORMAL_ALIASES`], [`THICKNESS_ALIASES`], [`RADIUS_ALIASES`];
//! frame folders use [`FRAME_NORMAL_ALIASES`] and [`FRAME_THICKNESS_ALIASES`]), unless
//! [`ReadOptions`] names them explicitly (then a missing name is an error). Every other
//! scalar attribute lands in [`PointCloud::extra`](crate::pointcloud::PointCloud::extra) as f32. Readers do not validate values.
//!
//! Triangle meshes (for comparing with meshed renders) are read by [`read_mesh`]: PLY with a
//! `face` element ([`ply::read_mesh`]; vertex attributes by the same aliases) or OBJ
//! ([`obj::read`]).
//!
//! Every reader checks counts against the file size before allocating and returns
//! [`Error::Format`] naming the file, the format and the problem (with the line or byte offset
//! where it applies); none panics on malformed input.

pub mod bgeo;
mod columns;
pub mod csv;
mod folder_hint;
pub mod formats;
pub mod frame_folder;
pub mod input;
mod melp;
pub mod melp_folder;
mod num;
pub mod obj;
mod part;
mod peek;
pub mod placeholder;
pub mod ply;
pub mod pvd;
mod read;
pub mod sim_arrays;
pub mod snapshot;
mod sources;
pub mod vtk;
pub mod vtu;
mod write_ply;
mod xml;

pub use formats::detect_format;
pub use obj::read_mesh;
pub use part::{CloudPart, PartKind};
pub use peek::{CountHint, peek_count};
pub use read::{read_as, read_bytes, read_cloud, read_cloud_described, read_parts, read_timestep};
pub use write_ply::{write_droplets_ply, write_mesh_ply, write_ply};

use std::path::Path;

use crate::error::{Error, Result};

/// Thickness attribute names tried in order: `rh` (film thickness), `thickness`, `h`.
/// Beware that SPH files often use `h` for the smoothing length; name the attribute
/// explicitly ([`ReadOptions::thickness_attr`]) if so.
pub const THICKNESS_ALIASES: &[&str] = &["rh", "thickness", "h"];

/// Normal attribute prefixes tried in order; a prefix `p` means the three attributes `px py pz`
/// or `p_x p_y p_z`: `n` → `nx ny nz`, `normal` → `normal_x normal_y normal_z`,
/// `normals`/`Normals` (VTK) and `N` (Houdini) → `N_x N_y N_z` (vectors are split that way).
pub const NORMAL_ALIASES: &[&str] = &["n", "normal", "normals", "Normals", "N"];

/// Thickness names tried in a frame folder (`rh_bin`, then `h_bin`).
pub const FRAME_THICKNESS_ALIASES: &[&str] = &["rh", "h"];

/// Normal names tried in a frame folder: `norm` (`norm_bin`), then [`NORMAL_ALIASES`].
pub const FRAME_NORMAL_ALIASES: &[&str] = &["norm", "n", "normal", "normals", "Normals", "N"];

/// Radius attribute names tried in order: `radius`, `pscale` (Houdini's per-point scale).
pub const RADIUS_ALIASES: &[&str] = &["radius", "pscale"];

/// How to read a particle file.
#[derive(Debug, Clone, PartialEq)]
pub struct ReadOptions {
    /// Factor turning the file's thickness values into nanometres: 1 for nm, 1e3 for µm,
    /// 1e9 for m. Must be finite and positive. Default 1. Used only if
    /// [`Self::thickness_unit_explicit`] is true.
    pub thickness_scale_to_nm: f64,
    /// True: the file's thickness is in the unit given by [`Self::thickness_scale_to_nm`].
    /// False (default): the format's own unit is used and the scale is ignored: metres for a
    /// frame folder (scale 1e9), nanometres for every other format.
    pub thickness_unit_explicit: bool,
    /// Thickness attribute name; `None` tries [`THICKNESS_ALIASES`].
    pub thickness_attr: Option<String>,
    /// Normal attribute prefix (`"n"` → `nx ny nz`, `"normal"` → `normal_x ..`); `None` tries
    /// [`NORMAL_ALIASES`].
    pub normal_attr: Option<String>,
    /// Radius attribute name; `None` tries [`RADIUS_ALIASES`].
    pub radius_attr: Option<String>,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            thickness_scale_to_nm: 1.0,
            thickness_unit_explicit: false,
            thickness_attr: None,
            normal_attr: None,
            radius_attr: None,
        }
    }
}

impl ReadOptions {
    /// Options for thickness in the unit `scale_to_nm` (nm per file unit), overriding the
    /// format's default unit; other fields default.
    pub fn with_thickness_scale(scale_to_nm: f64) -> Self {
        ReadOptions {
            thickness_scale_to_nm: scale_to_nm,
            thickness_unit_explicit: true,
            ..ReadOptions::default()
        }
    }

    /// The factor to apply to a format whose default unit is `format_default_to_nm` nm:
    /// [`Self::thickness_scale_to_nm`] if the unit is explicit, else the format's default.
    pub fn thickness_scale(&self, format_default_to_nm: f64) -> f64 {
        if self.thickness_unit_explicit {
            self.thickness_scale_to_nm
        } else {
            format_default_to_nm
        }
    }

    /// These options reading thickness in the unit named `unit` (`nm`, `um` or `µm`, `mm`,
    /// `m`), overriding the format's own; `None` keeps them as they are.
    ///
    /// # Errors
    /// [`Error::Invalid`] for another unit name.
    pub fn with_unit(mut self, unit: Option<&str>) -> Result<Self> {
        if let Some(u) = unit {
            let u: ThicknessUnit = u.parse().map_err(Error::invalid)?;
            self.thickness_scale_to_nm = u.nm_per_unit();
            self.thickness_unit_explicit = true;
        }
        Ok(self)
    }

    /// Checks the options themselves (not the file).
    ///
    /// # Errors
    /// [`Error::Invalid`] if `thickness_scale_to_nm` is not finite and positive.
    pub fn check(&self) -> Result<()> {
        let s = self.thickness_scale_to_nm;
        if !(s.is_finite() && s > 0.0) {
            return Err(Error::invalid(format!(
                "thickness scale to nm must be finite and positive, got {s}"
            )));
        }
        Ok(())
    }
}

/// A unit of the thickness values in a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ThicknessUnit {
    /// Nanometres.
    Nm,
    /// Micrometres (`um` or `µm`).
    Um,
    /// Millimetres.
    Mm,
    /// Metres.
    M,
}

impl ThicknessUnit {
    /// Nanometres in one of this unit.
    pub fn nm_per_unit(self) -> f64 {
        match self {
            ThicknessUnit::Nm => 1.0,
            ThicknessUnit::Um => 1e3,
            ThicknessUnit::Mm => 1e6,
            ThicknessUnit::M => 1e9,
        }
    }
}

impl std::str::FromStr for ThicknessUnit {
    type Err = String;

    fn from_str(unit: &str) -> std::result::Result<Self, String> {
        match unit {
            "nm" => Ok(ThicknessUnit::Nm),
            "um" | "µm" => Ok(ThicknessUnit::Um),
            "mm" => Ok(ThicknessUnit::Mm),
            "m" => Ok(ThicknessUnit::M),
            _ => Err(format!(
                "thickness unit '{unit}' is not one of nm, um, mm, m"
            )),
        }
    }
}

/// A particle file format filmsplat can read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum CloudFormat {
    /// Stanford PLY (ASCII or binary), read by [`ply`].
    Ply,
    /// VTK legacy `.vtk` (ASCII or binary), read by [`vtk`].
    VtkLegacy,
    /// VTK XML `.vtu` / `.vtp`, read by [`vtu`].
    VtkXml,
    /// Houdini classic BGEO (V5), plain or gzip-compressed, read by [`bgeo`].
    Bgeo,
    /// Delimited text with a header line naming the columns, read by [`csv`].
    Csv,
    /// A directory of `*_bin` files (`x_bin`, `norm_bin`, `rh_bin`, ...), read by
    /// [`frame_folder::read`]; with the droplets of a ruptured film (`*_3d`) as a second part.
    FrameFolder,
    /// A thin-film SPH snapshot folder (`snapshot/<frame>/`: `x.bin`, `e.bin`, `rh.bin`, ...
    /// and the droplets in `3d/`), read by [`snapshot::read_parts`].
    SnapshotFolder,
    /// A MELP foam frame folder (`l_tracker_points_R`, `l_h_bin_R`, ... per bubble R), read by
    /// [`melp_folder::read_parts`].
    MelpFolder,
    /// A ParaView `.pvd` collection of VTK XML files, read by [`read_timestep`].
    Pvd,
}

impl CloudFormat {
    /// Display name, e.g. `"PLY"` (its row of [`formats::FORMATS`]).
    pub fn name(self) -> &'static str {
        formats::info(self).name
    }
}

/// What filmsplat reads a stored attribute as.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AttributeRole {
    /// Particle positions (or one of their components).
    Position,
    /// Surface normals (or one component).
    Normal,
    /// Film thickness.
    Thickness,
    /// Splat radius.
    Radius,
    /// Kept as an extra attribute ([`PointCloud::extra`](crate::pointcloud::PointCloud::extra)).
    Extra,
    /// Not read (e.g. a PLY list property).
    Skipped,
}

impl std::fmt::Display for AttributeRole {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            AttributeRole::Position => "position",
            AttributeRole::Normal => "normal",
            AttributeRole::Thickness => "thickness",
            AttributeRole::Radius => "radius",
            AttributeRole::Extra => "extra",
            AttributeRole::Skipped => "skipped",
        })
    }
}

/// One attribute as the file stores it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StoredAttribute {
    /// The name in the file (`x`, `nx`, `POINTS`, `P`, `rh_bin` as `rh`, ...).
    pub name: String,
    /// The stored number type: `int8` .. `uint64`, `float32`, `float64`, `text` (CSV), or a
    /// PLY list such as `list uint8 int32`.
    pub stored: String,
    /// Values per particle (1 scalar, 3 vector).
    pub components: usize,
    /// What filmsplat reads it as.
    pub role: AttributeRole,
}

impl StoredAttribute {
    pub(crate) fn new(
        name: &str,
        stored: impl Into<String>,
        components: usize,
        role: AttributeRole,
    ) -> Self {
        StoredAttribute {
            name: name.to_string(),
            stored: stored.into(),
            components,
            role,
        }
    }
}

/// The scalar columns a `k`-component attribute `name` is split into (`name`, or
/// `name_x name_y name_z`, or `name_0 ..`): the names of its [`PointCloud::extra`](crate::pointcloud::PointCloud::extra) entries.
pub fn component_names(name: &str, k: usize) -> Vec<String> {
    columns::component_names(name, k)
}

/// An attribute name from a file made safe to print on one line (escaped, at most 40 chars).
pub fn show_name(name: &str) -> String {
    columns::show(name)
}

/// Reads a whole regular file (or pipe), refusing directories, devices and what does not fit in
/// memory (see [`input::read_all`]).
fn read_file(path: &Path) -> Result<Vec<u8>> {
    input::read_all(path, &|_| Ok(()))
}

/// Shorthand for an [`Error::Format`].
fn format_error(path: &Path, format: &'static str, message: impl Into<String>) -> Error {
    Error::Format {
        path: path.to_path_buf(),
        format,
        message: message.into(),
    }
}
