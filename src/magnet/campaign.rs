//! A helioscope's data-taking campaign from one trace: a vacuum setting and a
//! list of buffer-gas settings, each recording the axion masses it sees. The
//! photons' paths do not depend on the gas or the mass, only each axion's
//! conversion probability does, so every recorded photon adds its axion
//! weight × P(path, E, m_a, setting) / P_max to each (setting, mass) tally.
//!
//! - **The planner** is the rule of REST-for-Physics' sensitivity code
//!   (`TRestAxionField::GetMassDensityScanning`, rest-for-physics/axionlib
//!   PR #78; BabyIAXO's macro takes helium, 0.25 eV and a ramp-down of 20):
//!   the first setting's photon mass is where the vacuum P has fallen to half
//!   its value at m_a = 0; each next one lies FWHM(m)/f further, FWHM the
//!   full width at half maximum of the present setting's resonance in m_a
//!   (twice its upper half width, attenuation included) and
//!   f = e^(−m·ramp_down) + 1 (from 2 at low mass, where steps of half a width
//!   keep the coverage even, to 1); it stops once a setting's mass passes
//!   `up_to_ev`. traxer takes P on the bore's axis through the scene's own
//!   field (the map, not a uniform 2.5 T) at the planning energy (4.2 keV,
//!   REST's).
//! - **The masses**: `vacuum_masses` nodes log-spaced from `lightest_ev` up
//!   to the first setting, then `masses_per_step` evenly between each
//!   setting's photon mass and the next, the last setting's own mass the last.
//! - **Which setting records which mass**: what a setting would count at m
//!   is its P on the axis times its planned hours (the allocation's, with
//!   each setting's on-axis P at its own mass as its rate for "ksvz"); at
//!   each mass the settings that would count least are left out as long as
//!   together they count at most `sees` of all settings, at each of the
//!   tallies' lowest, the planning and the highest energies (REST combines,
//!   per mass, only the settings close to it). Their signal would move a
//!   signal-limited limit on g by ≲ `sees`/4, less where the background
//!   limits it (tested against a campaign where every setting records
//!   every mass).
//!
//! Data flow: `scene::magnet` reads the `campaign` table of `[magnet]` and
//! calls [`Campaign::plan`]; the photon loop calls [`Campaign::factors`] for
//! each recorded photon (`trace`); `sensor::campaign` adds them; `output`
//! writes the tallies and each setting's exposure ([`Campaign::hours`]).

use super::buffer_gas::{BufferGas, BufferGasDesc};
use super::conversion::momentum_transfer;
use super::exposure::{split_hours, Exposure};
use super::legendre::run_probabilities;
pub use super::planner::{CampaignError, PlanDesc, MAX_SETTINGS};
use super::{medium, ConversionPath, Magnet};
use serde::Deserialize;

