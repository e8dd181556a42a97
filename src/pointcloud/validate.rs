//! Validation of a loaded cloud (refuse bad values with counts and the first offending index)
//! and repair (drop or reset them), used by the CLI's `--repair`.

use super::PointCloud;
use crate::{Error, Result};
use glam::Vec3;

/// One kind of bad value found in a cloud.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// Number of particles affected (or, for a length mismatch, the attribute's entry count).
    pub count: usize,
    /// Index of the first affected particle (`None` for whole-cloud problems).
    pub first: Option<usize>,
    /// What is wrong, completing "N particles have …", e.g. "non-finite positions".
    pub what: String,
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.first {
            Some(first) => {
                let (noun, verb) = if self.count == 1 {
                    ("particle", "has")
                } else {
                    ("particles", "have")
                };
                write!(
                    f,
                    "{} {noun} {verb} {} (first: index {first})",
                    self.count, self.what
                )
            }
            None => write!(f, "{}", self.what),
        }
    }
}

/// Counts entries failing `bad` and remembers the first.
fn scan<T>(values: &[T], what: &str, bad: impl Fn(&T) -> bool, out: &mut Vec<Problem>) {
    let mut count = 0;
    let mut first = None;
    for (i, v) in values.iter().enumerate() {
        if bad(v) {
            count += 1;
            first.get_or_insert(i);
        }
    }
    if count > 0 {
        out.push(Problem {
            count,
            first,
            what: what.to_string(),
        });
    }
}

fn length_problem(name: &str, len: usize, n: usize, out: &mut Vec<Problem>) -> bool {
    if len != n {
        out.push(Problem {
            count: len,
            first: None,
            what: format!("attribute '{name}' has {len} entries for {n} particles"),
        });
        false
    } else {
        true
    }
}

/// Largest coordinate magnitude accepted, scene units: 1e15. Beyond it, squared distances in the
/// framing and ray tests leave the `f32` range (or lose all precision), so such clouds are
/// refused (rescale the data) rather than rendered as NaN.
pub const MAX_COORDINATE: f32 = 1e15;

/// True if a finite position lies farther than [`MAX_COORDINATE`] on some axis.
fn too_far(p: &Vec3) -> bool {
    p.is_finite() && p.abs().max_element() > MAX_COORDINATE
}

/// True if a normal cannot be normalised (zero, denormal-tiny or non-finite length).
fn normal_unusable(n: &Vec3) -> bool {
    n.try_normalize().is_none()
}

/// All problems of the cloud, in a fixed order. Cost: one pass over every attribute.
pub fn problems(cloud: &PointCloud) -> Vec<Problem> {
    let mut out = Vec::new();
    let n = cloud.len();
    if n == 0 {
        out.push(Problem {
            count: 0,
            first: None,
            what: "point cloud is empty (0 particles)".into(),
        });
        return out;
    }
    scan(
        &cloud.positions,
        "non-finite positions",
        |p| !p.is_finite(),
        &mut out,
    );
    if let Some(p) = cloud.positions.iter().find(|p| too_far(p)) {
        let what = format!(
            "coordinates beyond ±{MAX_COORDINATE:e} scene units, e.g. [{:e}, {:e}, {:e}] \
             (rescale the data)",
            p.x, p.y, p.z
        );
        scan(&cloud.positions, &what, too_far, &mut out);
    }
    if let Some(normals) = &cloud.normals
        && length_problem("normals", normals.len(), n, &mut out)
    {
        scan(normals, "non-finite normals", |m| !m.is_finite(), &mut out);
        scan(
            normals,
            "zero-length normals",
            |m| m.is_finite() && normal_unusable(m),
            &mut out,
        );
    }
    if let Some(t) = &cloud.thickness_nm
        && length_problem("thickness", t.len(), n, &mut out)
    {
        scan(t, "non-finite thickness", |h| !h.is_finite(), &mut out);
        scan(t, "negative thickness", |h| *h < 0.0, &mut out);
    }
    if let Some(r) = &cloud.radius
        && length_problem("radius", r.len(), n, &mut out)
    {
        scan(r, "non-finite radius", |x| !x.is_finite(), &mut out);
        scan(r, "zero or negative radius", |x| *x <= 0.0, &mut out);
    }
    for (name, v) in &cloud.extra {
        length_problem(name, v.len(), n, &mut out);
    }
    out
}

/// Refuses a cloud with any bad value: `Error::Invalid` whose one-line message lists every
/// problem with its count and first index, e.g. "3 particles have non-finite positions
/// (first: index 17); 1 particle has negative thickness (first: index 4)".
pub fn validate(cloud: &PointCloud) -> Result<()> {
    let p = problems(cloud);
    if p.is_empty() {
        return Ok(());
    }
    let msg: Vec<String> = p.iter().map(ToString::to_string).collect();
    Err(Error::invalid(msg.join("; ")))
}

