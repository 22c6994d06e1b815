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

/// Temperatures (K) a star's interior can have: the Sun's photosphere is 5.8e3 K,
/// its centre 1.5e7 K; beyond these the numbers are a unit or column mistake.
const TEMPERATURE_RANGE_K: (f64, f64) = (1e3, 1e9);
/// Densities (g/cm³) likewise: 1.7e-7 at the Sun's surface, 150 at its centre.
const DENSITY_RANGE_G_CM3: (f64, f64) = (1e-12, 1e4);
/// How far the mass fractions of a shell may add up from 1 (the B16 models add
/// up to 1 within 1e-5).
const MASS_FRACTION_SUM_TOLERANCE: f64 = 0.02;

/// Whether a shell describes a star-like plasma: temperature and density in
/// range, mass fractions in [0, 1] adding up to 1 (a model of all zeros, or
/// with shifted columns, emits nothing or nonsense).
fn check_plasma(shell: &Shell) -> Result<(), String> {
    let within = |x: f64, (lo, hi): (f64, f64)| x.is_finite() && x >= lo && x <= hi;
    if !within(shell.temperature_k, TEMPERATURE_RANGE_K) {
        return Err(format!(
            "temperature {:e} K: expected {:e} to {:e} K (column 3, in kelvin)",
            shell.temperature_k, TEMPERATURE_RANGE_K.0, TEMPERATURE_RANGE_K.1
        ));
    }
    if !within(shell.density_g_cm3, DENSITY_RANGE_G_CM3) {
        return Err(format!(
            "density {:e} g/cm³: expected {:e} to {:e} g/cm³ (column 4)",
            shell.density_g_cm3, DENSITY_RANGE_G_CM3.0, DENSITY_RANGE_G_CM3.1
        ));
    }
    if shell
        .mass_fractions
        .iter()
        .any(|x| !(0.0..=1.0).contains(x))
    {
        return Err("mass fractions must lie in [0, 1]".into());
    }
    let sum: f64 = shell.mass_fractions.iter().sum();
    if (sum - 1.0).abs() > MASS_FRACTION_SUM_TOLERANCE {
        return Err(format!(
            "the mass fractions add up to {sum}: expected 1 (within {MASS_FRACTION_SUM_TOLERANCE})"
        ));
    }
    Ok(())
}

/// A solar model: shells by increasing radius.
#[derive(Clone, Debug, PartialEq)]
pub struct SolarModel {
    pub shells: Vec<Shell>,
}

impl SolarModel {
    /// The reference to cite for a model file named `file_name`: the B16
    /// models traxer knows by their names (AGSS09met, GS98), else a request to
    /// cite the file's own source.
    pub fn citation(file_name: &str) -> String {
        ["AGSS09met", "GS98"]
            .iter()
            .find(|m| file_name.contains(&format!("B16-{m}")))
            .map_or(
                "a solar model file (not one of the B16 models traxer knows: cite its source)"
                    .to_string(),
                |m| format!("B16-{m}, N. Vinyoles et al., ApJ 835 (2017) 202, arXiv:1611.09867"),
            )
    }

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
            check_plasma(&shell).map_err(at)?;
            shells.push(shell);
        }
        if shells.len() < 2 {
            return Err(SolarDataError(format!(
                "{}: {} model row(s): a solar model lists the Sun's shells from the centre outwards (lines of {columns} numbers; the B16 files have 2000), and at least 2 are needed",
                path.display(),
                shells.len()
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

/// A plausible B16 row at radius `r`, for tests.
#[cfg(test)]
pub(crate) fn test_row(r: f64) -> String {
    let mut v = vec![
        "0.1".to_string(),
        r.to_string(),
        "1.5e7".into(),
        "150".into(),
    ];
    // Mass fractions adding up to 1.
    v.extend(["1e17".into(), "0.1".into(), "0.72".into()]);
    v.extend(std::iter::repeat_n("0.01".to_string(), 28));
    v.join(" ")
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
        let row = test_row;
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
