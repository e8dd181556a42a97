//! Anti-aliased text for chart axes and labels, from the embedded DejaVu Sans glyphs.
//!
//! Glyphs are stored once as 64 px/em coverage masters (rendered 4x oversampled, so effectively
//! unhinted outlines). At draw time each glyph is area-resampled (box filter, exact overlap) to
//! the requested size at its sub-pixel pen position, so any size from ~9 to ~64 px works; sizes
//! from 11 to 32 px look best. Advances and pair kerning come from the font in font units, so
//! spacing is exact at every size. The baseline is snapped to the pixel grid for crisp bottoms.
//!
//! Coverage is blended in sRGB-encoded space ([`blend`]): the result after
//! [`to_srgb8`](super::to_srgb8) (clamp, 0 EV) matches ordinary text rendering, so dark text on a
//! light background has its normal weight. (Blending in linear light would make dark-on-light
//! text look thin and washed out.) Text is drawn on a single line; characters the font lacks are
//! drawn as '?'. The font covers ASCII 32-126 and `° µ λ θ – − × ± ² ³ · Δ Å`.

use super::buffer::RgbImage;
use super::draw::blend;
use super::font::{Font, font};

/// Horizontal alignment of text relative to the anchor point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HAlign {
    /// The text starts at the anchor.
    Left,
    /// The text is centred on the anchor.
    Centre,
    /// The text ends at the anchor.
    Right,
}

/// Vertical alignment of text relative to the anchor point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VAlign {
    /// The anchor is on the top of the line box (the font's ascender, above all ink).
    Top,
    /// The anchor is half the cap height above the baseline: digits and capitals are centred
    /// on it (use for y-axis tick labels).
    Middle,
    /// The anchor is on the baseline.
    Baseline,
    /// The anchor is on the bottom of the line box (the font's descender, below all ink).
    Bottom,
}

/// Where the anchor point `(x, y)` given to [`draw_text`] sits on the text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Anchor {
    /// Horizontal alignment.
    pub h: HAlign,
    /// Vertical alignment.
    pub v: VAlign,
}

impl Anchor {
    /// An anchor from its two alignments.
    pub const fn new(h: HAlign, v: VAlign) -> Self {
        Anchor { h, v }
    }
    /// Left end, top of the line box.
    pub const TOP_LEFT: Anchor = Anchor::new(HAlign::Left, VAlign::Top);
    /// Centre, top of the line box (x-axis tick labels).
    pub const TOP_CENTRE: Anchor = Anchor::new(HAlign::Centre, VAlign::Top);
    /// Right end, top of the line box.
    pub const TOP_RIGHT: Anchor = Anchor::new(HAlign::Right, VAlign::Top);
    /// Left end, vertically centred.
    pub const MIDDLE_LEFT: Anchor = Anchor::new(HAlign::Left, VAlign::Middle);
    /// Centred both ways.
    pub const CENTRE: Anchor = Anchor::new(HAlign::Centre, VAlign::Middle);
    /// Right end, vertically centred (y-axis tick labels).
    pub const MIDDLE_RIGHT: Anchor = Anchor::new(HAlign::Right, VAlign::Middle);
    /// Left end on the baseline.
    pub const BASELINE_LEFT: Anchor = Anchor::new(HAlign::Left, VAlign::Baseline);
    /// Centre on the baseline.
    pub const BASELINE_CENTRE: Anchor = Anchor::new(HAlign::Centre, VAlign::Baseline);
    /// Right end on the baseline.
    pub const BASELINE_RIGHT: Anchor = Anchor::new(HAlign::Right, VAlign::Baseline);
}

/// Vertical metrics of the font at a size, in pixels (all positive).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FontMetrics {
    /// Baseline to top of the line box (no glyph reaches above it).
    pub ascent: f32,
    /// Baseline to bottom of the line box (no glyph reaches below it).
    pub descent: f32,
    /// Height of capital letters and digits.
    pub cap_height: f32,
    /// Height of lower-case letters such as 'x'.
    pub x_height: f32,
    /// Recommended baseline-to-baseline distance (`ascent + descent`).
    pub line_height: f32,
}

/// Vertical font metrics at `size_px` pixels per em.
pub fn font_metrics(size_px: f32) -> FontMetrics {
    let f = font();
    let ascent = f.ascender.max(f.ink_top) * size_px;
    let descent = (-f.descender).max(-f.ink_bottom) * size_px;
    FontMetrics {
        ascent,
        descent,
        cap_height: f.cap_height * size_px,
        x_height: f.x_height * size_px,
        line_height: ascent + descent,
    }
}

