//! Camera rays of a pinhole grid answered by rasterising the disks instead of walking the BVH
//! once per ray ([`DiskGeometry::primary_raster`]).
//!
//! Every camera ray starts at the eye, so the pixels whose rays can meet a disk are known in
//! closed form: the box around the projection of the disk's bounding sphere. Each disk is
//! projected once and binned into the image's 16×16 tiles, sorted front to back by the nearest
//! distance of its sphere from the eye. A tile then runs two passes over its bin:
//!
//! 1. the closest disk hit of every pixel (a z-buffer of exact ray–disk tests, ties to the
//!    lower particle index as in [`DiskGeometry::intersect`]), stopping at the first disk that
//!    starts beyond every pixel's closest hit;
//! 2. the members of every pixel's layer band, blended as `intersect` blends them, stopping at
//!    the first disk that starts beyond every band.
//!
//! The ray–disk test, the band and the blend are the ones `intersect` uses, so the closest disk,
//! its `t`, the layer's members (`coverage`), `t_exit` and `particle` are those of `intersect`;
//! the blended `t`, normal and thickness differ only by the order of the members' float sums
//! (a few ulps).
//!
//! A disk whose bounding sphere reaches the plane through the eye perpendicular to the view
//! has no bounded projection: it is binned into every tile as starting at distance 0, so every
//! ray tests it.

use glam::Vec3;
use rayon::prelude::*;

use super::disk_query::layer_hit;
use super::disks::DiskGeometry;
use super::primitives::intersect_disk;
use super::{Ray, SurfaceHit};

/// Side of the square tiles the disks are binned into, pixels.
pub const RASTER_TILE: usize = 16;

/// Relative and absolute (per unit distance) growth of a disk's bounding sphere so that float
/// rounding in the projection, the camera's rays and the exact test never drops a hit.
const GROW_REL: f64 = 1e-4;
const GROW_ABS: f64 = 1e-5;
/// Extra margin of a projected box, pixels.
const MARGIN_PX: f64 = 0.01;

/// A pinhole camera's grid of one ray per pixel: the ray of pixel (x, y) (x right, y down)
/// starts at `eye` and points along `forward + u·right + v·up` with
/// `u = (2 (x + 0.5) / width − 1) · half_width`, `v = (1 − 2 (y + 0.5) / height) · half_height`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PinholeGrid {
    /// Where every ray starts, scene units.
    pub eye: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// Unit right vector of the image plane (perpendicular to `forward`).
    pub right: Vec3,
    /// Unit up vector of the image plane (perpendicular to both).
    pub up: Vec3,
    /// Half the image plane's width at unit distance along `forward` (tan of half the
    /// horizontal field of view).
    pub half_width: f32,
    /// Half the image plane's height at unit distance (tan of half the vertical field of view).
    pub half_height: f32,
    /// Image width, pixels.
    pub width: usize,
    /// Image height, pixels.
    pub height: usize,
}

/// A disk binned into a tile: its nearest possible hit distance, its slot and its pixel box
/// (inclusive). 16 bytes.
#[derive(Clone, Copy, Debug)]
struct Entry {
    t_near: f32,
    slot: u32,
    x0: u16,
    x1: u16,
    y0: u16,
    y1: u16,
}

/// The disks of a [`DiskGeometry`] binned for one [`PinholeGrid`] (see the module docs).
/// Memory: 16 bytes per (disk, tile it overlaps) and 4 bytes a tile; on the 1M-disk shell at
/// 1280×720, about 1 M entries (≈ 17 bytes a pixel).
pub struct PrimaryRaster<'g> {
    geometry: &'g DiskGeometry,
    grid: PinholeGrid,
    tiles_x: usize,
    /// Start of each tile's entries in `entries` (one more than there are tiles).
    starts: Vec<u32>,
    entries: Vec<Entry>,
}

