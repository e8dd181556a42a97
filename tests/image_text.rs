//! Text rendering: placement, extent, anchors, rotation, distinct glyphs, size scaling, and
//! colour-independent anti-aliasing.

use filmsplat::image::{
    Anchor, HAlign, RgbImage, VAlign, draw_text, draw_text_vertical, font_metrics, linear_to_srgb,
    text_width,
};

const WHITE: [f32; 3] = [1.0; 3];
const INK: [f32; 3] = [0.0; 3];

/// Bounding box `(x0, y0, x1, y1)` (inclusive) of pixels whose sRGB value is below `thresh`.
fn ink_box(img: &RgbImage, thresh: f32) -> Option<(usize, usize, usize, usize)> {
    let mut b: Option<(usize, usize, usize, usize)> = None;
    for y in 0..img.height {
        for x in 0..img.width {
            if linear_to_srgb(img.get(x, y)[0]) < thresh {
                b = Some(match b {
                    None => (x, y, x, y),
                    Some((x0, y0, x1, y1)) => (x0.min(x), y0.min(y), x1.max(x), y1.max(y)),
                });
            }
        }
    }
    b
}

#[test]
fn label_is_dark_inside_its_box_and_untouched_outside() {
    let mut img = RgbImage::filled(200, 60, WHITE);
    let (x, y, size) = (20.0, 40.0, 22.0);
    draw_text(
        &mut img,
        x,
        y,
        "Hg 1500 nm",
        size,
        INK,
        Anchor::BASELINE_LEFT,
    );
    let m = font_metrics(size);
    let w = text_width("Hg 1500 nm", size);
    // Expected box: advance width horizontally; cap height (+ overshoot) above the baseline,
    // the descender of 'g' below it.
    let (bx0, bx1) = (x - 1.0, x + w + 1.0);
    let (by0, by1) = (y - m.cap_height - 1.0, y + m.descent + 1.0);
    let mut dark = 0;
    for py in 0..img.height {
        for px in 0..img.width {
            let v = linear_to_srgb(img.get(px, py)[0]);
            let (fx, fy) = (px as f32 + 0.5, py as f32 + 0.5);
            let inside = fx >= bx0 && fx <= bx1 && fy >= by0 && fy <= by1;
            if !inside {
                assert_eq!(img.get(px, py), WHITE, "ink outside the box at ({px},{py})");
            } else if v < 0.2 {
                dark += 1;
            }
        }
    }
    // Real strokes: a 22 px label has well over a hundred near-black pixels.
    assert!(dark > 150, "only {dark} dark pixels");
    // The ink reaches close to every side of the box (not drawn tiny or offset).
    let (x0, y0, x1, y1) = ink_box(&img, 0.5).unwrap();
    assert!((x0 as f32 - x).abs() <= 3.0, "left {x0}");
    assert!((x1 as f32 - (x + w)).abs() <= 3.0, "right {x1}");
    assert!((y0 as f32 - (y - m.cap_height)).abs() <= 1.5, "top {y0}");
    assert!(y1 as f32 > y + 2.0, "descender of g missing: bottom {y1}");
    // Baseline: 'H' ends exactly on the baseline row (y = 40 is the top edge of row 40).
    let h_col = x as usize + 2;
    assert!(linear_to_srgb(img.get(h_col, 39)[0]) < 0.2);
    assert!(linear_to_srgb(img.get(h_col, 40)[0]) > 0.9);
}

#[test]
fn widths_are_proportional_and_respect_letter_shapes() {
    assert!(text_width("iiii", 22.0) < 0.5 * text_width("WWWW", 22.0));
    let a = text_width("Film thickness (nm)", 11.0);
    let b = text_width("Film thickness (nm)", 33.0);
    assert!((b / a - 3.0).abs() < 1e-5);
    assert_eq!(text_width("", 20.0), 0.0);
    // Kerning: "AV" is narrower than "A" + "V".
    assert!(text_width("AV", 20.0) < text_width("A", 20.0) + text_width("V", 20.0) - 0.5);
}

#[test]
fn text_width_matches_drawn_extent() {
    for &size in &[11.0, 16.0, 22.0, 32.0] {
        for text in ["Hg 1500 nm", "HHHH", "Angle of incidence (degrees)"] {
            let w = text_width(text, size);
            let mut img = RgbImage::filled((w + 40.0) as usize, (2.0 * size) as usize + 10, WHITE);
            draw_text(
                &mut img,
                10.0,
                size * 1.5,
                text,
                size,
                INK,
                Anchor::BASELINE_LEFT,
            );
            let (x0, _, x1, _) = ink_box(&img, 0.99).unwrap();
            let extent = (x1 + 1 - x0) as f32;
            // Ink spans the advance width minus the outer side bearings (< 0.2 em together).
            assert!(extent <= w + 1.0, "{text}@{size}: ink {extent} > width {w}");
            assert!(
                extent >= w - 0.2 * size - 1.0,
                "{text}@{size}: ink {extent} << width {w}"
            );
        }
    }
}

