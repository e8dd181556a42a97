//! The colour table ([`FilmLut`]): film colours over (cos θ, thickness), built lazily a block
//! of thicknesses at a time and shared by every render in the process with the same index.

use super::{SpectralWeights, reference_grid_nm};
use crate::optics::FilmFresnel;
use rayon::prelude::*;
use std::fmt;
use std::sync::{Arc, Mutex, OnceLock};

/// Thickness intervals per block. A block holds `BLOCK + 1` entries per cos row (it shares its
/// last one with the next block's first), so a bilinear lookup never spans two blocks.
const BLOCK: usize = 64;
const BLOCKS: usize = FilmLut::THICKNESS_STEPS / BLOCK;
const _: () = assert!(BLOCKS * BLOCK == FilmLut::THICKNESS_STEPS);

/// Tables kept for reuse in one process (distinct film indices; the oldest goes first).
const CACHED_TABLES: usize = 8;

/// Precomputed film colours over (cos θ, thickness): the fastest shading, for previews.
///
/// Entries are the 1 nm spectral integral (f32 Airy path; a 2 nm grid misses the sharp
/// resonances of grazing incidence). The grid is uniform in `√cos θ`
/// ([`FilmLut::COS_STEPS`] intervals) and in `√(h / MAX_THICKNESS_NM)`
/// ([`FilmLut::THICKNESS_STEPS`] intervals), so it is densest where the colour changes fastest:
/// near grazing incidence and for nanometre-thin films (whose reflectance rises steeply at
/// grazing angles). Lookups interpolate bilinearly. Films thicker than
/// [`FilmLut::MAX_THICKNESS_NM`] return the incoherent limit (a neutral grey of reflectance
/// `2ρ/(1+ρ)`), which the table's last entries already approach.
///
/// Cost: the table is built lazily, 32 blocks of 64 thickness steps (all angles), each on the
/// first lookup that needs it (~10 ms of one core a block), so a render pays only for the
/// thicknesses its films have (the bubble sample's 25–1120 nm: 14 of the 32 blocks); ~3 MB
/// when full. [`FilmLut::new`] shares one table per film index within the process, so
/// sequences and repeated renders (the Python package) build each block once. The entries are
/// the same numbers, bit for bit, however and whenever they are built.
#[derive(Clone)]
pub struct FilmLut {
    table: Arc<Table>,
}

/// The shared state of one film index's table.
struct Table {
    ior: f32,
    weights: SpectralWeights,
    /// Incoherent reflectance per cos row.
    incoherent: Vec<f32>,
    /// Block `b`: entries `[ic * (BLOCK + 1) + j]` for thickness step `b * BLOCK + j`.
    blocks: Vec<OnceLock<Box<[[f32; 3]]>>>,
}

impl fmt::Debug for FilmLut {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("FilmLut")
            .field("ior", &self.table.ior)
            .field("blocks_built", &self.blocks_built())
            .finish()
    }
}

fn cos_at(ic: usize) -> f32 {
    (ic as f32 / FilmLut::COS_STEPS as f32).powi(2)
}

impl FilmLut {
    /// Intervals of the `√cos θ` grid.
    pub const COS_STEPS: usize = 128;
    /// Intervals of the `√thickness` grid.
    pub const THICKNESS_STEPS: usize = 2048;
    /// Thickest tabulated film, nm.
    pub const MAX_THICKNESS_NM: f32 = 5000.0;

    /// The table for film index `ior`: the process's shared one if a render already asked for
    /// this index, else a new (still empty) one. Cost: a lock and a lookup, or ~0.2 ms to set
    /// up a new table; entries are built on first use.
    pub fn new(ior: f32) -> Self {
        static CACHE: Mutex<Vec<Arc<Table>>> = Mutex::new(Vec::new());
        let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = cache.iter().find(|t| t.ior.to_bits() == ior.to_bits()) {
            return FilmLut { table: t.clone() };
        }
        let lut = Self::build_uncached(ior);
        if cache.len() == CACHED_TABLES {
            cache.remove(0);
        }
        cache.push(lut.table.clone());
        lut
    }

