//! Small anti-aliased drawing helpers for charts and figures: rectangles, lines, blending.
//!
//! Coordinates are in pixels with the origin at the top-left corner of the image; pixel `(i, j)`
//! covers `[i, i+1) x [j, j+1)`, so its centre is `(i + 0.5, j + 0.5)`. Shapes are clipped to the
//! image. Edges on integer coordinates (rectangles) or lines centred on pixel centres give
//! perfectly crisp results; other positions are anti-aliased by area coverage.

use super::buffer::RgbImage;
use super::tonemap::{linear_to_srgb, srgb_to_linear};

pub use super::colormap::viridis;

/// Blends `colour` (linear RGB) over `px` with opacity `alpha` (clamped to `[0, 1]`).
///
/// The interpolation happens on sRGB-encoded values, then is decoded back to linear: after
/// [`to_srgb8`](super::to_srgb8) with `Clamp` and 0 EV, anti-aliased edges look like ordinary
/// (sRGB-space) rasterised text and lines, e.g. dark text on white keeps its weight instead of
/// looking thin and washed out. Non-finite destination values are treated as 0.
#[inline]
pub fn blend(px: &mut [f32; 3], colour: [f32; 3], alpha: f32) {
    if alpha.is_nan() || alpha <= 0.0 {
        return;
    }
    if alpha >= 1.0 {
        *px = colour;
        return;
    }
    for (d, &c) in px.iter_mut().zip(&colour) {
        let de = if d.is_finite() {
            linear_to_srgb(*d)
        } else {
            0.0
        };
        let ce = linear_to_srgb(c);
        *d = srgb_to_linear(de + (ce - de) * alpha);
    }
}

/// Length of the overlap of `[a0, a1]` and `[b0, b1]` (0 if disjoint).
#[inline]
fn overlap(a0: f32, a1: f32, b0: f32, b1: f32) -> f32 {
    (a1.min(b1) - a0.max(b0)).max(0.0)
}

/// Fills the rectangle `[x0, x1) x [y0, y1)` (pixel units, corners in any order) with `colour`.
/// Partially covered edge pixels are blended by their covered area. Cost: O(area).
pub fn fill_rect(img: &mut RgbImage, x0: f32, y0: f32, x1: f32, y1: f32, colour: [f32; 3]) {
    let (x0, x1) = (x0.min(x1), x0.max(x1));
    let (y0, y1) = (y0.min(y1), y0.max(y1));
    if !(x0.is_finite() && x1.is_finite() && y0.is_finite() && y1.is_finite()) {
        return;
    }
    let ix0 = x0.floor().max(0.0) as i64;
    let iy0 = y0.floor().max(0.0) as i64;
    let ix1 = (x1.ceil() as i64).min(img.width as i64);
    let iy1 = (y1.ceil() as i64).min(img.height as i64);
    for j in iy0..iy1 {
        let cy = overlap(j as f32, j as f32 + 1.0, y0, y1);
        for i in ix0..ix1 {
            let a = cy * overlap(i as f32, i as f32 + 1.0, x0, x1);
            if let Some(px) = img.pixel_mut_checked(i, j) {
                blend(px, colour, a);
            }
        }
    }
}

/// Draws the outline of the rectangle `[x0, x1] x [y0, y1]` with lines of `width` pixels
/// centred on its edges. Integer corners + 0.5 give crisp 1-px frames.
pub fn stroke_rect(
    img: &mut RgbImage,
    x0: f32,
    y0: f32,
    x1: f32,
    y1: f32,
    width: f32,
    colour: [f32; 3],
) {
    let h = width / 2.0;
    fill_rect(img, x0 - h, y0 - h, x1 + h, y0 + h, colour);
    fill_rect(img, x0 - h, y1 - h, x1 + h, y1 + h, colour);
    fill_rect(img, x0 - h, y0 + h, x0 + h, y1 - h, colour);
    fill_rect(img, x1 - h, y0 + h, x1 + h, y1 - h, colour);
}

