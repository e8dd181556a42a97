//! Loading: the scene's `[input]` (files or a sample) read into parts, the films checked (or
//! repaired), deduplicated, scaled and completed (normals, radii, thickness estimated where
//! missing, radii fitted to the sampling), the droplets kept apart.

use super::config::FilmConfig;
use super::droplets::read_input_parts;
use super::fit_mode::FitRadii;
use super::input_config::{read_options, sample_kind, sample_params};
use super::one_film::{Ready, join_seams};
use super::prepared::Note;
pub use super::sample_check::check_sample_params;
use crate::io::{CloudPart, PartKind, ThicknessUnit, read_cloud};
use crate::optics::check_film_params;
use crate::pointcloud::area::{DETACHED, detached_at_own_size};
use crate::pointcloud::cut::Cut;
use crate::pointcloud::gaps::{
    AREA_OVERLAP, FAN_NEIGHBOURS, bound_by_area, fit_radii_clipped, own_radii,
};
use crate::pointcloud::knn::{KnnTable, PointIndex};
use crate::pointcloud::screen::screen_fit;
use crate::pointcloud::{
    EstimateOptions, PointCloud, fill_missing_keeping_table, repair, validate,
};
use crate::samples::sparse;
use crate::scene::SceneDesc;
use crate::{Error, Result};
use std::path::Path;

/// Thickness unit name → factor to nanometres (see [`ThicknessUnit`]).
///
/// # Errors
/// [`Error::Invalid`] for a name that is not nm, um (µm), mm or m.
pub fn thickness_unit_factor(unit: &str) -> Result<f64> {
    unit.parse::<ThicknessUnit>()
        .map(ThicknessUnit::nm_per_unit)
        .map_err(Error::invalid)
}

/// Loads (or generates) the scene's particle cloud, with thickness in nm: `input.cloud`'s
/// film (every film part of it as one cloud), or the sample.
pub fn load_cloud(desc: &SceneDesc, base: &Path) -> Result<PointCloud> {
    let input = &desc.input;
    match (&input.cloud, &input.sample) {
        (Some(_), Some(_)) => Err(Error::invalid(
            "input: give either cloud or sample, not both",
        )),
        (None, None) => Err(Error::invalid(
            "input: no particles given (set input.cloud or input.sample)",
        )),
        (None, Some(name)) => {
            let kind = sample_kind(name)?;
            let p = sample_params(input);
            check_sample_params(&p, input.sparse, "input.")?;
            let cloud = kind.generate(&p);
            Ok(match input.sparse {
                Some(f) if f < 1.0 => sparse(&cloud, f, p.seed),
                _ => cloud,
            })
        }
        (Some(path), None) => read_cloud(&base.join(path), &read_options(desc)?),
    }
}

/// Loads (or generates) every particle set of the scene: `input.cloud` and `input.clouds`
/// (each read into its parts: a simulator frame gives its film and droplets, a foam one film
/// per bubble), or the sample. Thickness in nm.
pub fn load_parts(desc: &SceneDesc, base: &Path) -> Result<Vec<CloudPart>> {
    let input = &desc.input;
    let paths = input.paths();
    if paths.is_empty() || input.sample.is_some() {
        let cloud = load_cloud(desc, base)?;
        return Ok(vec![CloudPart::film(
            input.sample.clone().unwrap_or_default(),
            cloud,
            Vec::new(),
        )]);
    }
    let opts = read_options(desc)?;
    let set = super::melp_sets::MelpSet::parse(input.melp_set.as_deref())?;
    let paths: Vec<_> = paths.into_iter().cloned().collect();
    let (paths, note) = super::melp_sets::choose(&paths, set);
    let mut notes: Vec<String> = note.into_iter().collect();
    let folder = paths
        .iter()
        .find(|p| crate::io::melp_folder::is_melp_folder(&base.join(p)));
    if let Some(f) = folder {
        notes.extend(super::melp_sets::folder_note(&base.join(f), set));
    }
    let mut parts = Vec::new();
    for p in paths {
        parts.extend(read_input_parts(&base.join(p), &opts)?);
    }
    if let Some(first) = parts.first_mut() {
        first.notes.extend(notes);
    }
    Ok(parts)
}

/// The error for a scene whose parts hold no particle at all, naming its first input.
pub(super) fn nothing_loaded(desc: &SceneDesc, base: &Path) -> Error {
    let what = desc
        .input
        .paths()
        .first()
        .map(|p| base.join(p).display().to_string());
    Error::invalid(format!(
        "{}point cloud is empty (0 particles)",
        what.map(|w| format!("{w}: ")).unwrap_or_default()
    ))
}

