//! The pieces of film the particles' own areas hold in a picture: 4-connected pixels whose
//! primary ray crosses them ([`FilmSpan::crosses`]). Shared by `tests/torn_fragments.rs` and
//! `examples/mls_bare.rs` (which loads this file by path).

use filmsplat::pipeline::Prepared;
use filmsplat::pointcloud::span::FilmSpan;
use rayon::prelude::*;

/// Whether each pixel's primary ray (through its centre) crosses the film `span` holds,
/// row-major.
pub fn data_mask(prepared: &Prepared, span: &FilmSpan) -> Vec<bool> {
    let (w, h) = (prepared.shot.settings.width, prepared.shot.settings.height);
    (0..w * h)
        .into_par_iter()
        .map(|k| {
            let (sx, sy) = ((k % w) as f32 + 0.5, (k / w) as f32 + 0.5);
            let ray = prepared
                .shot
                .camera
                .ray(sx / w as f32, sy / h as f32, w as f32 / h as f32);
            span.crosses(ray.origin, ray.dir, f32::INFINITY)
        })
        .collect()
}

/// The 4-connected pieces of `mask` (row-major, `w` wide), as pixel lists.
pub fn pieces(mask: &[bool], w: usize) -> Vec<Vec<usize>> {
    let h = mask.len() / w;
    let mut seen = vec![false; mask.len()];
    let mut all = Vec::new();
    for start in 0..mask.len() {
        if !mask[start] || seen[start] {
            continue;
        }
        seen[start] = true;
        let (mut stack, mut piece) = (vec![start], Vec::new());
        while let Some(k) = stack.pop() {
            piece.push(k);
            let (x, y) = (k % w, k / w);
            let near = [
                (x > 0).then(|| k - 1),
                (x + 1 < w).then(|| k + 1),
                (y > 0).then(|| k - w),
                (y + 1 < h).then(|| k + w),
            ];
            for n in near.into_iter().flatten() {
                if mask[n] && !seen[n] {
                    seen[n] = true;
                    stack.push(n);
                }
            }
        }
        all.push(piece);
    }
    all
}
