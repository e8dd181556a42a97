//! Foams: the walls two bubbles' particle sets both hold are drawn once
//! ([`crate::pointcloud::walls`]), before the films are completed, and the user is told.

use super::prepared::Note;
use crate::io::CloudPart;
use crate::pointcloud::walls::{WallReport, merge_shared_walls};

/// Merges the walls shared by two of the film parts (a foam written one set per bubble) and
/// notes what was merged; returns the pairs of parts that shared a wall (two bubbles, never
/// pieces of one film). Parts without normals or thickness, and single films, are left alone.
pub(super) fn merge_walls(films: &mut [CloudPart], notes: &mut Vec<Note>) -> Vec<(usize, usize)> {
    if films.len() < 2 {
        return Vec::new();
    }
    let mut clouds: Vec<_> = films
        .iter_mut()
        .map(|p| std::mem::take(&mut p.cloud))
        .collect();
    let report = merge_shared_walls(&mut clouds);
    for (p, c) in films.iter_mut().zip(clouds) {
        p.cloud = c;
    }
    if !report.is_empty() {
        notes.push(Note::new(describe(&report, films)));
    }
    report.walls.iter().map(|w| (w.kept, w.removed)).collect()
}

/// "foam: N walls shared by two bubbles drawn once (…)", one line.
fn describe(report: &WallReport, films: &[CloudPart]) -> String {
    let name = |i: usize| short_name(&films[i].label, i);
    let walls: Vec<String> = report
        .walls
        .iter()
        .map(|w| {
            format!(
                "{}|{}: {} + {} particles {:.2e} apart, {:.0} | {:.0} nm -> {:.0} nm",
                name(w.kept),
                name(w.removed),
                w.kept_particles,
                w.removed_particles,
                w.gap,
                w.kept_nm,
                w.other_nm,
                w.merged_nm
            )
        })
        .collect();
    let n = report.walls.len();
    format!(
        "foam: {n} wall{} shared by two bubbles drawn once ({}; each kept midway between its two \
         copies with their area-weighted mean thickness, the second copy's particles there removed)",
        if n == 1 { "" } else { "s" },
        walls.join("; ")
    )
}

/// A part's short name: its region number for MELP's `… (region R)`, else its place.
fn short_name(label: &str, i: usize) -> String {
    label
        .rsplit_once("(region ")
        .and_then(|(_, r)| r.strip_suffix(')'))
        .map_or_else(|| format!("part {i}"), |r| format!("region {r}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_regions_or_places() {
        assert_eq!(short_name("x/50 (region 2)", 0), "region 2");
        assert_eq!(short_name("a.ply", 3), "part 3");
    }
}
