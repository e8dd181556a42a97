//! Columnar readers' common end: named per-particle columns in, [`PointCloud`] out, and the
//! attribute-mapping rules every reader (PLY included) follows: [`resolve_roles`].
//!
//! Readers of VTK, VTU, BGEO, CSV and frame folders collect positions plus named scalar
//! columns (vector attributes already split by [`Columns::push`] into `name_x/_y/_z`), then
//! [`Columns::into_cloud`] picks normals, thickness and radius by the explicit names in
//! [`ReadOptions`] (absent = error) or else by the format's [`Aliases`], and keeps every other
//! column as an extra.

use glam::Vec3;

use crate::io::{AttributeRole, StoredAttribute};
use crate::io::{NORMAL_ALIASES, RADIUS_ALIASES, ReadOptions, THICKNESS_ALIASES};
use crate::pointcloud::PointCloud;

/// The alias lists one format uses, and its default thickness unit.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Aliases {
    pub thickness: &'static [&'static str],
    pub normal: &'static [&'static str],
    pub radius: &'static [&'static str],
    /// Factor from the format's default thickness unit to nm (1 for nm, 1e9 for m).
    pub default_scale_to_nm: f64,
}

/// The aliases of every format but the frame folder: thickness in nm.
pub(crate) const STANDARD: Aliases = Aliases {
    thickness: THICKNESS_ALIASES,
    normal: NORMAL_ALIASES,
    radius: RADIUS_ALIASES,
    default_scale_to_nm: 1.0,
};

/// Positions and named scalar columns, all of the same length, plus what the file stored.
#[derive(Debug, Default)]
pub(crate) struct Columns {
    pub positions: Vec<Vec3>,
    pub scalars: Vec<(String, Vec<f32>)>,
    /// The file's attributes as stored (positions first if noted), for `filmsplat info`.
    pub stored: Vec<StoredAttribute>,
    /// For each scalar column, the index into `stored` of the attribute it came from.
    pub owner: Vec<usize>,
}

/// Names of the scalar columns a `k`-component attribute called `name` becomes:
/// `name` (k = 1), `name_x name_y name_z` (k = 3), else `name_0 .. name_{k-1}`.
pub(crate) fn component_names(name: &str, k: usize) -> Vec<String> {
    match k {
        1 => vec![name.to_string()],
        3 => ["x", "y", "z"]
            .iter()
            .map(|a| format!("{name}_{a}"))
            .collect(),
        _ => (0..k).map(|c| format!("{name}_{c}")).collect(),
    }
}

/// Shows untrusted text in a one-line message: escaped and shortened to 40 characters.
pub(crate) fn show(text: &str) -> String {
    let mut s: String = text.chars().take(40).flat_map(char::escape_debug).collect();
    if text.chars().count() > 40 {
        s.push('…');
    }
    s
}

impl Columns {
    /// Adds a `k`-component attribute stored tuple by tuple in `data` (`data.len()` = k × n),
    /// split into scalar columns named by [`component_names`] (a scalar is moved, not copied).
    /// `stored` names the file's type (`float32`, `int64`, `text`, ...).
    pub fn push(&mut self, name: &str, k: usize, stored: &'static str, data: Vec<f32>) {
        self.stored
            .push(StoredAttribute::new(name, stored, k, AttributeRole::Extra));
        let owner = self.stored.len() - 1;
        if k == 1 {
            self.scalars.push((name.to_string(), data));
            self.owner.push(owner);
            return;
        }
        for (c, col) in component_names(name, k).into_iter().enumerate() {
            let v: Vec<f32> = data.iter().skip(c).step_by(k).copied().collect();
            self.scalars.push((col, v));
            self.owner.push(owner);
        }
    }

    /// Records that the positions came from the attribute `name` of type `stored`.
    pub fn note_positions(&mut self, name: &str, stored: &'static str) {
        self.stored.push(StoredAttribute::new(
            name,
            stored,
            3,
            AttributeRole::Position,
        ));
    }

