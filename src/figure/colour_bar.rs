//! A labelled vertical colour bar beside an image (for the false-colour views).

use crate::image::{Anchor, RgbImage, draw_line, draw_text, draw_text_vertical, fill_rect};

/// Width in pixels of the colour-bar panel of a `width`×`height` image: 150 px for a 540 px
/// high image, scaled with the height (0.35–4×) but never more than a third of the width.
/// A view with a bar renders the scene in the remaining `width − colour_bar_width` columns,
/// so the picture with its bar is exactly `width` wide.
pub fn colour_bar_width(width: usize, height: usize) -> usize {
    let s = (height as f32 / 540.0)
        .clamp(0.35, 4.0)
        .min(width as f32 / 450.0);
    ((150.0 * s).round() as usize).min(width.saturating_sub(1))
}

/// Returns `img` widened on the right by a `panel` pixels wide panel (see
/// [`colour_bar_width`]) holding a vertical colour bar from `min` (bottom) to `max` (top),
/// coloured by `ramp(t)` for t in [0, 1] (linear RGB), with tick labels and the `title`
/// written along it. Text and bar scale with the panel.
pub fn add_colour_bar(
    img: &RgbImage,
    panel: usize,
    title: &str,
    min: f32,
    max: f32,
    ramp: &dyn Fn(f32) -> [f32; 3],
) -> RgbImage {
    let h = img.height;
    if panel == 0 {
        return img.clone();
    }
    let s = panel as f32 / 150.0;
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
        let (w, h) = (300, 200);
        let panel = colour_bar_width(w, h);
        assert_eq!(panel, (150.0f32 * 200.0 / 540.0).round() as usize);
        let img = RgbImage::filled(w - panel, h, [0.5; 3]);
        let out = add_colour_bar(&img, panel, "thickness (nm)", 0.0, 1000.0, &|t| {
            [t, 0.0, 1.0 - t]
        });
        assert_eq!((out.width, out.height), (w, h));
        assert_eq!(out.get(50, 100), [0.5; 3]);
        // Column through the middle of the bar: red rises toward the top.
        let x = w - panel + (36.0 * panel as f32 / 150.0) as usize;
        let top = out.get(x, 25)[0];
        let bottom = out.get(x, 175)[0];
        assert!(top > 0.8 && bottom < 0.2, "{top} {bottom}");
    }

    #[test]
    fn the_panel_fits_any_size() {
        for (w, h) in [
            (1, 1),
            (2, 500),
            (64, 48),
            (320, 180),
            (180, 320),
            (1920, 1080),
        ] {
            let panel = colour_bar_width(w, h);
            assert!(panel < w && panel <= w / 3 + 1, "{w}x{h}: {panel}");
            let img = RgbImage::filled(w - panel, h, [0.5; 3]);
            let out = add_colour_bar(&img, panel, "t", 0.0, 1.0, &|t| [t; 3]);
            assert_eq!((out.width, out.height), (w, h));
        }
        assert_eq!(colour_bar_width(1920, 1080), 300);
    }
}