/// Splits the parts into the non-empty films and the droplet clouds, noting each part's notes
/// and the films left empty. Droplets go through the films' checks (or repair), each message
/// naming the part's file.
pub(super) fn split(
    parts: Vec<CloudPart>,
    repairing: bool,
    notes: &mut Vec<Note>,
) -> Result<(Vec<CloudPart>, Vec<PointCloud>)> {
    let mut films = Vec::new();
    let mut drops = Vec::new();
    for part in parts {
        notes.extend(part.notes.iter().map(Note::new));
        match part.kind {
            PartKind::Droplets => {
                let mut cloud = part.cloud;
                if repairing {
                    let report = repair(&mut cloud);
                    notes.push(Note::new(format!("{}: {report}", part.label)));
                }
                validate(&cloud).map_err(|e| Error::invalid(format!("{}: {e}", part.label)))?;
                drops.push(cloud);
            }
            PartKind::Film if part.cloud.is_empty() => {
                notes.push(Note::new(format!("{}: no film particles left", part.label)));
            }
            PartKind::Film => films.push(part),
        }
    }
    Ok((films, drops))
}

/// The films of a scene as one cloud, complete and checked.
#[derive(Debug, Default)]
pub(super) struct Films {
    /// Every film particle, with normals, radii and thickness (nm).
    pub cloud: PointCloud,
    /// The estimate's neighbour table, when there was one film and it needed one.
    pub neighbours: Option<KnnTable>,
    /// Every film came with its radii (none were estimated from spacing).
    pub had_radius: bool,
    /// Some film's radii were kept because a sample of its particles needed no fit (not
    /// every particle was judged: `pointcloud::screen`).
    pub screened: bool,
    /// The fit's verdict on each particle's splat (its cut at an open edge, its growth past its
    /// cell: see `pointcloud::cut`), one per particle of `cloud`; empty when the radii were not
    /// fitted.
    pub cuts: Vec<Cut>,
    /// Each particle's film part (its place among the films: a foam's bubble, an input file),
    /// one per particle of `cloud`; empty for one film. The MLS surface blends each part on its
    /// own (see `geometry::mls`'s sheets).
    pub sheets: Vec<u32>,
}

impl Films {
    /// The splat radii: the particles' radii times `film.radius_scale`; estimated radii make
    /// disks overlap into a closed film, so spheres drawn as particles get half of that, and
    /// each particle stays visible as its own ball.
    pub fn radii(&self, film: &FilmConfig) -> Vec<f32> {
        let estimated_scale = if self.had_radius {
            1.0
        } else {
            film.primitive.estimated_radius_scale()
        };
        let scale = film.radius_scale * estimated_scale;
        self.cloud
            .radius
            .iter()
            .flatten()
            .map(|r| r * scale)
            .collect()
    }
}

/// Readies every film ([`complete`], which checks every thickness against the film's index,
/// naming the part's file; `flags` = (repairing, the thickness unit was named)), completes
/// again as one the parts that are pieces of one film ([`join_seams`], see `one_film`), and
/// joins them into one cloud, each film its own sheet.
pub(super) fn films(
    films: Vec<CloudPart>,
    bubbles: &[(usize, usize)],
    film: &FilmConfig,
    flags: (bool, bool),
    notes: &mut Vec<Note>,
) -> Result<Films> {
    // The parts as read, for completing pieces of one film again together.
    let originals = if films.len() > 1 {
        films.clone()
    } else {
        Vec::new()
    };
    let mut ready = Vec::with_capacity(films.len());
    for part in films {
        let mut own = Vec::new();
        let mut part = complete(part, film, flags, &mut own)?;
        part.notes = own;
        ready.push(part);
    }
    let ready = join_seams(ready, originals, bubbles, |part, own| {
        complete(part, film, flags, own)
    })?;
    Ok(assemble(ready, notes))
}

/// The films as one cloud: each film's particles, cuts and sheet label after the last's.
fn assemble(ready: Vec<Ready>, notes: &mut Vec<Note>) -> Films {
    let single = ready.len() == 1;
    let mut clouds = Vec::with_capacity(ready.len());
    let mut out = Films {
        had_radius: true,
        ..Films::default()
    };
    for part in ready {
        notes.extend(part.notes);
        let (cloud, cuts) = (part.cloud, part.cuts);
        out.had_radius &= part.had_radius;
        out.screened |= part.screened;
        if !cuts.is_empty() && out.cuts.is_empty() {
            let before: usize = clouds.iter().map(PointCloud::len).sum();
            out.cuts = vec![Cut::None; before];
        }
        if !cuts.is_empty() || !out.cuts.is_empty() {
            let n = cloud.len();
            out.cuts
                .extend(cuts.into_iter().chain(std::iter::repeat(Cut::None)).take(n));
        }
        if single {
            out.neighbours = part.table;
        } else {
            let sheet = clouds.len() as u32;
            out.sheets.extend(std::iter::repeat_n(sheet, cloud.len()));
        }
        clouds.push(cloud);
    }
    out.cloud = if clouds.len() == 1 {
        clouds.pop().unwrap_or_default()
    } else {
        PointCloud::concat(&clouds)
    };
    out
}

