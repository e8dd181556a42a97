//! Summary statistics of a cloud, printed by `filmsplat info`.

use super::PointCloud;
use super::estimate::{median_positive, median_spacing};
use super::knn::KnnTable;
use glam::Vec3;
use std::fmt;

/// Bins of [`Histogram`] made by [`compute_stats`].
pub const HISTOGRAM_BINS: usize = 10;

/// Equal-width histogram over `[lo, hi]` (the last bin includes `hi`).
#[derive(Debug, Clone, PartialEq)]
pub struct Histogram {
    /// Lower edge of the first bin.
    pub lo: f32,
    /// Upper edge of the last bin.
    pub hi: f32,
    /// Counts per bin.
    pub counts: Vec<usize>,
}

impl Histogram {
    /// Bins the finite `values` into `bins` equal bins over their own range.
    pub fn of(values: &[f32], bins: usize) -> Histogram {
        let (lo, hi) = values
            .iter()
            .filter(|v| v.is_finite())
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        let mut counts = vec![0usize; bins.max(1)];
        if lo > hi {
            return Histogram {
                lo: 0.0,
                hi: 0.0,
                counts,
            };
        }
        let last = counts.len() - 1;
        let width = (hi as f64 - lo as f64) / counts.len() as f64;
        for &v in values.iter().filter(|v| v.is_finite()) {
            let b = if width > 0.0 {
                ((v as f64 - lo as f64) / width) as usize
            } else {
                0
            };
            counts[b.min(last)] += 1;
        }
        Histogram { lo, hi, counts }
    }
}

/// Range, mean and histogram of one scalar attribute.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Smallest finite value.
    pub min: f32,
    /// Largest finite value.
    pub max: f32,
    /// Mean of the finite values (f64 accumulation).
    pub mean: f64,
    /// Number of non-finite values.
    pub non_finite: usize,
    /// Distribution of the finite values.
    pub histogram: Histogram,
}

impl Summary {
    /// Summarises `values`; min/max/mean are NaN if none is finite.
    pub fn of(values: &[f32]) -> Summary {
        let (mut min, mut max, mut sum, mut n) = (f32::INFINITY, f32::NEG_INFINITY, 0.0f64, 0usize);
        for &v in values.iter().filter(|v| v.is_finite()) {
            min = min.min(v);
            max = max.max(v);
            sum += v as f64;
            n += 1;
        }
        if n == 0 {
            (min, max) = (f32::NAN, f32::NAN);
        }
        Summary {
            min,
            max,
            mean: if n == 0 { f64::NAN } else { sum / n as f64 },
            non_finite: values.len() - n,
            histogram: Histogram::of(values, HISTOGRAM_BINS),
        }
    }
}

/// Everything `filmsplat info` says about a cloud.
#[derive(Debug, Clone, PartialEq)]
pub struct CloudStats {
    /// Number of particles.
    pub count: usize,
    /// Particles with a non-finite position (excluded from the box and spacing).
    pub non_finite_positions: usize,
    /// Bounding box (min, max) of the finite positions, scene units.
    pub bounds: Option<(Vec3, Vec3)>,
    /// Median nearest-neighbour distance (scene units; 0 if undefined), see
    /// [`median_spacing`].
    pub median_spacing: f32,
    /// Thickness in nm, if present.
    pub thickness_nm: Option<Summary>,
    /// Splat radius in scene units, if present.
    pub radius: Option<Summary>,
    /// True if the cloud has no normals at all.
    pub normals_missing: bool,
    /// Normals that are zero-length or non-finite (need re-estimation).
    pub normals_degenerate: usize,
    /// Normals whose length differs from 1 by more than 10⁻³ (will be normalised).
    pub normals_not_unit: usize,
    /// Every extra attribute with its summary, in file order.
    pub extra: Vec<(String, Summary)>,
}

