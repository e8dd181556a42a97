//! Motion blur over a sequence: every frame's velocities checked before the first frame
//! renders (a NaN velocity in frame 200 fails at once, not after 199 frames of a movie).
//!
//! Cost: each frame's input is read once more, one frame at a time (its particles are
//! dropped before the next is read: memory as one frame's read), and its velocities scanned;
//! no estimate, geometry or render. An input that several frames share (a turntable's still
//! cloud) is read once.

use std::collections::HashSet;
use std::path::PathBuf;

use super::load::load_parts;
use super::motion::{stored_velocities, velocities};
use crate::io::PartKind;
use crate::scene::SceneDesc;
use crate::{Error, Result};

/// With an open shutter (`render.shutter` > 0 in frame `frames[0]`'s scene), reads every
/// frame of `frames` (`scene(f)`: frame `f`'s scene description and the folder its paths are
/// relative to) and checks its velocities as a render would: the films must hold one (velocity,
/// v or V), and no film or droplet particle a non-finite one. Nothing is read with the shutter
/// closed.
///
/// # Errors
/// The first frame's read error or bad velocity, as `frame F: FILE: particle I has a
/// non-finite velocity ...` (or the attributes the films hold when they have no velocity).
pub fn check_frames(
    frames: &[u64],
    scene: impl Fn(u64) -> Result<(SceneDesc, PathBuf)>,
) -> Result<()> {
    let Some(&first) = frames.first() else {
        return Ok(());
    };
    let (desc, _) = scene(first)?;
    if desc.render.shutter.unwrap_or(0.0) <= 0.0 {
        return Ok(());
    }
    // A still cloud (a turntable's every frame) is read and checked once.
    let mut checked: HashSet<Vec<PathBuf>> = HashSet::new();
    for &f in frames {
        let (desc, base) = scene(f)?;
        let inputs: Vec<PathBuf> = desc.input.paths().iter().map(|p| base.join(p)).collect();
        if !inputs.is_empty() && checked.contains(&inputs) {
            continue;
        }
        check_frame(&desc, &base).map_err(|e| Error::invalid(format!("frame {f}: {e}")))?;
        checked.insert(inputs);
    }
    Ok(())
}

/// One frame's velocities (see [`check_frames`]).
fn check_frame(desc: &SceneDesc, base: &std::path::Path) -> Result<()> {
    let parts = load_parts(desc, base)?;
    for part in &parts {
        match part.kind {
            PartKind::Film if !part.cloud.is_empty() => {
                velocities(&part.cloud, &part.label)?;
            }
            _ => {
                stored_velocities(&part.cloud, &part.label)?;
            }
        }
    }
    Ok(())
}
