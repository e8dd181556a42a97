//! Consistent orientation of unoriented (PCA) normals.
//!
//! Two strategies, chosen automatically by [`orient_normals`]:
//! * **Radial** — when the cloud is *star-shaped about its centroid* c (at least 95 % of the
//!   normals make |n·(p−c)/|p−c|| ≥ 0.3, as on a bubble, an ellipsoid or a dome), each normal is
//!   flipped to agree with p − c: outward, and per point, so noise never propagates. Points where
//!   the radial test is ambiguous take their sign from already-oriented neighbours.
//! * **Propagated** — otherwise (open films, saddles, tori, clusters), signs propagate over the
//!   symmetrised kNN graph along a minimum spanning tree with edge weight 1 − |nᵢ·nⱼ|
//!   (Hoppe et al. 1992, "Surface reconstruction from unorganized points"), so the sign is
//!   carried across the flattest paths first. Each connected component is seeded at its highest
//!   point with n·ẑ ≥ 0 (Hoppe's convention); afterwards the component is flipped if
//!   Σ n·(p − c) < −0.1·Σ|p − c| — by the divergence theorem Σ n·(p − c)·ΔA = 3·volume > 0 for
//!   an outward-oriented closed surface. (The seed already faces outward on a closed surface,
//!   whose top point faces up; the check guards against a noisy seed and turns open caps and
//!   bowls to their convex side, while flat or saddle-like sheets (sum ≈ 0) keep the seed's
//!   convention.)

use super::knn::KnnTable;
use glam::{DVec3, Vec3};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// How a set of normals was oriented.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Orientation {
    /// Outward from the centroid, per point (star-shaped cloud).
    Radial,
    /// Propagated over the kNN minimum spanning tree; `components` independent pieces.
    Propagated {
        /// Number of connected components of the kNN graph (each oriented separately).
        components: usize,
    },
    /// Signs taken from neighbouring normals that were already known (partial re-estimation).
    FromNeighbours,
    /// Nothing to orient (no valid normal).
    None,
}

impl std::fmt::Display for Orientation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Orientation::Radial => write!(f, "outward from the centroid (star-shaped cloud)"),
            Orientation::Propagated { components } => write!(
                f,
                "propagated over the kNN spanning tree ({components} component{})",
                if *components == 1 { "" } else { "s" }
            ),
            Orientation::FromNeighbours => write!(f, "agreeing with neighbouring input normals"),
            Orientation::None => write!(f, "none"),
        }
    }
}

/// Centroid of the finite positions (f64 accumulation); `None` if there is none.
pub(crate) fn centroid(positions: &[Vec3]) -> Option<Vec3> {
    let (sum, n) = positions
        .iter()
        .filter(|p| p.is_finite())
        .fold((DVec3::ZERO, 0usize), |(s, n), p| (s + p.as_dvec3(), n + 1));
    (n > 0).then(|| (sum / n as f64).as_vec3())
}

/// Orients `normals[i]` for every `valid[i]` (unit normals) in place; invalid entries untouched.
pub fn orient_normals(
    positions: &[Vec3],
    table: &KnnTable,
    normals: &mut [Vec3],
    valid: &[bool],
) -> Orientation {
    let Some(c) = centroid(positions) else {
        return Orientation::None;
    };
    let (mut total, mut confident) = (0usize, 0usize);
    for i in 0..normals.len() {
        if valid[i] {
            total += 1;
            if let Some(r) = (positions[i] - c).try_normalize() {
                confident += usize::from(normals[i].dot(r).abs() >= RADIAL_CONFIDENCE);
            }
        }
    }
    if total == 0 {
        return Orientation::None;
    }
    if confident as f64 >= 0.95 * total as f64 {
        let mut resolved = vec![false; normals.len()];
        for i in 0..normals.len() {
            if !valid[i] {
                continue;
            }
            if let Some(r) = (positions[i] - c).try_normalize() {
                let d = normals[i].dot(r);
                if d.abs() >= RADIAL_CONFIDENCE {
                    if d < 0.0 {
                        normals[i] = -normals[i];
                    }
                    resolved[i] = true;
                }
            }
        }
        propagate_signs(table, normals, valid, &mut resolved, |i| positions[i] - c);
        Orientation::Radial
    } else {
        let components = mst_orient(positions, table, normals, valid);
        Orientation::Propagated { components }
    }
}

/// |n·r̂| below which the radial direction says little about a normal's sign.
const RADIAL_CONFIDENCE: f32 = 0.3;

