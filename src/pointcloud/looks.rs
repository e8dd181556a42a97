//! The radius fit's second look ([`super::gaps`]): which particles it looks at again, among
//! how many neighbours, and how far it searches for them (see [`SecondLook`]).

use glam::Vec3;
use rayon::prelude::*;

use super::fan::{FanScratch, Fit, SPACING_RANK, fan_reach};
use super::knn::PointIndex;

/// Neighbours a particle that looks like an edge among the first look's neighbours is looked at again
/// with.
pub const WIDE_NEIGHBOURS: usize = 64;

/// Neighbours a particle whose fan the first look's neighbours bound is looked at with
/// first, before [`WIDE_NEIGHBOURS`] (see [`SecondLook::WhereItCanChange`]).
pub const MIDDLE_NEIGHBOURS: usize = 24;

/// Which particles the fit looks at again among their [`WIDE_NEIGHBOURS`] nearest, and how.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum SecondLook {
    /// Those whose verdict their first look's hull (12 neighbours) bounded, among their
    /// [`MIDDLE_NEIGHBOURS`] nearest first, and among their [`WIDE_NEIGHBOURS`] nearest those
    /// still bounded. Not the same radii as [`SecondLook::Bounded`] where more than
    /// [`MIDDLE_NEIGHBOURS`] particles lie within a fan's reach: on the double dam break (a
    /// 3D liquid cloud drawn as film), 8 of 4,732 radii (tests/fit_second_look.rs).
    WhereItCanChange,
    /// All of those among their [`WIDE_NEIGHBOURS`] nearest (the default), searched only as
    /// far as a fan can take a neighbour (√2 × its open distance), which gives the same fan
    /// as the whole row: where fewer than [`WIDE_NEIGHBOURS`] lie that near (on a film, about
    /// 30), the search is shorter. Rows that cannot be shown the same are searched whole.
    #[default]
    Bounded,
    /// As [`SecondLook::Bounded`], every row searched whole: the reference the tests hold the
    /// shorter searches to.
    BoundedWholeRows,
}

/// A particle's verdict and its distance to the [`SPACING_RANK`]-th neighbour of its first
/// look.
pub(super) type Looked = (Fit, Option<f32>);

/// One particle's fan from a row of neighbours (nearest first), the adrift left out.
pub(super) type FitRow<'a> =
    &'a (dyn Fn(&mut FanScratch, usize, &mut dyn Iterator<Item = (u32, f32)>) -> Fit + Sync);

/// What a second look needs of the cloud: its neighbour index, positions and unit normals,
/// the half-side of a fan's square (`longest`, scene units), which particles are adrift, the
/// fan of a row, and which particle each verdict is of (`None`: verdict `i` is particle `i`'s).
pub(super) struct Cloud<'a> {
    pub index: &'a PointIndex,
    pub ids: Option<&'a [u32]>,
    pub positions: &'a [Vec3],
    pub normals: &'a [Vec3],
    pub longest: f32,
    pub drifting: &'a (dyn Fn(usize) -> bool + Sync),
    pub fit: FitRow<'a>,
}

impl Cloud<'_> {
    /// The particle whose verdict is the `k`-th.
    fn id(&self, k: usize) -> usize {
        self.ids.map_or(k, |ids| ids[k] as usize)
    }
}