#[test]
fn anchors_place_the_text_where_asked() {
    let size = 20.0;
    let text = "0123";
    let w = text_width(text, size);
    let m = font_metrics(size);
    let check = |anchor: Anchor| {
        let mut img = RgbImage::filled(200, 100, WHITE);
        draw_text(&mut img, 100.0, 50.0, text, size, INK, anchor);
        let (x0, y0, x1, y1) = ink_box(&img, 0.99).unwrap();
        let (cx, cy) = ((x0 + x1 + 1) as f32 / 2.0, (y0 + y1 + 1) as f32 / 2.0);
        match anchor.h {
            HAlign::Left => assert!((x0 as f32 - 100.0).abs() <= 0.15 * size, "{anchor:?}"),
            HAlign::Centre => assert!((cx - 100.0).abs() <= 1.5, "{anchor:?} {cx}"),
            HAlign::Right => assert!((x1 as f32 + 1.0 - 100.0).abs() <= 0.15 * size, "{anchor:?}"),
        }
        match anchor.v {
            VAlign::Top => assert!(y0 >= 50 && (y0 as f32) < 50.0 + m.ascent - m.cap_height + 2.0),
            VAlign::Middle => assert!((cy - 50.0).abs() <= 1.0, "{anchor:?} {cy}"),
            // Round digits overshoot the baseline by a fraction of a pixel.
            VAlign::Baseline => assert!(y1 + 1 == 50 || y1 + 1 == 51, "{anchor:?} {y1}"),
            VAlign::Bottom => assert!(y1 < 50 && (y1 as f32) > 50.0 - m.descent - 2.0),
        }
        let _ = w;
    };
    for h in [HAlign::Left, HAlign::Centre, HAlign::Right] {
        for v in [
            VAlign::Top,
            VAlign::Middle,
            VAlign::Baseline,
            VAlign::Bottom,
        ] {
            check(Anchor::new(h, v));
        }
    }
}

#[test]
fn vertical_text_is_the_horizontal_text_rotated_ccw() {
    let (w, h) = (140usize, 40usize);
    let text = "Angle (°) λ";
    let mut a = RgbImage::filled(w, h, WHITE);
    draw_text(&mut a, 10.3, 28.0, text, 18.0, INK, Anchor::BASELINE_LEFT);
    // Rotating CCW maps horizontal (x, y) to (y, W - 1 - x) in an H x W image.
    let mut b = RgbImage::filled(h, w, WHITE);
    draw_text_vertical(
        &mut b,
        28.0,
        w as f32 - 10.3,
        text,
        18.0,
        INK,
        Anchor::BASELINE_LEFT,
    );
    let mut inked = 0;
    for y in 0..h {
        for x in 0..w {
            let (pa, pb) = (a.get(x, y), b.get(y, w - 1 - x));
            assert!((pa[0] - pb[0]).abs() < 1e-4, "({x},{y}): {pa:?} vs {pb:?}");
            inked += (pa[0] < 0.5) as usize;
        }
    }
    assert!(inked > 50);
    // Reads bottom to top: the first letter ('A') is at the bottom of the vertical label.
    let (_, y0, _, y1) = ink_box(&b, 0.5).unwrap();
    let (_, _, ax1, _) = ink_box(&a, 0.5).unwrap();
    assert_eq!(y0, w - 1 - ax1);
    assert!(y1 > y0 + 60);
}

#[test]
fn degenerate_input_draws_nothing_and_does_not_panic() {
    let mut img = RgbImage::filled(50, 20, WHITE);
    let before = img.clone();
    draw_text(&mut img, 5.0, 15.0, "", 12.0, INK, Anchor::BASELINE_LEFT);
    draw_text(&mut img, 5.0, 15.0, "abc", 0.0, INK, Anchor::BASELINE_LEFT);
    draw_text(
        &mut img,
        f32::NAN,
        15.0,
        "abc",
        12.0,
        INK,
        Anchor::BASELINE_LEFT,
    );
    draw_text(
        &mut img,
        5.0,
        15.0,
        "abc",
        f32::INFINITY,
        INK,
        Anchor::BASELINE_LEFT,
    );
    draw_text(
        &mut img,
        -1e6,
        1e6,
        "far away",
        12.0,
        INK,
        Anchor::BASELINE_LEFT,
    );
    draw_text_vertical(&mut img, 1e9, -1e9, "far away", 12.0, INK, Anchor::CENTRE);
    assert_eq!(img, before);
    // Partly off-image text is clipped; unknown characters draw as '?'.
    draw_text(
        &mut img,
        -5.0,
        10.0,
        "€€€ clipped text",
        16.0,
        INK,
        Anchor::MIDDLE_LEFT,
    );
    assert_ne!(img, before);
    assert_eq!(text_width("€", 10.0), text_width("?", 10.0));
}

/// A glyph's ink: the ink box's width and height, pixels, and its pixels inked (1) or not.
type Mask = (usize, usize, Vec<u8>);