impl PinholeGrid {
    /// The box of pixels whose rays can meet a sphere (`c`, `r`) and the nearest distance of
    /// the sphere from the eye; `Some(None)` for a sphere reaching the eye's plane, `None` for
    /// one that no ray of the grid can meet.
    fn project(&self, c: Vec3, r: f32) -> Option<Option<Entry>> {
        let oc = (c - self.eye).as_dvec3();
        let dist = oc.length();
        let r = r as f64 * (1.0 + GROW_REL) + GROW_ABS * dist;
        let basis = |v: Vec3| oc.dot(v.as_dvec3());
        let (cx, cy, cz) = (basis(self.right), basis(self.up), basis(self.forward));
        if cz < -r {
            return None;
        }
        if cz <= 1.01 * r {
            return Some(None);
        }
        // Tangent planes through the eye containing the up (right) axis: slopes u = x / z of
        // the lines through the origin tangent to the circle (cx, cz, r), both roots of
        // u² (cz² − r²) − 2 u cx cz + cx² − r² = 0.
        let slopes = |a: f64| {
            let (q, s) = (cz * cz - r * r, r * (a * a + cz * cz - r * r).sqrt());
            ((a * cz - s) / q, (a * cz + s) / q)
        };
        let (u0, u1) = slopes(cx);
        let (v0, v1) = slopes(cy);
        let (w, h) = (self.width as f64, self.height as f64);
        // Pixel coordinates of the ray's (u, v), inverted from the grid's definition.
        let px = |u: f64| (u / self.half_width as f64 + 1.0) * 0.5 * w - 0.5;
        let py = |v: f64| (1.0 - v / self.half_height as f64) * 0.5 * h - 0.5;
        let (x0, x1) = ((px(u0) - MARGIN_PX).ceil(), (px(u1) + MARGIN_PX).floor());
        let (y0, y1) = ((py(v1) - MARGIN_PX).ceil(), (py(v0) + MARGIN_PX).floor());
        if x1 < 0.0 || y1 < 0.0 || x0 > w - 1.0 || y0 > h - 1.0 || x0 > x1 || y0 > y1 {
            return None;
        }
        let clamp = |a: f64, n: f64| a.clamp(0.0, n - 1.0) as u16;
        Some(Some(Entry {
            t_near: ((dist - r).max(0.0) * (1.0 - 1e-5)) as f32,
            slot: 0,
            x0: clamp(x0, w),
            x1: clamp(x1, w),
            y0: clamp(y0, h),
            y1: clamp(y1, h),
        }))
    }

    /// The whole image as a pixel box.
    fn everything(&self) -> Entry {
        Entry {
            t_near: 0.0,
            slot: 0,
            x0: 0,
            x1: (self.width - 1) as u16,
            y0: 0,
            y1: (self.height - 1) as u16,
        }
    }

    /// True if the grid's numbers can be rasterised (finite, positive extents, orthonormal
    /// basis, at most 65535 pixels a side).
    fn usable(&self) -> bool {
        let unit = |v: Vec3| (v.length() - 1.0).abs() < 1e-4;
        let ortho = self.forward.dot(self.right).abs() < 1e-4
            && self.forward.dot(self.up).abs() < 1e-4
            && self.right.dot(self.up).abs() < 1e-4;
        self.eye.is_finite()
            && unit(self.forward)
            && unit(self.right)
            && unit(self.up)
            && ortho
            && self.half_width.is_finite()
            && self.half_height.is_finite()
            && self.half_width > 0.0
            && self.half_height > 0.0
            && (1..=65535).contains(&self.width)
            && (1..=65535).contains(&self.height)
    }
}

