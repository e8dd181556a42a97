//! Sheets: films that meet without joining smoothly (the walls of a foam, one particle set per
//! bubble) each get their own implicit function. The blend of f across two walls meeting at an
//! angle, or carrying their own orientation, mixes tangent planes that disagree: along the
//! junction the normals cancel and the zero set rounds off into the corner, where the particles'
//! weight is too low to count as film, or vanishes (pinholes along every junction line). With
//! sheets, f at a point blends only the particles of one sheet, so each wall runs into the
//! junction as it would alone, and a ray meets the first crossing of any sheet.

use std::cell::RefCell;

use super::MlsSurface;
use super::field::Cand;
use super::gathered::sort_by_entry;
use crate::geometry::{Ray, SurfaceHit};
use crate::{Error, Result};

/// The candidates of one sheet along the current ray, and the sheets along it (label, where
/// the ray first enters it).
type SheetScratch = (Vec<Cand>, Vec<(u32, f32)>);

thread_local! {
    /// Scratch of [`MlsSurface::march_sheets`] (see [`SheetScratch`]).
    static SHEET_CANDS: RefCell<SheetScratch> = const {
        RefCell::new((Vec::new(), Vec::new()))
    };
}

/// The most sheets a surface takes (labels are 0..MAX_SHEETS).
const MAX_SHEETS: u32 = 1 << 16;

impl MlsSurface {
    /// Splits the surface into sheets: `sheets[i]` (input order, below 65 536) names the
    /// sheet particle `i` belongs to; f then blends one sheet's particles at a time (see the
    /// `sheets` module). All zeros: one sheet, as built. Cost: O(n) plus the median weight's
    /// ~2000 point queries again.
    ///
    /// # Errors
    /// A length other than the particle count, or a label of 65 536 or more.
    pub fn set_sheets(&mut self, sheets: &[u32]) -> Result<()> {
        if sheets.len() != self.particles.len() {
            return Err(Error::invalid(format!(
                "mls: {} sheet labels for {} particles",
                sheets.len(),
                self.particles.len()
            )));
        }
        if let Some(i) = sheets.iter().position(|&s| s >= MAX_SHEETS) {
            return Err(Error::invalid(format!(
                "mls: sheet label {} of particle {i} is not below {MAX_SHEETS}",
                sheets[i]
            )));
        }
        self.sheets = if sheets.iter().all(|&s| s == sheets[0]) {
            Vec::new()
        } else {
            let order = self.bvh.order();
            order.iter().map(|&i| sheets[i as usize]).collect()
        };
        self.weight_threshold = self.params.min_weight * self.median_particle_weight();
        Ok(())
    }

    /// The number of sheets (1 unless [`MlsSurface::set_sheets`] split the surface).
    pub fn sheet_count(&self) -> usize {
        let mut seen: Vec<u32> = self.sheets.clone();
        seen.sort_unstable();
        seen.dedup();
        seen.len().max(1)
    }

    /// The sheet of the particle in `slot`.
    #[inline]
    pub(super) fn sheet(&self, slot: u32) -> u32 {
        self.sheets.get(slot as usize).copied().unwrap_or(0)
    }