/// One film part made ready to draw: validated (or repaired), coincident copies dropped,
/// thickness scaled (a thickness certainly in another unit refused, unless `unit_explicit`:
/// the user named the unit or a scale), what is missing estimated, radii fitted; with the
/// neighbour table if one was built (by the estimate, or for the fit), whether the part came
/// with radii, and the fit's cuts (empty when not fitted). Its notes go to `notes`.
fn complete(
    part: CloudPart,
    film: &FilmConfig,
    (repairing, unit_explicit): (bool, bool),
    notes: &mut Vec<Note>,
) -> Result<Ready> {
    let label = part.label;
    let mut cloud = part.cloud;
    let name = |e: Error| Error::invalid(format!("{label}: {e}"));
    if repairing {
        notes.push(Note::new(repair(&mut cloud).to_string()));
    } else {
        validate(&cloud).map_err(name)?;
    }
    let scale = film.thickness_scale;
    if let Some(t) = cloud.thickness_nm.as_mut().filter(|_| scale != 1.0) {
        t.iter_mut().for_each(|v| *v *= scale);
    }
    check_unit(&label, &cloud, unit_explicit, notes)?;
    // Before anything is dropped, so the index is the particle's in its own file.
    check_thickness(&cloud, film.ior).map_err(name)?;
    // Copies at one position would be a pile of identical disks no tree can split.
    let coincident = crate::pointcloud::dedupe::drop_coincident(&mut cloud);
    if coincident > 0 {
        notes.push(Note::new(format!(
            "{label}: {coincident} particles at the same position as an earlier one: drawn once"
        )));
    }
    let had_radius = cloud.radius.is_some();
    let estimate = EstimateOptions {
        default_thickness_nm: film.default_thickness_nm,
        ..EstimateOptions::default()
    };
    // One neighbour index and one table for the estimates and the fit.
    let mut index = None;
    let fit_k = if film.fit_radii.may_fit() {
        FAN_NEIGHBOURS
    } else {
        0
    };
    let (report, table) = fill_missing_keeping_table(&mut cloud, &estimate, fit_k, &mut index);
    notes.push(Note {
        routine: report.filled_nothing(),
        ..Note::new(report.to_string())
    });
    if repairing {
        validate(&cloud).map_err(name)?;
    }
    let own = bound_by_own_area(&label, &mut cloud, notes);
    let (table, cuts, screened) = fit(
        &label,
        &mut cloud,
        film.fit_radii,
        (index, table),
        &own,
        notes,
    );
    Ok(Ready {
        cloud,
        table,
        had_radius,
        cuts,
        screened,
        notes: Vec::new(),
    })
}

/// Fits `cloud`'s radii to the sampling as `mode` says (see [`FitRadii`]), with the
/// estimate's neighbour `index` and `table` if it built them; returns the table (the
/// estimate's, or the fit's 12-neighbour one), the fit's cuts (empty: none) and whether the
/// radii were kept on a sample's word (not every particle judged).
fn fit(
    label: &str,
    cloud: &mut PointCloud,
    mode: FitRadii,
    (index, mut table): (Option<PointIndex>, Option<KnnTable>),
    own: &[f32],
    notes: &mut Vec<Note>,
) -> (Option<KnnTable>, Vec<Cut>, bool) {
    let (Some(r), true) = (cloud.radius.as_mut(), mode.may_fit()) else {
        return (table, Vec::new(), false);
    };
    let index = index.unwrap_or_else(|| PointIndex::build(&cloud.positions));
    let normals = cloud.normals.as_deref().unwrap_or_default();
    if mode == FitRadii::Auto {
        // The fit run on a sample first: where it changes none of them, the radii are kept
        // and no 12-neighbour table is searched for it.
        let screen = screen_fit(&index, &cloud.positions, normals, r, own);
        notes.push(Note::new(format!("{label}: {screen}")));
        if screen.keeps_radii() {
            // Fitted without a change, an MLS support is never smaller than its own area
            // (`build::mls_radii`, where the cuts are given): the same here.
            let uncut = own.iter().any(|o| *o > 0.0);
            return (
                table,
                if uncut {
                    vec![Cut::None; r.len()]
                } else {
                    Vec::new()
                },
                screen.stride > 1,
            );
        }
    }
    // Radii fitted to the sampling: no pinholes inside, no bulge at open edges. The
    // estimate's table serves if it has the neighbours; else one whole table is searched
    // (the memory estimate counts it: 96 B a particle), which the disks' first-order
    // detail then reuses, and which parallelises better than slices of rows.
    if table.as_ref().is_none_or(|t| t.k < FAN_NEIGHBOURS) {
        table = Some(KnnTable::build_with(
            &index,
            &cloud.positions,
            FAN_NEIGHBOURS,
        ));
    }
    let t = table.as_ref().filter(|t| t.k >= FAN_NEIGHBOURS);
    let (fit, cut) = fit_radii_clipped(&index, &cloud.positions, normals, r, t, own);
    notes.push(Note::new(format!("{label}: {fit}")));
    trim_detached(label, r, own, table.as_ref(), notes);
    (table, cut, false)
}

