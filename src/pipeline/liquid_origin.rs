//! Where the 3D particles of a thin-film SPH frame came from, for `--liquid auto`: in this
//! simulator the 3D particles that exist at the run's frame 0 are liquid the case set up (drops
//! falling onto a film: bulk liquid), while those that appear later were shed by a rupture
//! (spray droplets, drawn at the volume their stored mass holds). Positions alone cannot tell a
//! packed cloud of fresh spray from a drop; the run's first frame can. Only the count in the
//! header of frame 0's `tracker_points_3d` is read. A snapshot folder (`run/snapshot/K`) asks
//! the same run's frame 0 (`run/0`).

use std::path::{Path, PathBuf};

use super::droplets::run_first_frame;
use crate::io::frame_folder::droplet_count;
use crate::io::{CloudFormat, detect_format};

/// What the run's first frame says about the 3D particles' origin.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) enum Origin {
    /// Frame 0 (the folder) holds this many 3D particles: liquid set up by the case.
    SetUp(PathBuf, usize),
    /// Frame 0 (the folder) holds none: every 3D particle was shed later.
    Shed(PathBuf),
    /// Not known (why, for the note): the geometric rule decides.
    Unknown(String),
}

/// The origin of the 3D particles of the inputs `inputs` (paths as given, resolved): `SetUp`
/// or `Shed` only if every input is a thin-film SPH frame folder whose run's frame 0 says so;
/// a missing or unreadable frame 0, another format, or inputs that disagree give `Unknown`.
pub(super) fn origin(inputs: &[PathBuf]) -> Origin {
    let mut found: Option<Origin> = None;
    for input in inputs {
        let o = origin_of(input);
        match (&found, &o) {
            (_, Origin::Unknown(_)) => return o,
            (None, _) => found = Some(o),
            (Some(Origin::SetUp(..)), Origin::SetUp(..))
            | (Some(Origin::Shed(_)), Origin::Shed(_)) => {}
            _ => {
                return Origin::Unknown(
                    "the inputs' runs disagree on frame 0's 3D particles".into(),
                );
            }
        }
    }
    found.unwrap_or_else(|| Origin::Unknown("no input folder".into()))
}

/// The origin for one input.
fn origin_of(input: &Path) -> Origin {
    // A snapshot `run/snapshot/K` belongs to the same run as the frame folders `run/K`: the
    // run's frame 0 tells for it too (a burst's spray in a snapshot is droplets, not a body).
    if !matches!(
        detect_format(input),
        Ok(CloudFormat::FrameFolder | CloudFormat::SnapshotFolder)
    ) {
        return Origin::Unknown(format!(
            "{} is not a thin-film SPH frame or snapshot folder",
            input.display()
        ));
    }
    let Some(first) = run_first_frame(input) else {
        return Origin::Unknown(format!("{} has no parent folder", input.display()));
    };
    if !matches!(detect_format(&first), Ok(CloudFormat::FrameFolder)) {
        return Origin::Unknown(format!("no frame 0 of this run ({})", first.display()));
    }
    match droplet_count(&first) {
        Ok(0) => Origin::Shed(first),
        Ok(n) => Origin::SetUp(first, n),
        Err(e) => Origin::Unknown(format!("frame 0 unreadable ({e})")),
    }
}

/// Whether the 3D particles `drops` tell by their own data that a rupture shed them, when no
/// frame 0 tells: the simulator gives a shed droplet the thickness `rh` of the film particle
/// it came from (`Add_Particle(X, V, M, RH)` in its `FluidSPHBubble.cpp`), so no two shed
/// droplets hold the same value, while liquid a case sets up shares one (the drops falling
/// onto a film all hold 1.87e-6 m, a liquid-only run 0). True if every particle stores an `rh`
/// (or, read back from a converted PLY, a thickness) and no two are alike (compared as
/// stored, f32), with at least two particles.
pub(super) fn shed_by_thickness(drops: &[crate::pointcloud::PointCloud]) -> bool {
    let mut values = Vec::new();
    for d in drops {
        // A frame converted to PLY reads `rh` back as the droplets' thickness.
        let stored = d.extra("rh").or(d.thickness_nm.as_deref());
        let Some(rh) = stored.filter(|r| r.len() == d.len()) else {
            return false;
        };
        values.extend(rh.iter().map(|v| v.to_bits()));
    }
    values.sort_unstable();
    values.len() >= 2 && values.windows(2).all(|w| w[0] != w[1])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pointcloud::PointCloud;

    fn with_rh(rh: &[f32]) -> PointCloud {
        let mut c = PointCloud {
            positions: vec![glam::Vec3::ZERO; rh.len()],
            ..PointCloud::default()
        };
        c.extra.push(("rh".into(), rh.to_vec()));
        c
    }

    #[test]
    fn spray_carries_its_films_thicknesses_set_up_liquid_one_value() {
        assert!(shed_by_thickness(&[
            with_rh(&[4.5e-7, 7.0e-7]),
            with_rh(&[9.3e-7])
        ]));
        // Set-up liquid: one shared value (or zero), and a part without rh, tell nothing.
        assert!(!shed_by_thickness(&[with_rh(&[1.87e-6; 3])]));
        assert!(!shed_by_thickness(&[with_rh(&[4.5e-7, 7.0e-7, 4.5e-7])]));
        assert!(!shed_by_thickness(&[
            with_rh(&[4.5e-7]),
            PointCloud::default()
        ]));
        let mut no_rh = with_rh(&[1.0, 2.0]);
        no_rh.extra.clear();
        assert!(!shed_by_thickness(&[no_rh]));
    }

    #[test]
    fn a_snapshot_asks_its_runs_frame_0() {
        // run/0 a frame folder without 3D particles; run/snapshot/50 and run/50 of that run.
        let run = std::env::temp_dir().join(format!("filmsplat-origin-{}", std::process::id()));
        let touch = |p: PathBuf| {
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, [0u8; 4]).unwrap();
        };
        touch(run.join("0/x_bin"));
        touch(run.join("50/x_bin"));
        touch(run.join("snapshot/50/x.bin"));
        let first = run.join("0");
        assert_eq!(origin_of(&run.join("50")), Origin::Shed(first.clone()));
        // Before, a snapshot was "not a frame folder" and positions decided (a burst's spray
        // became a body of water 46,000 times its stored volume).
        assert_eq!(origin_of(&run.join("snapshot/50")), Origin::Shed(first));
        std::fs::remove_dir_all(&run).unwrap();
        assert!(matches!(
            origin_of(&run.join("snapshot/50")),
            Origin::Unknown(_)
        ));
    }
}