    /// Builds the cloud: maps normals, thickness (scaled to nm) and radius; the rest are extras.
    /// Returns a one-line message if an explicitly named attribute is missing, a normal is
    /// incomplete, one column would be used twice, or a column has the wrong length.
    pub fn into_cloud(
        self,
        opts: &ReadOptions,
        al: &Aliases,
    ) -> Result<(PointCloud, Vec<StoredAttribute>), String> {
        let n = self.positions.len();
        let names: Vec<&str> = self.scalars.iter().map(|(s, _)| s.as_str()).collect();
        if let Some((name, v)) = self.scalars.iter().find(|(_, v)| v.len() != n) {
            return Err(format!(
                "attribute '{}' has {} values for {n} points",
                show(name),
                v.len()
            ));
        }
        let list = || {
            if names.is_empty() {
                "no attributes besides the positions".to_string()
            } else {
                let mut l: Vec<String> = names.iter().take(30).map(|s| show(s)).collect();
                if names.len() > 30 {
                    l.push("…".into());
                }
                format!("attributes: {}", l.join(", "))
            }
        };
        let roles = resolve_roles(&names, &[], opts, al, &list)?;
        let used = roles.used(names.len());
        let (normal, thickness, radius) = (roles.normal, roles.thickness, roles.radius);
        let mut stored = self.stored;
        for (i, role) in used.iter().enumerate() {
            if let (Some(role), Some(&o)) = (role, self.owner.get(i)) {
                stored[o].role = *role;
            }
        }

        let mut slots: Vec<Option<Vec<f32>>> = self.scalars.iter().map(|_| None).collect();
        let mut extra = Vec::new();
        for (i, (name, v)) in self.scalars.into_iter().enumerate() {
            if used[i].is_some() {
                slots[i] = Some(v);
            } else {
                extra.push((name, v));
            }
        }
        let mut take = |i: usize| slots[i].take().unwrap_or_default();
        let normals = normal.map(|[a, b, c]| {
            let (x, y, z) = (take(a), take(b), take(c));
            (0..n).map(|j| Vec3::new(x[j], y[j], z[j])).collect()
        });
        let scale = opts.thickness_scale(al.default_scale_to_nm);
        let thickness_nm = thickness.map(|i| {
            let mut t = take(i);
            if scale != 1.0 {
                t.iter_mut()
                    .for_each(|x| *x = (f64::from(*x) * scale) as f32);
            }
            t
        });
        let radius = radius.map(take);
        let cloud = PointCloud {
            positions: self.positions,
            normals,
            thickness_nm,
            radius,
            extra,
        };
        Ok((cloud, stored))
    }
}

/// Which named attributes play the roles of normal, thickness and radius.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct Roles {
    /// The three normal components.
    pub normal: Option<[usize; 3]>,
    /// The thickness attribute.
    pub thickness: Option<usize>,
    /// The radius attribute.
    pub radius: Option<usize>,
}

impl Roles {
    /// The role of each of `n` attributes (`None` = an extra).
    pub fn used(&self, n: usize) -> Vec<Option<AttributeRole>> {
        let mut used = vec![None; n];
        for i in self.normal.iter().flatten() {
            used[*i] = Some(AttributeRole::Normal);
        }
        if let Some(i) = self.thickness {
            used[i] = Some(AttributeRole::Thickness);
        }
        if let Some(i) = self.radius {
            used[i] = Some(AttributeRole::Radius);
        }
        used
    }
}