impl DiskGeometry {
    /// Bins the disks for the camera rays of `grid` (see the module docs); `None` if the grid
    /// is not usable (non-finite, not orthonormal, or over 65535 pixels a side). Cost: one
    /// projection per disk (parallel), a counting sort into tiles, a sort of each tile's bin.
    pub fn primary_raster(&self, grid: &PinholeGrid) -> Option<PrimaryRaster<'_>> {
        if !grid.usable() {
            return None;
        }
        let n = self.len();
        let projected: Vec<Option<Option<Entry>>> = (0..n)
            .into_par_iter()
            .with_min_len(4096)
            .map(|s| {
                let d = &self.disks[s];
                grid.project(d.center, d.radius)
            })
            .collect();
        let tiles_x = grid.width.div_ceil(RASTER_TILE);
        let tiles = tiles_x * grid.height.div_ceil(RASTER_TILE);
        let boxed = |s: usize| {
            projected[s].map(|e| {
                let mut e = e.unwrap_or_else(|| grid.everything());
                e.slot = s as u32;
                e
            })
        };
        let tiles_of = |e: &Entry| {
            let (tx0, tx1) = (e.x0 as usize / RASTER_TILE, e.x1 as usize / RASTER_TILE);
            let (ty0, ty1) = (e.y0 as usize / RASTER_TILE, e.y1 as usize / RASTER_TILE);
            (ty0..=ty1).flat_map(move |ty| (tx0..=tx1).map(move |tx| ty * tiles_x + tx))
        };
        // Counting sort into the tiles.
        let mut starts = vec![0u32; tiles + 1];
        for e in (0..n).filter_map(boxed) {
            for t in tiles_of(&e) {
                starts[t + 1] += 1;
            }
        }
        for t in 0..tiles {
            starts[t + 1] += starts[t];
        }
        let mut next = starts.clone();
        let empty = Entry {
            t_near: 0.0,
            slot: 0,
            x0: 0,
            x1: 0,
            y0: 0,
            y1: 0,
        };
        let mut entries = vec![empty; starts[tiles] as usize];
        for e in (0..n).filter_map(boxed) {
            for t in tiles_of(&e) {
                entries[next[t] as usize] = e;
                next[t] += 1;
            }
        }
        // Front to back within each tile (ties by slot: deterministic).
        let mut rest = entries.as_mut_slice();
        let mut bins = Vec::with_capacity(tiles);
        for t in 0..tiles {
            let (bin, tail) = rest.split_at_mut((starts[t + 1] - starts[t]) as usize);
            bins.push(bin);
            rest = tail;
        }
        bins.par_iter_mut().for_each(|bin| {
            bin.sort_unstable_by(|a, b| a.t_near.total_cmp(&b.t_near).then(a.slot.cmp(&b.slot)))
        });
        Some(PrimaryRaster {
            geometry: self,
            grid: *grid,
            tiles_x,
            starts,
            entries,
        })
    }

    /// The first film crossing of every pixel's camera ray of `grid`, row-major, top row
    /// first: for each pixel (x, y) the answer of [`DiskGeometry::intersect`]`(&ray(x, y), 0,
    /// ∞)` (up to the order of the blend's float sums, see the module docs). `ray(x, y)` must
    /// start at `grid.eye` and point through the pixel as the grid defines (e.g. a camera's ray
    /// through the pixel centre). `None` if the grid is not usable. Parallel over tiles.
    pub fn primary_layers(
        &self,
        grid: &PinholeGrid,
        ray: impl Fn(usize, usize) -> Ray + Sync,
    ) -> Option<Vec<Option<SurfaceHit>>> {
        let raster = self.primary_raster(grid)?;
        let (w, h) = (grid.width, grid.height);
        let tiles: Vec<_> = (0..raster.tiles())
            .into_par_iter()
            .map(|t| {
                let mut out = [None; RASTER_TILE * RASTER_TILE];
                raster.tile(t, &ray, &mut out);
                out
            })
            .collect();
        let mut hits = vec![None; w * h];
        for (t, out) in tiles.iter().enumerate() {
            let (x0, y0) = raster.tile_origin(t);
            for y in y0..(y0 + RASTER_TILE).min(h) {
                for x in x0..(x0 + RASTER_TILE).min(w) {
                    hits[y * w + x] = out[(y - y0) * RASTER_TILE + x - x0];
                }
            }
        }
        Some(hits)
    }
}

impl PrimaryRaster<'_> {
    /// Number of tiles (row-major, [`RASTER_TILE`] pixels a side, the last row and column cut
    /// at the image's edge).
    pub fn tiles(&self) -> usize {
        self.starts.len() - 1
    }

    /// Top-left pixel of tile `t`.
    pub fn tile_origin(&self, t: usize) -> (usize, usize) {
        (
            (t % self.tiles_x) * RASTER_TILE,
            (t / self.tiles_x) * RASTER_TILE,
        )
    }

    /// The first film crossings of tile `t`'s pixels into `out` (row-major within the tile,
    /// [`RASTER_TILE`] a row; `None` for a miss and outside the image). `ray` as for
    /// [`DiskGeometry::primary_layers`].
    pub fn tile(
        &self,
        t: usize,
        ray: &impl Fn(usize, usize) -> Ray,
        out: &mut [Option<SurfaceHit>; RASTER_TILE * RASTER_TILE],
    ) {
        let g = self.geometry;
        let (x0, y0) = self.tile_origin(t);
        let (x1, y1) = (
            (x0 + RASTER_TILE).min(self.grid.width),
            (y0 + RASTER_TILE).min(self.grid.height),
        );
        let bin = &self.entries[self.starts[t] as usize..self.starts[t + 1] as usize];
        let idle = Ray {
            origin: Vec3::ZERO,
            dir: Vec3::ZERO,
        };
        let mut rays = [idle; RASTER_TILE * RASTER_TILE];
        for y in y0..y1 {
            for x in x0..x1 {
                let r = ray(x, y);
                debug_assert!(r.origin == self.grid.eye, "camera rays start at the eye");
                if r.is_valid() {
                    rays[(y - y0) * RASTER_TILE + x - x0] = r;
                }
            }
        }
        // The pixels of entry `e` in this tile, as indices into the tile's arrays.
        let span = |e: &Entry| {
            let xs = (e.x0 as usize).max(x0)..=(e.x1 as usize).min(x1 - 1);
            let ys = (e.y0 as usize).max(y0)..=(e.y1 as usize).min(y1 - 1);
            ys.flat_map(move |y| xs.clone().map(move |x| (y - y0) * RASTER_TILE + x - x0))
        };
        let best = closest(g, bin, &rays, span);
        blend(g, bin, &rays, &best, span, out);
    }
}