/// Draws an anti-aliased line segment from `(x0, y0)` to `(x1, y1)`, `width` pixels wide, with
/// butt ends.
///
/// Coverage is the product of the box-filtered coverage across and along the segment: exact for
/// horizontal and vertical lines (a 1-px line through pixel centres is fully crisp), a close
/// approximation otherwise. Cost: O(bounding box area).
pub fn draw_line(
    img: &mut RgbImage,
    x0: f32,
    y0: f32,
    x1: f32,
    y1: f32,
    width: f32,
    colour: [f32; 3],
) {
    let (dx, dy) = (x1 - x0, y1 - y0);
    let len = (dx * dx + dy * dy).sqrt();
    if !(len > 0.0 && len.is_finite() && width > 0.0) {
        return;
    }
    let (ux, uy) = (dx / len, dy / len);
    let h = width / 2.0;
    let pad = h + 1.0;
    let bx0 = (x0.min(x1) - pad).floor().max(0.0) as i64;
    let by0 = (y0.min(y1) - pad).floor().max(0.0) as i64;
    let bx1 = ((x0.max(x1) + pad).ceil() as i64).min(img.width as i64);
    let by1 = ((y0.max(y1) + pad).ceil() as i64).min(img.height as i64);
    // Footprint half-sizes of a unit pixel box projected on the line axes: 0.5 for axis-aligned
    // lines, growing to 0.707 on diagonals (keeps diagonal lines from looking thin).
    let half_along = 0.5 * (ux.abs() + uy.abs());
    let half_across = half_along;
    for j in by0..by1 {
        for i in bx0..bx1 {
            let (px, py) = (i as f32 + 0.5 - x0, j as f32 + 0.5 - y0);
            let s = px * ux + py * uy; // along
            let d = -px * uy + py * ux; // across
            let ca = overlap(s - half_along, s + half_along, 0.0, len) / (2.0 * half_along);
            let cd = overlap(d - half_across, d + half_across, -h, h) / (2.0 * half_across);
            let a = (ca * cd).min(1.0);
            if a > 0.0
                && let Some(p) = img.pixel_mut_checked(i, j)
            {
                blend(p, colour, a);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WHITE: [f32; 3] = [1.0; 3];
    const BLACK: [f32; 3] = [0.0; 3];

    #[test]
    fn blend_is_srgb_space_interpolation() {
        let mut p = WHITE;
        blend(&mut p, BLACK, 0.5);
        // Half coverage of black on white is sRGB 0.5 (code 127.5), not linear 0.5 (code 188).
        assert!((linear_to_srgb(p[0]) - 0.5).abs() < 1e-5);
        assert!((p[0] - 0.214_041).abs() < 1e-5);
        let mut q = [0.3, 0.2, 0.1];
        blend(&mut q, BLACK, 0.0);
        assert_eq!(q, [0.3, 0.2, 0.1]);
        blend(&mut q, [0.9, 0.8, 0.7], 1.0);
        assert_eq!(q, [0.9, 0.8, 0.7]);
        let mut n = [f32::NAN; 3];
        blend(&mut n, WHITE, 0.5);
        assert!(n.iter().all(|v| v.is_finite()));
    }

    #[test]
    fn fill_rect_integer_is_exact_and_clipped() {
        let mut img = RgbImage::filled(10, 8, WHITE);
        fill_rect(&mut img, 2.0, 3.0, 5.0, 20.0, BLACK);
        for y in 0..8 {
            for x in 0..10 {
                let inside = (2..5).contains(&x) && y >= 3;
                assert_eq!(
                    img.get(x, y),
                    if inside { BLACK } else { WHITE },
                    "({x},{y})"
                );
            }
        }
        // Half-pixel edge: the column is half covered.
        let mut img = RgbImage::filled(4, 1, WHITE);
        fill_rect(&mut img, 0.0, 0.0, 1.5, 1.0, BLACK);
        assert_eq!(img.get(0, 0), BLACK);
        assert!((linear_to_srgb(img.get(1, 0)[0]) - 0.5).abs() < 1e-5);
        assert_eq!(img.get(2, 0), WHITE);
        fill_rect(&mut img, -100.0, -100.0, f32::NAN, 5.0, BLACK); // ignored, no panic
    }

    #[test]
    fn horizontal_line_through_centres_is_crisp() {
        let mut img = RgbImage::filled(20, 10, WHITE);
        draw_line(&mut img, 3.0, 4.5, 15.0, 4.5, 1.0, BLACK);
        for y in 0..10 {
            for x in 0..20 {
                let on = y == 4 && (3..15).contains(&x);
                assert_eq!(img.get(x, y), if on { BLACK } else { WHITE }, "({x},{y})");
            }
        }
        // Vertical 2-px line on a pixel boundary covers two full columns.
        let mut img = RgbImage::filled(10, 10, WHITE);
        draw_line(&mut img, 5.0, 1.0, 5.0, 9.0, 2.0, BLACK);
        assert_eq!(img.get(4, 5), BLACK);
        assert_eq!(img.get(5, 5), BLACK);
        assert_eq!(img.get(3, 5), WHITE);
        assert_eq!(img.get(6, 5), WHITE);
    }

    #[test]
    fn diagonal_line_ink_matches_area() {
        // Total coverage of a long diagonal line ~ length * width (area conservation).
        let mut img = RgbImage::filled(64, 64, BLACK);
        draw_line(&mut img, 8.0, 8.0, 56.0, 40.0, 1.5, WHITE);
        // With black background and white ink, sRGB-space coverage = encoded value.
        let ink: f32 = img.data.iter().map(|p| linear_to_srgb(p[0])).sum();
        let area = (48.0f32.hypot(32.0)) * 1.5;
        assert!((ink / area - 1.0).abs() < 0.08, "ink {ink} area {area}");
    }
}
