//! Estimation of missing per-particle attributes from the positions alone: spacing, splat radii
//! and oriented normals (kNN via kiddo 6, queries parallel over rayon's pool).
//!
//! All functions tolerate non-finite positions (such particles get fallback values) but give
//! meaningful results only on validated clouds.

use super::PointCloud;
use super::eigen::sym_eigen3;
use super::knn::{KnnTable, NO_NEIGHBOUR, PointIndex};
use super::orient::{Orientation, centroid, orient_normals, propagate_signs};
use glam::{DMat3, DVec3, Vec3};
use rayon::prelude::*;

/// Clouds larger than this are sub-sampled by [`median_spacing`].
pub const SPACING_SAMPLE: usize = 65_536;

/// Median of the finite, strictly positive values (exact duplicates do not define a spacing).
pub(crate) fn median_positive(values: impl Iterator<Item = f32>) -> Option<f32> {
    let mut v: Vec<f32> = values.filter(|d| d.is_finite() && *d > 0.0).collect();
    if v.is_empty() {
        return None;
    }
    let mid = v.len() / 2;
    let (_, m, _) = v.select_nth_unstable_by(mid, f32::total_cmp);
    Some(*m)
}

/// Distance from every particle to its nearest other particle (scene units); `f32::INFINITY`
/// for a particle with no finite neighbour (or a non-finite position). Cost: one tree build
/// plus one parallel 1-NN query a particle, O(n log n).
pub fn nn_distances(positions: &[Vec3]) -> Vec<f32> {
    let table = KnnTable::build(positions, 1);
    table.dist
}

/// Median nearest-neighbour distance (scene units), the cloud's typical particle spacing.
///
/// Exact duplicates (distance 0) are ignored. For clouds above [`SPACING_SAMPLE`] particles
/// the median is taken over that many evenly strided particles (deterministic; the tree is
/// still built over all particles, so each sampled distance is exact): the sampling error of a
/// median over 65 536 samples is well below 1 %. Returns 0 when fewer than two distinct finite
/// positions exist. Cost: O(n log n) tree build + O(min(n, 65 536) log n) queries.
pub fn median_spacing(positions: &[Vec3]) -> f32 {
    let index = PointIndex::build(positions);
    let n = positions.len();
    let m = n.min(SPACING_SAMPLE);
    let dists: Vec<f32> = (0..m)
        .into_par_iter()
        .map(|s| {
            let i = if m == n { s } else { s * n / m };
            let p = positions[i];
            if !p.is_finite() {
                return f32::INFINITY;
            }
            index
                .nearest_excluding(p, 1, i as u32)
                .first()
                .map_or(f32::INFINITY, |r| r.1)
        })
        .collect();
    median_positive(dists.into_iter()).unwrap_or(0.0)
}

/// Splat radii from local spacing: `rᵢ = scale · dₖ(i)`, dₖ the distance to the k-th nearest
/// other particle (scene units).
///
/// Why the k-th neighbour (k ≈ 6–8) rather than the nearest: d₁ measures the accidental closest
/// pair and underestimates spacing in clumpy SPH data, leaving holes; dₖ tracks the local
/// *density* (on a surface ρ ≈ k / (π dₖ²)). Why k = 8, `scale` = 0.6 (the
/// [`EstimateOptions`] defaults): on a Fibonacci (near-hexagonal) lattice of spacing d,
/// d₈ ≈ 1.54·d, so r ≈ 0.92·d against a hexagonal covering radius of d/√3 ≈ 0.58·d — disks
/// overlap and the film has no holes. Measured by ray casting on a 20 000-point sphere: no hole
/// with tangential jitter up to ±0.3·d per axis (scale 0.5 already leaves holes at ±0.2·d).
/// Larger radii would blur curvature and thickness detail. Uniformly random (Poisson-like)
/// samplings have larger gaps and need `scale` ≈ 1.0. Particles with no neighbour get
/// `scale ×` the median dₖ (or `scale` for a lone particle). Isolated particles (spray, sparse
/// regions) are capped at [`MAX_RADIUS_FACTOR`] × the median radius: a lone droplet stays a
/// droplet-sized splat instead of ballooning to the distance of its far neighbours, so sparse
/// data is shown honestly. Cost: O(n·k·log n), parallel.
pub fn estimate_radii(positions: &[Vec3], k: usize, scale: f32) -> Vec<f32> {
    let table = KnnTable::build(positions, k.max(1));
    radii_from_table(&table, k.max(1), scale)
}

