//! The radius fit's middle look ([`SecondLook::WhereItCanChange`], opt-in: particles whose
//! 12-neighbour hull bounds their verdict are looked at among 24 neighbours first, and only
//! those still bounded among 64) fits the same radii, bit for bit, and the same edge cuts and
//! counts as the default ([`SecondLook::Bounded`]: all of them among 64), on the sample
//! bubble and half bubble and on the real film frames in tests/data, edges, holes and
//! droplets included.

use std::path::{Path, PathBuf};

use filmsplat::io::PartKind;
use filmsplat::pipeline::load_parts;
use filmsplat::pointcloud::dedupe::drop_coincident;
use filmsplat::pointcloud::gaps::{
    FAN_NEIGHBOURS, GapReport, SecondLook, bound_by_area, fit_radii_looking, own_radii,
};
use filmsplat::pointcloud::knn::{KnnTable, PointIndex};
use filmsplat::pointcloud::{EstimateOptions, PointCloud, fill_missing};
use filmsplat::samples::{SampleKind, SampleParams};
use filmsplat::scene::SceneDesc;

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

/// Both rules on one film cloud, prepared as `render` prepares it; returns (before, new).
fn both_rules(mut cloud: PointCloud, label: &str) -> (GapReport, GapReport) {
    drop_coincident(&mut cloud);
    fill_missing(&mut cloud, &EstimateOptions::default());
    let own = own_radii(&cloud);
    let mut radii = cloud.radius.clone().expect("radii estimated");
    bound_by_area(&mut radii, &own);
    let normals = cloud.normals.clone().expect("normals estimated");
    let index = PointIndex::build(&cloud.positions);
    let table = KnnTable::build_with(&index, &cloud.positions, FAN_NEIGHBOURS);
    let fit = |look| {
        let mut r = radii.clone();
        let (report, clips) = fit_radii_looking(
            &index,
            &cloud.positions,
            &normals,
            &mut r,
            Some(&table),
            &own,
            look,
        );
        (r, clips, report)
    };
    let (r0, c0, before) = fit(SecondLook::Bounded);
    let (r1, c1, new) = fit(SecondLook::WhereItCanChange);
    let differ: Vec<usize> = (0..r0.len())
        .filter(|&i| r0[i].to_bits() != r1[i].to_bits() || c0[i] != c1[i])
        .collect();
    assert!(
        differ.is_empty(),
        "{label}: {} of {} particles fitted differently, e.g. {:?}: {:?} vs {:?}",
        differ.len(),
        r0.len(),
        &differ[..differ.len().min(5)],
        differ.iter().take(5).map(|&i| r0[i]).collect::<Vec<_>>(),
        differ.iter().take(5).map(|&i| r1[i]).collect::<Vec<_>>(),
    );
    let counts = |g: &GapReport| (g.grown, g.trimmed, g.edge);
    assert_eq!(counts(&before), counts(&new), "{label}");
    eprintln!("{label}: before {before:?}, new {new:?}");
    (before, new)
}

fn sample(name: &str, particles: usize) -> PointCloud {
    let p = SampleParams {
        particles,
        ..SampleParams::default()
    };
    SampleKind::from_name(name).unwrap().generate(&p)
}

#[test]
fn the_sample_bubble_settles_among_24_what_it_settled_among_64() {
    let (before, new) = both_rules(sample("bubble", 200_000), "bubble");
    // A third of the Fibonacci sphere's particles have a first-ring neighbour on their
    // 12-neighbour hull; all of them are settled by the middle look.
    assert!(before.wide_looks > 50_000, "{before:?}");
    assert_eq!(new.middle_looks, before.wide_looks, "{new:?}");
    assert_eq!(new.wide_looks, 0, "{new:?}");
    let (_, new) = both_rules(sample("half-bubble", 50_000), "half bubble");
    // The half bubble's rim still takes the wide look.
    assert!(new.edge > 0 && new.wide_looks > 0, "{new:?}");
}

#[test]
fn real_frames_fit_as_before() {
    for input in [
        "thin-film-sph/bursting_bubble/60",
        "thin-film-sph/bursting_bubble/100",
        "thin-film-sph/catenoid/45",
        "melp/bubble/l_particles_0100.vtp",
        "melp/foam3/50",
        // Not "double_dam_break_frame_26_4732_particles.vtk" (a 3D liquid cloud drawn as
        // film): there 8 of 4732 particles get a larger radius from the middle look (e.g.
        // particle 326: 0.0552 among 64, 0.0671 among 24), which is why it is not the default.
    ] {
        let mut desc = SceneDesc::default();
        desc.input.cloud = Some(data(input));
        let parts = load_parts(&desc, Path::new("")).unwrap();
        let mut films = 0;
        for part in parts.into_iter().filter(|p| p.kind == PartKind::Film) {
            films += 1;
            both_rules(part.cloud, input);
        }
        assert!(films > 0, "{input}");
    }
}
