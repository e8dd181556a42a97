//! compute_stats against hand-computed values.

use filmsplat::pointcloud::PointCloud;
use filmsplat::pointcloud::stats::{Histogram, compute_stats};
use glam::Vec3;

fn grid_cloud() -> PointCloud {
    // 10×10 grid with spacing 0.5 in the z = 2 plane.
    let positions: Vec<Vec3> = (0..100)
        .map(|i| Vec3::new((i % 10) as f32 * 0.5, (i / 10) as f32 * 0.5, 2.0))
        .collect();
    let mut normals = vec![Vec3::Z; 100];
    normals[3] = Vec3::ZERO;
    normals[4] = Vec3::splat(f32::NAN);
    normals[5] = Vec3::Z * 3.0;
    PointCloud {
        positions,
        normals: Some(normals),
        thickness_nm: Some((0..100).map(|i| i as f32 * 10.0).collect()), // 0..990
        radius: None,
        extra: vec![(
            "pressure".into(),
            vec![-1.0; 99].into_iter().chain([f32::NAN]).collect(),
        )],
    }
}

#[test]
fn stats_of_a_grid() {
    let s = compute_stats(&grid_cloud());
    assert_eq!(s.count, 100);
    assert_eq!(s.non_finite_positions, 0);
    assert_eq!(
        s.bounds,
        Some((Vec3::new(0.0, 0.0, 2.0), Vec3::new(4.5, 4.5, 2.0)))
    );
    assert!((s.median_spacing - 0.5).abs() < 1e-6);
    let t = s.thickness_nm.as_ref().unwrap();
    assert_eq!((t.min, t.max, t.non_finite), (0.0, 990.0, 0));
    assert!((t.mean - 495.0).abs() < 1e-9);
    assert_eq!(t.histogram.counts, vec![10; 10]);
    assert!(s.radius.is_none());
    assert!(!s.normals_missing);
    assert_eq!((s.normals_degenerate, s.normals_not_unit), (2, 1));
    assert_eq!(s.extra.len(), 1);
    let (name, p) = &s.extra[0];
    assert_eq!(
        (name.as_str(), p.min, p.max, p.non_finite),
        ("pressure", -1.0, -1.0, 1)
    );
    let text = s.to_string();
    for needle in [
        "particles    100",
        "thickness",
        "pressure",
        "radius       missing",
        "2 zero or non-finite",
    ] {
        assert!(text.contains(needle), "missing {needle:?} in:\n{text}");
    }
}

#[test]
fn stats_of_odd_clouds_do_not_panic() {
    let empty = compute_stats(&PointCloud::default());
    assert_eq!(
        (empty.count, empty.bounds, empty.median_spacing),
        (0, None, 0.0)
    );
    assert!(empty.normals_missing);
    assert!(!empty.to_string().is_empty());
    let nan = PointCloud {
        positions: vec![Vec3::NAN, Vec3::ONE],
        thickness_nm: Some(vec![f32::NAN, f32::NAN]),
        ..Default::default()
    };
    let s = compute_stats(&nan);
    assert_eq!(s.non_finite_positions, 1);
    assert_eq!(s.bounds, Some((Vec3::ONE, Vec3::ONE)));
    assert!(s.thickness_nm.as_ref().unwrap().mean.is_nan());
    assert!(s.to_string().contains("2 non-finite"));
}

#[test]
fn histogram_edges() {
    let h = Histogram::of(&[0.0, 1.0, 1.0, 0.5, f32::NAN], 2);
    assert_eq!((h.lo, h.hi, h.counts.clone()), (0.0, 1.0, vec![1, 3]));
    let flat = Histogram::of(&[3.0; 7], 4);
    assert_eq!(flat.counts, vec![7, 0, 0, 0]);
    assert_eq!(Histogram::of(&[], 3).counts, vec![0, 0, 0]);
}