/// Radii from an existing table (`k ≤ table.k`), see [`estimate_radii`].
pub(crate) fn radii_from_table(table: &KnnTable, k: usize, scale: f32) -> Vec<f32> {
    let dk: Vec<Option<f32>> = (0..table.len())
        .into_par_iter()
        .map(|i| table.kth_distance(i, k).filter(|d| d.is_finite()))
        .collect();
    let fallback = median_positive(dk.iter().flatten().copied()).unwrap_or(1.0);
    let cap = MAX_RADIUS_FACTOR * fallback;
    dk.into_iter()
        .map(|d| scale * d.filter(|d| *d > 0.0).unwrap_or(fallback).min(cap))
        .collect()
}

/// Largest estimated radius, as a multiple of the median estimated radius (see
/// [`estimate_radii`]).
pub const MAX_RADIUS_FACTOR: f32 = 2.0;

/// Unit normals with their orientation and how many were degenerate.
#[derive(Debug, Clone)]
pub struct NormalEstimate {
    /// One unit normal a particle.
    pub normals: Vec<Vec3>,
    /// Particles whose neighbourhood had no defined plane (fewer than 3 points, coincident or
    /// collinear); their normal is the mean of their neighbours' normals, else the nearest
    /// valid particle's, else radial from the centroid, else +Z.
    pub degenerate: usize,
    /// How the signs were chosen.
    pub orientation: Orientation,
}

/// Oriented unit normals by PCA over each particle and its `k` nearest neighbours
/// (k ≈ 10–16 is typical). See [`estimate_normals_detailed`].
pub fn estimate_normals(positions: &[Vec3], k: usize) -> Vec<Vec3> {
    estimate_normals_detailed(positions, k).normals
}

/// Oriented unit normals plus diagnostics.
///
/// Each normal is the eigenvector of the smallest eigenvalue of the covariance of the particle
/// and its `k` nearest neighbours (Jacobi solver in f64, coordinates relative to the particle).
/// A neighbourhood is degenerate when it has fewer than 3 points or its middle eigenvalue is
/// below 10⁻⁴ × the largest (collinear or coincident points). Orientation is outward for
/// star-shaped clouds and MST-propagated otherwise, see [`super::orient`].
/// Cost: O(n·k·log n) parallel for kNN + PCA; the propagated case adds a single-threaded
/// O(n·k·log n) spanning tree. Measured for 1M particles, k = 12, on a loaded 2-core machine:
/// ≈ 2.4 s in all (radial), ≈ 5 s (propagated).
pub fn estimate_normals_detailed(positions: &[Vec3], k: usize) -> NormalEstimate {
    let table = KnnTable::build(positions, k.max(2));
    normals_from_table(positions, &table, k.max(2))
}

/// PCA normal of particle `i` over its first `k` table neighbours; `None` if degenerate.
pub(crate) fn pca_normal(positions: &[Vec3], table: &KnnTable, i: usize, k: usize) -> Option<Vec3> {
    let p = positions[i];
    if !p.is_finite() {
        return None;
    }
    let mut pts = [DVec3::ZERO; 65];
    let mut m = 1usize; // pts[0] = the particle itself, at the origin
    for (j, _) in table.row(i).take(k.min(64)) {
        pts[m] = (positions[j as usize] - p).as_dvec3();
        m += 1;
    }
    if m < 3 {
        return None;
    }
    let mean = pts[..m].iter().sum::<DVec3>() / m as f64;
    let mut cov = DMat3::ZERO;
    for q in &pts[..m] {
        let d = *q - mean;
        cov += DMat3::from_cols(d * d.x, d * d.y, d * d.z);
    }
    let e = sym_eigen3(&cov);
    // NaN-safe: a non-finite spectrum fails the first test.
    let planar = e.values[2] > 0.0 && e.values[1] > 1e-4 * e.values[2];
    if !planar {
        return None;
    }
    e.vectors[0].as_vec3().try_normalize()
}

