//! A labelled vertical colour bar beside an image (for the false-colour views).

use crate::image::{Anchor, RgbImage, draw_line, draw_text, draw_text_vertical, fill_rect};

/// Returns `img` widened on the right by a panel holding a vertical colour bar from `min`
/// (bottom) to `max` (top), coloured by `ramp(t)` for t in [0, 1] (linear RGB), with tick
/// labels and the `title` written along it. Text and bar scale with the image height.
pub fn add_colour_bar(
    img: &RgbImage,
    title: &str,
    min: f32,
    max: f32,
    ramp: &dyn Fn(f32) -> [f32; 3],
) -> RgbImage {
    let h = img.height;
    let s = (h as f32 / 540.0).clamp(0.35, 4.0);
    let panel = (150.0 * s).round() as usize;
    let mut out = RgbImage::filled(img.width + panel, h, [0.012; 3]);
    for y in 0..h {
        for x in 0..img.width {
            out.set(x, y, img.get(x, y));
        }
    }
    let ink = [0.85; 3];
    let (x0, x1) = (img.width as f32 + 24.0 * s, img.width as f32 + 48.0 * s);
    let (y0, y1) = (0.1 * h as f32, 0.9 * h as f32);
    let rows = (y1 - y0).ceil() as usize;
    for r in 0..rows {
        let t = 1.0 - (r as f32 + 0.5) / rows as f32;
        fill_rect(
            &mut out,
            x0,
            y0 + r as f32,
            x1,
            y0 + r as f32 + 1.0,
            ramp(t),
        );
    }
    let size = 15.0 * s;
    let ticks = 5;
    // Enough decimals to tell neighbouring ticks apart, no more.
    let step = ((max - min) / ticks as f32).abs();
    let decimals = if step > 0.0 {
        (1.0 - step.log10().floor()).clamp(0.0, 6.0) as usize
    } else {
        0
    };
    for i in 0..=ticks {
        let t = i as f32 / ticks as f32;
        let y = y1 - t * (y1 - y0);
        let v = min + t * (max - min);
        draw_line(&mut out, x1, y, x1 + 6.0 * s, y, 1.0, ink);
        let label = format!("{v:.*}", decimals);
        draw_text(
            &mut out,
            x1 + 9.0 * s,
            y,
            &label,
            size,
            ink,
            Anchor::MIDDLE_LEFT,
        );
    }
    draw_text_vertical(
        &mut out,
        x0 - 10.0 * s,
        0.5 * (y0 + y1),
        title,
        size,
        ink,
        Anchor::CENTRE,
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bar_spans_the_ramp_and_keeps_the_image() {
        let img = RgbImage::filled(100, 200, [0.5; 3]);
        let out = add_colour_bar(&img, "thickness (nm)", 0.0, 1000.0, &|t| [t, 0.0, 1.0 - t]);
        assert_eq!(out.height, 200);
        assert!(out.width > 100);
        assert_eq!(out.get(50, 100), [0.5; 3]);
        // Column through the middle of the bar: red rises toward the top.
        let x = 100 + (36.0 * (200.0f32 / 540.0).clamp(0.35, 4.0)) as usize;
        let top = out.get(x, 25)[0];
        let bottom = out.get(x, 175)[0];
        assert!(top > 0.8 && bottom < 0.2, "{top} {bottom}");
    }
}
