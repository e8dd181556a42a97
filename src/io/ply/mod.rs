//! PLY reader (ASCII, binary little- and big-endian) for particle clouds and, with
//! [`read_mesh`], triangle meshes.
//!
//! Reads element `vertex`: positions `x y z` (required), normals, thickness and radius by the
//! aliases in [`crate::io`] (or the names given in [`ReadOptions`]), and every other scalar vertex
//! property into [`PointCloud::extra`] as f32 (so integers above 2^24 lose precision; f64
//! positions are narrowed to f32). List properties are skipped (except a mesh's face
//! indices, see [`read_mesh`]); elements before `vertex` are
//! skipped, elements after it are not read at all.
//!
//! Binary bodies are decoded column by column from 1 MiB chunks of whole records, each column by
//! a loop specialised for its type and byte order, so reading costs about as much as reading
//! the file's bytes. Before allocating, the element counts are checked against the file size.
//! ASCII bodies must hold one record per line (blank lines are ignored).
//! Values are not validated here (NaN positions are read as NaN).

mod ascii;
mod binary;
mod header;
pub(crate) use header::header_count;
mod source;

use std::fs::File;
use std::io::{self, Read};
use std::path::Path;

use glam::Vec3;

use self::header::{Element, Encoding, Header, PropKind};
use crate::error::{Error, Result};
use crate::io::columns::{STANDARD, resolve_roles};
use crate::io::{AttributeRole, ReadOptions, StoredAttribute};
use crate::pointcloud::{PointCloud, TriangleMesh};

/// Name used in error messages.
const FORMAT: &str = "PLY";

/// Reads the PLY file at `path` (streamed in 1 MiB chunks) into a [`PointCloud`] and every
/// vertex property with its type and role ([`StoredAttribute`]s); `opts` are checked by the
/// caller, [`crate::io::read_cloud`] or [`crate::io::read_as`] (see the module docs for what is
/// read).
///
/// Cost: one pass over the file; peak memory is the cloud plus a 1 MiB buffer.
///
/// # Errors
/// [`Error::Io`] if the file cannot be opened or read (missing, a directory, ...);
/// [`Error::Format`] naming the file and the problem for a malformed file or a missing or
/// ill-typed attribute.
pub(crate) fn read_file(
    path: &Path,
    opts: &ReadOptions,
) -> Result<(PointCloud, Vec<StoredAttribute>)> {
    with_file(path, |file, len| read_from(file, len, opts))
}

/// True if the PLY file at `path` marks its vertices as droplets (its header holds
/// `comment filmsplat part droplets`, as [`crate::io::write_droplets_ply`] writes). Reads the
/// header only.
///
/// # Errors
/// As [`read_file`], for a file whose header cannot be read.
pub(crate) fn holds_droplets(path: &Path) -> Result<bool> {
    with_file(path, |file, len| {
        let mut src = source::Source::new(file, len);
        Ok(header::parse(&mut src)?.droplets)
    })
}

/// Opens the file at `path` (refusing directories) and runs `read` on it with the file's length
/// (a regular file's length bounds its content; a pipe is first read into memory, bounded, by
/// [`crate::io::input::read_all`]). Failures become
/// [`Error::Io`] or [`Error::Format`] naming the file.
fn with_file<T>(
    path: &Path,
    read: impl FnOnce(Box<dyn Read>, Option<u64>) -> Result<T, Fail>,
) -> Result<T> {
    let len = match crate::io::input::kind(path)? {
        crate::io::input::Kind::File(len) => Some(len),
        crate::io::input::Kind::Dir => {
            return Err(Error::io(
                path,
                io::Error::new(io::ErrorKind::IsADirectory, "is a directory"),
            ));
        }
        // A pipe is read once, into memory, with a bound.
        _ => {
            let bytes = crate::io::input::read_all(path, &|_| Ok(()))?;
            let len = bytes.len() as u64;
            return read(Box::new(io::Cursor::new(bytes)), Some(len))
                .map_err(|f| fail_to_error(path, f));
        }
    };
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    read(Box::new(file), len).map_err(|f| fail_to_error(path, f))
}

/// The library error for a failure reading `path`.
fn fail_to_error(path: &Path, f: Fail) -> Error {
    match f {
        Fail::Io(e) => Error::io(path, e),
        Fail::Msg(message) => Error::Format {
            path: path.to_path_buf(),
            format: FORMAT,
            message,
        },
    }
}

