//! CIE 1931 2° colour matching functions (1 nm, 360–830 nm) and the CIE D65 illuminant
//! (5 nm, 300–780 nm), shipped as CSV data inside the crate (`src/spectrum/data/`, exported
//! from the CIE tables by the colour-science library).

use std::sync::OnceLock;

/// First wavelength of the colour matching function table, in nm.
pub const CMF_MIN_NM: f64 = 360.0;
/// Last wavelength of the colour matching function table, in nm.
pub const CMF_MAX_NM: f64 = 830.0;

const CMF_CSV: &str = include_str!("data/cie1931_2deg_1nm.csv");
const D65_CSV: &str = include_str!("data/cie_d65_5nm.csv");

/// The parsed tables.
#[derive(Debug)]
pub struct CieTables {
    /// x̄, ȳ, z̄ at 360, 361, …, 830 nm.
    cmf: Vec<[f64; 3]>,
    /// (wavelength nm, relative power) of D65 at 5 nm steps.
    d65: Vec<(f64, f64)>,
}

fn parse_rows(csv: &str, columns: usize) -> Vec<Vec<f64>> {
    csv.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let row: Vec<f64> = l
                .split(',')
                .map(|v| v.trim().parse().expect("bundled CIE table is valid"))
                .collect();
            assert_eq!(row.len(), columns, "bundled CIE table row width");
            row
        })
        .collect()
}

/// The bundled tables, parsed on first use (~50 µs).
pub fn tables() -> &'static CieTables {
    static TABLES: OnceLock<CieTables> = OnceLock::new();
    TABLES.get_or_init(|| {
        let cmf = parse_rows(CMF_CSV, 4)
            .into_iter()
            .map(|r| [r[1], r[2], r[3]])
            .collect();
        let d65 = parse_rows(D65_CSV, 2)
            .into_iter()
            .map(|r| (r[0], r[1]))
            .collect();
        CieTables { cmf, d65 }
    })
}

impl CieTables {
    /// Colour matching functions (x̄, ȳ, z̄) at `lambda_nm`, linearly interpolated between the
    /// 1 nm table entries; zero outside 360–830 nm.
    pub fn cmf(&self, lambda_nm: f64) -> [f64; 3] {
        if !(CMF_MIN_NM..=CMF_MAX_NM).contains(&lambda_nm) {
            return [0.0; 3];
        }
        let x = lambda_nm - CMF_MIN_NM;
        let i = (x.floor() as usize).min(self.cmf.len() - 2);
        let f = x - i as f64;
        let (a, b) = (self.cmf[i], self.cmf[i + 1]);
        [0, 1, 2].map(|k| a[k] + f * (b[k] - a[k]))
    }

    /// D65 relative spectral power at `lambda_nm`, linearly interpolated; held at the table's
    /// end values outside 300–780 nm (the CIE table's 780–830 nm tail differs by < 1e-4 in any
    /// colour computed here, since the colour matching functions vanish there).
    pub fn d65(&self, lambda_nm: f64) -> f64 {
        let first = self.d65[0];
        let last = self.d65[self.d65.len() - 1];
        if lambda_nm <= first.0 {
            return first.1;
        }
        if lambda_nm >= last.0 {
            return last.1;
        }
        let step = self.d65[1].0 - first.0;
        let x = (lambda_nm - first.0) / step;
        let i = (x.floor() as usize).min(self.d65.len() - 2);
        let f = x - i as f64;
        self.d65[i].1 + f * (self.d65[i + 1].1 - self.d65[i].1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_have_known_values() {
        let t = tables();
        assert_eq!(t.cmf.len(), 471);
        // ȳ peaks at 555 nm with value 1 (by definition of the photopic luminosity function).
        assert!((t.cmf(555.0)[1] - 1.0).abs() < 1e-3);
        // D65 is normalised to 100 at 560 nm.
        assert!((t.d65(560.0) - 100.0).abs() < 1e-9);
        assert_eq!(t.cmf(300.0), [0.0; 3]);
    }
}
