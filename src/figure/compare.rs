//! The comparison figure: two renders side by side with labels, and their per-pixel colour
//! difference as a viridis heat map with a colour bar.

use crate::image::{Anchor, RgbImage, draw_text, text_width, viridis};

use super::{add_colour_bar, colour_bar_width};

/// `[a | b | heat map + colour bar]` under a strip holding `labels[0]` over `a`, `labels[1]`
/// over `b` and `heat_title` over the map. `a` and `b` are displayed linear RGB of the same
/// size; `delta_e` is the per-pixel difference (row-major, one value per pixel), shown from 0
/// (dark) to `delta_e_max` (yellow; larger values saturate). Text scales with the image
/// height (at least 10 px).
pub fn side_by_side(
    a: &RgbImage,
    b: &RgbImage,
    labels: [&str; 2],
    delta_e: &[f32],
    delta_e_max: f32,
    heat_title: &str,
) -> RgbImage {
    let (w, h) = (a.width, a.height);
    let max = if delta_e_max > 0.0 && delta_e_max.is_finite() {
        delta_e_max
    } else {
        1.0
    };
    let mut heat = RgbImage::new(w, h);
    for (px, d) in heat.data.iter_mut().zip(delta_e) {
        *px = viridis((d / max).clamp(0.0, 1.0));
    }
    // The bar goes beside the heat map, which keeps the renders' size (the bar of a view is
    // sized to fit inside its image; this figure has room to spare).
    let panel = colour_bar_width(usize::MAX, h);
    let heat = add_colour_bar(&heat, panel, "ΔE00", 0.0, max, &viridis);
    let size = (0.06 * h as f32).max(10.0);
    let strip = (1.6 * size).ceil() as usize;
    let gap = (0.02 * w as f32).ceil() as usize;
    let width = 2 * w + heat.width + 2 * gap;
    let mut out = RgbImage::filled(width, h + strip, [0.012; 3]);
    let blit = |out: &mut RgbImage, img: &RgbImage, x0: usize| {
        // Clipped, so a `b` of another size cannot write outside its panel's rows.
        for y in 0..img.height.min(h) {
            for x in 0..img.width.min(out.width - x0) {
                out.set(x0 + x, strip + y, img.get(x, y));
            }
        }
    };
    let xs = [0, w + gap, 2 * (w + gap)];
    blit(&mut out, a, xs[0]);
    blit(&mut out, b, xs[1]);
    blit(&mut out, &heat, xs[2]);
    let ink = [0.85; 3];
    let y = 0.5 * strip as f32;
    let room = [w, w, heat.width].map(|r| r as f32 - 0.6 * size);
    for ((x, text), room) in xs.iter().zip([labels[0], labels[1], heat_title]).zip(room) {
        // Shrink a label that would run into the next panel (down to 6 px, then clipped).
        let fit = size * (room / text_width(text, size)).min(1.0);
        draw_text(
            &mut out,
            *x as f32 + 0.3 * size,
            y,
            text,
            fit.max(6.0),
            ink,
            Anchor::MIDDLE_LEFT,
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panels_hold_the_images_and_the_map() {
        let a = RgbImage::filled(40, 30, [0.2, 0.4, 0.6]);
        let b = RgbImage::filled(40, 30, [0.6, 0.4, 0.2]);
        let de: Vec<f32> = (0..1200).map(|i| if i < 600 { 0.0 } else { 5.0 }).collect();
        let out = side_by_side(&a, &b, ["A", "B"], &de, 5.0, "map");
        let strip = out.height - 30;
        assert!(strip >= 16);
        assert_eq!(out.get(35, strip + 25), [0.2, 0.4, 0.6]);
        let gap = 1;
        assert_eq!(out.get(40 + gap + 35, strip + 25), [0.6, 0.4, 0.2]);
        let x0 = 2 * (40 + gap);
        assert_eq!(out.get(x0 + 5, strip + 2), viridis(0.0));
        assert_eq!(out.get(x0 + 5, strip + 28), viridis(1.0));
    }
}