/// Gives every `valid && !resolved` normal the sign that agrees with its resolved neighbours
/// (Σ nᵢ·nⱼ ≥ 0), sweeping repeatedly so signs spread along chains; normals that no resolved
/// neighbour reaches agree with `fallback(i)`. `resolved` (initially: the normals whose sign
/// is trusted) is updated in place.
pub(crate) fn propagate_signs(
    table: &KnnTable,
    normals: &mut [Vec3],
    valid: &[bool],
    resolved: &mut [bool],
    fallback: impl Fn(usize) -> Vec3,
) {
    let mut pending: Vec<usize> = (0..normals.len())
        .filter(|&i| valid[i] && !resolved[i])
        .collect();
    while !pending.is_empty() {
        let before = pending.len();
        pending.retain(|&i| {
            let mut vote = 0.0f32;
            let mut any = false;
            for (j, _) in table.row(i) {
                let j = j as usize;
                if resolved[j] {
                    vote += normals[i].dot(normals[j]);
                    any = true;
                }
            }
            if !any {
                return true;
            }
            if vote < 0.0 {
                normals[i] = -normals[i];
            }
            resolved[i] = true;
            false
        });
        if pending.len() == before {
            break;
        }
    }
    for i in pending {
        if normals[i].dot(fallback(i)) < 0.0 {
            normals[i] = -normals[i];
        }
        resolved[i] = true;
    }
}

/// Symmetrised kNN adjacency in CSR form over valid nodes only.
fn symmetric_graph(table: &KnnTable, valid: &[bool]) -> (Vec<usize>, Vec<u32>) {
    let n = valid.len();
    let mut deg = vec![0usize; n + 1];
    for i in 0..n {
        if !valid[i] {
            continue;
        }
        for (j, _) in table.row(i) {
            if valid[j as usize] {
                deg[i] += 1;
                deg[j as usize] += 1;
            }
        }
    }
    let mut start = vec![0usize; n + 1];
    for i in 0..n {
        start[i + 1] = start[i] + deg[i];
    }
    let mut fill = start.clone();
    let mut adj = vec![0u32; start[n]];
    for i in 0..n {
        if !valid[i] {
            continue;
        }
        for (j, _) in table.row(i) {
            if valid[j as usize] {
                adj[fill[i]] = j;
                fill[i] += 1;
                adj[fill[j as usize]] = i as u32;
                fill[j as usize] += 1;
            }
        }
    }
    (start, adj)
}

/// Prim's MST over the Riemannian graph, flipping signs along tree edges. Returns the number of
/// components. A node is pushed only when its best edge weight improves (lazy decrease-key),
/// with (weight, node) packed in one u64. Cost: O(n·k·log n) time, ~12·k bytes a particle;
/// single-threaded.
fn mst_orient(positions: &[Vec3], table: &KnnTable, normals: &mut [Vec3], valid: &[bool]) -> usize {
    let n = normals.len();
    let (start, adj) = symmetric_graph(table, valid);
    let mut seeds: Vec<usize> = (0..n).filter(|&i| valid[i]).collect();
    seeds.sort_by(|&a, &b| positions[b].z.total_cmp(&positions[a].z));
    let mut done = vec![false; n];
    let mut best = vec![f32::INFINITY; n];
    let mut parent = vec![0u32; n];
    let mut heap: BinaryHeap<Reverse<u64>> = BinaryHeap::new();
    let mut members: Vec<usize> = Vec::new();
    let mut components = 0;
    for seed in seeds {
        if done[seed] {
            continue;
        }
        components += 1;
        if normals[seed].z < 0.0 {
            normals[seed] = -normals[seed];
        }
        members.clear();
        parent[seed] = seed as u32;
        best[seed] = 0.0;
        heap.push(Reverse(seed as u64));
        while let Some(Reverse(key)) = heap.pop() {
            let node = (key & 0xFFFF_FFFF) as usize;
            if done[node] {
                continue;
            }
            done[node] = true;
            members.push(node);
            if normals[node].dot(normals[parent[node] as usize]) < 0.0 {
                normals[node] = -normals[node];
            }
            let nn = normals[node];
            for &j in &adj[start[node]..start[node + 1]] {
                let ju = j as usize;
                if done[ju] {
                    continue;
                }
                let w = (1.0 - nn.dot(normals[ju]).abs()).max(0.0);
                if w < best[ju] {
                    best[ju] = w;
                    parent[ju] = node as u32;
                    heap.push(Reverse(((w.to_bits() as u64) << 32) | j as u64));
                }
            }
        }
        // Divergence-theorem check: closed surfaces end up outward.
        let c = members
            .iter()
            .fold(DVec3::ZERO, |s, &i| s + positions[i].as_dvec3())
            / members.len() as f64;
        let (mut flux, mut size) = (0.0f64, 0.0f64);
        for &i in &members {
            let d = positions[i].as_dvec3() - c;
            flux += normals[i].as_dvec3().dot(d);
            size += d.length();
        }
        if flux < -0.1 * size {
            for &i in &members {
                normals[i] = -normals[i];
            }
        }
    }
    components
}