/// Per pixel of a tile: the closest disk hit (slot, t, d2) or `None`.
type Closest = [Option<(u32, f32, f32)>; RASTER_TILE * RASTER_TILE];

/// Pass 1: the closest disk hit of each ray of the tile, ties to the lower particle index.
#[inline(always)]
fn closest<I: Iterator<Item = usize>>(
    g: &DiskGeometry,
    bin: &[Entry],
    rays: &[Ray; RASTER_TILE * RASTER_TILE],
    span: impl Fn(&Entry) -> I,
) -> Closest {
    let mut best: Closest = [None; RASTER_TILE * RASTER_TILE];
    // The farthest closest hit over the tile (∞ while a pixel has none); recomputed every few
    // disks, it only decreases, so a stale value is conservative.
    let mut far = f32::INFINITY;
    for (k, e) in bin.iter().enumerate() {
        if k % 8 == 7 {
            far = best
                .iter()
                .zip(rays)
                .filter(|(_, r)| r.dir != Vec3::ZERO)
                .map(|(b, _)| b.map_or(f32::INFINITY, |b| b.1))
                .fold(0.0, f32::max);
        }
        if e.t_near > far {
            break;
        }
        let d = &g.disks[e.slot as usize];
        for i in span(e) {
            let ray = &rays[i];
            if let Some((t, d2)) =
                intersect_disk(ray, d.center, d.normal, d.radius, 0.0, f32::INFINITY)
                && best[i].is_none_or(|(bs, bt, _)| {
                    t < bt || (t == bt && g.bvh.lower_particle(e.slot, bs))
                })
                && !g.cut_off(e.slot, ray, t)
            {
                best[i] = Some((e.slot, t, d2));
            }
        }
    }
    best
}

/// Pass 2: each pixel's layer, blended, into `out`.
#[inline(always)]
fn blend<I: Iterator<Item = usize>>(
    g: &DiskGeometry,
    bin: &[Entry],
    rays: &[Ray; RASTER_TILE * RASTER_TILE],
    best: &Closest,
    span: impl Fn(&Entry) -> I,
    out: &mut [Option<SurfaceHit>; RASTER_TILE * RASTER_TILE],
) {
    let mut sums = [None; RASTER_TILE * RASTER_TILE];
    let mut far = 0.0f32;
    for (i, b) in best.iter().enumerate() {
        if let Some(b) = b {
            let (sum, _, t_end) = g.layer_start(&rays[i], f32::INFINITY, *b);
            sums[i] = Some((sum, t_end));
            far = far.max(t_end);
        }
    }
    for e in bin {
        if e.t_near >= far {
            break;
        }
        let d = &g.disks[e.slot as usize];
        for i in span(e) {
            let (Some((slot0, _, _)), Some((sum, t_end))) = (best[i], &mut sums[i]) else {
                continue;
            };
            let ray = &rays[i];
            if e.slot != slot0
                && let Some((t, d2)) =
                    intersect_disk(ray, d.center, d.normal, d.radius, 0.0, *t_end)
                && !g.cut_off(e.slot, ray, t)
            {
                g.layer_add(sum, ray, slot0, (e.slot, t, d2));
            }
        }
    }
    for (o, (s, ray)) in out.iter_mut().zip(sums.iter().zip(rays)) {
        *o = s.map(|(sum, _)| layer_hit(ray, &sum));
    }
}