/// The attribute-mapping rules of every reader. `names` are the scalar attributes in file
/// order; `taken` lists attributes already claimed (e.g. PLY's `x y z` positions) and what for.
/// Normals, thickness and radius are the names in `opts` if given (absent = error), else the
/// first present alias of `al`; a normal prefix `p` means `px py pz` or `p_x p_y p_z`.
/// `list()` describes the available attributes for messages ("vertex has: x, y, z").
/// Errors: an explicit name not found, an incomplete aliased normal, an attribute used twice.
pub(crate) fn resolve_roles(
    names: &[&str],
    taken: &[(usize, &'static str)],
    opts: &ReadOptions,
    al: &Aliases,
    list: &dyn Fn() -> String,
) -> Result<Roles, String> {
    let find = |name: &str| names.iter().position(|&s| s == name);
    let triple = |p: &str| find_triple(&find, p);
    let normal = match &opts.normal_attr {
        Some(p) => match triple(p) {
            (Some(t), _) => Some(t),
            (None, _) => {
                return Err(format!(
                    "normal attribute '{0}' not found: need {0}x {0}y {0}z or {0}_x {0}_y {0}_z \
                     ({1})",
                    show(p),
                    list()
                ));
            }
        },
        None => {
            let mut hit = None;
            for p in al.normal {
                match triple(p) {
                    (Some(t), _) => {
                        hit = Some(t);
                        break;
                    }
                    (None, true) => {
                        return Err(format!(
                            "incomplete normal: some but not all of {p}x {p}y {p}z / \
                             {p}_x {p}_y {p}_z ({})",
                            list()
                        ));
                    }
                    (None, false) => {}
                }
            }
            hit
        }
    };
    let scalar = |explicit: &Option<String>, aliases: &[&str], what: &str| match explicit {
        Some(name) => find(name)
            .map(Some)
            .ok_or_else(|| format!("{what} attribute '{}' not found ({})", show(name), list())),
        None => Ok(aliases.iter().find_map(|a| find(a))),
    };
    let thickness = scalar(&opts.thickness_attr, al.thickness, "thickness")?;
    let radius = scalar(&opts.radius_attr, al.radius, "radius")?;

    let mut used: Vec<Option<&str>> = vec![None; names.len()];
    for &(i, what) in taken {
        used[i] = Some(what);
    }
    let claims = normal
        .iter()
        .flatten()
        .map(|&i| (i, "normal"))
        .chain(thickness.map(|i| (i, "thickness")))
        .chain(radius.map(|i| (i, "radius")));
    for (i, what) in claims {
        if let Some(old) = used[i] {
            return Err(format!(
                "attribute '{}' is used twice ({old} and {what})",
                show(names[i])
            ));
        }
        used[i] = Some(what);
    }
    Ok(Roles {
        normal,
        thickness,
        radius,
    })
}

/// Finds the three columns of a vector attribute with prefix `p`: `px py pz` or `p_x p_y p_z`,
/// by `find(name) -> column`. Returns the columns, or `None` and whether some (but not all)
/// of a triple exist (a partial triple is an error for the callers). Shared by every reader.
pub(super) fn find_triple(
    find: &dyn Fn(&str) -> Option<usize>,
    p: &str,
) -> (Option<[usize; 3]>, bool) {
    let mut partial = false;
    for sep in ["", "_"] {
        let f = ["x", "y", "z"].map(|a| find(&format!("{p}{sep}{a}")));
        if let [Some(a), Some(b), Some(c)] = f {
            return (Some([a, b, c]), false);
        }
        partial |= f.iter().any(Option::is_some);
    }
    (None, partial)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cols() -> Columns {
        let mut c = Columns {
            positions: vec![Vec3::ZERO, Vec3::ONE],
            ..Columns::default()
        };
        c.push("v", 3, "float32", vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        c.push("N", 3, "float32", vec![0.0, 0.0, 1.0, 0.0, 1.0, 0.0]);
        c.push("rh", 1, "float32", vec![1.0, 2.0]);
        c.push("pscale", 1, "float32", vec![0.5, 0.25]);
        c.push("q", 2, "float32", vec![1.0, 2.0, 3.0, 4.0]);
        c
    }

    #[test]
    fn maps_aliases_and_splits_vectors() {
        let c = cols()
            .into_cloud(&ReadOptions::default(), &STANDARD)
            .unwrap()
            .0;
        assert_eq!(c.normals.unwrap(), vec![Vec3::Z, Vec3::Y]);
        assert_eq!(c.thickness_nm.unwrap(), vec![1.0, 2.0]);
        assert_eq!(c.radius.unwrap(), vec![0.5, 0.25]);
        let names: Vec<&str> = c.extra.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["v_x", "v_y", "v_z", "q_0", "q_1"]);
        assert_eq!(c.extra[1].1, vec![2.0, 5.0]);
        assert_eq!(c.extra[4].1, vec![2.0, 4.0]);
    }

    #[test]
    fn records_stored_types_and_roles() {
        let (_, stored) = cols()
            .into_cloud(&ReadOptions::default(), &STANDARD)
            .unwrap();
        let got: Vec<(&str, usize, AttributeRole)> = stored
            .iter()
            .map(|a| (a.name.as_str(), a.components, a.role))
            .collect();
        use AttributeRole::*;
        assert_eq!(
            got,
            [
                ("v", 3, Extra),
                ("N", 3, Normal),
                ("rh", 1, Thickness),
                ("pscale", 1, Radius),
                ("q", 2, Extra)
            ]
        );
    }

    #[test]
    fn explicit_names_override_and_must_exist() {
        let o = ReadOptions {
            normal_attr: Some("v".into()),
            thickness_attr: Some("pscale".into()),
            radius_attr: Some("rh".into()),
            thickness_scale_to_nm: 1e3,
            thickness_unit_explicit: true,
        };
        let c = cols().into_cloud(&o, &STANDARD).unwrap().0;
        assert_eq!(c.normals.unwrap()[1], Vec3::new(4.0, 5.0, 6.0));
        assert_eq!(c.thickness_nm.unwrap(), vec![500.0, 250.0]);
        assert_eq!(c.radius.unwrap(), vec![1.0, 2.0]);
        for o in [
            ReadOptions {
                thickness_attr: Some("nope".into()),
                ..ReadOptions::default()
            },
            ReadOptions {
                normal_attr: Some("q".into()),
                ..ReadOptions::default()
            },
        ] {
            let e = cols().into_cloud(&o, &STANDARD).unwrap_err();
            assert!(e.contains("not found") && e.contains("v_x"), "{e}");
        }
        let o = ReadOptions {
            radius_attr: Some("rh".into()),
            ..ReadOptions::default()
        };
        let e = cols().into_cloud(&o, &STANDARD).unwrap_err();
        assert!(e.contains("used twice"), "{e}");
    }

    #[test]
    fn incomplete_normal_and_bad_length() {
        let mut c = Columns {
            positions: vec![Vec3::ZERO],
            scalars: vec![("nx".into(), vec![1.0]), ("ny".into(), vec![0.0])],
            ..Columns::default()
        };
        let e = c.into_cloud(&ReadOptions::default(), &STANDARD);
        assert!(e.unwrap_err().contains("incomplete normal"));
        c = Columns {
            positions: vec![Vec3::ZERO],
            scalars: vec![("a".into(), vec![1.0, 2.0])],
            ..Columns::default()
        };
        let e = c.into_cloud(&ReadOptions::default(), &STANDARD);
        assert!(e.unwrap_err().contains("'a' has 2 values for 1 points"));
    }
}
