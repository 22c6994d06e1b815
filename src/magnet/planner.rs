//! REST-for-Physics' density planner on traxer's own field
//! (`TRestAxionField::GetMassDensityScanning`, rest-for-physics/axionlib PR
//! #78): the photon masses of a campaign's gas settings, each where the
//! previous setting's resonance has fallen to half (see
//! [`super::campaign`] for the rule).
//!
//! Data flow: [`super::campaign::Campaign::plan`] calls [`plan_masses`] with
//! the bore's on-axis path.

use super::buffer_gas::BufferGas;
use super::{medium, ConversionPath, Magnet};
use serde::Deserialize;

/// REST's planner: up to which axion mass, how fast the step factor falls
/// from 2 to 1, the energy at which the widths are taken, and the field it
/// plans on: the scene's own (the bore's axis through the map), or with
/// `field_t` > 0 a uniform field of that strength over the bore's length
/// (REST's BabyIAXO planning takes 1.73 T over 10 m: then its 73 helium
/// settings up to 0.25 eV).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PlanDesc {
    pub up_to_ev: f64,
    #[serde(default = "ramp_down")]
    pub ramp_down: f64,
    #[serde(default = "planning_energy")]
    pub energy_kev: f64,
    /// 0: the scene's field.
    #[serde(default)]
    pub field_t: f64,
}

fn ramp_down() -> f64 {
    20.0
}

fn planning_energy() -> f64 {
    4.2
}

/// The most settings a plan makes.
pub const MAX_SETTINGS: usize = 2000;

message_error!(
    /// A campaign that cannot be planned, with the key and what is wrong.
    CampaignError
);

/// REST's planner on the scene's field: the photon masses of the gas settings.
pub fn plan_masses(
    plan: &PlanDesc,
    magnet: &Magnet,
    axis: &ConversionPath,
    gas_for_mass: &dyn Fn(f64) -> Result<BufferGas, CampaignError>,
) -> Result<Vec<f64>, CampaignError> {
    let (e, g) = (plan.energy_kev, magnet.g_agamma_gev);
    if !(plan.energy_kev.is_finite() && plan.energy_kev > 0.0) {
        return Err(format!("plan: energy_kev = {}: > 0", crate::text::number(e)).into());
    }
    if !(plan.ramp_down.is_finite() && plan.ramp_down >= 0.0) {
        return Err(format!(
            "plan: ramp_down = {}: ≥ 0",
            crate::text::number(plan.ramp_down)
        )
        .into());
    }
    if !(plan.field_t.is_finite() && plan.field_t >= 0.0) {
        return Err(format!(
            "plan: field_t = {}: a field in tesla > 0 to plan on a uniform field over the bore's length, or 0 for the scene's own",
            crate::text::number(plan.field_t)
        )
        .into());
    }
    let uniform;
    let axis = match plan.field_t > 0.0 {
        true => {
            uniform = ConversionPath::Uniform {
                b_ev2: plan.field_t * crate::constants::TESLA_EV2,
                length: 2.0 * magnet.half_length_mm * 1e-3 * crate::constants::INV_EV_PER_METRE,
            };
            &uniform
        }
        false => axis,
    };
    let vacuum = |m: f64| axis.probability_in(g, (0.0, 0.0), e, m);
    let first = half_point(&vacuum, 0.0).ok_or_else(|| {
        CampaignError(
            "plan: the vacuum P on the bore's axis never falls to half (no field?)".into(),
        )
    })?;
    if !(plan.up_to_ev.is_finite() && plan.up_to_ev > first) {
        return Err(format!(
            "plan: up_to_ev = {}: the planner starts at {:.4} eV, where the vacuum P has fallen to half; ask for a heavier mass",
            crate::text::number(plan.up_to_ev),
            first
        )
        .into());
    }
    let mut out = vec![first];
    let mut m = first;
    while m < plan.up_to_ev {
        let gas = gas_for_mass(m)?;
        let med = medium(Some(&gas), e);
        let p = |x: f64| axis.probability_in(g, med, e, x);
        let half = half_point(&p, gas.photon_mass_ev()).ok_or_else(|| {
            CampaignError(format!(
                "plan: the resonance at {m:.4} eV has no half width on the axis"
            ))
        })?;
        let fwhm = 2.0 * (half - gas.photon_mass_ev());
        m += fwhm / ((-m * plan.ramp_down).exp() + 1.0);
        out.push(m);
        if out.len() > MAX_SETTINGS {
            return Err(format!(
                "plan: more than {MAX_SETTINGS} settings up to {} eV: a lighter up_to_ev or a larger ramp_down",
                crate::text::number(plan.up_to_ev)
            )
            .into());
        }
    }
    Ok(out)
}

/// The mass above `from` where `p` falls to half its value at `from`
/// (bisection to 1e-12 relative); `None` if it does not within 100 eV.
fn half_point(p: &dyn Fn(f64) -> f64, from: f64) -> Option<f64> {
    let target = 0.5 * p(from);
    if target.is_nan() || target <= 0.0 {
        return None;
    }
    let mut step = 1e-6_f64.max(from * 1e-6);
    let mut hi = from + step;
    while p(hi) > target {
        step *= 2.0;
        hi = from + step;
        if hi > 100.0 {
            return None;
        }
    }
    let mut lo = from + step / 2.0;
    if lo >= hi || p(lo) <= target {
        lo = from;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if p(mid) > target {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-12 * hi {
            break;
        }
    }
    Some(0.5 * (lo + hi))
}
