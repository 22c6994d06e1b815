//! X-ray scattering cross-sections per atom (coherent + incoherent), from the
//! NIST FFAST tables (data/chantler/scattering.csv, compiled in): what
//! photoabsorption (Henke's f2) leaves out of a gas's total attenuation.
//!
//! Data flow: `magnet::buffer_gas` adds them to the photoabsorption for the
//! attenuation Γ of the bore's buffer gas.

use std::sync::OnceLock;

const TABLE: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/data/chantler/scattering.csv"
));

/// Per element (index Z − 1): ln E (keV) and ln σ (barn) at the table's nodes.
fn table() -> &'static Vec<Vec<(f64, f64)>> {
    static T: OnceLock<Vec<Vec<(f64, f64)>>> = OnceLock::new();
    T.get_or_init(|| {
        let mut t = vec![Vec::new(); 92];
        for line in TABLE.lines().filter(|l| !l.starts_with('#')).skip(1) {
            let c: Vec<&str> = line.split(',').collect();
            let z: usize = c[0].parse().expect("data/chantler/scattering.csv: Z");
            let e: f64 = c[2].parse().expect("data/chantler/scattering.csv: energy");
            let s: f64 = c[3].parse().expect("data/chantler/scattering.csv: sigma");
            t[z - 1].push((e.ln(), s.ln()));
        }
        t
    })
}

/// σ_coh+inc (cm² per atom) of element `z` at `energy_kev` (0.03–30 keV),
/// interpolated linearly in ln σ against ln E (within 0.3 % of FFAST's own
/// numbers between the nodes: scripts/make_chantler_tables.py).
pub fn cross_section_cm2(z: u32, energy_kev: f64) -> f64 {
    let rows = &table()[z as usize - 1];
    let x = energy_kev.ln();
    let i = rows.partition_point(|r| r.0 <= x).clamp(1, rows.len() - 1);
    let (a, b) = (rows[i - 1], rows[i]);
    let w = (x - a.0) / (b.0 - a.0);
    (a.1 + w * (b.1 - a.1)).exp() * 1e-24
}
