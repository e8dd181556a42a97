//! The passes over one tile of a [`PrimaryRaster`](super::PrimaryRaster).
//!
//! Pass 1 runs the disks of the tile's bin front to back, each tested against the rays of its
//! pixel box four at a time (lanes bit-identical to `intersect_disk`), and per pixel keeps what
//! `intersect`'s single-pass layer search keeps: the closest hit, and the hits up to
//! `t + LIMIT_SLACK · band` of the closest so far (its candidates). It stops at the first disk
//! that starts beyond every pixel's limit. Pass 2 blends each pixel's candidates within its
//! band; a pixel whose candidates may be incomplete (the same test as `intersect`'s) has its
//! band searched again over the bin with the scalar test.

use glam::{Vec3, Vec4};

use super::blend::LayerSum;
use super::disk_query::{DiskHit, LIMIT_SLACK, layer_hit, push_candidate};
use super::disks::DiskGeometry;
use super::primitives::{DISK_PARALLEL_COS, intersect_disk};
use super::ray4::lane_mask;
use super::{Ray, SurfaceHit};

/// Side of the square tiles the disks are binned into, pixels.
pub const RASTER_TILE: usize = 16;

/// A disk binned into a tile: its nearest possible hit distance, its slot and its pixel box
/// (inclusive). 16 bytes.
#[derive(Clone, Copy, Debug)]
pub(super) struct Entry {
    pub t_near: f32,
    pub slot: u32,
    pub x0: u16,
    pub x1: u16,
    pub y0: u16,
    pub y1: u16,
}

/// Pixels in a tile.
pub(super) const N: usize = RASTER_TILE * RASTER_TILE;

/// Candidates kept per pixel (12 bytes each; more send the pixel to the rescan).
const K: usize = 16;

/// The camera rays of one tile: as rays, and their directions as lanes (padded so four can be
/// read from any pixel). A pixel outside the image or with an unusable ray has a zero
/// direction, which no disk test accepts.
pub(super) struct TileRays {
    pub rays: [Ray; N],
    pub eye: Vec3,
    dx: [f32; N + 4],
    dy: [f32; N + 4],
    dz: [f32; N + 4],
}

impl TileRays {
    /// The rays of the pixels `x0..x1` × `y0..y1` (tile-local index `(y − y0)·RASTER_TILE +
    /// x − x0`), from `ray(x, y)`.
    pub fn new(
        eye: Vec3,
        (x0, x1): (usize, usize),
        (y0, y1): (usize, usize),
        ray: &impl Fn(usize, usize) -> Ray,
    ) -> TileRays {
        let idle = Ray {
            origin: eye,
            dir: Vec3::ZERO,
        };
        let mut tr = TileRays {
            rays: [idle; N],
            eye,
            dx: [0.0; N + 4],
            dy: [0.0; N + 4],
            dz: [0.0; N + 4],
        };
        for y in y0..y1 {
            for x in x0..x1 {
                let r = ray(x, y);
                debug_assert!(r.origin == eye, "camera rays start at the eye");
                if r.is_valid() && r.origin == eye {
                    let i = (y - y0) * RASTER_TILE + x - x0;
                    tr.rays[i] = r;
                    (tr.dx[i], tr.dy[i], tr.dz[i]) = (r.dir.x, r.dir.y, r.dir.z);
                }
            }
        }
        tr
    }

    /// Tests the disk `slot` against the rays of the tile-local box `xs` × `ys` (inclusive),
    /// four pixels at a time, for `0 < t < ∞`; calls `hit(pixel, t, d2)` for each hit that the
    /// disk's edge cut keeps. The same operations as `intersect_disk`, so the same bits.
    #[inline(always)]
    fn test_disk(
        &self,
        g: &DiskGeometry,
        slot: u32,
        (xs, ys): ((usize, usize), (usize, usize)),
        mut hit: impl FnMut(usize, f32, f32),
    ) {
        let d = &g.disks[slot as usize];
        let oc = d.center - self.eye;
        let num = Vec4::splat(d.normal.dot(oc));
        let (nx, ny, nz) = (
            Vec4::splat(d.normal.x),
            Vec4::splat(d.normal.y),
            Vec4::splat(d.normal.z),
        );
        let (ox, oy, oz) = (Vec4::splat(oc.x), Vec4::splat(oc.y), Vec4::splat(oc.z));
        let r2 = Vec4::splat(d.radius * d.radius);
        for ly in ys.0..=ys.1 {
            let mut lx = xs.0;
            while lx <= xs.1 {
                let i = ly * RASTER_TILE + lx;
                let lanes = (xs.1 + 1 - lx).min(4);
                let dx = Vec4::from_slice(&self.dx[i..i + 4]);
                let dy = Vec4::from_slice(&self.dy[i..i + 4]);
                let dz = Vec4::from_slice(&self.dz[i..i + 4]);
                let denom = nx * dx + ny * dy + nz * dz;
                let t = num / denom;
                let (px, py, pz) = (t * dx - ox, t * dy - oy, t * dz - oz);
                let d2 = px * px + py * py + pz * pz;
                let ok = denom.abs().cmpgt(Vec4::splat(DISK_PARALLEL_COS))
                    & t.cmpgt(Vec4::ZERO)
                    & t.cmplt(Vec4::splat(f32::INFINITY))
                    & d2.cmple(r2);
                let mut m = ok.bitmask() & lane_mask(lanes);
                while m != 0 {
                    let k = m.trailing_zeros() as usize;
                    m &= m - 1;
                    if !g.cut_off(slot, &self.rays[i + k], t[k]) {
                        hit(i + k, t[k], d2[k]);
                    }
                }
                lx += 4;
            }
        }
    }
}

