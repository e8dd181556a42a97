//! Temporal stability of a rendered sequence: how much the picture changes between adjacent
//! frames where the geometry hardly moves (flicker, crawling splat edges, noise), measured as
//! the mean per-pixel CIEDE2000 difference.

use super::buffer::RgbImage;
use super::metrics::delta_e_map;
use crate::{Error, Result};

/// The change between two frames over the pixels where the geometry moves little.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameChange {
    /// Mean ΔE₀₀ over the compared pixels (0 if there are none).
    pub mean_delta_e: f64,
    /// Number of compared pixels.
    pub pixels: usize,
    /// Number of pixels in a frame.
    pub total: usize,
}

/// Compares frames `a` and `b` (linear RGB, clipped to [0, 1] as in [`delta_e_map`]). With
/// depths (distance to the first film crossing, 0 where nothing was hit, one per pixel), only
/// pixels that hit a film in both frames with |d_a − d_b| ≤ `tolerance`·max(d_a, d_b) count;
/// without, every pixel does. Errors if sizes differ.
pub fn frame_change(
    a: &RgbImage,
    b: &RgbImage,
    depth: Option<(&[f32], &[f32])>,
    tolerance: f32,
) -> Result<FrameChange> {
    let d = delta_e_map(a, b)?;
    let keep: Vec<bool> = match depth {
        None => vec![true; d.len()],
        Some((da, db)) => {
            if da.len() != d.len() || db.len() != d.len() {
                return Err(Error::invalid(format!(
                    "depth has {} and {} pixels, the frames {}",
                    da.len(),
                    db.len(),
                    d.len()
                )));
            }
            da.iter()
                .zip(db)
                .map(|(&x, &y)| x > 0.0 && y > 0.0 && (x - y).abs() <= tolerance * x.max(y))
                .collect()
        }
    };
    let (sum, pixels) = d
        .iter()
        .zip(&keep)
        .filter(|(_, k)| **k)
        .fold((0.0f64, 0usize), |(s, n), (v, _)| (s + *v as f64, n + 1));
    Ok(FrameChange {
        mean_delta_e: if pixels > 0 { sum / pixels as f64 } else { 0.0 },
        pixels,
        total: d.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(w: usize, h: usize, c: [f32; 3]) -> RgbImage {
        RgbImage {
            width: w,
            height: h,
            data: vec![c; w * h],
        }
    }

    #[test]
    fn only_pixels_with_steady_depth_count() {
        let a = flat(4, 1, [0.2, 0.2, 0.2]);
        let mut b = a.clone();
        b.data[3] = [0.8, 0.1, 0.1]; // changes a lot, but its geometry moved
        b.data[1] = [0.25, 0.2, 0.2];
        let da = [1.0, 1.0, 0.0, 1.0];
        let db = [1.0, 1.005, 1.0, 2.0];
        let c = frame_change(&a, &b, Some((&da, &db)), 0.01).unwrap();
        // Pixels 0 and 1 count; 2 was empty in a, 3 moved.
        assert_eq!((c.pixels, c.total), (2, 4));
        let one = delta_e_map(&a, &b).unwrap()[1] as f64;
        assert!(one > 1.0 && (c.mean_delta_e - one / 2.0).abs() < 1e-9);
        let all = frame_change(&a, &b, None, 0.01).unwrap();
        assert_eq!(all.pixels, 4);
        assert!(all.mean_delta_e > c.mean_delta_e);
        assert_eq!(frame_change(&a, &a, None, 0.0).unwrap().mean_delta_e, 0.0);
        assert!(frame_change(&a, &b, Some((&da[..2], &db)), 0.01).is_err());
    }
}
