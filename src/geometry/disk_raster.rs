//! Camera rays of a pinhole grid answered by rasterising the disks instead of walking the BVH
//! once per ray ([`DiskGeometry::primary_raster`]).
//!
//! Every camera ray starts at the eye, so the pixels whose rays can meet a disk are known in
//! closed form: the box around the projection of the disk's rim (an ellipse; the box of its
//! bounding sphere's projection when the disk comes close to the eye's plane), grown for
//! rounding. Each disk is projected once and binned into the image's 16×16 tiles, sorted front to back by the nearest
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

use super::disk_raster_tile::{Entry, N, RASTER_TILE, TileRays, trace};
use super::disks::DiskGeometry;
use super::{Ray, SurfaceHit};

/// Relative and absolute (per unit distance) growth of a disk's bounding sphere so that float
/// rounding in the projection, the camera's rays and the exact test never drops a hit.
const GROW_REL: f64 = 1e-4;
const GROW_ABS: f64 = 1e-5;
/// Most disks reaching the eye's plane (each tested by every ray) a raster is built with.
const MAX_AT_EYE: usize = 64;
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

/// The disks of a [`DiskGeometry`] binned for one [`PinholeGrid`] (see the module docs).
/// Memory: 16 bytes per (disk, tile it overlaps) and 4 bytes a tile; on the 1M-disk shell at
/// 1280×720, 0.70 M entries (≈ 12 bytes a pixel). Binning holds 20 bytes a disk more until it
/// returns, and up to 24 MB of per-chunk counts (parallel chunks of ≥ 2^17 disks); a tile's passes use about 60 KB of stack.
pub struct PrimaryRaster<'g> {
    geometry: &'g DiskGeometry,
    grid: PinholeGrid,
    tiles_x: usize,
    /// Start of each tile's entries in `entries` (one more than there are tiles).
    starts: Vec<u32>,
    entries: Vec<Entry>,
}

impl PinholeGrid {
    /// The box of pixels whose rays can meet the disk (`c`, `r`, unit normal `n`) and the
    /// nearest distance of its bounding sphere from the eye; `Some(None)` for a sphere reaching
    /// the eye's plane, `None` for a disk that no ray of the grid can meet.
    fn project(&self, c: Vec3, r: f32, n: Vec3) -> Option<Option<Entry>> {
        let oc = (c - self.eye).as_dvec3();
        let dist = oc.length();
        let slab = GROW_ABS * dist;
        let r = r as f64 * (1.0 + GROW_REL) + slab;
        let basis = |v: Vec3| oc.dot(v.as_dvec3());
        let (cx, cy, cz) = (basis(self.right), basis(self.up), basis(self.forward));
        if cz < -r || self.outside_frustum(cx, cy, cz, r) {
            return None;
        }
        if cz <= 1.01 * r {
            return Some(None);
        }
        let nb = |v: Vec3| n.dot(v) as f64;
        let (nx, ny, nz) = (nb(self.right), nb(self.up), nb(self.forward));
        // The disk (grown radius r) thickened by a slab of half-width `slab` (the off-plane
        // reach of an accepted hit's rounding): its support along m is at most
        // √((r + slab)(r |m − (m·n) n|² + slab |m|²)) ((a + b)² ≤ (1 + k) a² + (1 + 1/k) b²,
        // k = slab / r). The tangent planes through the eye containing the up (right) axis,
        // m = (1, 0, −u): (cx − u cz)² = R r (1 + u² − (nx − u nz)²) + R slab (1 + u²) with
        // R = r + slab, i.e. q u² − 2 b u + k = 0; q > 0 keeps the set in front of the eye's
        // plane (else the sphere's box).
        let (rr, ss) = ((r + slab) * r, (r + slab) * (r + slab));
        let q = cz * cz - ss + rr * nz * nz;
        let slopes = |a: f64, na: f64| {
            let b = a * cz + rr * na * nz;
            let k = a * a - ss + rr * na * na;
            let s = (b * b - q * k).max(0.0).sqrt();
            ((b - s) / q, (b + s) / q)
        };
        // The sphere's tangent planes: roots of u² (cz² − r²) − 2 u cx cz + cx² − r² = 0.
        let sphere = |a: f64| {
            let (q, s) = (cz * cz - r * r, r * (a * a + cz * cz - r * r).sqrt());
            ((a * cz - s) / q, (a * cz + s) / q)
        };
        let ((u0, u1), (v0, v1)) = if q > 0.03 * cz * cz {
            (slopes(cx, nx), slopes(cy, ny))
        } else {
            (sphere(cx), sphere(cy))
        };
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

    /// True if the sphere at camera coordinates (`cx`, `cy`, `cz`) with radius `r` lies wholly
    /// beyond one of the four side planes of the frustum of the pixel centres (grown by two
    /// pixels): a cheap test before the projection.
    #[inline]
    fn outside_frustum(&self, cx: f64, cy: f64, cz: f64, r: f64) -> bool {
        // The plane through the eye containing the up axis and the edge slope `a`: its
        // outward unit normal is (1, −a)/√(1 + a²) in the (x, z) plane.
        let beyond = |x: f64, a: f64| (x - a * cz) > r * (1.0 + a * a).sqrt();
        let (w, h) = (self.width as f64, self.height as f64);
        let a = self.half_width as f64 * (1.0 + 4.0 / w);
        let b = self.half_height as f64 * (1.0 + 4.0 / h);
        beyond(cx, a) || beyond(-cx, a) || beyond(cy, b) || beyond(-cy, b)
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
    /// is not usable (non-finite, not orthonormal, or over 65535 pixels a side) or more than 64
    /// disks reach the eye's plane (each would be tested by every ray). Cost: one
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
                grid.project(d.center, d.radius, d.normal)
            })
            .collect();
        // Disks reaching the eye's plane are tested by every ray: past a few, the BVH is
        // cheaper.
        if projected
            .par_iter()
            .filter(|p| matches!(p, Some(None)))
            .count()
            > MAX_AT_EYE
        {
            return None;
        }
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
        let (starts, entries) = bin(n, tiles, &boxed, &tiles_of);
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
                let mut out = [None; N];
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
        out: &mut [Option<SurfaceHit>; N],
    ) {
        let (x0, y0) = self.tile_origin(t);
        let (x1, y1) = (
            (x0 + RASTER_TILE).min(self.grid.width),
            (y0 + RASTER_TILE).min(self.grid.height),
        );
        let bin = &self.entries[self.starts[t] as usize..self.starts[t + 1] as usize];
        let rays = TileRays::new(self.grid.eye, (x0, x1), (y0, y1), ray);
        // The tile-local pixel box of an entry (it overlaps the tile: it was binned there).
        let span = |e: &Entry| {
            (
                (e.x0 as usize).max(x0) - x0,
                (e.x1 as usize).min(x1 - 1) - x0,
            )
        };
        let span_y = |e: &Entry| {
            (
                (e.y0 as usize).max(y0) - y0,
                (e.y1 as usize).min(y1 - 1) - y0,
            )
        };
        trace(self.geometry, bin, &rays, |e| (span(e), span_y(e)), out);
    }
}