/// Vertical stretch factor that puts the x-height on a whole number of pixels (with the
/// baseline on the grid, the tops and bottoms of lower-case letters are then crisp, as with
/// hinting). At most a few per cent; 1 above 48 px where it no longer matters.
fn vertical_snap(f: &Font, size_px: f32) -> f32 {
    let xh = f.x_height * size_px;
    if size_px > 48.0 || xh < 1.0 {
        1.0
    } else {
        xh.round() / xh
    }
}

/// Glyph indices and pen positions (em) of a string, plus its total advance (em).
fn layout(f: &Font, text: &str) -> (Vec<(usize, f32)>, f32) {
    let mut out = Vec::with_capacity(text.len());
    let mut pen = 0.0;
    let mut prev: Option<usize> = None;
    for c in text.chars() {
        let g = f.index(c);
        if let Some(p) = prev {
            pen += f.kern(p, g);
        }
        out.push((g, pen));
        pen += f.glyphs[g].advance;
        prev = Some(g);
    }
    (out, pen)
}

/// Advance width of `text` at `size_px` pixels per em, in pixels (with kerning). This is the
/// horizontal extent used for alignment; ink may overhang it by a fraction of a pixel.
pub fn text_width(text: &str, size_px: f32) -> f32 {
    layout(font(), text).1 * size_px
}

/// A coverage mask in the text's own frame (u right, v down), integer-aligned.
struct Mask {
    u0: i64,
    v0: i64,
    w: usize,
    h: usize,
    cov: Vec<f32>,
}

/// Area-resampling weights of `n` master pixels placed at output position `g` with `scale`
/// output pixels per master pixel: returns the first output index and, per output pixel, the
/// first master index and the weights.
fn box_weights(g: f32, scale: f32, n: usize) -> (i64, Vec<(usize, Vec<f32>)>) {
    let end = g + n as f32 * scale;
    let o0 = g.floor() as i64;
    let o1 = end.ceil() as i64;
    let mut rows = Vec::with_capacity((o1 - o0).max(0) as usize);
    for o in o0..o1 {
        // Output pixel [o, o+1] in master coordinates.
        let a = ((o as f32 - g) / scale).max(0.0);
        let b = (((o + 1) as f32 - g) / scale).min(n as f32);
        let k0 = a.floor() as usize;
        let k1 = (b.ceil() as usize).min(n);
        let w = (k0..k1)
            .map(|k| ((b.min(k as f32 + 1.0) - a.max(k as f32)).max(0.0)) * scale)
            .collect();
        rows.push((k0, w));
    }
    (o0, rows)
}

/// Renders `text` with its pen origin (left end of the baseline) at `(u, v)` in its frame.
fn render_mask(f: &Font, text: &str, size_px: f32, u: f32, v: f32) -> Option<Mask> {
    let (glyphs, _) = layout(f, text);
    let scale = size_px / f.master_px;
    let scale_v = scale * vertical_snap(f, size_px);
    let mut placed = Vec::with_capacity(glyphs.len());
    let (mut umin, mut vmin, mut umax, mut vmax) = (i64::MAX, i64::MAX, i64::MIN, i64::MIN);
    for (gi, pen) in glyphs {
        let g = &f.glyphs[gi];
        if g.width == 0 || g.height == 0 {
            continue;
        }
        let gu = u + pen * size_px + g.left as f32 * scale;
        let gv = v + g.top as f32 * scale_v;
        let (cu0, wu) = box_weights(gu, scale, g.width);
        let (cv0, wv) = box_weights(gv, scale_v, g.height);
        umin = umin.min(cu0);
        vmin = vmin.min(cv0);
        umax = umax.max(cu0 + wu.len() as i64);
        vmax = vmax.max(cv0 + wv.len() as i64);
        placed.push((g, cu0, wu, cv0, wv));
    }
    if placed.is_empty() {
        return None;
    }
    let (w, h) = ((umax - umin) as usize, (vmax - vmin) as usize);
    let mut cov = vec![0.0f32; w * h];
    let mut tmp = Vec::new();
    for (g, cu0, wu, cv0, wv) in placed {
        // Horizontal pass: every master row to output columns.
        tmp.clear();
        tmp.resize(g.height * wu.len(), 0.0f32);
        for r in 0..g.height {
            let row = &g.bitmap[r * g.width..(r + 1) * g.width];
            for (c, (k0, ws)) in wu.iter().enumerate() {
                let s: f32 = ws.iter().zip(&row[*k0..]).map(|(w, &p)| w * p as f32).sum();
                tmp[r * wu.len() + c] = s * (1.0 / 255.0);
            }
        }
        // Vertical pass: output rows, accumulated into the mask.
        for (ro, (k0, ws)) in wv.iter().enumerate() {
            let mrow = (cv0 - vmin) as usize + ro;
            let base = mrow * w + (cu0 - umin) as usize;
            for c in 0..wu.len() {
                let s: f32 = ws
                    .iter()
                    .enumerate()
                    .map(|(i, wt)| wt * tmp[(k0 + i) * wu.len() + c])
                    .sum();
                cov[base + c] += s;
            }
        }
    }
    Some(Mask {
        u0: umin,
        v0: vmin,
        w,
        h,
        cov,
    })
}

