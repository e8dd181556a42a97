//! The render summary's pinhole figure is the data-aware one: the front layer missing where the
//! particles themselves hold film (`pipeline::pinholes::front_layer_of`), the share that counts
//! the data's own gaps beside it.

mod cli_support;
use cli_support::{data, disk_ply_header, filmsplat, tmp};

/// The two figures of the summary line in `err`: (pinholes %, missing % counting the data's
/// gaps).
fn figures(err: &str) -> (f64, f64) {
    let line = err
        .lines()
        .find(|l| l.contains("pinholes at "))
        .unwrap_or_else(|| panic!("no pinhole figure in: {err}"));
    let number_after = |key: &str| -> f64 {
        let rest = &line[line.find(key).unwrap_or_else(|| panic!("{key}: {line}")) + key.len()..];
        rest.split_whitespace().next().unwrap().parse().unwrap()
    };
    let counting = line
        .split("; ")
        .find(|s| s.contains("counting the gaps"))
        .unwrap();
    let all: f64 = counting.split_whitespace().next().unwrap().parse().unwrap();
    (number_after("pinholes at "), all)
}

fn render(input: &str, extra: &[&str]) -> (f64, f64) {
    let out = tmp("pinholes.png");
    let mut args = vec![
        "render",
        input,
        "-o",
        out.to_str().unwrap(),
        "--size",
        "320x180",
        "--spp",
        "1",
    ];
    args.extend_from_slice(extra);
    let (code, _, err) = filmsplat(&args);
    assert_eq!(code, 0, "{err}");
    figures(&err)
}

#[test]
fn gaps_in_the_data_are_not_called_pinholes() {
    // Bursting frame 60: the film torn open, its rim ragged; the front layer is missing at
    // 0.7 % of the interior, every pixel of it where the particles hold no film.
    let (pinholes, all) = render(&data("thin-film-sph/bursting_bubble/60"), &[]);
    eprintln!("burst 60: pinholes {pinholes} %, counting the data's gaps {all} %");
    assert!(
        all > 0.3,
        "the data's gaps show in the interior figure: {all} %"
    );
    assert_eq!(pinholes, 0.0, "no pinhole where the data has none");
}

#[test]
fn holes_between_disks_the_data_covers_are_pinholes() {
    // A flat square film of 40 × 40 particles drawn (--raw-radii) at a third of their spacing:
    // the renderer leaves a hole between every four disks, inside the film the data spans.
    let n = 40;
    let spacing = 1.0 / (n - 1) as f32;
    let mut s = disk_ply_header(n * n);
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (i as f32 * spacing - 0.5, j as f32 * spacing - 0.5);
            s += &format!("{x} {y} 0 0 0 1 {} 400\n", spacing / 3.0);
        }
    }
    let input = tmp("sparse_square.ply");
    std::fs::write(&input, s).unwrap();
    let (pinholes, all) = render(input.to_str().unwrap(), &["--raw-radii"]);
    eprintln!("sparse square: pinholes {pinholes} %, counting the data's gaps {all} %");
    assert!(
        pinholes > 5.0,
        "the holes between the disks are pinholes: {pinholes} %"
    );
    assert!(pinholes <= all);
}
