//! Droplet size, decided the same way in every frame of a run: the droplets a reader gives
//! (positions and what their files hold) get the radius of a water sphere of the volume the
//! simulator stored for them ([`crate::pointcloud::droplet_size`]).
//!
//! In this order, the first that holds a volume:
//! 1. the droplets' own stored masses (a snapshot's `3d/m.bin`): each droplet its own sphere;
//! 2. the run's first frame `0` (beside a frame folder; `snapshot/K` → the run's folder): the
//!    film particles' median `SA·H` (a film particle becomes a droplet of its mass);
//! 3. this input's own film parts (`SA·H`, or mass `m` over ρ);
//! 4. the run's snapshots (`snapshot/K/`, lowest K first): their film's `SA·H` or `m / ρ`;
//! 5. up to [`EARLIER_FRAMES`] frames before this one (`K−1`, `K−2`, ...);
//! 6. else half the droplets' median spacing, with a warning that no volume is stored.
//!
//! A run whose films all have one particle volume (the thin-film SPH code's do) thus draws
//! every droplet at one size in every frame, the film's or not.

use crate::Result;
use crate::io::{CloudPart, PartKind, ReadOptions, read_parts};
use crate::pointcloud::droplet_size::{
    VolumeSource, film_particle_volume, radii_from_mass, spacing_radius, stored_droplet_volume,
    volume_radius,
};
use std::path::{Path, PathBuf};

/// Most frames before this one searched for a film volume (step 5 above).
pub const EARLIER_FRAMES: u32 = 16;

/// Reads every particle set of `path` ([`crate::io::read_parts`]) and sizes its droplets
/// (see the module docs); each droplet part gets a note saying where its size came from.
///
/// # Errors
/// As [`crate::io::read_parts`] for `path`; other frames of the run that cannot be read are
/// passed over.
pub fn read_input_parts(path: &Path, opts: &ReadOptions) -> Result<Vec<CloudPart>> {
    let mut parts = read_parts(path, opts)?;
    parts.extend(super::beside::droplets_beside(path, opts)?);
    size_droplets(path, &mut parts);
    Ok(parts)
}

/// Gives every droplet part of `parts` (read from `input`) without radii its radii and a note.
pub fn size_droplets(input: &Path, parts: &mut [CloudPart]) {
    let needs = |p: &CloudPart| {
        p.kind == PartKind::Droplets && p.cloud.radius.is_none() && !p.cloud.is_empty()
    };
    if !parts.iter().any(needs) {
        return;
    }
    let mut run: Option<Option<(f64, String)>> = None;
    for i in 0..parts.len() {
        if !needs(&parts[i]) {
            continue;
        }
        if let Some(r) = radii_from_mass(&parts[i].cloud) {
            let note = format!(
                "{}: water spheres of each droplet's stored mass m over 1000 kg/m³, radius {}",
                parts[i].label,
                span(&r)
            );
            parts[i].cloud.radius = Some(r);
            parts[i].notes.push(note);
            continue;
        }
        let found = run.get_or_insert_with(|| run_volume(input, parts)).clone();
        let part = &mut parts[i];
        let n = part.cloud.len();
        let (r, note) = match found {
            Some((v, from)) => {
                let r = volume_radius(v) as f32;
                (
                    r,
                    format!(
                        "{}: water spheres of radius {r:.3e} m, the volume {v:.4e} m³ {from}",
                        part.label
                    ),
                )
            }
            None => {
                let r = spacing_radius(&part.cloud.positions);
                (
                    r,
                    format!(
                        "warning: {}: no droplet volume stored (no mass, and no film SA·H or m in \
                         this input, the run's frame 0, its snapshots or the {EARLIER_FRAMES} \
                         frames before): spheres of half the median droplet spacing, radius \
                         {r:.3e}, a guess",
                        part.label
                    ),
                )
            }
        };
        part.cloud.radius = Some(vec![r; n]);
        part.notes.push(note);
    }
}