/// Full estimate from a table (`k ≤ table.k`).
pub(crate) fn normals_from_table(positions: &[Vec3], table: &KnnTable, k: usize) -> NormalEstimate {
    let raw: Vec<Option<Vec3>> = (0..positions.len())
        .into_par_iter()
        .map(|i| pca_normal(positions, table, i, k))
        .collect();
    let valid: Vec<bool> = raw.iter().map(Option::is_some).collect();
    let mut normals: Vec<Vec3> = raw.into_iter().map(|n| n.unwrap_or(Vec3::ZERO)).collect();
    let orientation = orient_normals(positions, table, &mut normals, &valid);
    let degenerate = fill_degenerate(positions, table, &mut normals, &valid);
    NormalEstimate {
        normals,
        degenerate,
        orientation,
    }
}

/// Replaces every `!valid` normal by the normalised sum of its (valid, oriented) neighbours'
/// normals, spreading along chains; else the nearest valid particle's normal; else radial
/// from the centroid; else +Z. Returns the count.
fn fill_degenerate(
    positions: &[Vec3],
    table: &KnnTable,
    normals: &mut [Vec3],
    valid: &[bool],
) -> usize {
    let mut ok = valid.to_vec();
    let mut pending: Vec<usize> = (0..normals.len()).filter(|&i| !valid[i]).collect();
    let count = pending.len();
    while !pending.is_empty() {
        let before = pending.len();
        pending.retain(|&i| {
            let sum: Vec3 = table
                .row(i)
                .filter(|(j, _)| ok[*j as usize])
                .map(|(j, _)| normals[j as usize])
                .sum();
            match sum.try_normalize() {
                Some(n) => {
                    normals[i] = n;
                    ok[i] = true;
                    false
                }
                None => true,
            }
        });
        if pending.len() == before {
            break;
        }
    }
    if !pending.is_empty() {
        // Cut off from every valid normal in the kNN graph (e.g. a stack of > k duplicates):
        // copy the nearest valid particle's normal.
        let masked: Vec<Vec3> = (0..positions.len())
            .map(|i| if ok[i] { positions[i] } else { Vec3::NAN })
            .collect();
        let index = PointIndex::build(&masked);
        let c = centroid(positions).unwrap_or(Vec3::ZERO);
        for i in pending {
            let p = positions[i];
            let near = p
                .is_finite()
                .then(|| index.nearest_excluding(p, 1, NO_NEIGHBOUR));
            normals[i] = match near.as_deref() {
                Some([(j, _), ..]) => normals[*j as usize],
                _ => (p - c).try_normalize().unwrap_or(Vec3::Z),
            };
        }
    }
    count
}

/// Parameters of [`fill_missing`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EstimateOptions {
    /// Neighbours used for PCA normals (default 12).
    pub k_normals: usize,
    /// The k of the k-th-neighbour distance used for radii (default 8).
    pub k_radius: usize,
    /// Radius = `radius_scale` × k-th-neighbour distance (default 0.6; see [`estimate_radii`]).
    pub radius_scale: f32,
    /// Thickness given to every particle when the cloud has none, in nm (default 500).
    pub default_thickness_nm: f32,
}

impl Default for EstimateOptions {
    fn default() -> Self {
        EstimateOptions {
            k_normals: 12,
            k_radius: 8,
            radius_scale: 0.6,
            default_thickness_nm: 500.0,
        }
    }
}

