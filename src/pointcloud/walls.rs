//! Foam walls shared by two bubbles, drawn once.
//!
//! A foam simulator that tracks every bubble as its own closed film (MELP's foam driver,
//! wang-mengdi/melp-thin-film `melp/ParticleALEFoam.h`, one particle set per region) stores each
//! wall between two bubbles twice: once in each bubble's set, a few millimetres apart, facing
//! opposite ways and each with its own thickness. The writer treats the two copies as one film
//! seen by two bubbles: each copy carries half the wall's surface tension ("one half of it,
//! since we are only considering the inner interface"), their velocities are averaged weighted
//! by each copy's local area (`Update_Particle_Sharing_Momentum`, the `sa_ratio` weights) and
//! Lagrangian particles move from the thicker copy to the thinner one
//! (`Interchange_L_Particles`), which relaxes both towards one thickness: the area-weighted
//! mean of the two, the value that conserves their liquid.
//!
//! Drawing both copies doubles the film (two layers blended into a patchwork of both
//! thicknesses, or two MLS sheets whose opposite normals cancel). [`merge_shared_walls`] finds
//! the particles of one set that lie on another set's sheet — within half a spacing along the
//! normal (closer than the splats can tell apart), the planes their positions lie on parallel or
//! opposite (not the stored normals, which lean off the wall near a Plateau border), the other
//! sheet sampled all around them — and keeps one copy: the lower-numbered set's particles move
//! to the middle of the two copies, turn to face across the wall (the mean of the two copies'
//! planes) and take the writer's shared value of the thickness, the
//! area-weighted mean (h_own + ρ·h_other) / (1 + ρ) with ρ = 1 (the writer's `sa_ratio`, the
//! other copy's local area over the own, is 1 where both copies tile the wall, which is where a
//! particle is taken as on it), h_other interpolated from the other copy; the other set's
//! particles on that wall are removed. Towards a Plateau border, where fewer of a kept
//! particle's neighbours lie on the wall, it is merged in proportion (moved that fraction of the
//! way, thickness and normal blended as far), so the kept copy bends from the merged wall into
//! its own outer film instead of stepping by half the gap; the other copy is removed only where
//! the kept one is fully merged. The rest of each bubble is left as it is.

use glam::Vec3;

use super::PointCloud;
use super::estimate::pca_normal;
use super::knn::{KnnTable, PointIndex};
use super::stats::median_nearest;
use super::validate::keep_particles;

/// Neighbours of the other copy searched around each particle.
const NEIGHBOURS: usize = 12;
/// Support radius of the interpolation, in spacings of the coarser set.
const SUPPORT: f32 = 1.5;
/// Copies closer than this many spacings along the normal are one wall.
const MAX_GAP: f32 = 0.5;
/// The other copy's local plane must pass within this many spacings of the particle sideways
/// (else the particle lies past the other copy's edge).
const MAX_SIDEWAYS: f32 = 1.0;
/// |cos| between the particle's normal and the other copy's: parallel or opposite within 45°
/// (the copies of a wall are parallel; where they meet at a Plateau border they touch at an
/// angle before parting).
const MIN_ALIGN: f32 = 0.7;
/// The other copy's normals around the particle must agree this well (|Σ w n| / Σ w): one sheet,
/// not a junction where sheets meet.
const MIN_COHERENCE: f32 = 0.8;

/// One wall found between two sets.
#[derive(Debug, Clone, PartialEq)]
pub struct Wall {
    /// The set whose copy is kept (moved to the middle).
    pub kept: usize,
    /// The set whose copy is removed.
    pub removed: usize,
    /// Particles of the kept copy on the wall.
    pub kept_particles: usize,
    /// Particles of the removed copy on the wall.
    pub removed_particles: usize,
    /// Median distance between the copies along the normal, scene units.
    pub gap: f32,
    /// Median thickness of the kept copy on the wall before merging, nm.
    pub kept_nm: f32,
    /// Median thickness of the other copy there, nm.
    pub other_nm: f32,
    /// Median merged thickness, nm.
    pub merged_nm: f32,
}