/// The ink of `text` drawn black on white at `size` px, baseline-left at (8, 1.5 size), as a
/// coverage mask (1 - sRGB value) cropped to its ink box, with that box's size.
fn glyph_mask(text: &str, size: f32) -> Mask {
    let w = text_width(text, size);
    let mut img = RgbImage::filled((w + 16.0) as usize, (2.0 * size) as usize + 8, WHITE);
    draw_text(
        &mut img,
        8.0,
        size * 1.5,
        text,
        size,
        INK,
        Anchor::BASELINE_LEFT,
    );
    let (x0, y0, x1, y1) = ink_box(&img, 0.5).unwrap();
    let mask = (y0..=y1)
        .flat_map(|y| (x0..=x1).map(move |x| (x, y)))
        .map(|(x, y)| u8::from(linear_to_srgb(img.get(x, y)[0]) < 0.5))
        .collect();
    (x1 + 1 - x0, y1 + 1 - y0, mask)
}

/// Every digit, and the letters most easily confused with digits, draw a glyph of their own:
/// tick labels must read. Digits sit between the baseline and the cap height (no descender).
#[test]
fn digits_and_confusable_letters_draw_distinct_glyphs() {
    let size = 20.0;
    let m = font_metrics(size);
    let chars = "0123456789OoISZBg"; // l and I are one stroke in this sans face
    let masks: Vec<(char, Mask)> = chars
        .chars()
        .map(|c| (c, glyph_mask(&c.to_string(), size)))
        .collect();
    for (i, (a, ma)) in masks.iter().enumerate() {
        for (b, mb) in &masks[i + 1..] {
            assert_ne!(ma, mb, "'{a}' and '{b}' draw the same glyph");
        }
    }
    for (c, (_, h, mask)) in &masks[..10] {
        let ink: usize = mask.iter().map(|&v| v as usize).sum();
        assert!(ink >= 15, "'{c}': only {ink} inked pixels at {size} px");
        let want = m.cap_height;
        assert!(
            (*h as f32 - want).abs() <= 2.0,
            "'{c}': ink {h} px tall, cap height {want}"
        );
    }
    // '1' is the narrowest digit's ink; '0' and '8' are closed (wider than '1').
    let width = |c: char| masks.iter().find(|(x, _)| *x == c).unwrap().1.0;
    assert!(width('1') < width('0') && width('1') < width('8'));
}

/// Ink grows with the square of the size: doubling the size doubles the ink box's sides and
/// quadruples the inked area (within the rounding of the edges).
#[test]
fn ink_area_scales_with_the_square_of_the_size() {
    for text in ["Film 250 nm", "WAVE", "0123456789"] {
        let (w1, h1, m1) = glyph_mask(text, 14.0);
        let (w2, h2, m2) = glyph_mask(text, 28.0);
        let area = |m: &[u8]| m.iter().map(|&v| v as f32).sum::<f32>();
        let ratio = area(&m2) / area(&m1);
        assert!((3.3..4.7).contains(&ratio), "{text}: area ratio {ratio}");
        let (rw, rh) = (w2 as f32 / w1 as f32, h2 as f32 / h1 as f32);
        assert!((1.85..2.15).contains(&rw), "{text}: width ratio {rw}");
        assert!((1.8..2.2).contains(&rh), "{text}: height ratio {rh}");
    }
}

/// Text is an alpha blend in sRGB values: with the coverage `a` measured from black on white
/// (1 - value), white on black gives `a` and any colour `c` on white gives `c a + (1 - a)` at
/// every pixel: anti-aliasing does not depend on the colour.
#[test]
fn coverage_is_the_same_for_every_colour() {
    let (w, h) = (160, 40);
    let text = "Ta To 3-5 AVAWAY";
    let draw = |bg: [f32; 3], ink: [f32; 3]| {
        let mut img = RgbImage::filled(w, h, bg);
        draw_text(&mut img, 4.3, 27.0, text, 17.0, ink, Anchor::BASELINE_LEFT);
        img
    };
    let black_on_white = draw(WHITE, INK);
    let white_on_black = draw(INK, WHITE);
    let red = [0.8, 0.1, 0.05];
    let red_on_white = draw(WHITE, red);
    let red_srgb = red.map(linear_to_srgb);
    let mut partial = 0;
    for y in 0..h {
        for x in 0..w {
            let a = 1.0 - linear_to_srgb(black_on_white.get(x, y)[0]);
            let b = linear_to_srgb(white_on_black.get(x, y)[0]);
            assert!((a - b).abs() < 2e-3, "({x},{y}): {a} vs {b}");
            for (k, &c) in red_srgb.iter().enumerate() {
                let got = linear_to_srgb(red_on_white.get(x, y)[k]);
                let want = c * a + (1.0 - a);
                assert!((got - want).abs() < 2e-3, "({x},{y})[{k}]: {got} vs {want}");
            }
            partial += usize::from(a > 0.05 && a < 0.95);
        }
    }
    assert!(partial > 50, "anti-aliased edges: {partial} partial pixels");
}