/// Pen origin `(u, v)` in the text frame for an anchor at `(ax, ay)`; the baseline is snapped
/// to an integer.
fn origin(f: &Font, text: &str, size_px: f32, ax: f32, ay: f32, anchor: Anchor) -> (f32, f32) {
    let width = layout(f, text).1 * size_px;
    let m = font_metrics(size_px);
    let u = match anchor.h {
        HAlign::Left => ax,
        HAlign::Centre => ax - width / 2.0,
        HAlign::Right => ax - width,
    };
    let v = match anchor.v {
        VAlign::Top => ay + m.ascent,
        VAlign::Middle => ay + m.cap_height / 2.0,
        VAlign::Baseline => ay,
        VAlign::Bottom => ay - m.descent,
    };
    (u, v.round())
}

/// Draws `text` at `size_px` pixels per em in `colour` (linear RGB), horizontally, with the
/// `anchor` point of the text at `(x, y)` (pixels; y down). Clipped to the image.
///
/// Cost: area resampling of each glyph plus an sRGB-space blend per inked pixel, about 10 us
/// per glyph at 22 px (a 19-character label: ~0.2 ms measured on a busy 2-core machine).
pub fn draw_text(
    img: &mut RgbImage,
    x: f32,
    y: f32,
    text: &str,
    size_px: f32,
    colour: [f32; 3],
    anchor: Anchor,
) {
    stamp(img, (x, y), text, size_px, colour, anchor, |cu, cv| {
        (cu, cv)
    });
}

/// Like [`draw_text`] but rotated 90 degrees counter-clockwise: the text reads bottom to top
/// (for a y-axis label). `anchor` is relative to the text's own direction: `Left` is its start
/// (bottom end), `Top` its top side (towards smaller x).
pub fn draw_text_vertical(
    img: &mut RgbImage,
    x: f32,
    y: f32,
    text: &str,
    size_px: f32,
    colour: [f32; 3],
    anchor: Anchor,
) {
    // Text frame (u along the text, v "down" the glyphs) maps to the image as u = -y, v = x;
    // frame cell (cu, cv) is image pixel (cv, -cu - 1).
    stamp(img, (-y, x), text, size_px, colour, anchor, |cu, cv| {
        (cv, -cu - 1)
    });
}

/// Renders `text` anchored at `at` in the text's own frame and blends each inked cell into the
/// image pixel `to_image(cu, cv)` (identity for horizontal text, a rotation for vertical).
fn stamp(
    img: &mut RgbImage,
    at: (f32, f32),
    text: &str,
    size_px: f32,
    colour: [f32; 3],
    anchor: Anchor,
    to_image: impl Fn(i64, i64) -> (i64, i64),
) {
    if !(size_px > 0.0 && size_px.is_finite() && at.0.is_finite() && at.1.is_finite()) {
        return;
    }
    let f = font();
    let (u, v) = origin(f, text, size_px, at.0, at.1, anchor);
    let Some(m) = render_mask(f, text, size_px, u, v) else {
        return;
    };
    for r in 0..m.h {
        for c in 0..m.w {
            let a = m.cov[r * m.w + c];
            if a > 0.0 {
                let (ix, iy) = to_image(m.u0 + c as i64, m.v0 + r as i64);
                if let Some(px) = img.pixel_mut_checked(ix, iy) {
                    blend(px, colour, a.min(1.0));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_weights_conserve_area() {
        for &(g, s, n) in &[
            (0.0, 1.0, 5),
            (3.3, 0.25, 64),
            (-2.7, 0.37, 13),
            (1.5, 2.0, 3),
        ] {
            let (_, rows) = box_weights(g, s, n);
            let total: f32 = rows.iter().flat_map(|(_, w)| w.iter()).sum();
            assert!((total - n as f32 * s).abs() < 1e-4, "{g} {s} {n}: {total}");
            for (_, w) in &rows {
                assert!(w.iter().sum::<f32>() <= 1.0 + 1e-5);
            }
        }
        // Identity at scale 1 on the grid.
        let (o, rows) = box_weights(2.0, 1.0, 3);
        assert_eq!(o, 2);
        assert_eq!(rows, vec![(0, vec![1.0]), (1, vec![1.0]), (2, vec![1.0])]);
    }
}