/// What [`fill_missing`] did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EstimateReport {
    /// Particles in the cloud.
    pub particles: usize,
    /// Normals computed by PCA (all if the cloud had none, else the zero/non-finite ones).
    pub normals_estimated: usize,
    /// Estimated normals whose neighbourhood was degenerate (filled from neighbours).
    pub normals_degenerate: usize,
    /// Input normals rescaled to unit length (length off by more than 10⁻³).
    pub normals_normalised: usize,
    /// How estimated normals were oriented (`None` if none was estimated).
    pub orientation: Option<Orientation>,
    /// Radii computed from spacing (all if absent, else the non-finite or non-positive ones).
    pub radii_estimated: usize,
    /// Particles given the default thickness (all, if the cloud had no thickness).
    pub thickness_filled: usize,
    /// Median nearest-neighbour distance, when a neighbour table was built.
    pub median_spacing: Option<f32>,
    /// Anything else worth telling (one line each).
    pub notes: Vec<String>,
}

impl std::fmt::Display for EstimateReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "estimation over {} particles:", self.particles)?;
        if self.normals_estimated > 0 {
            write!(f, "  normals: {} estimated by PCA", self.normals_estimated)?;
            if self.normals_degenerate > 0 {
                write!(
                    f,
                    " ({} degenerate, filled from neighbours)",
                    self.normals_degenerate
                )?;
            }
            if let Some(o) = self.orientation {
                write!(f, ", oriented {o}")?;
            }
            writeln!(f)?;
        }
        if self.normals_normalised > 0 {
            writeln!(
                f,
                "  normals: {} rescaled to unit length",
                self.normals_normalised
            )?;
        }
        if self.radii_estimated > 0 {
            writeln!(
                f,
                "  radii: {} estimated from spacing",
                self.radii_estimated
            )?;
        }
        if self.thickness_filled > 0 {
            writeln!(
                f,
                "  thickness: {} set to the default",
                self.thickness_filled
            )?;
        }
        if let Some(s) = self.median_spacing {
            writeln!(f, "  median spacing: {s:.6}")?;
        }
        for n in &self.notes {
            writeln!(f, "  note: {n}")?;
        }
        if self.filled_nothing() {
            writeln!(f, "  nothing to fill")?;
        }
        Ok(())
    }
}

impl EstimateReport {
    /// True if nothing was estimated, rescaled or filled (the report says "nothing to fill").
    pub fn filled_nothing(&self) -> bool {
        self.normals_estimated
            + self.normals_normalised
            + self.radii_estimated
            + self.thickness_filled
            == 0
    }
}

/// Fills what the cloud lacks: normals (absent, zero or non-finite entries are estimated;
/// present ones are normalised and keep their sign), radii (absent, non-finite or ≤ 0 entries)
/// and thickness (absent → `default_thickness_nm` everywhere). Attribute arrays whose length
/// does not match the particle count are replaced (and noted). Re-estimated normals among
/// present ones take the sign of their neighbours' input normals. One kNN table with
/// k = max(k_normals, k_radius) serves both estimates. Cost: see [`estimate_normals_detailed`].
pub fn fill_missing(cloud: &mut PointCloud, opts: &EstimateOptions) -> EstimateReport {
    fill_missing_keeping_table(cloud, opts, 0, &mut None).0
}

/// Drops normals or radii whose count does not match the particles', with a note.
fn drop_mismatched(cloud: &mut PointCloud, report: &mut EstimateReport) {
    let n = cloud.len();
    if let Some(v) = &cloud.normals
        && v.len() != n
    {
        report.notes.push(format!(
            "normals had {} entries for {n} particles; replaced",
            v.len()
        ));
        cloud.normals = None;
    }
    if let Some(v) = &cloud.radius
        && v.len() != n
    {
        report.notes.push(format!(
            "radii had {} entries for {n} particles; replaced",
            v.len()
        ));
        cloud.radius = None;
    }
}