    /// A new, empty table of its own for film index `ior`, not shared with other renders (for
    /// measuring the build).
    pub fn build_uncached(ior: f32) -> Self {
        let grid: Vec<f32> = reference_grid_nm().iter().map(|&l| l as f32).collect();
        let incoherent = (0..=Self::COS_STEPS)
            .map(|ic| FilmFresnel::new(cos_at(ic), ior).incoherent_reflectance())
            .collect();
        FilmLut {
            table: Arc::new(Table {
                ior,
                weights: SpectralWeights::new(&grid),
                incoherent,
                blocks: (0..BLOCKS).map(|_| OnceLock::new()).collect(),
            }),
        }
    }

    /// Builds every block now, in parallel (a warm table for what follows). Cost ~0.5 s of
    /// CPU when empty.
    pub fn prebuild(&self) {
        (0..BLOCKS).into_par_iter().for_each(|b| {
            self.block(b);
        });
    }

    /// Number of thickness blocks built so far (of 32).
    pub fn blocks_built(&self) -> usize {
        self.table
            .blocks
            .iter()
            .filter(|b| b.get().is_some())
            .count()
    }

    /// The film index the table was built for.
    pub fn ior(&self) -> f32 {
        self.table.ior
    }

    /// Block `b`, built on first use (single-threaded: it may be asked for from inside a
    /// parallel render, where a nested parallel build could wait on itself).
    #[inline]
    fn block(&self, b: usize) -> &[[f32; 3]] {
        let cell = &self.table.blocks[b];
        match cell.get() {
            Some(v) => v,
            None => cell.get_or_init(|| self.table.build_block(b)),
        }
    }

    /// Reflected colour (linear sRGB, white = 1) at `cos_i` in [0, 1] and `thickness_nm` >= 0.
    /// Cost: ~5 ns once the block is built.
    #[inline]
    pub fn reflectance_rgb(&self, cos_i: f32, thickness_nm: f32) -> [f32; 3] {
        let fc = cos_i.clamp(0.0, 1.0).sqrt() * Self::COS_STEPS as f32;
        let ic = (fc as usize).min(Self::COS_STEPS - 1);
        let tc = fc - ic as f32;
        let lerp3 = |a: [f32; 3], b: [f32; 3], t: f32| [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]));
        if thickness_nm.is_nan() || thickness_nm > Self::MAX_THICKNESS_NM {
            let inc = &self.table.incoherent;
            let g = inc[ic] + tc * (inc[ic + 1] - inc[ic]);
            return [g; 3];
        }
        let fh =
            (thickness_nm.max(0.0) / Self::MAX_THICKNESS_NM).sqrt() * Self::THICKNESS_STEPS as f32;
        let ih = (fh as usize).min(Self::THICKNESS_STEPS - 1);
        let th = fh - ih as f32;
        let (b, j) = (ih / BLOCK, ih % BLOCK);
        let blk = self.block(b);
        let at = |c: usize, h: usize| blk[c * (BLOCK + 1) + h];
        let lo = lerp3(at(ic, j), at(ic, j + 1), th);
        let hi = lerp3(at(ic + 1, j), at(ic + 1, j + 1), th);
        lerp3(lo, hi, tc)
    }
}

