//! kNN table and spacing against brute-force oracles.

use filmsplat::pointcloud::estimate::{SPACING_SAMPLE, median_spacing, nn_distances};
use filmsplat::pointcloud::knn::{KnnTable, NO_NEIGHBOUR};
use filmsplat::samples::fibonacci_sphere;
use filmsplat::samples::rng::SplitMix64;
use glam::Vec3;

fn random_cloud(n: usize, seed: u64) -> Vec<Vec3> {
    let mut g = SplitMix64::new(seed);
    let mut v: Vec<Vec3> = (0..n)
        .map(|_| {
            Vec3::new(
                g.next_f64() as f32,
                g.next_f64() as f32,
                g.next_f64() as f32 * 0.2,
            )
        })
        .collect();
    // A few exact duplicates.
    for i in 0..20 {
        v[n - 1 - i] = v[i];
    }
    v
}

fn brute_sorted_dists(p: &[Vec3], i: usize) -> Vec<f32> {
    let mut d: Vec<f32> = (0..p.len())
        .filter(|&j| j != i)
        .map(|j| p[i].distance(p[j]))
        .collect();
    d.sort_by(f32::total_cmp);
    d
}

#[test]
fn knn_table_matches_brute_force() {
    let p = random_cloud(1500, 3);
    let k = 8;
    let t = KnnTable::build(&p, k);
    assert_eq!(t.len(), p.len());
    for i in 0..p.len() {
        let want = brute_sorted_dists(&p, i);
        let got: Vec<(u32, f32)> = t.row(i).collect();
        assert_eq!(got.len(), k);
        for (m, (j, d)) in got.iter().enumerate() {
            assert_ne!(*j as usize, i, "a particle is not its own neighbour");
            assert!((d - p[i].distance(p[*j as usize])).abs() < 1e-6);
            assert!(
                (d - want[m]).abs() <= 1e-6 * want[m].max(1e-3),
                "row {i} slot {m}"
            );
        }
    }
}

#[test]
fn knn_table_short_rows_and_non_finite() {
    let mut p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(f32::NAN, 0.0, 0.0)];
    p.push(Vec3::splat(f32::INFINITY));
    let t = KnnTable::build(&p, 8);
    assert_eq!(t.row(0).count(), 2, "only two other finite particles exist");
    assert_eq!(t.row(3).count(), 0);
    assert_eq!(t.idx[3 * 8], NO_NEIGHBOUR);
    assert!(
        t.row(1).all(|(j, _)| j < 3),
        "non-finite particles are nobody's neighbour"
    );
    assert_eq!(t.kth_distance(0, 8), Some(1.0));
}

#[test]
fn nn_distances_and_median_match_brute_force() {
    let p = random_cloud(2000, 9);
    let nn = nn_distances(&p);
    let mut positive = Vec::new();
    for (i, got) in nn.iter().enumerate() {
        let want = brute_sorted_dists(&p, i)[0];
        assert!((got - want).abs() <= 1e-6, "{i}: {got} vs {want}");
        if want > 0.0 {
            positive.push(want);
        }
    }
    assert_eq!(nn[0], 0.0, "duplicate has distance 0");
    positive.sort_by(f32::total_cmp);
    assert_eq!(median_spacing(&p), positive[positive.len() / 2]);
}

#[test]
fn median_spacing_sampled_is_close_and_matches_lattice() {
    let n = SPACING_SAMPLE * 2 + 123;
    let p = fibonacci_sphere(n, 2.0);
    let full = {
        let mut d = nn_distances(&p);
        let mid = d.len() / 2;
        *d.select_nth_unstable_by(mid, f32::total_cmp).1
    };
    let sampled = median_spacing(&p);
    assert!((sampled / full - 1.0).abs() < 0.01, "{sampled} vs {full}");
    // The Fibonacci lattice is near-hexagonal: NN spacing ≈ hex spacing of the same density.
    let hex = filmsplat::samples::fibonacci_spacing(n, 2.0);
    assert!((sampled / hex - 1.0).abs() < 0.15, "{sampled} vs {hex}");
}

#[test]
fn degenerate_inputs_do_not_panic() {
    assert_eq!(median_spacing(&[]), 0.0);
    assert_eq!(median_spacing(&[Vec3::ONE]), 0.0);
    assert_eq!(median_spacing(&[Vec3::ONE; 50]), 0.0);
    assert_eq!(nn_distances(&[Vec3::ONE]), vec![f32::INFINITY]);
}

/// The estimate asked for the radius fit's 12 neighbours on a cloud that lacks only radii
/// (which need 8): one table of 12 whose radii are those of the 8-neighbour estimate, searched
/// with an index it hands back for the fit. Fails when `min_k` is ignored (a table of 8) or the
/// index is not kept.
#[test]
fn estimate_widens_its_table_and_shares_its_index_for_the_fit() {
    use filmsplat::pointcloud::{EstimateOptions, PointCloud, fill_missing_keeping_table};
    let positions = random_cloud(3000, 5);
    let cloud = PointCloud {
        normals: Some(vec![Vec3::Z; positions.len()]),
        positions,
        thickness_nm: None,
        radius: None,
        extra: Vec::new(),
    };
    let opts = EstimateOptions::default();
    let (mut narrow, mut wide) = (cloud.clone(), cloud);
    let (_, t8) = fill_missing_keeping_table(&mut narrow, &opts, 0, &mut None);
    let mut index = None;
    let (_, t12) = fill_missing_keeping_table(&mut wide, &opts, 12, &mut index);
    assert_eq!(t8.map(|t| t.k), Some(opts.k_radius));
    let t12 = t12.expect("a table");
    assert_eq!(t12.k, 12);
    assert_eq!(narrow.radius, wide.radius);
    let index = index.expect("the index kept");
    assert_eq!(index.len(), wide.len());
    let again = KnnTable::build_with(&index, &wide.positions, 12);
    assert_eq!((again.idx, again.dist), (t12.idx, t12.dist));
}
