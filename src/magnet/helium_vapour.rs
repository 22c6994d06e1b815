//! The saturated vapour pressure of liquid helium-3 and helium-4 (the ITS-90
//! vapour-pressure equations, `data/gases/helium_vapour_pressure.toml`): a
//! buffer gas set above it at its temperature would be liquid, and the ideal
//! gas law that gives its photon mass would not hold.
//!
//! Data flow: `scene::magnet_in_scene` asks [`liquid_helium`] of a helium
//! buffer gas and warns.

use serde::Deserialize;
use std::collections::BTreeMap;
use std::sync::OnceLock;

const SHIPPED: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/data/gases/helium_vapour_pressure.toml"
));

#[derive(Deserialize)]
struct Table {
    range: Vec<Range>,
    critical: BTreeMap<String, Critical>,
}

/// One ITS-90 equation: T90 = A0 + Σ Ai x^i, x = (ln(p/Pa) − B) / C.
#[derive(Deserialize)]
struct Range {
    isotope: String,
    t_min_k: f64,
    t_max_k: f64,
    a: Vec<f64>,
    b: f64,
    c: f64,
}

#[derive(Deserialize)]
struct Critical {
    t_k: f64,
    p_pa: f64,
}

fn table() -> &'static Table {
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(|| toml::from_str(SHIPPED).expect("the shipped vapour-pressure table parses"))
}

impl Range {
    fn temperature_k(&self, p_pa: f64) -> f64 {
        let x = (p_pa.ln() - self.b) / self.c;
        self.a.iter().rev().fold(0.0, |t, a| t * x + a)
    }
}

/// The saturated vapour pressure (Pa) of `isotope` ("He3" or "He4") at
/// `t_k`: `None` above its critical temperature (no liquid at any
/// pressure) or below the ITS-90 equations' range. The equation gives T of
/// p; p of T is found by bisection on ln p (T rises with p).
pub fn saturated_vapour_pressure_pa(isotope: &str, t_k: f64) -> Option<f64> {
    let t = table();
    let critical = t.critical.get(isotope)?;
    let ranges: Vec<&Range> = t.range.iter().filter(|r| r.isotope == isotope).collect();
    let t_min = ranges
        .iter()
        .map(|r| r.t_min_k)
        .fold(f64::INFINITY, f64::min);
    if !(t_min..=critical.t_k).contains(&t_k) {
        return None;
    }
    // The range holding t_k (the last one reaches on to the critical point).
    let range = ranges.iter().find(|r| t_k <= r.t_max_k).or(ranges.last())?;
    let (mut lo, mut hi) = (0.0f64, critical.p_pa.ln());
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if range.temperature_k(mid.exp()) < t_k {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some((0.5 * (lo + hi)).exp())
}

/// For helium at `pressure_mbar` and `temperature_k`: why it would be liquid
/// whichever isotope is meant (above the saturated vapour pressure of
/// helium-3, the higher of the two), or `None`.
pub fn liquid_helium(pressure_mbar: f64, temperature_k: f64) -> Option<String> {
    let p_pa = pressure_mbar * 100.0;
    let lowest = table()
        .range
        .iter()
        .filter(|r| r.isotope == "He3")
        .map(|r| r.t_min_k)
        .fold(f64::INFINITY, f64::min);
    let (he3, at) = match saturated_vapour_pressure_pa("He3", temperature_k) {
        Some(p) => (p, temperature_k),
        // Colder than the equations reach: the vapour pressure is lower still.
        None if temperature_k < lowest => (saturated_vapour_pressure_pa("He3", lowest)?, lowest),
        None => return None,
    };
    (p_pa > he3).then(|| {
        let he4 = saturated_vapour_pressure_pa("He4", temperature_k)
            .map_or(String::new(), |p| format!(", helium-4's {:.4} mbar", p / 100.0));
        format!(
            "helium at {} mbar and {} K would be liquid: above the saturated vapour pressure of either isotope (helium-3's {:.4} mbar at {at} K{he4}; ITS-90, data/gases/helium_vapour_pressure.toml); the ideal gas law, and the photon mass from it, do not hold",
            crate::text::number(pressure_mbar),
            crate::text::number(temperature_k),
            he3 / 100.0
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_boiling_points_and_the_lambda_point_come_out() {
        // Independent facts: the normal boiling points (101 325 Pa) of
        // helium-4, 4.2221 K, and helium-3, 3.19 K (3.1905 K on the older T62
        // scale: 5 % in pressure allows for the scales' few mK); helium-4's
        // vapour pressure at its lambda point 2.1768 K, 5.0418 kPa (Donnelly
        // & Barenghi, J. Phys. Chem. Ref. Data 27, 1217 (1998)).
        let at = |iso: &str, t: f64| saturated_vapour_pressure_pa(iso, t).unwrap();
        assert!((at("He4", 4.2221) / 101_325.0 - 1.0).abs() < 2e-3);
        assert!((at("He3", 3.1905) / 101_325.0 - 1.0).abs() < 0.05);
        assert!((at("He4", 2.1768) / 5041.8 - 1.0).abs() < 2e-3);
        // Above the critical temperature there is no liquid.
        assert!(saturated_vapour_pressure_pa("He3", 4.0).is_none());
    }

    #[test]
    fn liquid_only_above_both_isotopes_vapour_pressure() {
        // BabyIAXO's and CAST's settings stay gas; 1 bar at 1.8 K is liquid.
        assert!(liquid_helium(10.0, 1.8).is_none());
        assert!(liquid_helium(1000.0, 1.8).is_some());
        // 30 mbar at 1.8 K: above helium-4's 16 mbar but below helium-3's.
        assert!(liquid_helium(30.0, 1.8).is_none());
        assert!(liquid_helium(1000.0, 300.0).is_none());
    }
}