/// Computes [`CloudStats`]. Cost: O(n) plus [`median_spacing`] (a k-d tree build, O(n log n)).
pub fn compute_stats(cloud: &PointCloud) -> CloudStats {
    let finite: Vec<&Vec3> = cloud.positions.iter().filter(|p| p.is_finite()).collect();
    let bounds = (!finite.is_empty()).then(|| {
        finite
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(**p), hi.max(**p))
            })
    });
    let (mut degenerate, mut not_unit) = (0, 0);
    if let Some(normals) = &cloud.normals {
        for m in normals {
            if m.try_normalize().is_none() {
                degenerate += 1;
            } else if (m.length() - 1.0).abs() > 1e-3 {
                not_unit += 1;
            }
        }
    }
    CloudStats {
        count: cloud.len(),
        non_finite_positions: cloud.len() - finite.len(),
        bounds,
        median_spacing: median_spacing(&cloud.positions),
        thickness_nm: cloud.thickness_nm.as_deref().map(Summary::of),
        radius: cloud.radius.as_deref().map(Summary::of),
        normals_missing: cloud.normals.is_none(),
        normals_degenerate: degenerate,
        normals_not_unit: not_unit,
        extra: cloud
            .extra
            .iter()
            .map(|(k, v)| (k.clone(), Summary::of(v)))
            .collect(),
    }
}

/// `v` with `prec` decimals, or in scientific notation where that would hide it (magnitudes
/// below 10⁻³ or from 10⁷ on, e.g. a thickness of 5e-7 m or a mass of 1e-8 kg).
pub fn number(v: f32, prec: usize) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-3..1e7).contains(&a) {
        format!("{v:.prec$}")
    } else {
        format!("{v:.3e}")
    }
}

fn write_summary(
    f: &mut fmt::Formatter<'_>,
    name: &str,
    unit: &str,
    s: &Summary,
    hist: bool,
) -> fmt::Result {
    let prec = if unit == " nm" { 1 } else { 4 };
    write!(
        f,
        "{name:<12} min {} max {} mean {}{unit}",
        number(s.min, prec),
        number(s.max, prec),
        number(s.mean as f32, prec)
    )?;
    if s.non_finite > 0 {
        write!(f, " ({} non-finite)", s.non_finite)?;
    }
    writeln!(f)?;
    if hist {
        let h = &s.histogram;
        let peak = h.counts.iter().copied().max().unwrap_or(0).max(1);
        let width = (h.hi - h.lo) / h.counts.len() as f32;
        for (b, &c) in h.counts.iter().enumerate() {
            let lo = h.lo + width * b as f32;
            let bar = "#".repeat((c * 40).div_ceil(peak));
            writeln!(f, "  {:>10.2} – {:<10.2} {c:>9} {bar}", lo, lo + width)?;
        }
    }
    Ok(())
}

impl fmt::Display for CloudStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "particles    {}", self.count)?;
        if self.non_finite_positions > 0 {
            write!(
                f,
                " ({} with non-finite positions)",
                self.non_finite_positions
            )?;
        }
        writeln!(f)?;
        match self.bounds {
            Some((lo, hi)) => {
                let s = hi - lo;
                writeln!(
                    f,
                    "bounds       [{:.4}, {:.4}, {:.4}] – [{:.4}, {:.4}, {:.4}]  (size {:.4} × {:.4} × {:.4})",
                    lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, s.x, s.y, s.z
                )?;
            }
            None => writeln!(f, "bounds       none (no finite position)")?,
        }
        writeln!(
            f,
            "spacing      median nearest-neighbour distance {:.6}",
            self.median_spacing
        )?;
        if self.normals_missing {
            writeln!(f, "normals      missing (will be estimated)")?;
        } else {
            writeln!(
                f,
                "normals      present; {} zero or non-finite, {} not unit length",
                self.normals_degenerate, self.normals_not_unit
            )?;
        }
        match &self.thickness_nm {
            Some(s) => write_summary(f, "thickness", " nm", s, true)?,
            None => writeln!(f, "thickness    missing (the default will be used)")?,
        }
        match &self.radius {
            Some(s) => write_summary(f, "radius", "", s, false)?,
            None => writeln!(f, "radius       missing (will be estimated from spacing)")?,
        }
        if !self.extra.is_empty() {
            writeln!(f, "extra attributes:")?;
            for (name, s) in &self.extra {
                write_summary(f, &format!("  {name}"), "", s, false)?;
            }
        }
        Ok(())
    }
}

/// Median distance from a particle to its nearest neighbour in `table` (its first row entry),
/// over the finite, strictly positive ones; 0 when there is none.
pub(crate) fn median_nearest(table: &KnnTable) -> f32 {
    median_positive((0..table.len()).filter_map(|i| table.row(i).next().map(|(_, d)| d)))
        .unwrap_or(0.0)
}
