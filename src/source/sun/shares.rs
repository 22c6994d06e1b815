//! ABC's four processes cell by cell: the share of atomic recombination and
//! de-excitation, electron–ion and electron–electron bremsstrahlung and Compton
//! in each (radius, energy) cell of an ABC emission table, so that a trace can
//! split each ABC photon's weight among them and record one image per process.
//!
//! The processes come from different parts of the Sun (Compton and the
//! bremsstrahlung follow the electron density and temperature differently), so
//! their images differ; the shares carry that, cell by cell. The built-in table's
//! shares are shipped in `data/solar/abc_b16_agss09met_process_shares.csv`
//! (written by `traxer solar-flux --emission abc --model ...`, rounded to four
//! decimals; `scripts/solar_table.sh`), and computed exactly for an emission
//! made from a solar model.
//!
//! Data flow: [`super::builtin::compose`] attaches the shares to ABC's
//! [`super::builtin::CouplingPart`]; [`super::SunEmission`] hands a photon's
//! shares to the sensors' process images.

use super::emission::EmissionTable;
use super::model::SolarDataError;
use std::sync::{Arc, OnceLock};

/// Per cell of an ABC table (radius-major, as its rates), the four processes'
/// shares in the order of [`super::abc::PROCESSES`], summing to 1 (all 0 for a
/// cell that emits nothing).
pub type ProcessShares = Arc<Vec<[f64; 4]>>;

const SHARES_CSV: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/data/solar/abc_b16_agss09met_process_shares.csv"
));

/// The shares of the built-in ABC table, parsed once.
pub fn builtin_shares() -> &'static ProcessShares {
    static SHARES: OnceLock<ProcessShares> = OnceLock::new();
    SHARES.get_or_init(|| {
        Arc::new(
            parse(
                SHARES_CSV,
                super::tables::tables(super::tables::BuiltinModel::B16Agss09met)
                    .abc
                    .rates
                    .len(),
            )
            .expect("the shipped ABC process shares are valid (tested)"),
        )
    })
}

/// Scaled so that the four add up to 1 (to rounding), or all 0.
fn normalised(s: [f64; 4]) -> [f64; 4] {
    let sum: f64 = s.iter().sum();
    if sum > 0.0 {
        s.map(|x| x / sum)
    } else {
        [0.0; 4]
    }
}

/// The shares of an ABC emission's process tables (all on one grid).
pub fn shares_of(processes: &[EmissionTable; 4]) -> Vec<[f64; 4]> {
    (0..processes[0].rates.len())
        .map(|k| normalised(std::array::from_fn(|p| processes[p].rates[k])))
        .collect()
}

/// The shares as CSV: a `#` comment, the header, one row per cell of the
/// table (radius-major), four decimals.
pub fn to_csv(shares: &[[f64; 4]], comment: &str) -> String {
    let mut out = String::new();
    for line in comment.lines() {
        out.push_str(&format!("# {line}\n"));
    }
    out.push_str(&super::abc::PROCESSES.join(","));
    out.push('\n');
    for s in shares {
        let row: Vec<String> = s.iter().map(|x| format!("{x:.4}")).collect();
        out.push_str(&row.join(","));
        out.push('\n');
    }
    out
}

/// Reads shares written by [`to_csv`] for a table of `cells` cells.
pub fn parse(text: &str, cells: usize) -> Result<Vec<[f64; 4]>, SolarDataError> {
    let mut rows = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.starts_with('#'));
    let expected = super::abc::PROCESSES.join(",");
    match rows.next() {
        Some((_, header)) if header.trim() == expected => {}
        _ => return Err(format!("process shares: the header must be {expected}").into()),
    }
    let mut out = Vec::with_capacity(cells);
    for (n, line) in rows {
        let values: Vec<f64> = line
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| SolarDataError(format!("process shares line {}: not numbers", n + 1)))?;
        let share: [f64; 4] = values.try_into().map_err(|_| {
            SolarDataError(format!("process shares line {}: expected 4 shares", n + 1))
        })?;
        let sum: f64 = share.iter().sum();
        if share.iter().any(|s| !(0.0..=1.0).contains(s))
            || !(sum == 0.0 || (sum - 1.0).abs() < 3e-4)
        {
            return Err(format!(
                "process shares line {}: shares must lie in [0, 1] and add up to 1 (to their four decimals)",
                n + 1
            )
            .into());
        }
        out.push(normalised(share));
    }
    if out.len() != cells {
        return Err(format!(
            "process shares: {} rows for a table of {cells} cells",
            out.len()
        )
        .into());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_shares_cover_the_table_and_add_up_to_one() {
        let s = builtin_shares();
        assert_eq!(s.len(), super::super::builtin::abc_table().rates.len());
        for (k, row) in s.iter().enumerate() {
            let sum: f64 = row.iter().sum();
            let emits = super::super::builtin::abc_table().rates[k] > 0.0;
            assert!(
                (sum - 1.0).abs() < 1e-14 || (!emits && sum == 0.0),
                "{k}: {row:?}"
            );
        }
    }

    #[test]
    fn shares_round_trip_through_csv_and_bad_rows_are_refused() {
        let shares = vec![[0.25, 0.5, 0.125, 0.125], [0.0; 4], [0.1, 0.2, 0.3, 0.4]];
        let text = to_csv(&shares, "test");
        assert_eq!(parse(&text, 3).unwrap(), shares);
        assert!(parse(&text, 4).is_err());
        let bad = text.replace("0.1000,0.2000", "0.9000,0.2000");
        assert!(parse(&bad, 3).is_err());
    }
}