/// [`fill_missing`], also handing back the kNN table it built (if it needed one), so a caller
/// that needs neighbours too (e.g. the curvature estimate, the radius fit) does not search
/// them again: the table then holds at least `min_k` a row (the estimates read the nearest
/// ones, the same), searched with `index` (built into it if `None`, kept for the caller).
pub fn fill_missing_keeping_table(
    cloud: &mut PointCloud,
    opts: &EstimateOptions,
    min_k: usize,
    index: &mut Option<PointIndex>,
) -> (EstimateReport, Option<KnnTable>) {
    let n = cloud.len();
    let mut report = EstimateReport {
        particles: n,
        ..Default::default()
    };
    drop_mismatched(cloud, &mut report);
    let need_normal: Vec<bool> = match &cloud.normals {
        None => vec![true; n],
        Some(v) => v.iter().map(|m| m.try_normalize().is_none()).collect(),
    };
    let need_radius: Vec<bool> = match &cloud.radius {
        None => vec![true; n],
        Some(v) => v.iter().map(|r| !(r.is_finite() && *r > 0.0)).collect(),
    };
    let n_normals = need_normal.iter().filter(|b| **b).count();
    let n_radii = need_radius.iter().filter(|b| **b).count();
    let k_n = opts.k_normals.max(2);
    let k_r = opts.k_radius.max(1);
    let k = match (n_normals > 0, n_radii > 0) {
        (true, true) => k_n.max(k_r),
        (true, false) => k_n,
        (false, true) => k_r,
        (false, false) => 0,
    };
    let table = (k > 0 && n > 0).then(|| {
        let index = index.get_or_insert_with(|| PointIndex::build(&cloud.positions));
        KnnTable::build_with(index, &cloud.positions, k.max(min_k))
    });
    if let Some(t) = &table {
        report.median_spacing = median_positive((0..n).filter_map(|i| t.kth_distance(i, 1)));
    }

    match (&mut cloud.normals, &table) {
        (None, Some(t)) => {
            let est = normals_from_table(&cloud.positions, t, k_n);
            report.normals_estimated = n;
            report.normals_degenerate = est.degenerate;
            report.orientation = Some(est.orientation);
            cloud.normals = Some(est.normals);
        }
        (Some(normals), t) => {
            for (m, need) in normals.iter_mut().zip(&need_normal) {
                if !need && (m.length() - 1.0).abs() > 1e-3 {
                    *m = m.normalize();
                    report.normals_normalised += 1;
                }
            }
            if let Some(t) = t.as_ref().filter(|_| n_normals > 0) {
                let (est, degenerate) = reestimate(&cloud.positions, t, k_n, normals, &need_normal);
                report.normals_estimated = est;
                report.normals_degenerate = degenerate;
                report.orientation = Some(Orientation::FromNeighbours);
            }
        }
        (None, None) => {}
    }

    if let Some(t) = table.as_ref().filter(|_| n_radii > 0) {
        let est = radii_from_table(t, k_r, opts.radius_scale);
        let radius = cloud.radius.get_or_insert_with(|| vec![0.0; n]);
        for i in 0..n {
            if need_radius[i] {
                radius[i] = est[i];
            }
        }
        report.radii_estimated = n_radii;
    }

    if cloud.thickness_nm.is_none() {
        cloud.thickness_nm = Some(vec![opts.default_thickness_nm; n]);
        report.thickness_filled = n;
    }
    (report, table)
}

/// PCA for the `need`ed entries of present normals, signed to agree with neighbouring input
/// normals. Returns (estimated, degenerate).
fn reestimate(
    positions: &[Vec3],
    table: &KnnTable,
    k: usize,
    normals: &mut [Vec3],
    need: &[bool],
) -> (usize, usize) {
    let raw: Vec<Option<Vec3>> = (0..positions.len())
        .into_par_iter()
        .map(|i| {
            if need[i] {
                pca_normal(positions, table, i, k)
            } else {
                None
            }
        })
        .collect();
    let mut valid: Vec<bool> = need.iter().map(|b| !b).collect();
    let mut resolved = valid.clone();
    for (i, r) in raw.iter().enumerate() {
        if let Some(m) = r {
            normals[i] = *m;
            valid[i] = true;
        } else if need[i] {
            normals[i] = Vec3::ZERO;
        }
    }
    let c = centroid(positions).unwrap_or(Vec3::ZERO);
    propagate_signs(table, normals, &valid, &mut resolved, |i| positions[i] - c);
    let degenerate = fill_degenerate(positions, table, normals, &valid);
    (need.iter().filter(|b| **b).count(), degenerate)
}