/// The `campaign` table of a scene's `[magnet]`.
///
/// ```toml
/// [magnet.campaign]
/// enabled = true                 # optional: false traces the scene's one setting
/// gas = "He"                     # the buffer gas's formula
/// temperature_k = 1.8
/// plan = { up_to_ev = 0.25, ramp_down = 20.0, energy_kev = 4.2 }   # REST's rule, or
/// pressures_mbar = [0.5, 1.0]    # the settings by hand (ascending)
/// vacuum = true                  # a vacuum setting too
/// lightest_ev = 1e-4             # the vacuum's masses from here (log-spaced)
/// vacuum_masses = 40
/// masses_per_step = 7            # masses between one setting's photon mass and the next
/// sees = 0.01                    # a setting records a mass where its P is ≥ this of the best
/// vacuum_hours = 13140.0         # exposure: the vacuum setting's tracking time
/// gas_hours = 13140.0            # the gas settings' together, split by
/// allocation = "equal"           # "equal", "ksvz" (REST's), or
/// fractions = []                 # one fraction per gas setting (adding up to 1)
/// ksvz_first_settings = 5        # "ksvz": the first gas settings share equally
/// ksvz_first_share = 0.3333      # this share of gas_hours (REST: 0.5 of 1.5 years)
/// energy_kev = [1.0, 10.0, 18]   # the tallies' energy bins: [min, max, count]
/// rings_mm = [20.0, 40]          # and rings about centre_mm: [outer radius, count]
/// centre_mm = [0.0, 0.0]         # on the sensor (its local frame)
/// ```
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CampaignDesc {
    #[serde(default = "yes")]
    pub enabled: bool,
    #[serde(default = "helium")]
    pub gas: String,
    pub temperature_k: f64,
    #[serde(default)]
    pub plan: Option<PlanDesc>,
    #[serde(default)]
    pub pressures_mbar: Option<Vec<f64>>,
    #[serde(default = "yes")]
    pub vacuum: bool,
    #[serde(default = "lightest")]
    pub lightest_ev: f64,
    #[serde(default = "forty")]
    pub vacuum_masses: usize,
    #[serde(default = "seven")]
    pub masses_per_step: usize,
    #[serde(default = "one_per_cent")]
    pub sees: f64,
    pub vacuum_hours: f64,
    pub gas_hours: f64,
    #[serde(default = "equal")]
    pub allocation: String,
    #[serde(default)]
    pub fractions: Vec<f64>,
    #[serde(default = "five")]
    pub ksvz_first_settings: usize,
    #[serde(default = "a_third")]
    pub ksvz_first_share: f64,
    #[serde(default = "energy_bins")]
    pub energy_kev: [f64; 3],
    #[serde(default = "rings")]
    pub rings_mm: [f64; 2],
    #[serde(default)]
    pub centre_mm: [f64; 2],
}

fn yes() -> bool {
    true
}
fn helium() -> String {
    "He".into()
}
fn lightest() -> f64 {
    1e-4
}
fn forty() -> usize {
    40
}
fn seven() -> usize {
    7
}
fn five() -> usize {
    5
}
fn a_third() -> f64 {
    1.0 / 3.0
}
fn one_per_cent() -> f64 {
    0.01
}
fn equal() -> String {
    "equal".into()
}
fn energy_bins() -> [f64; 3] {
    [1.0, 10.0, 18.0]
}
fn rings() -> [f64; 2] {
    [20.0, 40.0]
}

/// One setting of the campaign: vacuum (`gas` none) or a buffer gas.
#[derive(Clone, Debug, PartialEq)]
pub struct Setting {
    pub gas: Option<BufferGas>,
    /// The photon mass m_γ (eV; 0 in vacuum).
    pub photon_mass_ev: f64,
}

impl Setting {
    pub fn pressure_mbar(&self) -> f64 {
        self.gas.as_ref().map_or(0.0, |g| g.desc.pressure_mbar)
    }

    pub fn label(&self) -> String {
        match &self.gas {
            None => "vacuum".into(),
            Some(g) => format!(
                "{} {:.4} mbar at {} K",
                g.desc.mixture.keys().next().map_or("", |k| k.as_str()),
                g.desc.pressure_mbar,
                crate::text::number(g.desc.temperature_k)
            ),
        }
    }
}

/// A planned campaign: its settings, mass nodes, which setting records
/// which mass, and the tallies' bins.
#[derive(Clone, Debug, PartialEq)]
pub struct Campaign {
    pub desc: CampaignDesc,
    pub settings: Vec<Setting>,
    /// The mass nodes (eV), ascending.
    pub masses: Vec<f64>,
    /// (setting, mass) index pairs recorded, by setting then mass.
    pub pairs: Vec<(u32, u32)>,
    /// The tallies' energy bin edges (keV) and ring edges (mm).
    pub energy_edges: Vec<f64>,
    pub ring_edges: Vec<f64>,
}

/// The most (setting, mass) pairs × bins a campaign tallies: 4 × 10⁶ sums of
/// 16 bytes, 64 MB per sensor for the run and as much for each chunk being
/// traced.
pub const MAX_TALLY_SUMS: usize = 6_000_000;