/// What pass 1 leaves per pixel: the closest hit, the current collecting limit, the smallest
/// limit it had, the number of candidates and whether some did not fit.
#[derive(Clone, Copy)]
struct Search {
    best: Option<DiskHit>,
    lim: f32,
    min_lim: f32,
    nc: usize,
    overflow: bool,
}

/// Both passes over the tile's bin; the crossings into `out`. `span(e)` is the tile-local
/// pixel box of entry `e`.
#[inline(always)]
pub(super) fn trace(
    g: &DiskGeometry,
    bin: &[Entry],
    tr: &TileRays,
    span: impl Fn(&Entry) -> ((usize, usize), (usize, usize)),
    out: &mut [Option<SurfaceHit>; N],
) {
    let start = Search {
        best: None,
        lim: f32::INFINITY,
        min_lim: f32::INFINITY,
        nc: 0,
        overflow: false,
    };
    let mut px = [start; N];
    let mut cands = [[(0u32, 0f32, 0f32); K]; N];
    let live: Vec<usize> = (0..N).filter(|&i| tr.rays[i].dir != Vec3::ZERO).collect();
    search(g, bin, tr, &span, &live, &mut px, &mut cands);
    // Pass 2: blend each pixel's layer from its candidates, or mark it for the rescan.
    let mut sums: [Option<(LayerSum, f32)>; N] = [None; N];
    let mut rescan = Vec::new();
    for &i in &live {
        let p = &px[i];
        let Some(best) = p.best else { continue };
        let ray = &tr.rays[i];
        let (mut sum, t0, t_end) = g.layer_start(ray, f32::INFINITY, best);
        if t_end > t0 {
            if p.overflow || t_end > p.min_lim {
                rescan.push(i);
            } else {
                for &(s, t, d2) in &cands[i][..p.nc] {
                    if t < t_end {
                        g.layer_add(&mut sum, ray, best.0, (s, t, d2));
                    }
                }
            }
        }
        sums[i] = Some((sum, t_end));
    }
    if !rescan.is_empty() {
        band_rescan(g, bin, tr, &span, &px, &rescan, &mut sums);
    }
    for (o, (s, ray)) in out.iter_mut().zip(sums.iter().zip(&tr.rays)) {
        *o = s.map(|(sum, _)| layer_hit(ray, &sum));
    }
}

/// Pass 1: per pixel the closest hit and the candidates of its layer (see the module docs).
#[inline(always)]
fn search(
    g: &DiskGeometry,
    bin: &[Entry],
    tr: &TileRays,
    span: &impl Fn(&Entry) -> ((usize, usize), (usize, usize)),
    live: &[usize],
    px: &mut [Search; N],
    cands: &mut [[DiskHit; K]; N],
) {
    // The largest limit over the tile; recomputed every few disks. A limit can grow when a
    // closer hit has a wider band, but `min_lim` sends such a pixel to the rescan.
    let mut far = f32::INFINITY;
    for (k, e) in bin.iter().enumerate() {
        if k % 8 == 7 {
            far = live.iter().map(|&i| px[i].lim).fold(0.0, f32::max);
        }
        if e.t_near > far {
            break;
        }
        let d = &g.disks[e.slot as usize];
        tr.test_disk(g, e.slot, span(e), |i, t, d2| {
            let p = &mut px[i];
            // As `search_layer`: inclusive of the limit (ties with the closest hit).
            let hi = if p.lim < f32::INFINITY {
                p.lim.next_up()
            } else {
                f32::INFINITY
            };
            if t >= hi {
                return;
            }
            let s = e.slot;
            let closer = p
                .best
                .is_none_or(|(bs, bt, _)| t < bt || (t == bt && g.bvh.lower_particle(s, bs)));
            let candidate = if closer {
                let cos = d.normal.dot(tr.rays[i].dir).abs();
                p.lim = t + LIMIT_SLACK * g.blend.band(d.radius, cos);
                p.min_lim = p.min_lim.min(p.lim);
                p.best.replace((s, t, d2))
            } else {
                Some((s, t, d2))
            };
            if let Some(c) = candidate {
                p.overflow |= !push_candidate(&mut cands[i], &mut p.nc, c, p.lim);
            }
        });
    }
}

/// The layers of the pixels `rescan` searched again: every disk of the bin that starts before
/// the band's end, with the scalar test over the band (as `intersect`'s second traversal).
#[cold]
fn band_rescan(
    g: &DiskGeometry,
    bin: &[Entry],
    tr: &TileRays,
    span: &impl Fn(&Entry) -> ((usize, usize), (usize, usize)),
    px: &[Search; N],
    rescan: &[usize],
    sums: &mut [Option<(LayerSum, f32)>; N],
) {
    let far = rescan
        .iter()
        .filter_map(|&i| sums[i].map(|s| s.1))
        .fold(0.0, f32::max);
    for e in bin {
        if e.t_near >= far {
            break;
        }
        let d = &g.disks[e.slot as usize];
        let ((x0, x1), (y0, y1)) = span(e);
        for &i in rescan {
            let (x, y) = (i % RASTER_TILE, i / RASTER_TILE);
            let (Some((slot0, _, _)), Some((sum, t_end))) = (px[i].best, &mut sums[i]) else {
                continue;
            };
            let ray = &tr.rays[i];
            if (x0..=x1).contains(&x)
                && (y0..=y1).contains(&y)
                && e.slot != slot0
                && let Some((t, d2)) =
                    intersect_disk(ray, d.center, d.normal, d.radius, 0.0, *t_end)
                && !g.cut_off(e.slot, ray, t)
            {
                g.layer_add(sum, ray, slot0, (e.slot, t, d2));
            }
        }
    }
}