/// What [`merge_shared_walls`] did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WallReport {
    /// Every wall found, in set order.
    pub walls: Vec<Wall>,
}

impl WallReport {
    /// True if no wall was found.
    pub fn is_empty(&self) -> bool {
        self.walls.is_empty()
    }
}

/// The other copy's sheet seen from one particle.
#[derive(Debug, Clone, Copy)]
struct Facing {
    /// Signed distance to the other copy's local plane along its normal.
    gap: f32,
    /// The other copy's unit normal there.
    normal: Vec3,
    /// The other copy's interpolated thickness, nm.
    thickness: f32,
}

/// One set prepared for queries.
struct Set<'a> {
    cloud: &'a PointCloud,
    index: PointIndex,
    /// Each particle's [`NEIGHBOURS`] nearest in its own set.
    table: KnnTable,
    /// Each particle's normal as its neighbours' positions give it (the plane of it and its
    /// [`NEIGHBOURS`] nearest, signed as its stored normal; the stored normal where they lie on
    /// no plane). A simulator's stored normals are smoothed over its kernel, and near a Plateau
    /// border, where the wall bends into the bubble's outer film, they lean 20–30° off the wall
    /// the positions lie on (MELP's foam, frame 50: 0.92 of the wall's normal half way out,
    /// where the positions' plane gives 0.999), so the two copies' stored normals part while
    /// the copies still lie on one plane.
    plane: Vec<Vec3>,
    /// Median nearest-neighbour distance, scene units.
    spacing: f32,
}

impl<'a> Set<'a> {
    fn new(cloud: &'a PointCloud) -> Self {
        let index = PointIndex::build(&cloud.positions);
        let table = KnnTable::build_with(&index, &cloud.positions, NEIGHBOURS);
        let spacing = median_nearest(&table);
        let plane = plane_normals(cloud, &table);
        Set {
            cloud,
            index,
            table,
            plane,
            spacing,
        }
    }

    /// The weighted local sheet of this set around `p` within `support`: centroid, normal sum,
    /// thickness (nm) and the normals' agreement |Σ w n| / Σ w (`None` if no particle is within
    /// it). Weights (1 − d²/R²)³, as the MLS surface's.
    fn sheet(&self, p: Vec3, support: f32) -> Option<(Vec3, Vec3, f32, f32)> {
        let thickness = self.cloud.thickness_nm.as_deref()?;
        let (mut sw, mut c, mut n, mut t) = (0.0f32, Vec3::ZERO, Vec3::ZERO, 0.0f32);
        let mut reference: Option<Vec3> = None;
        for (j, d) in self.index.nearest_excluding(p, NEIGHBOURS, u32::MAX) {
            let u = 1.0 - (d / support).powi(2);
            if u <= 0.0 {
                continue;
            }
            let w = u * u * u;
            let j = j as usize;
            if !(thickness[j].is_finite() && self.cloud.positions[j].is_finite()) {
                continue;
            }
            // Normals of one sheet may come with either sign: align them to the first.
            let nj = self.plane[j];
            if nj == Vec3::ZERO || !nj.is_finite() {
                continue;
            }
            let r = *reference.get_or_insert(nj);
            let nj = if nj.dot(r) < 0.0 { -nj } else { nj };
            sw += w;
            c += w * self.cloud.positions[j];
            n += w * nj;
            t += w * thickness[j];
        }
        (sw > 0.0).then(|| (c / sw, n, t / sw, n.length() / sw))
    }

    /// The sheet of this set facing `p` (normal `np`) if `p` lies on it (within the gap and
    /// sideways limits), and whether it is one wall with `p`'s sheet: parallel or opposite
    /// normals, the other sheet coherent.
    fn facing(&self, p: Vec3, np: Vec3, support: f32, spacing: f32) -> Option<(Facing, bool)> {
        let (c, n, thickness, coherence) = self.sheet(p, support)?;
        let normal = n.normalize_or_zero();
        let gap = (c - p).dot(normal);
        let sideways = ((c - p) - gap * normal).length();
        let on = gap.abs() <= MAX_GAP * spacing && sideways <= MAX_SIDEWAYS * spacing;
        let wall =
            coherence >= MIN_COHERENCE && normal.dot(np.normalize_or_zero()).abs() >= MIN_ALIGN;
        on.then_some((
            Facing {
                gap,
                normal,
                thickness,
            },
            wall,
        ))
    }