impl Campaign {
    /// Plans the campaign `desc` on `magnet` (its field and coupling; its own
    /// gas and mass are the scene's single setting, not the campaign's).
    pub fn plan(desc: &CampaignDesc, magnet: &Magnet) -> Result<Campaign, CampaignError> {
        check(desc)?;
        let axis = on_axis(magnet);
        let mut settings = Vec::new();
        if desc.vacuum {
            settings.push(Setting {
                gas: None,
                photon_mass_ev: 0.0,
            });
        }
        let per_mbar = gas_at(desc, 1.0)?.photon_mass2_ev2;
        let gas_for_mass = |m: f64| gas_at(desc, m * m / per_mbar);
        let gas: Vec<BufferGas> = match (&desc.plan, &desc.pressures_mbar) {
            (Some(plan), None) => super::planner::plan_masses(plan, magnet, &axis, &gas_for_mass)?
                .into_iter()
                .map(&gas_for_mass)
                .collect::<Result<_, _>>()?,
            (None, Some(p)) => p.iter().map(|&p| gas_at(desc, p)).collect::<Result<_, _>>()?,
            _ => {
                return Err(
                    "give the gas settings as plan = { up_to_ev = … } (REST's planner) or pressures_mbar = [ … ], one of them".into(),
                )
            }
        };
        for g in gas {
            if let Some(why) = crate::magnet::helium_vapour::liquid_helium(
                g.desc.pressure_mbar,
                g.desc.temperature_k,
            )
            .filter(|_| desc.gas == "He")
            {
                return Err(format!(
                    "the setting at {} mbar would be liquid: {why}; plan to a lower mass or a warmer bore",
                    crate::text::number(g.desc.pressure_mbar)
                )
                .into());
            }
            settings.push(Setting {
                photon_mass_ev: g.photon_mass_ev(),
                gas: Some(g),
            });
        }
        if settings.is_empty() {
            return Err("no settings: vacuum = false and no gas settings".into());
        }
        let masses = mass_nodes(desc, &settings);
        let (e_lo, e_hi, nb) = (desc.energy_kev[0], desc.energy_kev[1], desc.energy_kev[2]);
        let energy_edges: Vec<f64> = (0..=nb as usize)
            .map(|i| e_lo + (e_hi - e_lo) * i as f64 / nb)
            .collect();
        let nr = desc.rings_mm[1] as usize;
        let ring_edges: Vec<f64> = (0..=nr)
            .map(|i| desc.rings_mm[0] * i as f64 / nr as f64)
            .collect();
        let checks = [e_lo, desc.plan.as_ref().map_or(4.2, |p| p.energy_kev), e_hi];
        let hours = planned_hours(desc, &settings, &axis, magnet.g_agamma_gev);
        let pairs = seen_pairs(
            magnet,
            &axis,
            (&settings, &hours),
            &masses,
            (&checks, desc.sees),
        );
        let sums = pairs.len() * (energy_edges.len() - 1) * nr;
        if sums > MAX_TALLY_SUMS {
            return Err(format!(
                "{} (setting, mass) pairs × {} energy bins × {nr} rings = {sums} tallied sums, more than {MAX_TALLY_SUMS} ({} MB per sensor, as much again per chunk being traced): fewer masses (masses_per_step, vacuum_masses), bins (energy_kev, rings_mm) or settings, or a larger `sees`",
                pairs.len(),
                energy_edges.len() - 1,
                MAX_TALLY_SUMS * 16 / 1_000_000
            )
            .into());
        }
        Ok(Campaign {
            desc: desc.clone(),
            settings,
            masses,
            pairs,
            energy_edges,
            ring_edges,
        })
    }

    /// Sums per pair: energy bins × rings.
    pub fn bins(&self) -> usize {
        (self.energy_edges.len() - 1) * (self.ring_edges.len() - 1)
    }

    /// The bin of a photon converted at `local` (mm, the sensor's frame) with
    /// `energy_kev`, energy major; `None` outside the energies or the rings.
    pub fn bin(&self, local: [f64; 2], energy_kev: f64) -> Option<usize> {
        let e = &self.energy_edges;
        let r = &self.ring_edges;
        let (de, dr) = (e[1] - e[0], r[1]);
        let ie = ((energy_kev - e[0]) / de).floor();
        let radius = (local[0] - self.desc.centre_mm[0]).hypot(local[1] - self.desc.centre_mm[1]);
        let ir = (radius / dr).floor();
        let (ne, nr) = ((e.len() - 1) as f64, (r.len() - 1) as f64);
        (ie >= 0.0 && ie < ne && ir < nr).then(|| ie as usize * (r.len() - 1) + ir as usize)
    }

