//! Where the 3D particles of a thin-film SPH frame came from, for `--liquid auto`: in this
//! simulator the 3D particles that exist at the run's frame 0 are liquid the case set up (drops
//! falling onto a film: bulk liquid), while those that appear later were shed by a rupture
//! (spray droplets, drawn at the volume their stored mass holds). Positions alone cannot tell a
//! packed cloud of fresh spray from a drop; the run's first frame can. Only the count in the
//! header of frame 0's `tracker_points_3d` is read.

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
    if !matches!(detect_format(input), Ok(CloudFormat::FrameFolder)) {
        return Origin::Unknown(format!(
            "{} is not a thin-film SPH frame folder",
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
