//! validate() refuses each bad case with the right count and first index; repair() fixes what
//! it can; fill_missing() completes the cloud.

use filmsplat::Error;
use filmsplat::pointcloud::PointCloud;
use filmsplat::pointcloud::estimate::{EstimateOptions, fill_missing};
use filmsplat::pointcloud::orient::Orientation;
use filmsplat::pointcloud::validate::{problems, repair, validate};
use filmsplat::samples::fibonacci_sphere;
use glam::Vec3;

fn good(n: usize) -> PointCloud {
    let positions = fibonacci_sphere(n, 1.0);
    PointCloud {
        normals: Some(positions.clone()),
        thickness_nm: Some((0..n).map(|i| 100.0 + i as f32).collect()),
        radius: Some(vec![0.05; n]),
        extra: vec![("density".into(), (0..n).map(|i| i as f32).collect())],
        positions,
    }
}

fn message(cloud: &PointCloud) -> String {
    match validate(cloud) {
        Err(Error::Invalid(m)) => m,
        other => panic!("expected Invalid, got {other:?}"),
    }
}

#[test]
fn good_cloud_passes() {
    assert!(validate(&good(100)).is_ok());
    let bare = PointCloud {
        positions: vec![Vec3::ONE],
        ..Default::default()
    };
    assert!(validate(&bare).is_ok());
}

#[test]
fn empty_cloud_is_refused() {
    assert_eq!(
        message(&PointCloud::default()),
        "point cloud is empty (0 particles)"
    );
}

type Breaker = Box<dyn Fn(&mut PointCloud)>;

#[test]
fn each_bad_case_is_counted_with_its_first_index() {
    let cases: Vec<(Breaker, &str)> = vec![
        (
            Box::new(|c| {
                for i in [17, 40, 99] {
                    c.positions[i].y = f32::NAN;
                }
                c.positions[40] = Vec3::splat(f32::INFINITY);
            }),
            "3 particles have non-finite positions (first: index 17)",
        ),
        (
            Box::new(|c| c.normals.as_mut().unwrap()[5] = Vec3::new(0.0, f32::NAN, 0.0)),
            "1 particle has non-finite normals (first: index 5)",
        ),
        (
            Box::new(|c| {
                c.normals.as_mut().unwrap()[8] = Vec3::ZERO;
                c.normals.as_mut().unwrap()[3] = Vec3::ZERO;
            }),
            "2 particles have zero-length normals (first: index 3)",
        ),
        (
            Box::new(|c| {
                c.thickness_nm.as_mut().unwrap()[0] = -1.0;
                c.thickness_nm.as_mut().unwrap()[50] = -0.001;
            }),
            "2 particles have negative thickness (first: index 0)",
        ),
        (
            Box::new(|c| c.thickness_nm.as_mut().unwrap()[60] = f32::INFINITY),
            "1 particle has non-finite thickness (first: index 60)",
        ),
        (
            Box::new(|c| c.radius.as_mut().unwrap()[7] = f32::NAN),
            "1 particle has non-finite radius (first: index 7)",
        ),
        (
            Box::new(|c| {
                c.radius.as_mut().unwrap()[9] = 0.0;
                c.radius.as_mut().unwrap()[90] = -2.0;
            }),
            "2 particles have zero or negative radius (first: index 9)",
        ),
        (
            Box::new(|c| c.thickness_nm.as_mut().unwrap().pop().map(|_| ()).unwrap()),
            "attribute 'thickness' has 99 entries for 100 particles",
        ),
        (
            Box::new(|c| c.extra[0].1.push(1.0)),
            "attribute 'density' has 101 entries for 100 particles",
        ),
    ];
    for (break_it, want) in cases {
        let mut c = good(100);
        break_it(&mut c);
        assert_eq!(message(&c), want);
        assert!(!want.contains('\n'));
    }
}

#[test]
fn several_problems_in_one_line() {
    let mut c = good(100);
    c.positions[4] = Vec3::NAN;
    c.thickness_nm.as_mut().unwrap()[2] = -5.0;
    let m = message(&c);
    assert_eq!(
        m,
        "1 particle has non-finite positions (first: index 4); \
         1 particle has negative thickness (first: index 2)"
    );
    assert_eq!(problems(&c).len(), 2);
}