/// Disks binned in parallel chunks: each chunk counts its entries per tile, then writes them
/// into its own slice of each tile's bin (chunk after chunk, so a bin stays in slot order
/// before its sort); each bin sorted front to back (ties by slot: deterministic). Returns the
/// bins' starts (one more than `tiles`) and the entries.
fn bin<I: Iterator<Item = usize>>(
    n: usize,
    tiles: usize,
    boxed: &(impl Fn(usize) -> Option<Entry> + Sync),
    tiles_of: &(impl Fn(&Entry) -> I + Sync),
) -> (Vec<u32>, Vec<Entry>) {
    // At least 2^17 disks a chunk, and at most 2^20 (chunk, tile) pairs (24 bytes each).
    let chunk = (1usize << 17).max(n.div_ceil(((1usize << 20) / tiles).max(1)));
    let ranges: Vec<_> = (0..n.div_ceil(chunk))
        .map(|k| k * chunk..((k + 1) * chunk).min(n))
        .collect();
    let counts: Vec<Vec<u32>> = ranges
        .par_iter()
        .map(|r| {
            let mut c = vec![0u32; tiles];
            for e in r.clone().filter_map(boxed) {
                tiles_of(&e).for_each(|t| c[t] += 1);
            }
            c
        })
        .collect();
    let mut starts = vec![0u32; tiles + 1];
    for t in 0..tiles {
        starts[t + 1] = starts[t] + counts.iter().map(|c| c[t]).sum::<u32>();
    }
    let empty = Entry {
        t_near: 0.0,
        slot: 0,
        x0: 0,
        x1: 0,
        y0: 0,
        y1: 0,
    };
    let mut entries = vec![empty; starts[tiles] as usize];
    let mut rest = entries.as_mut_slice();
    let mut parts: Vec<Vec<&mut [Entry]>> = ranges.iter().map(|_| Vec::new()).collect();
    for t in 0..tiles {
        for (part, c) in parts.iter_mut().zip(&counts) {
            let (a, tail) = std::mem::take(&mut rest).split_at_mut(c[t] as usize);
            part.push(a);
            rest = tail;
        }
    }
    parts.par_iter_mut().zip(&ranges).for_each(|(slices, r)| {
        let mut cur = vec![0usize; tiles];
        for e in r.clone().filter_map(boxed) {
            for t in tiles_of(&e) {
                slices[t][cur[t]] = e;
                cur[t] += 1;
            }
        }
    });
    drop(parts);
    let mut rest = entries.as_mut_slice();
    let mut bins = Vec::with_capacity(tiles);
    for t in 0..tiles {
        let (bin, tail) =
            std::mem::take(&mut rest).split_at_mut((starts[t + 1] - starts[t]) as usize);
        bins.push(bin);
        rest = tail;
    }
    bins.par_iter_mut().for_each(|bin| {
        bin.sort_unstable_by(|a, b| a.t_near.total_cmp(&b.t_near).then(a.slot.cmp(&b.slot)))
    });
    (starts, entries)
}
