//! `filmsplat film` against the independent reference tables, and its error paths.

mod cli_support;
use cli_support::filmsplat;

fn csv(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect()
}

fn reference(name: &str) -> Vec<Vec<f64>> {
    csv(
        &std::fs::read_to_string(format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR")))
            .unwrap(),
    )
}

/// Distinct values of column `k` (in order of first appearance) among rows with `ior`.
fn distinct(rows: &[Vec<f64>], ior: f64, k: usize) -> String {
    let mut seen: Vec<f64> = Vec::new();
    for r in rows.iter().filter(|r| r[0] == ior) {
        if !seen.contains(&r[k]) {
            seen.push(r[k]);
        }
    }
    seen.iter()
        .map(|v| v.to_string())
        .collect::<Vec<_>>()
        .join(",")
}

#[test]
fn every_reflectance_row_of_the_reference_is_met() {
    let reference = reference("thinfilm_rt.csv");
    let mut matched = 0;
    for ior in [1.33, 1.5] {
        let (code, out, err) = filmsplat(&[
            "film",
            "--thickness",
            &distinct(&reference, ior, 1),
            "--angle",
            &distinct(&reference, ior, 2),
            "--ior",
            &ior.to_string(),
            "--wavelengths",
            "380:780:10",
        ]);
        assert_eq!(code, 0, "{err}");
        assert!(out.starts_with("thickness_nm,angle_deg,wavelength_nm,R,T,Rs,Rp\n"));
        let rows = csv(&out);
        for want in reference.iter().filter(|r| r[0] == ior) {
            let got = rows
                .iter()
                .find(|g| g[0] == want[1] && g[1] == want[2] && g[2] == want[3])
                .unwrap_or_else(|| panic!("no CLI row for {want:?}"));
            for k in 0..4 {
                assert!(
                    (got[3 + k] - want[4 + k]).abs() < 1e-6,
                    "{got:?} vs {want:?}"
                );
            }
            matched += 1;
        }
    }
    assert_eq!(matched, 2624);
}

#[test]
fn every_colour_row_of_the_reference_is_met() {
    let reference = reference("thinfilm_rgb_d65.csv");
    let mut matched = 0;
    for ior in [1.33, 1.5] {
        if !reference.iter().any(|r| r[0] == ior) {
            continue;
        }
        let (code, out, err) = filmsplat(&[
            "film",
            "--rgb",
            "--thickness",
            &distinct(&reference, ior, 1),
            "--angle",
            &distinct(&reference, ior, 2),
            "--ior",
            &ior.to_string(),
        ]);
        assert_eq!(code, 0, "{err}");
        assert!(out.starts_with("thickness_nm,angle_deg,r,g,b\n"));
        let rows = csv(&out);
        for want in reference.iter().filter(|r| r[0] == ior) {
            let got = rows
                .iter()
                .find(|g| g[0] == want[1] && g[1] == want[2])
                .unwrap();
            for k in 0..3 {
                assert!(
                    (got[2 + k] - want[3 + k]).abs() < 2e-3,
                    "{got:?} vs {want:?}"
                );
            }
            matched += 1;
        }
    }
    assert_eq!(matched, 378);
}

#[test]
fn bad_arguments_give_one_line_errors_and_exit_code_2() {
    for args in [
        &["film", "--thickness", "-5", "--angle", "0"][..],
        &["film", "--thickness", "nan", "--angle", "0"],
        &["film", "--thickness", "100", "--angle", "95"],
        &["film", "--thickness", "100", "--angle", "0", "--ior", "0.5"],
        &[
            "film",
            "--thickness",
            "100",
            "--angle",
            "0",
            "--wavelengths",
            "0:10:1",
        ],
        &["film", "--thickness", "100"],
        &["film", "--thickness", "1:0:1", "--angle", "0"],
        &["film", "--bogus"],
    ] {
        let (code, out, err) = filmsplat(args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(out.is_empty() || !out.contains("NaN"), "{args:?}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        let first = err.lines().next().unwrap_or("");
        assert!(first.contains("error"), "{args:?}: {err}");
    }
}

#[test]
fn help_explains_units() {
    let (code, out, _) = filmsplat(&["film", "--help"]);
    assert_eq!(code, 0);
    for word in ["nanometres", "degrees", "--ior", "--rgb", "--wavelengths"] {
        assert!(out.contains(word), "{word}");
    }
}