/// What [`repair`] did.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RepairReport {
    /// Particles before repair.
    pub before: usize,
    /// Particles dropped for a non-finite position (or one beyond [`MAX_COORDINATE`]).
    pub dropped_position: usize,
    /// Particles dropped for a non-finite or negative thickness (and a good position).
    pub dropped_thickness: usize,
    /// Zero-length or non-finite normals set to zero, to be re-estimated by `fill_missing`.
    pub normals_reset: usize,
    /// Non-finite or non-positive radii set to zero, to be re-estimated by `fill_missing`.
    pub radii_reset: usize,
    /// Attributes removed because their length did not match the particle count.
    pub discarded: Vec<String>,
}

impl RepairReport {
    /// Particles kept.
    pub fn after(&self) -> usize {
        self.before - self.dropped_position - self.dropped_thickness
    }

    /// True if repair changed nothing.
    pub fn is_clean(&self) -> bool {
        self.dropped_position + self.dropped_thickness + self.normals_reset + self.radii_reset == 0
            && self.discarded.is_empty()
    }
}

impl std::fmt::Display for RepairReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.is_clean() {
            return write!(f, "repair: nothing to repair ({} particles)", self.before);
        }
        let counts = [
            (
                self.dropped_position,
                "dropped ",
                " with non-finite positions (or beyond ±1e15)",
            ),
            (self.dropped_thickness, "dropped ", " with bad thickness"),
            (
                self.normals_reset,
                "",
                " unusable normals marked for re-estimation",
            ),
            (self.radii_reset, "", " bad radii marked for re-estimation"),
        ];
        let mut parts: Vec<String> = counts
            .iter()
            .filter(|(n, _, _)| *n > 0)
            .map(|(n, before, after)| format!("{before}{n}{after}"))
            .collect();
        for d in &self.discarded {
            parts.push(format!("discarded attribute '{d}' (wrong length)"));
        }
        write!(
            f,
            "repair: {}; {} of {} particles kept",
            parts.join(", "),
            self.after(),
            self.before
        )
    }
}

/// Makes a cloud valid where possible: drops particles with non-finite positions or with
/// non-finite/negative thickness, sets unusable normals to zero and bad radii to 0 so that
/// [`super::estimate::fill_missing`] re-estimates them, and removes attributes of the wrong
/// length. An empty result stays invalid (validate says so). Cost: O(n) time, one extra copy.
pub fn repair(cloud: &mut PointCloud) -> RepairReport {
    let n = cloud.len();
    let mut report = RepairReport {
        before: n,
        ..Default::default()
    };
    if cloud.normals.as_ref().is_some_and(|v| v.len() != n) {
        cloud.normals = None;
        report.discarded.push("normals".into());
    }
    if cloud.thickness_nm.as_ref().is_some_and(|v| v.len() != n) {
        cloud.thickness_nm = None;
        report.discarded.push("thickness".into());
    }
    if cloud.radius.as_ref().is_some_and(|v| v.len() != n) {
        cloud.radius = None;
        report.discarded.push("radius".into());
    }
    cloud.extra.retain(|(name, v)| {
        let ok = v.len() == n;
        if !ok {
            report.discarded.push(name.clone());
        }
        ok
    });

    let keep: Vec<bool> = (0..n)
        .map(|i| {
            if !cloud.positions[i].is_finite() || too_far(&cloud.positions[i]) {
                report.dropped_position += 1;
                return false;
            }
            if let Some(t) = &cloud.thickness_nm
                && !(t[i].is_finite() && t[i] >= 0.0)
            {
                report.dropped_thickness += 1;
                return false;
            }
            true
        })
        .collect();
    if keep.iter().any(|k| !k) {
        keep_particles(cloud, &keep);
    }
    if let Some(v) = &mut cloud.normals {
        for m in v.iter_mut().filter(|m| normal_unusable(m)) {
            *m = Vec3::ZERO;
            report.normals_reset += 1;
        }
    }
    if let Some(v) = &mut cloud.radius {
        for r in v.iter_mut().filter(|r| !(r.is_finite() && **r > 0.0)) {
            *r = 0.0;
            report.radii_reset += 1;
        }
    }
    report
}

/// Keeps the particles whose `keep` flag is set, in order, with all their attributes.
pub(crate) fn keep_particles(cloud: &mut PointCloud, keep: &[bool]) {
    compact(&mut cloud.positions, keep);
    if let Some(v) = &mut cloud.normals {
        compact(v, keep);
    }
    for v in [&mut cloud.thickness_nm, &mut cloud.radius]
        .into_iter()
        .flatten()
    {
        compact(v, keep);
    }
    for (_, v) in &mut cloud.extra {
        compact(v, keep);
    }
}

/// Keeps the entries whose `keep` flag is set, in order.
pub(crate) fn compact<T: Copy>(v: &mut Vec<T>, keep: &[bool]) {
    let mut w = 0;
    for r in 0..v.len() {
        if keep[r] {
            v[w] = v[r];
            w += 1;
        }
    }
    v.truncate(w);
}
