//! A uniform grid of hashed cells over particle positions, for exact k-nearest queries on
//! surface samplings: the particles sorted by cell, a query scanning rings of cells around its
//! own until no unscanned cell can hold a nearer particle.
//!
//! Answers are exact and ordered by squared distance, then particle index (ties included),
//! the squared distance summed as `dx² + dy² + dz²` in `f32` like kiddo's. The cell side is
//! the 90th percentile of a sample's distance to its [`SIZE_RANK`]-th neighbour, so most
//! 12-neighbour queries end after the 27 cells around their own. Only occupied cells are
//! stored (memory O(n) however far a few particles lie); a cloud whose cells would hold too
//! many particles (coincident copies, a dense cluster beside far outliers) is refused at
//! build, and a query that would need more than [`MAX_RING`] rings is refused too: the caller
//! then asks the k-d tree ([`super::knn::PointIndex`] does both).

use glam::Vec3;
use rayon::prelude::*;

/// Cells per axis at most: a cell's coordinates are packed 21 bits each into one key.
const AXIS_CELLS: i64 = 1 << 21;

/// Rings of cells a query scans around its own before it gives up.
pub(crate) const MAX_RING: i64 = 6;

/// Particles (evenly strided) whose neighbour distance sizes the cells.
const SIZE_SAMPLE: usize = 2048;

/// The neighbour rank whose distance sizes the cells.
pub(crate) const SIZE_RANK: usize = 12;

/// Most rows of cells (`y`, `z`) a grid may have, a particle (plus [`SPARE_ROWS`]): a cloud
/// whose extent needs more is left to the tree.
const ROWS_PER_PARTICLE: u64 = 8;

/// Rows of cells any cloud may have.
const SPARE_ROWS: u64 = 4096;

/// Most candidate pairs a particle on average (Σ over cells of count², over n) before the grid
/// is refused as too crowded.
const CROWD_BUDGET: u64 = 256;

/// Particles sorted by cell, and the occupied cells' keys.
pub(crate) struct Grid {
    /// Corner of cell (0, 0, 0) (scene units).
    lo: Vec3,
    /// Cell side (scene units) and its inverse.
    h: f32,
    inv_h: f32,
    /// Margin (scene units) taken off a ring's reach for the rounding of cell coordinates.
    eps: f32,
    /// Cells per axis.
    span: [i64; 3],
    /// Occupied cells' keys, ascending.
    keys: Vec<u64>,
    /// Row (`y`, `z`) of cells holds the occupied cells `rows[r]..rows[r + 1]` of `keys`,
    /// `r = y + z · span[1]`.
    rows: Vec<u32>,
    /// Cell `c` holds `items[starts[c]..starts[c + 1]]`.
    starts: Vec<u32>,
    /// Particle indices, by cell then index.
    pub(crate) items: Vec<u32>,
    /// Their positions.
    pts: Vec<Vec3>,
}

/// The candidates for the `k` nearest: `(squared distance, index)`, unordered while a search
/// goes on, the `k` best ascending once it is done.
pub(crate) struct Best {
    k: usize,
    pub(crate) v: Vec<(f32, u32)>,
}

/// Order by squared distance, then index.
fn by_distance(a: &(f32, u32), b: &(f32, u32)) -> std::cmp::Ordering {
    a.0.total_cmp(&b.0).then(a.1.cmp(&b.1))
}

impl Best {
    /// An empty list keeping `k` entries.
    pub(crate) fn new(k: usize) -> Self {
        Best {
            k,
            v: Vec::with_capacity(4 * k),
        }
    }

    /// Entries kept.
    pub(crate) fn k(&self) -> usize {
        self.k
    }

    fn offer(&mut self, d2: f32, j: u32) {
        self.v.push((d2, j));
    }

    /// The `k`-th smallest squared distance among the candidates (keeping only the `k` best:
    /// no later candidate can bring back one ranked below them), if there are `k`.
    fn kth(&mut self) -> Option<f32> {
        let k = self.k;
        if self.v.len() < k {
            return None;
        }
        if self.v.len() > k {
            self.v.select_nth_unstable_by(k - 1, by_distance);
            self.v.truncate(k);
        }
        self.v.iter().map(|c| c.0).reduce(f32::max)
    }

    /// Keeps the `k` best, ascending.
    fn finish(&mut self) {
        self.kth();
        self.v.sort_unstable_by(by_distance);
    }
}

fn key(c: [i64; 3]) -> u64 {
    ((c[2] as u64) << 42) | ((c[1] as u64) << 21) | c[0] as u64
}

