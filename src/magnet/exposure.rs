//! A campaign's exposure: how its tracking time is split over its settings.
//! `magnet::campaign` asks for the planned hours (each setting's P on the
//! axis as its rate) to choose which masses a setting records, and `output`
//! for the hours written with the run (each setting's traced rate), which
//! `reach` reads.
//!
//! The "ksvz" rule is REST-for-Physics' (rest-for-physics/axionlib,
//! `examples/03.IAXO/GenerateSignalComponents.C`, as BabyIAXO's curve was
//! made: `GenerateSignalComponents("BabyIAXO.rml", "GasSignal", 1.5, 5, 0.5)`):
//! the first `ksvz_first_settings` gas settings (5) share
//! `ksvz_first_share` of the gas time equally (0.5 of 1.5 years); every
//! later setting gets a share of the rest ∝ 1 / (g_KSVZ(m_γ)⁴ S), S its
//! signal rate at its own mass, the time that gives each the same number of
//! counts on the KSVZ line, g ∝ m_a (REST's factor 3.75523 × m cancels in
//! the normalisation). Without the first settings' share the lightest gas
//! setting, whose KSVZ coupling is the weakest, would take most of the time.

/// A campaign's exposure keys (`magnet::campaign::CampaignDesc`'s).
pub struct Exposure<'a> {
    pub vacuum_hours: f64,
    pub gas_hours: f64,
    /// "equal" or "ksvz".
    pub allocation: &'a str,
    /// One per gas setting, or none.
    pub fractions: &'a [f64],
    pub ksvz_first_settings: usize,
    pub ksvz_first_share: f64,
}

/// Each setting's hours: `vacuum_hours` for the vacuum setting, the gas
/// settings' `gas_hours` split equally, by `fractions`, or by the KSVZ rule
/// with `signal[s]` the setting's rate at its own photon mass.
/// `photon_mass_ev[s]` is a gas setting's photon mass, `None` for vacuum.
/// With no more gas settings than `ksvz_first_settings`, "ksvz" splits all
/// the gas time equally (there are no later settings to give the rest to).
pub fn split_hours(desc: &Exposure, photon_mass_ev: &[Option<f64>], signal: &[f64]) -> Vec<f64> {
    let gas: Vec<usize> = (0..photon_mass_ev.len())
        .filter(|&s| photon_mass_ev[s].is_some())
        .collect();
    let mut out = vec![desc.vacuum_hours; photon_mass_ev.len()];
    let first = desc.ksvz_first_settings;
    let shares: Vec<f64> = match desc.allocation {
        "ksvz" if gas.len() > first => {
            let later: Vec<f64> = gas[first..]
                .iter()
                .map(|&s| match signal[s] > 0.0 {
                    // A setting that recorded nothing gets no time (none
                    // would make it see anything).
                    true => 1.0 / (photon_mass_ev[s].unwrap_or(0.0).powi(4) * signal[s]),
                    false => 0.0,
                })
                .collect();
            let total: f64 = later.iter().sum();
            let (head, tail) = match total > 0.0 {
                true => (desc.ksvz_first_share, 1.0 - desc.ksvz_first_share),
                false => (1.0, 0.0),
            };
            let equal = std::iter::repeat_n(head / first.max(1) as f64, first);
            equal
                .chain(later.iter().map(|w| match total > 0.0 {
                    true => tail * w / total,
                    false => 0.0,
                }))
                .collect()
        }
        _ if !desc.fractions.is_empty() => normalised(desc.fractions),
        _ => normalised(&vec![1.0; gas.len()]),
    };
    for (k, &s) in gas.iter().enumerate() {
        out[s] = desc.gas_hours * shares[k];
    }
    out
}

/// `weights` over their sum.
fn normalised(weights: &[f64]) -> Vec<f64> {
    let total: f64 = weights.iter().sum();
    weights.iter().map(|w| w / total).collect()
}
