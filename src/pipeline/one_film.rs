//! Film parts that are pieces of one film — a frame written one file per rank or block, a
//! file cut by hand — found from the data, not from names: a part's open-edge particles (the
//! ones the radius fit cut, see `pointcloud::clip`) that lie within [`CONTACT_SPACINGS`]
//! spacings of another part's particle, on its tangent plane and with an aligned normal, are
//! a seam, not an edge. Parts joined by seams are completed again as one cloud (one neighbour
//! table, one radius fit, cuts only at the joined film's real edges) and drawn as one sheet.
//!
//! Parts that do not meet that way stay apart: closed bubbles (no open edge), a foam's bubbles
//! (their walls meet at Plateau borders at about 120°, |n·n'| ≈ 0.5), droplets (not films).

use super::prepared::Note;
use crate::Result;
use crate::io::CloudPart;
use crate::pointcloud::PointCloud;
use crate::pointcloud::cut::Cut;
use crate::pointcloud::knn::{KnnTable, PointIndex};
use crate::pointcloud::stats::median_nearest;
use glam::Vec3;

/// How near (in the part's median nearest-neighbour spacings) another part's particle lies to
/// an open-edge particle for the two to meet at a seam.
pub const CONTACT_SPACINGS: f32 = 1.5;

/// Least |n·n'| of two particles that meet at a seam (cos 25°).
pub const ALIGNED: f32 = 0.9;

/// Farthest (in spacings) the other part's particle lies off the edge particle's tangent plane.
pub const ON_PLANE: f32 = 0.5;

/// Least number of edge particles touching another part for the two to be one film: a seam
/// holds a row of them; a stray particle does not join two films.
pub const MIN_CONTACTS: usize = 3;

/// Neighbours looked at around each edge particle.
const LOOK: usize = 8;

/// One completed film part as the seam test reads it.
pub struct Piece<'a> {
    /// Positions (scene units).
    pub positions: &'a [Vec3],
    /// Unit normals, one a particle (sign ignored); empty: the part joins nothing.
    pub normals: &'a [Vec3],
    /// The fit's verdicts, one a particle (see `pointcloud::cut`); empty: not fitted, so no
    /// edge is known and the part joins nothing.
    pub cuts: &'a [Cut],
    /// The part's median nearest-neighbour distance (scene units).
    pub spacing: f32,
}

impl Piece<'_> {
    /// Whether particle `i` is on an open edge of its part.
    fn on_edge(&self, i: usize) -> bool {
        self.normals.len() == self.positions.len() && self.cuts.get(i).is_some_and(Cut::cuts)
    }
}

/// One film part made ready to draw (by `load::complete`), with the notes that gave.
pub(super) struct Ready {
    /// The particles, complete.
    pub cloud: PointCloud,
    /// The neighbour table built for the estimate or the fit, if any.
    pub table: Option<KnnTable>,
    /// The part came with its radii.
    pub had_radius: bool,
    /// The fit's verdicts, one a particle (empty: not fitted).
    pub cuts: Vec<Cut>,
    /// Its radii were kept on a sample's word (see `load::fit`).
    pub screened: bool,
    /// What completing it said, in order.
    pub notes: Vec<Note>,
}