impl Grid {
    /// The grid over the finite `positions`, or `None` where it does not suit them (no finite
    /// point, an extent that overflows, or cells too crowded). Cost: two parallel sorts of the
    /// particles by cell, and [`SIZE_SAMPLE`] queries.
    pub(crate) fn build(positions: &[Vec3]) -> Option<Grid> {
        let finite: Vec<u32> = (0..positions.len() as u32)
            .into_par_iter()
            .filter(|&i| positions[i as usize].is_finite())
            .collect();
        let n = finite.len();
        let first = *finite.first()?;
        let p0 = positions[first as usize];
        let (lo, hi) = finite
            .par_iter()
            .map(|&i| (positions[i as usize], positions[i as usize]))
            .reduce(|| (p0, p0), |a, b| (a.0.min(b.0), a.1.max(b.1)));
        let extent = (hi - lo).max_element();
        if !extent.is_finite() || extent <= 0.0 {
            return None;
        }
        let finest = extent / (AXIS_CELLS - 2) as f32;
        // First cells of about cbrt(n) to the longest axis, only to measure the spacing.
        let coarse = extent / (n as f32).cbrt().max(1.0);
        let probe = Self::with_cells(positions, &finite, lo, hi, coarse.max(finest))?;
        let m = n.min(SIZE_SAMPLE);
        let mut d: Vec<f32> = (0..m)
            .into_par_iter()
            .filter_map(|s| {
                let i = finite[s * n / m];
                let mut best = Best::new(SIZE_RANK);
                probe
                    .nearest_into(positions[i as usize], i, &mut best)
                    .then_some(())?;
                best.v.last().map(|b| b.0.max(0.0).sqrt())
            })
            .collect();
        if d.is_empty() {
            return None;
        }
        d.sort_unstable_by(f32::total_cmp);
        let h = d[(d.len() * 9 / 10).min(d.len() - 1)].max(finest);
        let grid = Self::with_cells(positions, &finite, lo, hi, h)?;
        let crowd: u64 = grid
            .starts
            .windows(2)
            .map(|w| ((w[1] - w[0]) as u64).pow(2))
            .sum();
        (crowd <= CROWD_BUDGET * n as u64).then_some(grid)
    }

    /// Cells of side `h` over the `finite` particles within `lo..=hi`.
    fn with_cells(positions: &[Vec3], finite: &[u32], lo: Vec3, hi: Vec3, h: f32) -> Option<Grid> {
        let inv_h = 1.0 / h;
        if !(h > 0.0 && inv_h.is_finite()) {
            return None;
        }
        let cells = ((hi - lo) * inv_h).floor();
        let span = [cells.x, cells.y, cells.z].map(|c| (c as i64 + 1).clamp(1, AXIS_CELLS));
        let n_rows = span[1] as u64 * span[2] as u64;
        if n_rows > ROWS_PER_PARTICLE * finite.len() as u64 + SPARE_ROWS {
            return None;
        }
        let cell_of = |p: Vec3| {
            let c = ((p - lo) * inv_h).floor();
            key([0, 1, 2].map(|a| (c[a] as i64).clamp(0, span[a] - 1)))
        };
        let mut keyed: Vec<u128> = finite
            .par_iter()
            .map(|&i| ((cell_of(positions[i as usize]) as u128) << 32) | i as u128)
            .collect();
        keyed.par_sort_unstable();
        let items: Vec<u32> = keyed.par_iter().map(|&v| v as u32).collect();
        let pts: Vec<Vec3> = items.par_iter().map(|&i| positions[i as usize]).collect();
        let mut keys = Vec::new();
        let mut starts = Vec::new();
        for (s, &v) in keyed.iter().enumerate() {
            let k = (v >> 32) as u64;
            if keys.last() != Some(&k) {
                keys.push(k);
                starts.push(s as u32);
            }
        }
        starts.push(keyed.len() as u32);
        // Occupied cells counted per row, then summed into each row's first cell.
        let mut rows = vec![0u32; n_rows as usize + 1];
        let row_of = |k: u64| ((k >> 42) * span[1] as u64 + ((k >> 21) & 0x1f_ffff)) as usize;
        for &k in &keys {
            rows[row_of(k) + 1] += 1;
        }
        for r in 1..rows.len() {
            rows[r] += rows[r - 1];
        }
        let reach = lo.abs().max(hi.abs()).max_element();
        Some(Grid {
            lo,
            h,
            inv_h,
            eps: 1e-4 * h + 8.0 * f32::EPSILON * reach,
            span,
            keys,
            rows,
            starts,
            items,
            pts,
        })
    }

    /// Number of particles in the grid.
    pub(crate) fn len(&self) -> usize {
        self.items.len()
    }

    /// The position of the particle at sorted place `s` (see [`Grid::items`]).
    pub(crate) fn point(&self, s: usize) -> Vec3 {
        self.pts[s]
    }