    /// Which particles of this set lie on `other`'s sheet as one wall, and the share of their
    /// own neighbours within `support` that pass the wall test, as 2·(passing)/(all): above 1
    /// where most pass (which fills the odd particle of a wavy wall that fails it alone, and
    /// drops the odd one where two sheets merely cross). Towards a Plateau border, where the
    /// wall bends into the outer films, half a particle's neighbours or more may lie across the
    /// border; such particles, left where they were, stood up to a centimetre off their moved
    /// neighbours and drew pale scallops and a second rim along the border (MELP's double
    /// bubble, frame 40), so the kept copy is merged by this share (capped at 1).
    fn on_wall(&self, other: &Set, support: f32, spacing: f32) -> Vec<Option<(Facing, f32)>> {
        let found: Vec<Option<(Facing, bool)>> = (0..self.cloud.len())
            .map(|i| {
                let p = self.cloud.positions[i];
                other.facing(p, self.plane[i], support, spacing)
            })
            .collect();
        (0..self.cloud.len())
            .map(|i| {
                let (f, _) = found[i]?;
                let p = self.cloud.positions[i];
                let near = self.index.nearest_excluding(p, NEIGHBOURS, u32::MAX);
                let (mut yes, mut all) = (0, 0);
                for (j, _) in near.into_iter().filter(|(_, d)| *d <= support) {
                    all += 1;
                    yes += usize::from(found[j as usize].is_some_and(|(_, w)| w));
                }
                let share = (2 * yes) as f32 / all.max(1) as f32;
                (yes > 0).then_some((f, share))
            })
            .collect()
    }
}

impl Set<'_> {
    /// The particles flagged in `on` whose neighbours within `reach` are all flagged too: the
    /// removed copy keeps its last row on the wall, so it overlaps the kept copy's edge where
    /// the copies part instead of leaving a crack between the two bubbles' films (MLS: 0.035 %
    /// of the foam's interior missing at 1 spp without).
    fn inside(&self, on: &[bool], reach: f32) -> Vec<bool> {
        (0..on.len())
            .map(|i| on[i] && self.table.row(i).all(|(j, d)| d > reach || on[j as usize]))
            .collect()
    }
}

/// The positions' normals of [`Set::plane`].
fn plane_normals(cloud: &PointCloud, table: &KnnTable) -> Vec<Vec3> {
    let stored = cloud.normals.as_deref().unwrap_or_default();
    (0..cloud.len())
        .map(|i| {
            let s = stored.get(i).map_or(Vec3::ZERO, |n| n.normalize_or_zero());
            match pca_normal(&cloud.positions, table, i, NEIGHBOURS) {
                Some(n) if n.dot(s) < 0.0 => -n,
                Some(n) => n,
                None => s,
            }
        })
        .collect()
}

/// Finds the walls that two of `sets` both hold and keeps one copy of each (see the module
/// docs). Sets without normals or thickness are left alone. Cost: O(n log n) for the trees and
/// O(n·k log n) per pair of sets whose bounds overlap, k = 12 neighbours.
pub fn merge_shared_walls(sets: &mut [PointCloud]) -> WallReport {
    let mut report = WallReport::default();
    let usable = |c: &PointCloud| c.len() >= 2 && c.normals.is_some() && c.thickness_nm.is_some();
    for a in 0..sets.len() {
        for b in a + 1..sets.len() {
            if !usable(&sets[a]) || !usable(&sets[b]) || !bounds_meet(&sets[a], &sets[b]) {
                continue;
            }
            if let Some(w) = merge_pair(sets, a, b) {
                report.walls.push(w);
            }
        }
    }
    report
}

