//! A labelled vertical colour bar beside an image (for the false-colour views).

use crate::image::{
    Anchor, RgbImage, draw_line, draw_text, draw_text_vertical, fill_rect, is_one_value,
};

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
/// written along it. Text and bar scale with the panel. The labels say what is there: six
/// ticks for a range; one tick `all V` when every value is V (a range narrower than a
/// millionth of its values); no ramp and one label `no film` when the range is empty or not
/// finite (nothing of the film in view).
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
    let labels = BarLabels::of(min, max);
    // Nothing to show: no ramp, only the label saying so.
    let rows = if labels == BarLabels::Nothing {
        0
    } else {
        (y1 - y0).ceil() as usize
    };
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
    let label_at = |out: &mut RgbImage, y: f32, label: &str| {
        draw_line(out, x1, y, x1 + 6.0 * s, y, 1.0, ink);
        draw_text(out, x1 + 9.0 * s, y, label, size, ink, Anchor::MIDDLE_LEFT);
    };
    match labels {
        BarLabels::Nothing => label_at(&mut out, 0.5 * (y0 + y1), "no film"),
        BarLabels::Constant(v) => label_at(
            &mut out,
            0.5 * (y0 + y1),
            &format!("all {}", constant_label(v)),
        ),
        BarLabels::Ticks { ticks, decimals } => {
            for i in 0..=ticks {
                let t = i as f32 / ticks as f32;
                let v = min + t * (max - min);
                label_at(&mut out, y1 - t * (y1 - y0), &format!("{v:.*}", decimals));
            }
        }
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

/// What the bar's labels say about the range `min..max`.
#[derive(Debug, Clone, Copy, PartialEq)]
enum BarLabels {
    /// No value at all (an empty or non-finite range: nothing of the film is in view).
    Nothing,
    /// One value (the range is empty, or narrower than a millionth of its values).
    Constant(f32),
    /// `ticks + 1` evenly spaced labels with `decimals` decimals: enough to tell neighbouring
    /// ticks apart, no more.
    Ticks { ticks: usize, decimals: usize },
}

impl BarLabels {
    fn of(min: f32, max: f32) -> Self {
        if !(min.is_finite() && max.is_finite()) || min > max {
            return BarLabels::Nothing;
        }
        if is_one_value(min, max) {
            return BarLabels::Constant(0.5 * (min + max));
        }
        let ticks = 5;
        let step = (max - min) / ticks as f32;
        let decimals = (1.0 - step.log10().floor()).clamp(0.0, 6.0) as usize;
        BarLabels::Ticks { ticks, decimals }
    }
}

/// A single value, with its significant digits (up to 6): `0.002`, `0`, `1.500e-9`.
fn constant_label(v: f32) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-3..1e6).contains(&a) {
        let decimals = (5.0 - a.log10().floor()).clamp(0.0, 8.0) as usize;
        let t = format!("{v:.*}", decimals);
        if t.contains('.') {
            t.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            t
        }
    } else {
        format!("{v:.3e}")
    }
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
    fn labels_say_what_is_there() {
        assert_eq!(
            BarLabels::of(f32::INFINITY, f32::NEG_INFINITY),
            BarLabels::Nothing
        );
        assert_eq!(BarLabels::of(f32::NAN, 1.0), BarLabels::Nothing);
        assert_eq!(BarLabels::of(0.0, 0.0), BarLabels::Constant(0.0));
        assert_eq!(BarLabels::of(0.002, 0.002), BarLabels::Constant(0.002));
        assert_eq!(
            BarLabels::of(100.0, 500.0),
            BarLabels::Ticks {
                ticks: 5,
                decimals: 0
            }
        );
        assert_eq!(constant_label(0.0), "0");
        assert_eq!(constant_label(0.002), "0.002");
        assert_eq!(constant_label(13836.0), "13836");
        assert_eq!(constant_label(1.5e-9), "1.500e-9");
        // A bar of nothing and a bar of one value differ from a bar of a range; each draws.
        let img = RgbImage::filled(100, 200, [0.5; 3]);
        let ramp = |t: f32| [t; 3];
        let none = add_colour_bar(&img, 60, "t", f32::INFINITY, f32::NEG_INFINITY, &ramp);
        let one = add_colour_bar(&img, 60, "t", 0.002, 0.002, &ramp);
        let range = add_colour_bar(&img, 60, "t", 0.0, 1.0, &ramp);
        assert_ne!(none.data, one.data);
        assert_ne!(one.data, range.data);
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