/// The parts grouped into films ([`group`]: open edges that meet another part's film are
/// seams); each group of several parts completed again from `originals` (the parts as read,
/// in the order of `ready`) by `complete` as one cloud, and said in a note.
pub(super) fn join_seams(
    ready: Vec<Ready>,
    originals: Vec<CloudPart>,
    bubbles: &[(usize, usize)],
    mut complete: impl FnMut(CloudPart, &mut Vec<Note>) -> Result<Ready>,
) -> Result<Vec<Ready>> {
    if ready.len() < 2 {
        return Ok(ready);
    }
    let pieces: Vec<Piece> = ready
        .iter()
        .map(|r| Piece {
            positions: &r.cloud.positions,
            normals: r.cloud.normals.as_deref().unwrap_or_default(),
            cuts: &r.cuts,
            spacing: r.table.as_ref().map_or(0.0, median_nearest),
        })
        .collect();
    let groups = group(&pieces, bubbles);
    if groups.len() == ready.len() {
        return Ok(ready);
    }
    let mut ready: Vec<Option<Ready>> = ready.into_iter().map(Some).collect();
    let mut originals: Vec<Option<CloudPart>> = originals.into_iter().map(Some).collect();
    let mut out = Vec::with_capacity(groups.len());
    for g in groups {
        if let [i] = g[..] {
            out.extend(ready[i].take());
            continue;
        }
        let parts: Vec<CloudPart> = g.iter().filter_map(|&i| originals[i].take()).collect();
        let labels: Vec<&str> = parts.iter().map(|p| p.label.as_str()).collect();
        let label = joined_label(&labels);
        let clouds: Vec<PointCloud> = parts.into_iter().map(|p| p.cloud).collect();
        let mut own = vec![Note::new(format!(
            "{label}: {} film parts hold one film (open edges of one within {} spacings of \
             another's particles, on its tangent plane): fitted as one sheet",
            g.len(),
            CONTACT_SPACINGS
        ))];
        let whole = CloudPart::film(label, PointCloud::concat(&clouds), Vec::new());
        let mut joined = complete(whole, &mut own)?;
        joined.notes = own;
        out.push(joined);
    }
    Ok(out)
}

/// The labels of parts joined into one film: all of them up to three, else the first two
/// and how many more.
fn joined_label(labels: &[&str]) -> String {
    match labels {
        [a, b, _, _, ..] => format!("{a} + {b} + {} more", labels.len() - 2),
        _ => labels.join(" + "),
    }
}