    /// P / P_max of an axion of `energy_kev` on `path` for every pair, in the
    /// pairs' order, into `out` (cleared first): the factor on the photon's
    /// axion weight for each (setting, mass) tally.
    pub fn factors(
        &self,
        magnet: &Magnet,
        path: &ConversionPath,
        energy_kev: f64,
        out: &mut Vec<f64>,
    ) {
        out.clear();
        let g = magnet.g_agamma_gev * 1e-9;
        // The settings' runs of pairs (pairs are by setting), each with its
        // medium; the transfers q first, and the largest |x| = |κ|L/2.
        let mut runs = Vec::with_capacity(self.settings.len());
        let mut largest_x: f64 = 0.0;
        let length = match path {
            ConversionPath::Uniform { length, .. } => *length,
            ConversionPath::Sampled(field) => field.length(),
        };
        let mut start = 0;
        while start < self.pairs.len() {
            let s = self.pairs[start].0;
            let end = start + self.pairs[start..].partition_point(|p| p.0 == s);
            let (m_gamma2, gamma) = medium(self.settings[s as usize].gas.as_ref(), energy_kev);
            out.extend(self.pairs[start..end].iter().map(|p| {
                let q = momentum_transfer(self.masses[p.1 as usize], m_gamma2, energy_kev * 1e3);
                largest_x = largest_x.max(0.5 * length * (0.25 * gamma * gamma + q * q).sqrt());
                q
            }));
            runs.push((start..end, gamma));
            start = end;
        }
        run_probabilities(path, g, (&runs, largest_x), out);
        for f in out.iter_mut() {
            *f /= magnet.weight_scale;
        }
    }

    /// Each setting's tracking hours ([`super::exposure`]), where `signal[s]`
    /// is the setting's traced rate at its own photon mass.
    pub fn hours(&self, signal: &[f64]) -> Vec<f64> {
        split_hours_of(&self.desc, &self.settings, signal)
    }
}

/// [`split_hours`] of a campaign's `settings` (their photon masses, `None`
/// for vacuum).
fn split_hours_of(desc: &CampaignDesc, settings: &[Setting], signal: &[f64]) -> Vec<f64> {
    let exposure = Exposure {
        vacuum_hours: desc.vacuum_hours,
        gas_hours: desc.gas_hours,
        allocation: &desc.allocation,
        fractions: &desc.fractions,
        ksvz_first_settings: desc.ksvz_first_settings,
        ksvz_first_share: desc.ksvz_first_share,
    };
    let masses = settings
        .iter()
        .map(|s| s.gas.as_ref().map(|_| s.photon_mass_ev));
    split_hours(&exposure, &masses.collect::<Vec<_>>(), signal)
}

/// The hours the plan expects each setting to get: [`split_hours`] with
/// each setting's P on the axis at its own photon mass and the planning
/// energy as its rate (all 1 where no setting has hours, so that P alone
/// decides what a setting sees).
fn planned_hours(
    desc: &CampaignDesc,
    settings: &[Setting],
    axis: &ConversionPath,
    g: f64,
) -> Vec<f64> {
    let e = desc.plan.as_ref().map_or(4.2, |p| p.energy_kev);
    let signal: Vec<f64> = settings
        .iter()
        .map(|s| axis.probability_in(g, medium(s.gas.as_ref(), e), e, s.photon_mass_ev))
        .collect();
    let hours = split_hours_of(desc, settings, &signal);
    match hours.iter().any(|h| *h > 0.0) {
        true => hours,
        false => vec![1.0; settings.len()],
    }
}

/// The bore's axis: the line along which the planner takes P.
fn on_axis(magnet: &Magnet) -> ConversionPath {
    let (o, d) = super::probe::lines(magnet, super::probe::Where::Line([0.0, 0.0]))[0];
    magnet.path_of(o, d)
}