/// Looks again, as `look` says, at the particles whose first look was bounded or isolated
/// (an edge seen among the nearest few may be a seam of an anisotropic sampling, with film
/// beyond the next rows, and the hull of a lopsided neighbourhood may stop short of film that
/// goes on); returns how many were looked at among [`MIDDLE_NEIGHBOURS`] and among
/// [`WIDE_NEIGHBOURS`].
pub(super) fn second_looks(c: &Cloud, looked: &mut [Looked], look: SecondLook) -> (usize, usize) {
    let again = |_: usize, (f, _): &Looked| match f {
        Fit::Isolated(_) => true,
        Fit::Sheet { bounded, .. } => *bounded,
    };
    let wider = |k: usize| {
        move |s: &mut FanScratch, slot: usize, _: Option<f32>| {
            let i = c.id(slot);
            let row = c.index.nearest_excluding(c.positions[i], k, i as u32);
            (c.fit)(s, i, &mut row.into_iter())
        }
    };
    // Most particles the nearest twelve's hull bounds (a first-ring neighbour on that hull)
    // are settled among their MIDDLE_NEIGHBOURS nearest, for less than half the cost.
    let mut middle_looks = 0;
    if look == SecondLook::WhereItCanChange {
        middle_looks = refit_where(looked, again, keep(wider(MIDDLE_NEIGHBOURS)));
    }
    let wide_looks = if look == SecondLook::Bounded {
        let within = |s: &mut FanScratch, slot: usize, sixth: Option<f32>| {
            let i = c.id(slot);
            if (c.drifting)(i) {
                return Fit::Isolated(f32::INFINITY);
            }
            let normal = c.normals[i];
            match wide_row(
                c.index,
                (c.positions, normal),
                i,
                c.longest,
                sixth,
                c.drifting,
            ) {
                Some(row) => (c.fit)(s, i, &mut row.into_iter()),
                None => wider(WIDE_NEIGHBOURS)(s, slot, sixth),
            }
        };
        refit_where(looked, again, keep(within))
    } else {
        refit_where(looked, again, keep(wider(WIDE_NEIGHBOURS)))
    };
    (middle_looks, wide_looks)
}

/// The row of particle `i` (at `positions[i]`, unit normal `normal`) that gives the fan its
/// [`WIDE_NEIGHBOURS`] nearest would: its nearest within [`fan_reach`] of it, at most
/// [`WIDE_NEIGHBOURS`], found for the `sixth` (its distance to the [`SPACING_RANK`]-th
/// neighbour not `drifting`) of its first look. `None` when that row cannot be shown to be
/// the same: it holds fewer than [`SPACING_RANK`] particles not drifting, or the
/// [`SPACING_RANK`]-th of them sets a longer reach than it was searched within, or two of its
/// particles lie at one distance.
fn wide_row(
    index: &PointIndex,
    (positions, normal): (&[Vec3], Vec3),
    i: usize,
    longest: f32,
    sixth: Option<f32>,
    drifting: &dyn Fn(usize) -> bool,
) -> Option<Vec<(u32, f32)>> {
    let searched = fan_reach(longest, sixth, normal);
    if !searched.is_finite() {
        return None;
    }
    let p = positions[i];
    let row = index.nearest_within_excluding(p, WIDE_NEIGHBOURS, searched, i as u32);
    // Neighbours at one distance may come in another order than the whole row's, and a fan
    // taken in another order may differ in the last bits.
    if row.windows(2).any(|w| w[0].1 == w[1].1) {
        return None;
    }
    if row.len() == WIDE_NEIGHBOURS {
        // The radius cut nothing: this is the whole row of the WIDE_NEIGHBOURS nearest.
        return Some(row);
    }
    let sixth = row
        .iter()
        .filter(|(j, _)| !drifting(*j as usize))
        .nth(SPACING_RANK - 1)?
        .1;
    (fan_reach(longest, Some(sixth), normal) <= searched).then_some(row)
}

/// A later look, `look(scratch, i, sixth)`, as a [`refit_where`] on the first look's
/// verdicts and distances to the [`SPACING_RANK`]-th neighbour, which it keeps.
fn keep<L>(look: L) -> impl Fn(&mut FanScratch, usize, &Looked) -> Looked
where
    L: Fn(&mut FanScratch, usize, Option<f32>) -> Fit,
{
    move |s, i, old| (look(s, i, old.1), old.1)
}

/// Sets `fits[i]` to `refit(scratch, i, &fits[i])` for every particle `i` that
/// `pick(i, &fits[i])`, in parallel; returns how many.
pub(super) fn refit_where<T: Send>(
    fits: &mut [T],
    pick: impl Fn(usize, &T) -> bool,
    refit: impl Fn(&mut FanScratch, usize, &T) -> T + Sync + Send,
) -> usize {
    let todo: Vec<(usize, &mut T)> = fits
        .iter_mut()
        .enumerate()
        .filter(|(i, f)| pick(*i, f))
        .collect();
    let count = todo.len();
    todo.into_par_iter()
        .with_min_len(512)
        .for_each_init(FanScratch::default, |s, (i, f)| *f = refit(s, i, f));
    count
}