/// [`read_file`] for a file's content already in memory; `path` only names the source in
/// errors. Never panics, whatever the bytes.
pub(crate) fn parse_bytes(
    bytes: &[u8],
    path: &Path,
    opts: &ReadOptions,
) -> Result<(PointCloud, Vec<StoredAttribute>)> {
    read_from(bytes, Some(bytes.len() as u64), opts).map_err(|f| fail_to_error(path, f))
}

/// Internal failure: an I/O error or a message about the content (the path is added later).
#[derive(Debug)]
enum Fail {
    Io(io::Error),
    Msg(String),
}

impl Fail {
    fn msg(m: impl Into<String>) -> Self {
        Fail::Msg(m.into())
    }
}

impl From<io::Error> for Fail {
    fn from(e: io::Error) -> Self {
        Fail::Io(e)
    }
}

/// Reads a whole PLY stream; `len` is its total length if known (enables the size check).
fn read_from<R: Read>(
    reader: R,
    len: Option<u64>,
    opts: &ReadOptions,
) -> Result<(PointCloud, Vec<StoredAttribute>), Fail> {
    let mut src = source::Source::new(reader, len);
    let header = header::parse(&mut src)?;
    let vi = header
        .elements
        .iter()
        .position(|e| e.name == "vertex")
        .ok_or_else(|| Fail::msg("no 'vertex' element in the header"))?;
    let plan = resolve(&header.elements[vi], opts).map_err(Fail::Msg)?;
    let count = header.elements[vi].count;
    let reserve = match len {
        Some(len) => {
            check_sizes(&header, vi, len.saturating_sub(src.position()))?;
            count
        }
        None => count.min(1 << 16),
    };
    let mut out = Outputs::new(&plan, usize::try_from(reserve).unwrap_or(usize::MAX));
    match header.encoding {
        Encoding::Ascii => {
            ascii::read(&mut src, &header, vi, &plan, &mut out)?;
        }
        Encoding::BinaryLe => binary::read::<R, false>(&mut src, &header, vi, &plan, &mut out)?,
        Encoding::BinaryBe => binary::read::<R, true>(&mut src, &header, vi, &plan, &mut out)?,
    }
    Ok(out.into_cloud(plan, opts.thickness_scale(1.0)))
}

/// Reads the PLY mesh at `path`: element `vertex` as `read_file` reads it (positions, normals,
/// thickness by the same aliases, extras), and element `face`, whose list property
/// `vertex_indices` (or `vertex_index`) gives each polygon's vertices. Polygons are
/// fan-triangulated; faces with fewer than three vertices are skipped. `face` must come after
/// `vertex` (as every writer puts it); other elements are skipped.
///
/// # Errors
/// As `read_file`, plus [`Error::Format`] if there is no `face` element or index list, an index
/// is not an integer or is beyond the vertex count (naming the face).
pub fn read_mesh(path: &Path, opts: &ReadOptions) -> Result<TriangleMesh> {
    opts.check()?;
    with_file(path, |file, len| read_mesh_from(file, len, opts))
}

/// Triangles being collected from a face element.
pub(super) struct Faces {
    vertices: usize,
    triangles: Vec<[u32; 3]>,
}

impl Faces {
    /// Checks a polygon's indices and adds its fan triangulation.
    pub(super) fn push(&mut self, poly: &[f64]) -> Result<(), String> {
        if let Some(&bad) = poly
            .iter()
            .find(|&&x| !(x >= 0.0 && x.fract() == 0.0 && x < self.vertices as f64))
        {
            return Err(format!(
                "vertex index {bad} is not one of the {} vertices",
                self.vertices
            ));
        }
        for k in 1..poly.len().saturating_sub(1) {
            self.triangles
                .push([poly[0] as u32, poly[k] as u32, poly[k + 1] as u32]);
        }
        Ok(())
    }
}