/// "a" or "a..b" for the range of `r` (metres).
fn span(r: &[f32]) -> String {
    let lo = r.iter().copied().fold(f32::INFINITY, f32::min);
    let hi = r.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    if hi > lo {
        format!("{lo:.3e}..{hi:.3e} m")
    } else {
        format!("{lo:.3e} m")
    }
}

/// The run's film particle volume (m³) and where it came from (steps 2..5 of the module docs).
fn run_volume(input: &Path, parts: &[CloudPart]) -> Option<(f64, String)> {
    let (root, frame) = run_of(input);
    let first = run_first_frame(input);
    let described = |(v, src): (f64, VolumeSource), from: &Path| {
        let from = from.display();
        let tail = match src {
            VolumeSource::DropletMass => format!("of a 3D particle ({src} of {from})"),
            _ => format!(
                "of a film particle ({src} of the film of {from}); the simulator turns a film \
                 particle into a droplet of its mass"
            ),
        };
        (v, tail)
    };
    if let Some(first) = first.filter(|f| f != input)
        && let Some(v) = frame_volume(&first)
    {
        return Some(described(v, &first));
    }
    if let Some(v) = parts
        .iter()
        .filter(|p| p.kind == PartKind::Film)
        .find_map(|p| film_particle_volume(&p.cloud))
    {
        return Some(described(v, input));
    }
    let root = root?;
    for snap in snapshots(&root) {
        if let Some(v) = frame_volume(&snap) {
            return Some(described(v, &snap));
        }
    }
    let k = frame?;
    (1..=EARLIER_FRAMES.min(k))
        .map(|d| root.join((k - d).to_string()))
        .find_map(|f| frame_volume(&f).map(|v| described(v, &f)))
}

/// The run's first frame folder (`run/0`) for a frame `run/K` or a snapshot `run/snapshot/K`,
/// whether or not it exists; `None` for a file or a folder with no parent. The droplets take
/// their volume from it, and the liquid's origin is told by it.
pub(super) fn run_first_frame(input: &Path) -> Option<PathBuf> {
    run_of(input).0.map(|root| root.join("0"))
}

/// The folder holding a run's frames and this input's frame number: a frame folder `run/K`
/// gives (`run`, K); a snapshot `run/snapshot/K` gives (`run`, K). `None` for a file.
fn run_of(input: &Path) -> (Option<PathBuf>, Option<u32>) {
    if !input.is_dir() {
        return (None, None);
    }
    let frame = input
        .file_name()
        .and_then(|n| n.to_str())
        .and_then(|n| n.parse::<u32>().ok());
    let parent = input.parent().map(Path::to_path_buf);
    let root = match parent {
        Some(p) if p.file_name().is_some_and(|n| n == "snapshot") => {
            p.parent().map(Path::to_path_buf)
        }
        p => p,
    };
    (root.filter(|r| r.is_dir()), frame)
}

/// The run's snapshot folders `root/snapshot/K`, lowest K first (at most 64).
fn snapshots(root: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(root.join("snapshot")) else {
        return Vec::new();
    };
    let mut k: Vec<(u32, PathBuf)> = entries
        .flatten()
        .filter_map(|e| {
            let n = e.file_name().to_str()?.parse::<u32>().ok()?;
            Some((n, e.path()))
        })
        .collect();
    k.sort();
    k.into_iter().take(64).map(|(_, p)| p).collect()
}

/// The film particle volume of another frame (or snapshot) of the run, if it reads and
/// stores one. Only folders are tried.
fn frame_volume(dir: &Path) -> Option<(f64, VolumeSource)> {
    if !dir.is_dir() {
        return None;
    }
    let parts = read_parts(dir, &ReadOptions::default()).ok()?;
    let film = parts
        .iter()
        .filter(|p| p.kind == PartKind::Film)
        .find_map(|p| film_particle_volume(&p.cloud));
    film.or_else(|| {
        parts
            .iter()
            .filter(|p| p.kind == PartKind::Droplets)
            .find_map(|p| stored_droplet_volume(&p.cloud))
    })
}