impl Table {
    /// The entries of block `b`: thickness steps `b·BLOCK ..= (b+1)·BLOCK`, every cos row.
    fn build_block(&self, b: usize) -> Box<[[f32; 3]]> {
        let mut out = Vec::with_capacity((FilmLut::COS_STEPS + 1) * (BLOCK + 1));
        for ic in 0..=FilmLut::COS_STEPS {
            let fresnel = FilmFresnel::new(cos_at(ic), self.ior);
            for ih in b * BLOCK..=(b + 1) * BLOCK {
                let v = ih as f32 / FilmLut::THICKNESS_STEPS as f32;
                let h = v * v * FilmLut::MAX_THICKNESS_NM;
                out.push(self.weights.film_reflectance_rgb(&fresnel, h));
            }
        }
        out.into_boxed_slice()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table as it was built before it went lazy: every entry at once, row-major.
    fn eager_entries(ior: f32) -> Vec<[f32; 3]> {
        let grid: Vec<f32> = reference_grid_nm().iter().map(|&l| l as f32).collect();
        let weights = SpectralWeights::new(&grid);
        let n_h = FilmLut::THICKNESS_STEPS + 1;
        (0..(FilmLut::COS_STEPS + 1) * n_h)
            .into_par_iter()
            .map(|k| {
                let (ic, ih) = (k / n_h, k % n_h);
                let v = ih as f32 / FilmLut::THICKNESS_STEPS as f32;
                let fresnel = FilmFresnel::new(cos_at(ic), ior);
                weights.film_reflectance_rgb(&fresnel, v * v * FilmLut::MAX_THICKNESS_NM)
            })
            .collect()
    }

    /// The eager table's bilinear lookup, as the renderer did it.
    fn eager_lookup(rgb: &[[f32; 3]], cos_i: f32, thickness_nm: f32) -> [f32; 3] {
        let n_h = FilmLut::THICKNESS_STEPS + 1;
        let fc = cos_i.clamp(0.0, 1.0).sqrt() * FilmLut::COS_STEPS as f32;
        let ic = (fc as usize).min(FilmLut::COS_STEPS - 1);
        let tc = fc - ic as f32;
        let lerp3 = |a: [f32; 3], b: [f32; 3], t: f32| [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]));
        let fh = (thickness_nm.max(0.0) / FilmLut::MAX_THICKNESS_NM).sqrt()
            * FilmLut::THICKNESS_STEPS as f32;
        let ih = (fh as usize).min(n_h - 2);
        let th = fh - ih as f32;
        let at = |c: usize, h: usize| rgb[c * n_h + h];
        let lo = lerp3(at(ic, ih), at(ic, ih + 1), th);
        let hi = lerp3(at(ic + 1, ih), at(ic + 1, ih + 1), th);
        lerp3(lo, hi, tc)
    }

    #[test]
    fn lazy_blocks_give_the_eager_tables_bits() {
        let ior = 1.41;
        let eager = eager_entries(ior);
        let lut = FilmLut::build_uncached(ior);
        let mut s = 7u32;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            s as f32 / u32::MAX as f32
        };
        // Random points, every grid node and block seam, and both ends.
        let mut cases: Vec<(f32, f32)> = (0..20_000)
            .map(|_| (rnd(), rnd() * rnd() * FilmLut::MAX_THICKNESS_NM))
            .collect();
        for ih in 0..=FilmLut::THICKNESS_STEPS {
            let v = ih as f32 / FilmLut::THICKNESS_STEPS as f32;
            cases.push((rnd(), v * v * FilmLut::MAX_THICKNESS_NM));
        }
        cases.extend([(0.0, 0.0), (1.0, FilmLut::MAX_THICKNESS_NM), (0.5, -3.0)]);
        for (c, h) in cases {
            let (a, b) = (lut.reflectance_rgb(c, h), eager_lookup(&eager, c, h));
            assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "cos {c}, {h} nm");
        }
        assert_eq!(lut.blocks_built(), BLOCKS);
    }

    #[test]
    fn only_the_thicknesses_looked_up_are_built_and_tables_are_shared() {
        let lut = FilmLut::build_uncached(1.5);
        assert_eq!(lut.blocks_built(), 0);
        for k in 0..100 {
            lut.reflectance_rgb(k as f32 / 99.0, 300.0 + k as f32);
        }
        // 300–399 nm is √(h/5000)·2048 = 501.6–578.5: blocks 7, 8 and 9 of 32.
        assert_eq!(lut.blocks_built(), 3, "{lut:?}");
        let (a, b) = (FilmLut::new(1.2345), FilmLut::new(1.2345));
        assert!(Arc::ptr_eq(&a.table, &b.table));
        assert!(!Arc::ptr_eq(&a.table, &FilmLut::new(1.2346).table));
        a.reflectance_rgb(1.0, 100.0);
        assert_eq!(b.blocks_built(), 1);
    }
}