/// True if the two sets' bounding boxes, grown by 5 % of the larger diagonal (a flat wall's
/// box is flat), overlap.
fn bounds_meet(a: &PointCloud, b: &PointCloud) -> bool {
    let bounds = |c: &PointCloud| {
        c.positions
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(*p), hi.max(*p))
            })
    };
    let ((alo, ahi), (blo, bhi)) = (bounds(a), bounds(b));
    let m = 0.05 * (ahi - alo).length().max((bhi - blo).length());
    (alo - m).cmple(bhi + m).all() && (blo - m).cmple(ahi + m).all()
}

/// A particle of the kept copy settled on the merged wall: its index, the other copy as it sees
/// it, the plane its own copy's positions give it, and how far it is merged (0–1, see
/// [`Set::on_wall`]).
type Settle = (usize, Facing, Vec3, f32);

/// Merges the wall of sets `a` (kept) and `b` (removed), if they share one.
fn merge_pair(sets: &mut [PointCloud], a: usize, b: usize) -> Option<Wall> {
    let (moves, drop) = {
        let (sa, sb) = (Set::new(&sets[a]), Set::new(&sets[b]));
        let spacing = sa.spacing.max(sb.spacing);
        if spacing <= 0.0 {
            return None;
        }
        let support = SUPPORT * spacing;
        let moves: Vec<Settle> = sa
            .on_wall(&sb, support, spacing)
            .into_iter()
            .enumerate()
            .filter_map(|(i, f)| f.map(|(f, share)| (i, f, sa.plane[i], share.min(1.0))))
            .collect();
        let on: Vec<bool> = sb
            .on_wall(&sa, support, spacing)
            .iter()
            .map(|f| f.is_some_and(|(_, share)| share > 1.0))
            .collect();
        (moves, sb.inside(&on, spacing))
    };
    let removed = drop.iter().filter(|d| **d).count();
    if moves.iter().all(|m| m.3 < 1.0) || removed == 0 {
        return None;
    }
    let stats = settle_on_wall(&mut sets[a], &moves)?;
    remove(&mut sets[b], &drop);
    let column = |k: usize| -> f32 {
        let mut v: Vec<f32> = stats.iter().map(|s| s[k]).collect();
        median(&mut v)
    };
    Some(Wall {
        kept: a,
        removed: b,
        kept_particles: stats.len(),
        removed_particles: removed,
        gap: column(0),
        kept_nm: column(1),
        other_nm: column(2),
        merged_nm: column(3),
    })
}

/// Moves the particles of `settle` to the middle of the two copies, facing across the wall,
/// with the copies' mean thickness, each by its share (position, normal and thickness
/// blended from where it was by that fraction); returns per fully merged particle the copies'
/// distance and its thickness before, the other copy's and the merged one (`None` without
/// thickness).
fn settle_on_wall(cloud: &mut PointCloud, settle: &[Settle]) -> Option<Vec<[f32; 4]>> {
    let mut stats = Vec::with_capacity(settle.len());
    for &(i, f, own, share) in settle {
        if let Some(n) = cloud.normals.as_mut() {
            let wall = wall_normal(own, f.normal, n[i]);
            n[i] = n[i].normalize_or(wall).lerp(wall, share).normalize_or(wall);
        }
        let t = cloud.thickness_nm.as_mut()?;
        let merged = 0.5 * (t[i] + f.thickness);
        if share >= 1.0 {
            stats.push([f.gap.abs(), t[i], f.thickness, merged]);
        }
        t[i] += share * (merged - t[i]);
        cloud.positions[i] += share * 0.5 * f.gap * f.normal;
    }
    Some(stats)
}

/// The merged wall's normal at a kept particle: the mean of the planes of its own copy (`own`)
/// and of the other copy (`other`, either sign), signed as its stored normal `stored`. Both
/// copies lie on the wall's plane where their stored normals lean off it (see [`Set::plane`]),
/// so the kept disks lie in the wall.
fn wall_normal(own: Vec3, other: Vec3, stored: Vec3) -> Vec3 {
    let other = if other.dot(own) < 0.0 { -other } else { other };
    let n = (own + other).normalize_or(own);
    if n.dot(stored) < 0.0 { -n } else { n }
}

