//! A standard solar model read from a file in the B16 format (Vinyoles et al.,
//! ApJ 835 (2017) 202; the files of the public SolarAxionFlux repository): lines
//! starting with `#` are comments; each other line holds 35 numbers — mass and
//! radius (fractions of the solar mass and radius), temperature [K], density
//! [g/cm³], pressure, luminosity fraction, then the mass fractions of the 29 species
//! of data/solar/species.csv in that order.
//!
//! Data flow: `traxer solar-flux --model FILE` reads a model here;
//! [`super::primakoff`] turns it into an emission table.

use std::path::Path;

message_error!(
    /// A solar model or emission file that cannot be used, with the file, the line
    /// and what is expected.
    SolarDataError
);

const SPECIES: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/data/solar/species.csv"
));

/// Columns before the mass fractions: mass, radius, T, ρ, P, L.
const LEADING_COLUMNS: usize = 6;

/// One species of the model: name, nuclear charge, mass (u).
#[derive(Clone, Debug, PartialEq)]
pub struct Species {
    pub name: String,
    pub charge: f64,
    pub mass_u: f64,
}

/// The species of the B16 format, in column order (data/solar/species.csv).
pub fn species() -> Vec<Species> {
    SPECIES
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("species"))
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            Species {
                name: f[0].to_string(),
                charge: f[1].parse().expect("data/solar/species.csv: Z (tested)"),
                mass_u: f[2].parse().expect("data/solar/species.csv: mass (tested)"),
            }
        })
        .collect()
}

/// One shell of the model.
#[derive(Clone, Debug, PartialEq)]
pub struct Shell {
    /// Fraction of the solar radius.
    pub radius: f64,
    pub temperature_k: f64,
    pub density_g_cm3: f64,
    /// Mass fractions, in the order of [`species`].
    pub mass_fractions: Vec<f64>,
}

/// A solar model: shells by increasing radius.
#[derive(Clone, Debug, PartialEq)]
pub struct SolarModel {
    pub shells: Vec<Shell>,
}

impl SolarModel {
    pub fn read(path: &Path) -> Result<SolarModel, SolarDataError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| SolarDataError(format!("{}: cannot read: {e}", path.display())))?;
        SolarModel::parse(&text, path)
    }

    /// Parses the text of a model file (`path` only names it in messages).
    pub fn parse(text: &str, path: &Path) -> Result<SolarModel, SolarDataError> {
        let n_species = species().len();
        let columns = LEADING_COLUMNS + n_species;
        let mut shells: Vec<Shell> = Vec::new();
        for (k, line) in text.lines().enumerate() {
            let at = |what: String| SolarDataError(format!("{}:{}: {what}", path.display(), k + 1));
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let values: Vec<f64> = line
                .split_whitespace()
                .map(|v| v.parse::<f64>())
                .collect::<Result<_, _>>()
                .map_err(|_| at(format!("expected {columns} numbers separated by spaces")))?;
            if values.len() != columns {
                return Err(at(format!(
                    "{} columns; a B16-format model has {columns} (mass, radius, T [K], rho [g/cm³], P, L, then {n_species} mass fractions)",
                    values.len()
                )));
            }
            let shell = Shell {
                radius: values[1],
                temperature_k: values[2],
                density_g_cm3: values[3],
                mass_fractions: values[LEADING_COLUMNS..].to_vec(),
            };
            if !(shell.radius > 0.0 && shell.radius <= 1.0) {
                return Err(at(format!(
                    "radius {}: expected a fraction of the solar radius in (0, 1]",
                    shell.radius
                )));
            }
            if shells.last().is_some_and(|s| s.radius >= shell.radius) {
                return Err(at(format!(
                    "radius {} does not increase (rows must be sorted by radius, without repeats)",
                    shell.radius
                )));
            }
            let positive = |x: f64| x > 0.0 && x.is_finite();
            if !positive(shell.temperature_k) || !positive(shell.density_g_cm3) {
                return Err(at("temperature and density must be positive".into()));
            }
            if shell
                .mass_fractions
                .iter()
                .any(|x| !(0.0..=1.0).contains(x))
            {
                return Err(at("mass fractions must lie in [0, 1]".into()));
            }
            shells.push(shell);
        }
        if shells.len() < 2 {
            return Err(SolarDataError(format!(
                "{}: no model rows (expected lines of {columns} numbers)",
                path.display()
            )));
        }
        Ok(SolarModel { shells })
    }

    /// The model at radius `r` (fraction of R_sun), linearly interpolated between
    /// its rows (the innermost row below the first radius, the outermost above the
    /// last).
    pub fn at(&self, r: f64) -> Shell {
        let s = &self.shells;
        let k = s.partition_point(|x| x.radius < r);
        if k == 0 {
            return s[0].clone();
        }
        if k == s.len() {
            return s[s.len() - 1].clone();
        }
        let (a, b) = (&s[k - 1], &s[k]);
        let t = (r - a.radius) / (b.radius - a.radius);
        let mix = |x: f64, y: f64| x + t * (y - x);
        Shell {
            radius: r,
            temperature_k: mix(a.temperature_k, b.temperature_k),
            density_g_cm3: mix(a.density_g_cm3, b.density_g_cm3),
            mass_fractions: a
                .mass_fractions
                .iter()
                .zip(&b.mass_fractions)
                .map(|(&x, &y)| mix(x, y))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_species_table_is_complete_and_ordered() {
        let s = species();
        assert_eq!(s.len(), 29);
        assert_eq!((s[0].name.as_str(), s[0].charge), ("H1", 1.0));
        assert_eq!((s[28].name.as_str(), s[28].charge), ("Ni", 28.0));
        // Masses within 1 u of A for every species: no shifted column.
        assert!(s
            .iter()
            .all(|x| x.mass_u > 2.0 * x.charge - 1.0 || x.charge == 1.0));
    }

    #[test]
    fn rows_out_of_order_are_refused_with_their_line() {
        let row = |r: f64| {
            let mut v = vec![
                "0.1".to_string(),
                r.to_string(),
                "1.5e7".into(),
                "150".into(),
            ];
            v.extend(["1e17".into(), "0.1".into()]);
            v.extend(std::iter::repeat_n("0.01".to_string(), 29));
            v.join(" ")
        };
        let text = format!("# header\n{}\n{}\n", row(0.2), row(0.1));
        let e = SolarModel::parse(&text, Path::new("m.dat")).unwrap_err();
        assert!(
            e.0.starts_with("m.dat:3: radius 0.1 does not increase"),
            "{e}"
        );
        let ok = SolarModel::parse(&format!("{}\n{}\n", row(0.1), row(0.3)), Path::new("m"));
        let m = ok.unwrap();
        assert!((m.at(0.2).temperature_k - 1.5e7).abs() < 1e-6);
    }
}