/// The parts grouped into films: each group (part indices ascending; groups ordered by their
/// first part) holds the parts joined by seams, directly or through others. Parts paired in
/// `bubbles` share a foam wall (`pointcloud::walls`): two bubbles, whose walls' rims lie on each
/// other's film where the copies part, never joined. Cost: one index over every particle,
/// [`LOOK`] neighbours searched per edge particle.
pub fn group(pieces: &[Piece], bubbles: &[(usize, usize)]) -> Vec<Vec<usize>> {
    let n = pieces.len();
    let mut parent: Vec<usize> = (0..n).collect();
    if n > 1 {
        for ((a, b), count) in contacts(pieces) {
            let wall = bubbles.contains(&(a, b)) || bubbles.contains(&(b, a));
            if count >= MIN_CONTACTS && !wall {
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut slot = vec![usize::MAX; n];
    for i in 0..n {
        let r = root(&mut parent, i);
        if slot[r] == usize::MAX {
            slot[r] = groups.len();
            groups.push(Vec::new());
        }
        groups[slot[r]].push(i);
    }
    groups
}

/// The root of `i` in the union–find forest `parent` (paths halved on the way).
fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// For each pair of parts (a < b), how many edge particles of either meet the other.
fn contacts(pieces: &[Piece]) -> Vec<((usize, usize), usize)> {
    let starts: Vec<usize> = pieces
        .iter()
        .scan(0, |s, p| {
            let start = *s;
            *s += p.positions.len();
            Some(start)
        })
        .collect();
    let all: Vec<Vec3> = pieces
        .iter()
        .flat_map(|p| p.positions.iter().copied())
        .collect();
    let index = PointIndex::build(&all);
    let locate = |g: usize| {
        let part = starts.partition_point(|&s| s <= g) - 1;
        (part, g - starts[part])
    };
    let mut pairs: Vec<((usize, usize), usize)> = Vec::new();
    for (a, piece) in pieces.iter().enumerate() {
        let reach = CONTACT_SPACINGS * piece.spacing;
        for i in (0..piece.positions.len()).filter(|&i| piece.on_edge(i)) {
            let (p, n) = (piece.positions[i], piece.normals[i]);
            let mut met: Vec<usize> = Vec::new();
            for (g, d) in index.nearest_excluding(p, LOOK, (starts[a] + i) as u32) {
                let (b, j) = locate(g as usize);
                let other = &pieces[b];
                if b == a || d > reach || met.contains(&b) || other.normals.len() <= j {
                    continue;
                }
                let q = other.positions[j];
                if n.dot(other.normals[j]).abs() >= ALIGNED
                    && n.dot(q - p).abs() <= ON_PLANE * piece.spacing
                {
                    met.push(b);
                }
            }
            for b in met {
                let key = (a.min(b), a.max(b));
                match pairs.iter_mut().find(|(k, _)| *k == key) {
                    Some((_, c)) => *c += 1,
                    None => pairs.push((key, 1)),
                }
            }
        }
    }
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    /// A flat grid of `w`×`h` particles at spacing 1 starting at x = `x0` in the plane
    /// z = `z`, with normal `n`; the particles in the columns listed in `edge_cols` are cut.
    fn grid(x0: f32, z: f32, w: usize, h: usize, edge_cols: &[usize]) -> (Vec<Vec3>, Vec<Cut>) {
        let cut = Cut::Edge([Vec4::new(1.0, 0.0, 0.0, 0.5), Vec4::new(0.0, 1.0, 0.0, 0.5)]);
        let mut pos = Vec::new();
        let mut cuts = Vec::new();
        for c in 0..w {
            for r in 0..h {
                pos.push(Vec3::new(x0 + c as f32, r as f32, z));
                cuts.push(if edge_cols.contains(&c) {
                    cut
                } else {
                    Cut::None
                });
            }
        }
        (pos, cuts)
    }

    fn piece<'a>(p: &'a [Vec3], n: &'a [Vec3], c: &'a [Cut]) -> Piece<'a> {
        Piece {
            positions: p,
            normals: n,
            cuts: c,
            spacing: 1.0,
        }
    }

    #[test]
    fn halves_of_one_sheet_join_and_parallel_sheets_do_not() {
        // Two halves of one plane cut at x = 4.5 (edge columns on both sides of the cut), and
        // a third sheet one spacing above, parallel (a foam's second wall copy): within reach
        // but off the tangent plane.
        let (pa, ca) = grid(0.0, 0.0, 5, 6, &[0, 4]);
        let (pb, cb) = grid(5.0, 0.0, 5, 6, &[0, 4]);
        let (pc, cc) = grid(0.0, 1.0, 10, 6, &[0, 9]);
        let n = vec![Vec3::Z; 30];
        let nc = vec![Vec3::Z; 60];
        let pieces = [
            piece(&pa, &n, &ca),
            piece(&pb, &n, &cb),
            piece(&pc, &nc, &cc),
        ];
        assert_eq!(group(&pieces, &[]), vec![vec![0, 1], vec![2]]);
        // Two bubbles that shared a foam wall are never one film, however their rims meet.
        assert_eq!(group(&pieces, &[(1, 0)]), vec![vec![0], vec![1], vec![2]]);
    }

    #[test]
    fn edges_meeting_at_an_angle_or_far_apart_stay_apart() {
        // Same halves, the second turned edge-on (normal along x: a Plateau border's angle).
        let (pa, ca) = grid(0.0, 0.0, 5, 6, &[0, 4]);
        let (pb, cb) = grid(5.0, 0.0, 5, 6, &[0, 4]);
        let (na, nb) = (vec![Vec3::Z; 30], vec![Vec3::X; 30]);
        assert_eq!(
            group(&[piece(&pa, &na, &ca), piece(&pb, &nb, &cb)], &[]),
            vec![vec![0], vec![1]]
        );
        // Aligned but three spacings apart: two films.
        let (pc, cc) = grid(7.0, 0.0, 5, 6, &[0, 4]);
        assert_eq!(
            group(&[piece(&pa, &na, &ca), piece(&pc, &na, &cc)], &[]),
            vec![vec![0], vec![1]]
        );
        // Touching, aligned, but no edge known (not fitted): apart.
        assert_eq!(
            group(&[piece(&pa, &na, &[]), piece(&pb, &na, &[])], &[]),
            vec![vec![0], vec![1]]
        );
    }

    #[test]
    fn chains_join_through_a_middle_part() {
        let (pa, ca) = grid(0.0, 0.0, 3, 6, &[0, 2]);
        let (pb, cb) = grid(3.0, 0.0, 3, 6, &[0, 2]);
        let (pc, cc) = grid(6.0, 0.0, 3, 6, &[0, 2]);
        let n = vec![Vec3::Z; 18];
        // Listed out of order: the far parts first.
        let pieces = [
            piece(&pc, &n, &cc),
            piece(&pa, &n, &ca),
            piece(&pb, &n, &cb),
        ];
        assert_eq!(group(&pieces, &[]), vec![vec![0, 1, 2]]);
    }
}