/// The campaign's gas at `pressure_mbar`.
fn gas_at(desc: &CampaignDesc, pressure_mbar: f64) -> Result<BufferGas, CampaignError> {
    BufferGas::new(&BufferGasDesc {
        mixture: [(desc.gas.clone(), 1.0)].into(),
        pressure_mbar,
        temperature_k: desc.temperature_k,
    })
    .map_err(|e| CampaignError(format!("gas = \"{}\": {}", desc.gas, e.0)))
}

/// The keys' values that no campaign can have.
fn check(d: &CampaignDesc) -> Result<(), CampaignError> {
    let positive = |key: &str, v: f64| match v.is_finite() && v > 0.0 {
        true => Ok(()),
        false => Err(CampaignError(format!(
            "{key} = {}: must be a number > 0",
            crate::text::number(v)
        ))),
    };
    positive("temperature_k", d.temperature_k)?;
    positive("lightest_ev", d.lightest_ev)?;
    positive("sees", d.sees)?;
    if d.sees >= 1.0 {
        return Err("sees = … must be below 1 (a fraction of the best setting's P)".into());
    }
    for (key, v) in [("vacuum_hours", d.vacuum_hours), ("gas_hours", d.gas_hours)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(format!("{key} = {}: hours are ≥ 0", crate::text::number(v)).into());
        }
    }
    let [e0, e1, ne] = d.energy_kev;
    if !(e0.is_finite() && e0 > 0.0 && e1 > e0 && ne >= 1.0 && ne.fract() == 0.0) {
        return Err(format!(
            "energy_kev = [{}, {}, {}]: [min, max, count] with 0 < min < max and a whole count ≥ 1",
            crate::text::number(e0),
            crate::text::number(e1),
            crate::text::number(ne)
        )
        .into());
    }
    let [r, nr] = d.rings_mm;
    if !(r.is_finite() && r > 0.0 && nr >= 1.0 && nr.fract() == 0.0 && nr <= 10_000.0) {
        return Err(format!(
            "rings_mm = [{}, {}]: [outer radius > 0, a whole count of rings, 1 … 10000]",
            crate::text::number(r),
            crate::text::number(nr)
        )
        .into());
    }
    if !d.centre_mm.iter().all(|c| c.is_finite()) {
        return Err(format!(
            "centre_mm = [{}, {}]: a point on the sensor (mm, finite)",
            crate::text::number(d.centre_mm[0]),
            crate::text::number(d.centre_mm[1])
        )
        .into());
    }
    if d.masses_per_step == 0 || d.masses_per_step > 1000 {
        return Err(format!("masses_per_step = {}: 1 … 1000", d.masses_per_step).into());
    }
    if d.vacuum && (d.vacuum_masses == 0 || d.vacuum_masses > 10_000) {
        return Err(format!("vacuum_masses = {}: 1 … 10000", d.vacuum_masses).into());
    }
    if !(d.ksvz_first_share.is_finite() && (0.0..1.0).contains(&d.ksvz_first_share)) {
        return Err(format!(
            "ksvz_first_share = {}: a share of gas_hours, 0 ≤ share < 1",
            crate::text::number(d.ksvz_first_share)
        )
        .into());
    }
    match d.allocation.as_str() {
        "equal" | "ksvz" => {}
        other => {
            return Err(format!(
            "allocation = \"{other}\": \"equal\" or \"ksvz\" (or fractions = [ … ] with \"equal\")"
        )
            .into())
        }
    }
    check_split(d)
}