/// No splat larger than the particle's own area allows, fitted or not ([`bound_by_area`]);
/// returns the particles' own radii ([`own_radii`]).
fn bound_by_own_area(label: &str, cloud: &mut PointCloud, notes: &mut Vec<Note>) -> Vec<f32> {
    let own = own_radii(cloud);
    if let Some(r) = cloud.radius.as_mut() {
        let bounded = bound_by_area(r, &own);
        if bounded > 0 {
            notes.push(Note::new(format!(
                "{label}: {bounded} splat radii bounded by {AREA_OVERLAP} × the radius of the particle's own area, √(SA/π)"
            )));
        }
    }
    own
}

/// A particle left past a rupture is drawn at its own size, not grown towards the film
/// ([`detached_at_own_size`], from each particle's nearest neighbour in `table`).
fn trim_detached(
    label: &str,
    radii: &mut [f32],
    own: &[f32],
    table: Option<&KnnTable>,
    notes: &mut Vec<Note>,
) {
    let Some(t) = table.filter(|_| !own.is_empty()) else {
        return;
    };
    let detached = detached_at_own_size(radii, own, |i| t.row(i).next());
    if detached > 0 {
        notes.push(Note::new(format!(
            "{label}: {detached} particles detached from the film (nearest neighbour farther \
             than {DETACHED} × both particles' own area radii): drawn at their own size, √(SA/π)"
        )));
    }
}

/// A thickness certainly in another unit would render a blank (or white) film: refused, unless
/// the user named the unit (`unit_explicit`: then they meant it, and are warned).
fn check_unit(
    label: &str,
    cloud: &PointCloud,
    unit_explicit: bool,
    notes: &mut Vec<Note>,
) -> Result<()> {
    if let Some(hint) = cloud.thickness_nm.as_deref().and_then(thickness_unit_hint) {
        if !unit_explicit {
            return Err(Error::invalid(format!(
                "{label}: {hint}, or --thickness-unit nm to render the values as they are"
            )));
        }
        notes.push(Note::warning(format!("{label}: {hint}")));
    }
    Ok(())
}

/// Refuses a thickness the optics cannot take (outside 0..1e6 nm), with a hint when the file's
/// unit looks wrong.
fn check_thickness(cloud: &PointCloud, ior: f32) -> Result<()> {
    let thickness_ok = |v: &f32| check_film_params(ior as f64, *v as f64).is_ok();
    if let Some((i, v)) = cloud
        .thickness_nm
        .iter()
        .flatten()
        .enumerate()
        .find(|(_, v)| !thickness_ok(v))
    {
        let hint = cloud
            .thickness_nm
            .as_deref()
            .and_then(thickness_unit_hint)
            .map(|h| format!(": {h}"))
            .unwrap_or_default();
        return Err(Error::invalid(format!(
            "particle {i} has thickness {v} nm after scaling, outside 0..1e6 nm{hint}"
        )));
    }
    Ok(())
}

/// A hint when thickness values (nm) are implausible for a soap film as read: all below
/// 0.001 nm (a file in metres read as nm) or all above 1 mm (a file in nm read as metres).
pub fn thickness_unit_hint(thickness_nm: &[f32]) -> Option<String> {
    let finite = thickness_nm.iter().filter(|v| v.is_finite());
    let max = finite.clone().fold(f32::NEG_INFINITY, |a, b| a.max(*b));
    let min = finite.fold(f32::INFINITY, |a, b| a.min(*b));
    if max > 0.0 && max < 1e-3 {
        Some(format!(
            "thickness values are all below 0.001 nm (max {max:.3e} nm): the file's unit is almost \
             certainly not nm (a film in metres?); add --thickness-unit m (film.thickness_unit = \"m\")"
        ))
    } else if min > 1e6 {
        Some(format!(
            "thickness values are all above 1 mm (min {min:.3e} nm): the file's unit is almost \
             certainly not the one read; if it is nm, read it with --thickness-unit nm \
             (film.thickness_unit = \"nm\")"
        ))
    } else {
        None
    }
}