    /// Keeps only the candidates of the sheet that weighs most at `x` (the one the point is
    /// nearest, relative to the supports); nothing to do with one sheet.
    pub(super) fn keep_heaviest_sheet(&self, x: glam::Vec3, cands: &mut Vec<Cand>) {
        if self.sheets.is_empty() {
            return;
        }
        let heaviest = cands
            .iter()
            .map(|c| (c, 1.0 - (x - c.p).length_squared() * c.inv_h2))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(c, _)| self.sheet(c.slot));
        if let Some(s) = heaviest {
            cands.retain(|c| self.sheet(c.slot) == s);
        }
    }

    /// [`MlsSurface::march_all`] for each sheet among `cands` on its own, the nearest crossing
    /// of any. One sheet: `march_all` itself.
    pub(super) fn march_sheets(&self, ray: &Ray, cands: &mut [Cand]) -> Option<SurfaceHit> {
        let inf = f32::INFINITY;
        // One sheet along the ray (the common case) needs no split.
        let first = cands.first().map_or(0, |c| self.sheet(c.slot));
        if self.sheets.is_empty() || cands.iter().all(|c| self.sheet(c.slot) == first) {
            return self.march_all(ray, cands, inf);
        }
        // In order once, so each sheet's share is in order too.
        sort_by_entry(cands);
        SHEET_CANDS.with_borrow_mut(|(own, labels)| {
            // The sheets in the order the ray first enters them: a near sheet's crossing,
            // found first, stops the farther sheets' marches at it (`stop`). In label order a
            // far wall was often marched to its crossing before the near one was looked at.
            // Each with where it is first entered.
            labels.clear();
            for c in cands.iter() {
                let s = self.sheet(c.slot);
                if !labels.iter().any(|l| l.0 == s) {
                    labels.push((s, c.ta));
                }
            }
            let mut best: Option<SurfaceHit> = None;
            for &(s, entry) in labels.iter() {
                // Intervals starting past the nearest crossing so far cannot hold a nearer one;
                // this sheet's and every later one's start there.
                let stop = best.map_or(inf, |b| b.t);
                if entry > stop {
                    break;
                }
                own.clear();
                own.extend(cands.iter().filter(|c| self.sheet(c.slot) == s));
                if let Some(h) = self.march_all(ray, own, stop)
                    && best.is_none_or(|b| h.t < b.t)
                {
                    best = Some(h);
                }
            }
            best
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// Three walls of spacing `s` meeting at 120° along the z axis (a foam's Plateau border),
    /// each sampled up to half a spacing from the junction, wall k labelled `labels[k]`, the
    /// first wall's normals flipped if `flip_first` (as one bubble's set would have it): the
    /// surface (sheets not set), its labels and the walls' directions.
    fn three_walls(
        s: f32,
        labels: [u32; 3],
        flip_first: bool,
    ) -> (MlsSurface, Vec<u32>, Vec<Vec3>) {
        let dirs: Vec<Vec3> = [90f32, 210.0, 330.0]
            .iter()
            .map(|a| Vec3::new(a.to_radians().cos(), a.to_radians().sin(), 0.0))
            .collect();
        let (mut p, mut n, mut label) = (Vec::new(), Vec::new(), Vec::new());
        for (k, d) in dirs.iter().enumerate() {
            let normal = Vec3::Z.cross(*d) * if k == 0 && flip_first { -1.0 } else { 1.0 };
            for i in 0..12 {
                for j in -10..=10 {
                    p.push((i as f32 + 0.5) * s * *d + j as f32 * s * Vec3::Z);
                    n.push(normal);
                    label.push(labels[k]);
                }
            }
        }
        let m = MlsSurface::build(&p, &n, &vec![0.6 * s; p.len()], &vec![400.0; p.len()]).unwrap();
        (m, label, dirs)
    }

    /// Rays aimed from around the junction of [`three_walls`] (normals oriented per wall) at
    /// points of the walls near it: the rays that miss every wall.
    fn junction_misses(sheets: bool) -> usize {
        let s = 0.1f32;
        let (mut m, label, dirs) = three_walls(s, [0, 1, 2], true);
        if sheets {
            m.set_sheets(&label).unwrap();
            assert_eq!(m.sheet_count(), 3);
        }
        let mut misses = 0;
        for c in 0..12 {
            let a = (15.0 + 30.0 * c as f32).to_radians();
            let eye = 3.0 * Vec3::new(a.cos(), a.sin(), 0.3);
            for d in &dirs {
                for i in 0..30 {
                    let target = (i as f32 * 0.1 * s) * *d + 0.37 * s * Vec3::Z;
                    let dist = (target - eye).length();
                    let ray = Ray::new(eye, (target - eye) / dist);
                    let hit = m.intersect(&ray, 0.0, 10.0);
                    misses += hit.is_none_or(|h| h.t > dist + 0.5 * s) as usize;
                }
            }
        }
        misses
    }

    /// The nearest crossing over the sheets, each sheet's spheres marched to their first
    /// crossing on their own (no order, no early stop), and the sheet it lies in; with the
    /// sheet entered first along the ray.
    fn nearest_of_each_sheet(m: &MlsSurface, ray: &Ray, t_min: f32) -> (Option<(f32, u32)>, u32) {
        let mut cands = Vec::new();
        m.gather_all(ray, t_min, f32::INFINITY, &mut cands);
        sort_by_entry(&mut cands);
        let first = cands.first().map_or(0, |c| m.sheet(c.slot));
        let mut labels: Vec<u32> = cands.iter().map(|c| m.sheet(c.slot)).collect();
        labels.sort_unstable();
        labels.dedup();
        let nearest = labels
            .iter()
            .filter_map(|&s| {
                let mut own: Vec<Cand> = cands
                    .iter()
                    .filter(|c| m.sheet(c.slot) == s)
                    .copied()
                    .collect();
                m.march_all(ray, &mut own, f32::INFINITY).map(|h| (h.t, s))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        (nearest, first)
    }

    /// Rays through the junction of three walls (labels in an order unrelated to where the
    /// rays meet them), some starting part way along: the crossing found is bit for bit the
    /// nearest of the sheets' own crossings, also where the sheet the ray enters first is not
    /// the one it crosses first (those cases are counted, so an early stop there would fail).
    #[test]
    fn the_crossing_is_the_nearest_of_every_sheet() {
        let (mut m, label, _) = three_walls(0.1, [7, 2, 5], false);
        m.set_sheets(&label).unwrap();
        let mut rnd = crate::geometry::ray4::test_rng(0x5eed_0fa1);
        let (mut hits, mut not_first) = (0, 0);
        for k in 0..3000 {
            let eye = Vec3::new(2.0 * rnd(), 2.0 * rnd(), 0.5 * rnd());
            let target = 1.2 * Vec3::new(rnd(), rnd(), 0.0) + 0.5 * rnd() * Vec3::Z;
            let ray = Ray::new(eye, target - eye);
            let t_min = if k % 3 == 0 { 0.3 * rnd().abs() } else { 0.0 };
            let (want, first) = nearest_of_each_sheet(&m, &ray, t_min);
            let got = m
                .intersect(&ray, t_min, f32::INFINITY)
                .map(|h| h.t.to_bits());
            assert_eq!(got, want.map(|w| w.0.to_bits()), "ray {k}");
            hits += want.is_some() as usize;
            not_first += want.is_some_and(|w| w.1 != first) as usize;
        }
        assert!(
            hits > 1000 && not_first > 20,
            "{hits} hits, {not_first} not in the first sheet"
        );
    }

    #[test]
    fn walls_meeting_at_a_junction_leave_no_gap_when_blended_one_at_a_time() {
        assert_eq!(junction_misses(true), 0);
    }

    #[test]
    fn blending_all_walls_at_once_opens_the_junction() {
        // The failure the sheets remove (so the test above can fail).
        assert!(junction_misses(false) > 0);
    }

    #[test]
    fn sheet_labels_are_checked() {
        let p = [Vec3::ZERO, Vec3::X];
        let n = [Vec3::Z, Vec3::Z];
        let mut m = MlsSurface::build(&p, &n, &[0.5, 0.5], &[100.0, 100.0]).unwrap();
        assert!(
            m.set_sheets(&[0])
                .unwrap_err()
                .to_string()
                .contains("1 sheet labels")
        );
        assert!(
            m.set_sheets(&[0, 70_000])
                .unwrap_err()
                .to_string()
                .contains("particle 1")
        );
        m.set_sheets(&[3, 3]).unwrap();
        assert_eq!(m.sheet_count(), 1);
    }
}