fn read_mesh_from<R: Read>(
    reader: R,
    len: Option<u64>,
    opts: &ReadOptions,
) -> Result<TriangleMesh, Fail> {
    let mut src = source::Source::new(reader, len);
    let header = header::parse(&mut src)?;
    let find = |name: &str| header.elements.iter().position(|e| e.name == name);
    let vi = find("vertex").ok_or_else(|| Fail::msg("no 'vertex' element in the header"))?;
    let fi = find("face")
        .ok_or_else(|| Fail::msg("no 'face' element in the header (a point cloud, not a mesh?)"))?;
    if fi < vi {
        return Err(Fail::msg(
            "the 'face' element comes before 'vertex' (not supported; write vertices first)",
        ));
    }
    let face = &header.elements[fi];
    let li = face
        .props
        .iter()
        .position(|p| p.name == "vertex_indices" || p.name == "vertex_index")
        .ok_or_else(|| Fail::msg("element 'face' has no 'vertex_indices' list"))?;
    match face.props[li].kind {
        PropKind::List { item, .. } if item.is_integer() => {}
        _ => {
            return Err(Fail::msg(
                "face property 'vertex_indices' must be a list of integers",
            ));
        }
    }
    let plan = resolve(&header.elements[vi], opts).map_err(Fail::Msg)?;
    let count = header.elements[vi].count;
    let reserve = match len {
        Some(len) => {
            check_sizes(&header, fi, len.saturating_sub(src.position()))?;
            count
        }
        None => count.min(1 << 16),
    };
    let mut out = Outputs::new(&plan, usize::try_from(reserve).unwrap_or(usize::MAX));
    let mut faces = Faces {
        vertices: usize::try_from(count).unwrap_or(usize::MAX),
        triangles: Vec::new(),
    };
    let at = (vi, fi, li);
    match header.encoding {
        Encoding::Ascii => {
            let line = ascii::read(&mut src, &header, vi, &plan, &mut out)?;
            ascii::read_faces(&mut src, &header, at, line, &mut faces)?;
        }
        Encoding::BinaryLe => {
            binary::read::<R, false>(&mut src, &header, vi, &plan, &mut out)?;
            binary::read_faces::<R, false>(&mut src, &header, at, &mut faces)?;
        }
        Encoding::BinaryBe => {
            binary::read::<R, true>(&mut src, &header, vi, &plan, &mut out)?;
            binary::read_faces::<R, true>(&mut src, &header, at, &mut faces)?;
        }
    }
    Ok(TriangleMesh {
        vertices: out.into_cloud(plan, opts.thickness_scale(1.0)).0,
        triangles: faces.triangles,
    })
}

/// Checks that the body can hold the elements up to and including `vertex` (index `vi`), before
/// anything is allocated from the header's counts.
fn check_sizes(header: &Header, vi: usize, body_len: u64) -> Result<(), Fail> {
    let mut need: u128 = 0;
    for e in &header.elements[..=vi] {
        let min = u128::from(e.min_record_bytes(header.encoding));
        let total = min * u128::from(e.count);
        if need + total > u128::from(body_len) {
            let at = (u128::from(body_len) - need) / min; // min > 0 since total > 0
            let exact = header.elements[..=vi]
                .iter()
                .all(|e| header.encoding != Encoding::Ascii && e.fixed_stride().is_some());
            return Err(Fail::msg(format!(
                "file too short for its header: data runs out {}{} {at} of {} \
                 (the header needs at least {} bytes after end_header, the file has {body_len})",
                if exact { "in " } else { "at or before " },
                header::show(&e.name),
                e.count,
                need + total
            )));
        }
        need += total;
    }
    Ok(())
}

impl Target {
    /// What the property is read as.
    fn role(self) -> AttributeRole {
        match self {
            Target::Pos(_) => AttributeRole::Position,
            Target::Normal(_) => AttributeRole::Normal,
            Target::Thickness => AttributeRole::Thickness,
            Target::Radius => AttributeRole::Radius,
            Target::Extra(_) => AttributeRole::Extra,
            Target::Ignore => AttributeRole::Skipped,
        }
    }
}

/// Where one vertex property goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Target {
    /// Position component 0..3.
    Pos(usize),
    /// Normal component 0..3.
    Normal(usize),
    Thickness,
    Radius,
    /// Index into [`Plan::extra_names`].
    Extra(usize),
    /// A list property (skipped).
    Ignore,
}

/// The decode plan: one target per vertex property, in file order.
#[derive(Debug)]
struct Plan {
    targets: Vec<Target>,
    extra_names: Vec<String>,
    has_normals: bool,
    has_thickness: bool,
    has_radius: bool,
    /// The vertex properties as stored, for `filmsplat info`.
    stored: Vec<StoredAttribute>,
}