/// The hand-given pressures and exposure fractions of a campaign.
fn check_split(d: &CampaignDesc) -> Result<(), CampaignError> {
    if let Some(p) = &d.pressures_mbar {
        if p.is_empty() {
            return Err("pressures_mbar = []: no gas settings (leave the key out for a vacuum campaign, or plan them: plan = { up_to_ev = … })".into());
        }
        for (i, w) in p.windows(2).enumerate() {
            if w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater) {
                return Err(format!(
                    "pressures_mbar: entry {} ({}) is not above entry {} ({}): the settings go up in pressure",
                    i + 2,
                    crate::text::number(w[1]),
                    i + 1,
                    crate::text::number(w[0])
                )
                .into());
            }
        }
        if p[0] <= 0.0 || !p.iter().all(|x| x.is_finite()) {
            return Err(
                "pressures_mbar: every pressure is a number > 0 (vacuum is vacuum = true)".into(),
            );
        }
    }
    if !d.fractions.is_empty() {
        if d.allocation != "equal" {
            return Err(
                "fractions = [ … ] gives the split itself: leave allocation out (or \"equal\")"
                    .into(),
            );
        }
        let sum: f64 = d.fractions.iter().sum();
        if d.fractions.iter().any(|f| !(f.is_finite() && *f >= 0.0)) || (sum - 1.0).abs() > 1e-6 {
            return Err(format!(
                "fractions: {} values adding up to {sum}: each ≥ 0, together 1",
                d.fractions.len()
            )
            .into());
        }
    }
    Ok(())
}

/// The mass nodes: the vacuum's, log-spaced from `lightest_ev` to the first gas
/// setting (or to where the vacuum P falls to 1 %, without gas), then
/// `masses_per_step` between each gas setting's photon mass and the next.
fn mass_nodes(d: &CampaignDesc, settings: &[Setting]) -> Vec<f64> {
    let gas: Vec<f64> = settings
        .iter()
        .filter(|s| s.gas.is_some())
        .map(|s| s.photon_mass_ev)
        .collect();
    let mut out = Vec::new();
    if d.vacuum {
        let top = gas
            .first()
            .copied()
            .unwrap_or(0.1)
            .max(d.lightest_ev * 10.0);
        let n = d.vacuum_masses;
        for i in 0..n {
            out.push(d.lightest_ev * (top / d.lightest_ev).powf(i as f64 / n as f64));
        }
    }
    for w in gas.windows(2) {
        for i in 0..d.masses_per_step {
            out.push(w[0] + (w[1] - w[0]) * i as f64 / d.masses_per_step as f64);
        }
    }
    if let Some(&last) = gas.last() {
        out.push(last);
    }
    out.retain(|m| m.is_finite());
    out.dedup();
    out
}

/// The (setting, mass) pairs recorded: at each of `energies` and each mass,
/// every setting but those that together would count (P on the axis × the
/// planned hours: not P alone, the vacuum's hours are some 70 gas settings'
/// each) at most `sees` of what all settings count there.
fn seen_pairs(
    magnet: &Magnet,
    axis: &ConversionPath,
    (settings, hours): (&[Setting], &[f64]),
    masses: &[f64],
    (energies, sees): (&[f64], f64),
) -> Vec<(u32, u32)> {
    let g = magnet.g_agamma_gev;
    // p[e][s][m]: P × the setting's planned hours, what it would count.
    let p: Vec<Vec<Vec<f64>>> = energies
        .iter()
        .map(|&e| {
            settings
                .iter()
                .zip(hours)
                .map(|(s, h)| {
                    let med = medium(s.gas.as_ref(), e);
                    masses
                        .iter()
                        .map(|&m| h * axis.probability_in(g, med, e, m))
                        .collect()
                })
                .collect()
        })
        .collect();
    // At each energy and mass the settings that would count least are left
    // out while together they count at most `sees` of all of them.
    let mut seen = vec![vec![false; masses.len()]; settings.len()];
    let mut order: Vec<usize> = (0..settings.len()).collect();
    for at_e in &p {
        for m in 0..masses.len() {
            let total: f64 = at_e.iter().map(|s| s[m]).sum();
            order.sort_by(|&a, &b| at_e[a][m].total_cmp(&at_e[b][m]));
            let mut left_out = 0.0;
            for &s in &order {
                left_out += at_e[s][m];
                if total > 0.0 && left_out > sees * total {
                    seen[s][m] = true;
                }
            }
        }
    }
    let mut pairs = Vec::new();
    for (s, row) in seen.iter().enumerate() {
        for (m, &seen) in row.iter().enumerate() {
            if seen {
                pairs.push((s as u32, m as u32));
            }
        }
    }
    pairs
}
