//! PLY reader (ASCII, binary little- and big-endian) for particle clouds.
//!
//! Reads element `vertex`: positions `x y z` (required), normals, thickness and radius by the
//! aliases in [`crate::io`] (or the names given in [`ReadOptions`]), and every other scalar vertex
//! property into [`PointCloud::extra`] as f32 (so integers above 2^24 lose precision; f64
//! positions are narrowed to f32). List properties are skipped; elements before `vertex` are
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
mod source;

use std::fs::File;
use std::io::{self, Read};
use std::path::Path;

use glam::Vec3;

use self::header::{Element, Encoding, Header, PropKind};
use crate::error::{Error, Result};
use crate::io::{NORMAL_ALIASES, RADIUS_ALIASES, ReadOptions, THICKNESS_ALIASES};
use crate::pointcloud::PointCloud;

/// Name used in error messages.
const FORMAT: &str = "PLY";

/// Reads the PLY file at `path` into a [`PointCloud`] (see the module docs for what is read).
///
/// Cost: one pass over the file; peak memory is the cloud plus a 1 MiB buffer.
///
/// # Errors
/// [`Error::Io`] if the file cannot be opened or read (missing, a directory, ...);
/// [`Error::Format`] naming the file and the problem for a malformed file or a missing or
/// ill-typed attribute; [`Error::Invalid`] for a bad option.
pub fn read(path: &Path, opts: &ReadOptions) -> Result<PointCloud> {
    opts.check()?;
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if meta.is_dir() {
        return Err(Error::io(
            path,
            io::Error::new(io::ErrorKind::IsADirectory, "is a directory"),
        ));
    }
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    // Only a regular file's length bounds its content; pipes report 0.
    let len = meta.is_file().then_some(meta.len());
    read_from(file, len, opts).map_err(|f| match f {
        Fail::Io(e) => Error::io(path, e),
        Fail::Msg(message) => Error::Format {
            path: path.to_path_buf(),
            format: FORMAT,
            message,
        },
    })
}

/// Reads a PLY file's content already in memory, as [`read`] does; `path` only names the
/// source in errors. Never panics, whatever the bytes.
///
/// # Errors
/// As [`read`], without the I/O errors.
pub fn read_bytes(bytes: &[u8], path: &Path, opts: &ReadOptions) -> Result<PointCloud> {
    opts.check()?;
    read_from(bytes, Some(bytes.len() as u64), opts).map_err(|f| match f {
        Fail::Io(e) => Error::io(path, e),
        Fail::Msg(message) => Error::Format {
            path: path.to_path_buf(),
            format: FORMAT,
            message,
        },
    })
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
fn read_from<R: Read>(reader: R, len: Option<u64>, opts: &ReadOptions) -> Result<PointCloud, Fail> {
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
        Encoding::Ascii => ascii::read(&mut src, &header, vi, &plan, &mut out)?,
        Encoding::BinaryLe => binary::read::<R, false>(&mut src, &header, vi, &plan, &mut out)?,
        Encoding::BinaryBe => binary::read::<R, true>(&mut src, &header, vi, &plan, &mut out)?,
    }
    Ok(out.into_cloud(plan, opts.thickness_scale(1.0)))
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
}

/// Maps the vertex properties to targets: explicit names first (absent = error), then aliases.
fn resolve(v: &Element, opts: &ReadOptions) -> Result<Plan, String> {
    let names: Vec<&str> = v.props.iter().map(|p| p.name.as_str()).collect();
    let list = || {
        names
            .iter()
            .map(|n| header::show(n))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let find = |name: &str| names.iter().position(|&n| n == name);
    let mut targets: Vec<Option<Target>> = vec![None; names.len()];
    let mut claim = |i: usize, t: Target, what: &str| -> Result<(), String> {
        if let PropKind::List { .. } = v.props[i].kind {
            return Err(format!(
                "vertex property '{}' ({what}) is a list; expected a scalar",
                header::show(names[i])
            ));
        }
        if let Some(old) = targets[i] {
            return Err(format!(
                "vertex property '{}' is used twice ({old:?} and {what})",
                header::show(names[i])
            ));
        }
        targets[i] = Some(t);
        Ok(())
    };

    for (c, axis) in ["x", "y", "z"].into_iter().enumerate() {
        let i = find(axis)
            .ok_or_else(|| format!("vertex has no '{axis}' property (it has: {})", list()))?;
        claim(i, Target::Pos(c), "position")?;
    }

    // Normals: a prefix p means p+x/y/z or p+_x/_y/_z.
    let triple = |p: &str| crate::io::columns::find_triple(&find, p);
    let normal = match &opts.normal_attr {
        Some(p) => match triple(p) {
            (Some(t), _) => Some(t),
            (None, _) => {
                return Err(format!(
                    "normal attribute '{0}' not found: need {0}x {0}y {0}z or {0}_x {0}_y {0}_z \
                     (vertex has: {1})",
                    header::show(p),
                    list()
                ));
            }
        },
        None => {
            let mut hit = None;
            for p in NORMAL_ALIASES {
                match triple(p) {
                    (Some(t), _) => {
                        hit = Some(t);
                        break;
                    }
                    (None, true) => {
                        return Err(format!(
                            "incomplete normal: vertex has some but not all of {p}x {p}y {p}z / \
                             {p}_x {p}_y {p}_z (vertex has: {})",
                            list()
                        ));
                    }
                    (None, false) => {}
                }
            }
            hit
        }
    };
    if let Some(idx) = normal {
        for (c, i) in idx.into_iter().enumerate() {
            claim(i, Target::Normal(c), "normal")?;
        }
    }

    let mut scalar = |explicit: &Option<String>, aliases: &[&str], t: Target, what: &str| {
        let i = match explicit {
            Some(name) => Some(find(name).ok_or_else(|| {
                format!(
                    "{what} attribute '{}' not found (vertex has: {})",
                    header::show(name),
                    list()
                )
            })?),
            None => aliases.iter().find_map(|a| find(a)),
        };
        if let Some(i) = i {
            claim(i, t, what)?;
        }
        Ok::<bool, String>(i.is_some())
    };
    let has_thickness = scalar(
        &opts.thickness_attr,
        THICKNESS_ALIASES,
        Target::Thickness,
        "thickness",
    )?;
    let has_radius = scalar(&opts.radius_attr, RADIUS_ALIASES, Target::Radius, "radius")?;

    let mut extra_names = Vec::new();
    let targets = targets
        .into_iter()
        .zip(&v.props)
        .map(|(t, p)| match (t, p.kind) {
            (Some(t), _) => t,
            (None, PropKind::List { .. }) => Target::Ignore,
            (None, PropKind::Scalar(_)) => {
                extra_names.push(p.name.clone());
                Target::Extra(extra_names.len() - 1)
            }
        })
        .collect();
    Ok(Plan {
        targets,
        extra_names,
        has_normals: normal.is_some(),
        has_thickness,
        has_radius,
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

    fn into_cloud(self, plan: Plan, scale: f64) -> PointCloud {
        let mut thickness_nm = self.thickness;
        if scale != 1.0 {
            for t in thickness_nm.iter_mut().flatten() {
                *t = (f64::from(*t) * scale) as f32;
            }
        }
        PointCloud {
            positions: self.positions,
            normals: self.normals,
            thickness_nm,
            radius: self.radius,
            extra: plan.extra_names.into_iter().zip(self.extra).collect(),
        }
    }
}

/// "vertex 12 of 100" for messages.
fn record_name(e: &Element, i: u64) -> String {
    format!("{} {i} of {}", header::show(&e.name), e.count)
}