    /// Offers `best` every particle but `exclude` in the cells `x0..=x1` of row (`y`, `z`).
    fn scan_row(&self, q: Vec3, [x0, x1, y, z]: [i64; 4], exclude: u32, best: &mut Best) {
        let (x0, x1) = (x0.max(0), x1.min(self.span[0] - 1));
        if x0 > x1 || !(0..self.span[1]).contains(&y) || !(0..self.span[2]).contains(&z) {
            return;
        }
        let (a, b) = (key([x0, y, z]), key([x1, y, z]));
        let r = (y + z * self.span[1]) as usize;
        let (row_start, row_end) = (self.rows[r] as usize, self.rows[r + 1] as usize);
        let mut c = row_start + self.keys[row_start..row_end].partition_point(|&k| k < a);
        while c < row_end && self.keys[c] <= b {
            let (s, e) = (self.starts[c] as usize, self.starts[c + 1] as usize);
            for (p, &j) in self.pts[s..e].iter().zip(&self.items[s..e]) {
                if j != exclude {
                    let (dx, dy, dz) = (q.x - p.x, q.y - p.y, q.z - p.z);
                    best.offer(dx * dx + dy * dy + dz * dz, j);
                }
            }
            c += 1;
        }
    }

    /// The `best.k` nearest particles to `q` but `exclude` into `best` (which starts empty),
    /// ascending by (squared distance, index). False, with `best` incomplete, when that would
    /// take more than [`MAX_RING`] rings of cells. Cost: about the particles in the cells
    /// scanned, plus a binary search over the occupied cells a row of cells.
    pub(crate) fn nearest_into(&self, q: Vec3, exclude: u32, best: &mut Best) -> bool {
        if best.k == 0 {
            return true;
        }
        let f = ((q - self.lo) * self.inv_h).floor();
        let c = [f.x, f.y, f.z].map(|v| v.clamp(-(AXIS_CELLS as f32), AXIS_CELLS as f32) as i64);
        for r in 0..=MAX_RING {
            for z in c[2] - r..=c[2] + r {
                for y in c[1] - r..=c[1] + r {
                    if (z - c[2]).abs() == r || (y - c[1]).abs() == r {
                        self.scan_row(q, [c[0] - r, c[0] + r, y, z], exclude, best);
                    } else {
                        self.scan_row(q, [c[0] - r, c[0] - r, y, z], exclude, best);
                        self.scan_row(q, [c[0] + r, c[0] + r, y, z], exclude, best);
                    }
                }
            }
            // Every particle not yet scanned lies beyond one face of the scanned block.
            let mut reach = f32::INFINITY;
            for a in 0..3 {
                if c[a] - r > 0 {
                    reach = reach.min(q[a] - (self.lo[a] + (c[a] - r) as f32 * self.h));
                }
                if c[a] + r < self.span[a] - 1 {
                    reach = reach.min(self.lo[a] + (c[a] + r + 1) as f32 * self.h - q[a]);
                }
            }
            if reach == f32::INFINITY {
                best.finish();
                return true;
            }
            let reach = reach - self.eps;
            if reach > 0.0 && best.kth().is_some_and(|d2| d2 < reach * reach) {
                best.finish();
                return true;
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `k` nearest by a sorted scan of every finite particle: the oracle.
    fn brute(pos: &[Vec3], q: Vec3, k: usize, exclude: u32) -> Vec<(f32, u32)> {
        let mut all: Vec<(f32, u32)> = (0..pos.len() as u32)
            .filter(|&j| j != exclude && pos[j as usize].is_finite())
            .map(|j| {
                let p = pos[j as usize];
                let (dx, dy, dz) = (q.x - p.x, q.y - p.y, q.z - p.z);
                (dx * dx + dy * dy + dz * dz, j)
            })
            .collect();
        all.sort_unstable_by(by_distance);
        all.truncate(k);
        all
    }

    #[test]
    fn grid_answers_as_a_sorted_scan_ties_included() {
        let mut s = 7u32;
        let mut rnd = move || {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            s as f32 / u32::MAX as f32
        };
        let shell: Vec<Vec3> = (0..3000)
            .map(|_| Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize())
            .collect();
        // A square lattice: distances tie four ways.
        let lattice: Vec<Vec3> = (0..2500)
            .map(|i| Vec3::new((i % 50) as f32 * 0.25, (i / 50) as f32 * 0.25, 0.0))
            .collect();
        let line: Vec<Vec3> = (0..500).map(|i| Vec3::X * (i / 3) as f32).collect();
        let mut clustered: Vec<Vec3> = (0..2000).map(|_| Vec3::new(rnd(), rnd(), 0.0)).collect();
        clustered.push(Vec3::splat(1e6));
        clustered.push(Vec3::NAN);
        for pos in [shell, lattice, line, clustered] {
            let Some(grid) = Grid::build(&pos) else {
                continue;
            };
            for k in [1, 12, 64] {
                for i in (0..pos.len()).step_by(7) {
                    let mut best = Best::new(k);
                    if grid.nearest_into(pos[i], i as u32, &mut best) {
                        assert_eq!(best.v, brute(&pos, pos[i], k, i as u32), "{i} k {k}");
                    }
                }
            }
        }
    }
}
