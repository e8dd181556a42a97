//! Text rendering: placement, extent, anchors, rotation; plus an optional visual test card
//! (set FILMSPLAT_TEXTCARD=/path/card.png to write it).

use filmsplat::image::{
    Anchor, HAlign, RgbImage, ToneMap, VAlign, draw_line, draw_text, draw_text_vertical, fill_rect,
    font_metrics, linear_to_srgb, save_png, stroke_rect, text_width, viridis,
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

/// Writes a visual test card when FILMSPLAT_TEXTCARD is set (for looking at the typesetting).
#[test]
fn text_card() {
    let mut img = RgbImage::filled(1000, 720, WHITE);
    let sample = "Film thickness (nm) 0 250 500 λ = 550 nm θ = 45° Hg 1500 nm 3–5 µm";
    let mut y = 14.0;
    for size in [
        9.0, 10.0, 11.0, 12.0, 13.0, 14.0, 16.0, 18.0, 20.0, 22.0, 24.0, 28.0, 32.0,
    ] {
        let m = font_metrics(size);
        y += m.ascent;
        draw_text(
            &mut img,
            80.0,
            y,
            &format!("{size}px"),
            11.0,
            [0.4; 3],
            Anchor::BASELINE_RIGHT,
        );
        draw_text(&mut img, 90.0, y, sample, size, INK, Anchor::BASELINE_LEFT);
        y += m.descent + 4.0;
    }
    // Light text on dark.
    y = y.round();
    fill_rect(&mut img, 0.0, y, 1000.0, y + 40.0, [0.02, 0.02, 0.03]);
    draw_text(
        &mut img,
        90.0,
        y + 20.0,
        "Light on dark: AVAWAY Wave 0.18 = mid-grey, Ta To",
        16.0,
        WHITE,
        Anchor::MIDDLE_LEFT,
    );
    y += 50.0;
    // A small chart: frame, ticks, labels, vertical label, viridis bar.
    let (x0, y0, x1, y1) = (150.0, y + 20.0, 700.0, y + 260.0);
    stroke_rect(&mut img, x0 + 0.5, y0 + 0.5, x1 - 0.5, y1 - 0.5, 1.0, INK);
    for i in 0..=4 {
        let x = (x0 + (x1 - x0) * i as f32 / 4.0).round() + 0.5;
        draw_line(&mut img, x, y1, x, y1 + 6.0, 1.0, INK);
        draw_text(
            &mut img,
            x,
            y1 + 8.0,
            &format!("{}", i * 250),
            13.0,
            INK,
            Anchor::TOP_CENTRE,
        );
        let yy = (y0 + (y1 - y0) * i as f32 / 4.0).round() + 0.5;
        draw_line(&mut img, x0 - 6.0, yy, x0, yy, 1.0, INK);
        draw_text(
            &mut img,
            x0 - 9.0,
            yy,
            &format!("{}°", 80 - 20 * i),
            13.0,
            INK,
            Anchor::MIDDLE_RIGHT,
        );
    }
    draw_line(&mut img, x0, y1, x1, y0, 1.5, [0.8, 0.1, 0.05]);
    draw_text(
        &mut img,
        (x0 + x1) / 2.0,
        y1 + 44.0,
        "Film thickness (nm)",
        16.0,
        INK,
        Anchor::BASELINE_CENTRE,
    );
    draw_text_vertical(
        &mut img,
        95.0,
        (y0 + y1) / 2.0,
        "Angle of incidence θ (°)",
        16.0,
        INK,
        Anchor::CENTRE,
    );
    let (bx0, bx1) = (780.0, 810.0);
    for j in y0 as usize..y1 as usize {
        let t = 1.0 - (j as f32 + 0.5 - y0) / (y1 - y0);
        fill_rect(&mut img, bx0, j as f32, bx1, j as f32 + 1.0, viridis(t));
    }
    stroke_rect(&mut img, bx0 - 0.5, y0 - 0.5, bx1 + 0.5, y1 + 0.5, 1.0, INK);
    for i in 0..=4 {
        let yy = (y1 - (y1 - y0) * i as f32 / 4.0).round() - 0.5;
        draw_line(&mut img, bx1, yy, bx1 + 5.0, yy, 1.0, INK);
        draw_text(
            &mut img,
            bx1 + 8.0,
            yy,
            &format!("{} nm", 200 * i),
            13.0,
            INK,
            Anchor::MIDDLE_LEFT,
        );
    }
    draw_text_vertical(
        &mut img,
        900.0,
        (y0 + y1) / 2.0,
        "Thickness",
        14.0,
        INK,
        Anchor::CENTRE,
    );
    assert!(ink_box(&img, 0.5).is_some());
    if let Ok(path) = std::env::var("FILMSPLAT_TEXTCARD") {
        save_png(std::path::Path::new(&path), &img, 0.0, ToneMap::Clamp).unwrap();
    }
}