/// Maps the vertex properties to targets by the shared rules
/// ([`crate::io::columns::resolve_roles`]): `x y z` are the positions, then explicit names
/// (absent = error), then aliases. A list property cannot play a role.
fn resolve(v: &Element, opts: &ReadOptions) -> Result<Plan, String> {
    let names: Vec<&str> = v.props.iter().map(|p| p.name.as_str()).collect();
    let list = || {
        let l: Vec<String> = names.iter().map(|n| header::show(n)).collect();
        format!("vertex has: {}", l.join(", "))
    };
    let find = |name: &str| names.iter().position(|&n| n == name);
    let mut pos = [0usize; 3];
    for (c, axis) in ["x", "y", "z"].into_iter().enumerate() {
        pos[c] =
            find(axis).ok_or_else(|| format!("vertex has no '{axis}' property ({})", list()))?;
    }
    let taken = pos.map(|i| (i, "position"));
    let roles = resolve_roles(&names, &taken, opts, &STANDARD, &list)?;
    let mut targets: Vec<Option<Target>> = vec![None; names.len()];
    for (c, i) in pos.into_iter().enumerate() {
        targets[i] = Some(Target::Pos(c));
    }
    for (c, i) in roles.normal.into_iter().flatten().enumerate() {
        targets[i] = Some(Target::Normal(c));
    }
    if let Some(i) = roles.thickness {
        targets[i] = Some(Target::Thickness);
    }
    if let Some(i) = roles.radius {
        targets[i] = Some(Target::Radius);
    }

    let mut extra_names = Vec::new();
    let mut stored = Vec::with_capacity(names.len());
    let mut plan_targets = Vec::with_capacity(names.len());
    for (t, p) in targets.into_iter().zip(&v.props) {
        let target = match (t, p.kind) {
            (Some(t), PropKind::List { .. }) => {
                return Err(format!(
                    "vertex property '{}' ({}) is a list; expected a scalar",
                    header::show(&p.name),
                    t.role()
                ));
            }
            (Some(t), _) => t,
            (None, PropKind::List { .. }) => Target::Ignore,
            (None, PropKind::Scalar(_)) => {
                extra_names.push(p.name.clone());
                Target::Extra(extra_names.len() - 1)
            }
        };
        stored.push(StoredAttribute::new(
            &p.name,
            p.kind.name(),
            1,
            target.role(),
        ));
        plan_targets.push(target);
    }
    Ok(Plan {
        targets: plan_targets,
        extra_names,
        has_normals: roles.normal.is_some(),
        has_thickness: roles.thickness.is_some(),
        has_radius: roles.radius.is_some(),
        stored,
    })
}

/// The columns being filled, all of the same length.
struct Outputs {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    thickness: Option<Vec<f32>>,
    radius: Option<Vec<f32>>,
    extra: Vec<Vec<f32>>,
}

impl Outputs {
    fn new(plan: &Plan, reserve: usize) -> Self {
        let v3 = || Vec::with_capacity(reserve);
        let f = || Vec::with_capacity(reserve);
        Outputs {
            positions: v3(),
            normals: plan.has_normals.then(v3),
            thickness: plan.has_thickness.then(f),
            radius: plan.has_radius.then(f),
            extra: plan.extra_names.iter().map(|_| f()).collect(),
        }
    }

    /// Number of records so far.
    fn len(&self) -> usize {
        self.positions.len()
    }

    /// Appends `k` zeroed records.
    fn grow(&mut self, k: usize) {
        let n = self.len() + k;
        self.positions.resize(n, Vec3::ZERO);
        if let Some(v) = &mut self.normals {
            v.resize(n, Vec3::ZERO);
        }
        for v in [&mut self.thickness, &mut self.radius]
            .into_iter()
            .flatten()
        {
            v.resize(n, 0.0);
        }
        for v in &mut self.extra {
            v.resize(n, 0.0);
        }
    }

    /// Stores value `x` of record `i` (slow path: one value at a time).
    fn set(&mut self, t: Target, i: usize, x: f32) {
        let slot = match t {
            Target::Pos(c) => self.positions.get_mut(i).map(|p| &mut p[c]),
            Target::Normal(c) => self
                .normals
                .as_mut()
                .and_then(|v| v.get_mut(i))
                .map(|p| &mut p[c]),
            Target::Thickness => self.thickness.as_mut().and_then(|v| v.get_mut(i)),
            Target::Radius => self.radius.as_mut().and_then(|v| v.get_mut(i)),
            Target::Extra(k) => self.extra.get_mut(k).and_then(|v| v.get_mut(i)),
            Target::Ignore => None,
        };
        if let Some(s) = slot {
            *s = x;
        }
    }

    fn into_cloud(self, plan: Plan, scale: f64) -> (PointCloud, Vec<StoredAttribute>) {
        let mut thickness_nm = self.thickness;
        if scale != 1.0 {
            for t in thickness_nm.iter_mut().flatten() {
                *t = (f64::from(*t) * scale) as f32;
            }
        }
        let cloud = PointCloud {
            positions: self.positions,
            normals: self.normals,
            thickness_nm,
            radius: self.radius,
            extra: plan.extra_names.into_iter().zip(self.extra).collect(),
        };
        (cloud, plan.stored)
    }
}

/// "vertex 12 of 100" for messages.
fn record_name(e: &Element, i: u64) -> String {
    format!("{} {i} of {}", header::show(&e.name), e.count)
}