#[test]
fn repair_drops_bad_particles_and_marks_bad_normals_and_radii() {
    let mut c = good(100);
    c.positions[10] = Vec3::NAN;
    c.positions[20] = Vec3::NAN;
    c.thickness_nm.as_mut().unwrap()[30] = -1.0;
    c.thickness_nm.as_mut().unwrap()[10] = f32::NAN; // same particle as a bad position
    c.normals.as_mut().unwrap()[40] = Vec3::ZERO;
    c.normals.as_mut().unwrap()[41] = Vec3::splat(f32::NAN);
    c.radius.as_mut().unwrap()[50] = -1.0;
    let r = repair(&mut c);
    assert_eq!(
        (r.before, r.dropped_position, r.dropped_thickness, r.after()),
        (100, 2, 1, 97)
    );
    assert_eq!((r.normals_reset, r.radii_reset), (2, 1));
    assert!(r.to_string().contains("97 of 100 particles kept"), "{r}");
    assert_eq!(c.len(), 97);
    // Order kept, every attribute compacted alike: extra "density" holds the original index.
    let density = c.extra("density").unwrap();
    let kept: Vec<usize> = (0..100).filter(|i| ![10, 20, 30].contains(i)).collect();
    for (new, &old) in kept.iter().enumerate() {
        assert_eq!(density[new], old as f32);
        assert_eq!(c.thickness_nm.as_ref().unwrap()[new], 100.0 + old as f32);
    }
    // Normals/radii marked for re-estimation: still invalid until fill_missing.
    assert!(validate(&c).is_err());
    let report = fill_missing(&mut c, &EstimateOptions::default());
    assert_eq!(
        (
            report.normals_estimated,
            report.radii_estimated,
            report.thickness_filled
        ),
        (2, 1, 0)
    );
    assert_eq!(report.orientation, Some(Orientation::FromNeighbours));
    validate(&c).unwrap();
    for (p, n) in c.positions.iter().zip(c.normals.as_ref().unwrap()) {
        assert!(
            n.dot(p.normalize()) > 0.95,
            "re-estimated normal agrees with its neighbours"
        );
    }
}

#[test]
fn repair_of_a_clean_cloud_changes_nothing() {
    let mut c = good(50);
    let before = c.clone();
    let r = repair(&mut c);
    assert!(r.is_clean());
    assert_eq!(c.positions, before.positions);
    assert_eq!(c.thickness_nm, before.thickness_nm);
}

#[test]
fn fill_missing_on_bare_positions() {
    let n = 5000;
    let mut c = PointCloud {
        positions: fibonacci_sphere(n, 2.0),
        ..Default::default()
    };
    let opts = EstimateOptions {
        default_thickness_nm: 321.0,
        ..Default::default()
    };
    let report = fill_missing(&mut c, &opts);
    assert_eq!(report.normals_estimated, n);
    assert_eq!(report.radii_estimated, n);
    assert_eq!(report.thickness_filled, n);
    assert_eq!(report.orientation, Some(Orientation::Radial));
    assert!(report.median_spacing.unwrap() > 0.0);
    validate(&c).unwrap();
    assert!(c.thickness_nm.as_ref().unwrap().iter().all(|&t| t == 321.0));
    for (p, m) in c.positions.iter().zip(c.normals.as_ref().unwrap()) {
        assert!(m.dot(p.normalize()) > 0.999);
    }
    // A second pass has nothing to do.
    let again = fill_missing(&mut c, &opts);
    assert_eq!(
        again.normals_estimated + again.radii_estimated + again.thickness_filled,
        0
    );
    assert_eq!(again.normals_normalised, 0);
    assert!(again.to_string().contains("nothing to fill"));
}

#[test]
fn fill_missing_keeps_input_signs_and_normalises() {
    let n = 3000;
    let positions = fibonacci_sphere(n, 1.0);
    // Inward normals of length 2, some zero: re-estimated ones must follow the inward sign.
    let mut normals: Vec<Vec3> = positions.iter().map(|p| -*p * 2.0).collect();
    for i in (0..n).step_by(97) {
        normals[i] = Vec3::ZERO;
    }
    let zeros = n.div_ceil(97);
    let mut c = PointCloud {
        positions,
        normals: Some(normals),
        ..Default::default()
    };
    let report = fill_missing(&mut c, &EstimateOptions::default());
    assert_eq!(report.normals_estimated, zeros);
    assert_eq!(report.normals_normalised, n - zeros);
    for (p, m) in c.positions.iter().zip(c.normals.as_ref().unwrap()) {
        assert!((m.length() - 1.0).abs() < 1e-5);
        assert!(m.dot(-p.normalize()) > 0.99);
    }
}

#[test]
fn fill_missing_replaces_wrong_length_attributes() {
    let mut c = good(200);
    c.normals.as_mut().unwrap().truncate(10);
    let report = fill_missing(&mut c, &EstimateOptions::default());
    assert_eq!(report.normals_estimated, 200);
    assert_eq!(report.notes.len(), 1);
    validate(&c).unwrap();
}