/// Removes the particles flagged in `drop`, with all their attributes.
fn remove(cloud: &mut PointCloud, drop: &[bool]) {
    let keep: Vec<bool> = drop.iter().map(|d| !d).collect();
    keep_particles(cloud, &keep);
}

/// The median of `v` (0 if empty).
fn median(v: &mut [f32]) -> f32 {
    if v.is_empty() {
        return 0.0;
    }
    let mid = v.len() / 2;
    *v.select_nth_unstable_by(mid, f32::total_cmp).1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square grid of `n`² particles (spacing 1) in the plane through `o` spanned by `u`, `v`.
    fn sheet(o: Vec3, u: Vec3, v: Vec3, n: i32, h: f32) -> PointCloud {
        let positions: Vec<Vec3> = (0..n * n)
            .map(|k| o + (k % n) as f32 * u + (k / n) as f32 * v)
            .collect();
        let normal = u.cross(v).normalize();
        PointCloud {
            normals: Some(vec![normal; positions.len()]),
            thickness_nm: Some(vec![h; positions.len()]),
            positions,
            ..PointCloud::default()
        }
    }

    #[test]
    fn two_copies_of_a_wall_become_one_and_crossing_sheets_stay() {
        // Two copies 0.15 spacings apart, opposite normals, 600 and 400 nm.
        let a = sheet(Vec3::ZERO, Vec3::X, Vec3::Y, 12, 600.0);
        let b = sheet(Vec3::new(0.3, 0.3, 0.15), Vec3::Y, Vec3::X, 12, 400.0);
        let mut sets = vec![a, b];
        let r = merge_shared_walls(&mut sets);
        assert_eq!(r.walls.len(), 1);
        assert!(sets[1].len() < 20, "{}", sets[1].len());
        assert!((r.walls[0].merged_nm - 500.0).abs() < 1.0);
        assert!((r.walls[0].gap - 0.15).abs() < 1e-3);
        // A sheet crossing at a right angle shares no wall.
        let a = sheet(Vec3::ZERO, Vec3::X, Vec3::Y, 12, 600.0);
        let c = sheet(Vec3::new(0.0, 5.5, -5.0), Vec3::X, Vec3::Z, 12, 400.0);
        let mut sets = vec![a, c];
        assert!(merge_shared_walls(&mut sets).is_empty());
        assert_eq!(sets[1].len(), 144);
    }

    #[test]
    fn copies_whose_stored_normals_lean_off_the_wall_are_one_wall_lying_in_it() {
        // A simulator's normals smoothed over a Plateau border: each copy's stored normals
        // lean 25° off the wall, the two copies' opposite ways (50° apart, below MIN_ALIGN),
        // while their positions lie on two planes 0.15 spacings apart.
        let lean = |c: &mut PointCloud, n: Vec3| c.normals = Some(vec![n; c.len()]);
        let (s, c) = (25f32.to_radians().sin(), 25f32.to_radians().cos());
        let mut a = sheet(Vec3::ZERO, Vec3::X, Vec3::Y, 12, 600.0);
        lean(&mut a, Vec3::new(s, 0.0, c));
        let mut b = sheet(Vec3::new(0.3, 0.3, 0.15), Vec3::Y, Vec3::X, 12, 400.0);
        lean(&mut b, Vec3::new(s, 0.0, -c));
        let mut sets = vec![a, b];
        let r = merge_shared_walls(&mut sets);
        assert_eq!(r.walls.len(), 1, "{r:?}");
        assert!(sets[1].len() < 20, "{}", sets[1].len());
        // The kept copy's particles moved to the middle lie in it and face across it.
        let moved: Vec<usize> = (0..sets[0].len())
            .filter(|&i| (sets[0].positions[i].z - 0.075).abs() < 1e-4)
            .collect();
        assert!(moved.len() > 100, "{}", moved.len());
        for i in moved {
            let n = sets[0].normals.as_ref().unwrap()[i];
            assert!(n.dot(Vec3::Z) > 0.9998, "{i}: {n}");
        }
    }
}
