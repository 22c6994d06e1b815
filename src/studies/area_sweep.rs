//! The settings of an effective-area sweep ([`AreaSweep`]) and their checks,
//! which front ends run before loading the scene and
//! [`super::effective_area::sweep`] runs again.

use super::{Sampling, StudyError};
use serde::Serialize;

/// What to sweep. Serialised, it is the sweep's identity (the keys its record
/// has always had).
#[derive(Clone, Debug, Serialize)]
pub struct AreaSweep {
    /// Energies (keV).
    #[serde(rename = "energies_kev")]
    pub energies: Vec<f64>,
    /// Off-axis angles (arcminutes), tilting the beam in the source's
    /// `off_axis_azimuth` direction.
    pub angles_arcmin: Vec<f64>,
    /// Photons per angle, seed, threads, and the sensor to count on.
    #[serde(flatten)]
    pub sampling: Sampling,
    /// Count only within this radius (mm) of the image centre (the centroid of
    /// the photons on the sensor at that angle).
    pub radius_mm: Option<f64>,
}

/// The most energy × angle points a sweep may have (a few numbers each in
/// memory and in the record: about 100 MB of record at most).
pub const MAX_SWEEP_POINTS: u64 = 1_000_000;

/// Checks the sweep's numbers (`sweep` does too; front ends call it first, before
/// loading the scene).
pub fn check(s: &AreaSweep) -> Result<(), StudyError> {
    let bad = |m: String| Err(StudyError::Input(m));
    if s.energies.is_empty() || s.energies.iter().any(|e| !(0.03..=30.0).contains(e)) {
        return bad("energies must lie within 0.03–30 keV (the Henke tables)".into());
    }
    // A curve over unsorted or repeated energies is drawn as a Z and repeats
    // rows of the table: refused, so that every row is one energy, in order.
    if let Some(k) = (1..s.energies.len()).find(|&k| s.energies[k] <= s.energies[k - 1]) {
        return bad(format!(
            "energies must increase, each given once: {} keV (number {}) follows {} keV; give them sorted, without repeats",
            s.energies[k],
            k + 1,
            s.energies[k - 1]
        ));
    }
    // The size before the angles' repeats: refused at once, however long.
    let points = s.energies.len() as u64 * s.angles_arcmin.len() as u64;
    if points > MAX_SWEEP_POINTS {
        return bad(format!(
            "{} energies × {} angles = {points} points: at most {MAX_SWEEP_POINTS} (each point is kept in memory and in the sweep's record)",
            s.energies.len(),
            s.angles_arcmin.len()
        ));
    }
    if let Some(k) = first_repeat(&s.angles_arcmin) {
        return bad(format!(
            "angles: {}′ is given twice (number {}); each off-axis angle once",
            s.angles_arcmin[k],
            k + 1
        ));
    }
    if s.angles_arcmin.is_empty()
        || s.angles_arcmin
            .iter()
            .any(|a| !a.is_finite() || a.abs() >= 5400.0)
    {
        return bad("angles are off-axis angles in arcminutes, below 90°".into());
    }
    if s.sampling.photons < 2 {
        return bad("photons must be at least 2 per angle".into());
    }
    if let Some(r) = s.radius_mm.filter(|&r| !(r.is_finite() && r > 0.0)) {
        return bad(format!(
            "the counting radius (--radius, radius_mm in Python) is {r}: it must be a positive length in mm"
        ));
    }
    Ok(())
}

/// The position of the first value equal to an earlier one, in O(n log n): a
/// search of each value among those before it took a minute on a sweep the
/// size cap refuses anyway.
pub(crate) fn first_repeat(values: &[f64]) -> Option<usize> {
    // −0 and +0 are one angle: sorted as +0.
    let key = |i: usize| if values[i] == 0.0 { 0.0 } else { values[i] };
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| key(a).total_cmp(&key(b)).then(a.cmp(&b)));
    // Equal values sit together, the earliest first: each later one of a run
    // is a repeat.
    order
        .windows(2)
        .filter(|w| values[w[0]] == values[w[1]])
        .map(|w| w[1])
        .min()
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_first_repeat_is_the_earliest_value_seen_before() {
        use super::first_repeat;
        assert_eq!(first_repeat(&[1.0, 2.0, 3.0]), None);
        assert_eq!(first_repeat(&[3.0, 1.0, 2.0, 1.0, 3.0]), Some(3));
        assert_eq!(first_repeat(&[0.0, 5.0, -0.0]), Some(2));
        assert_eq!(first_repeat(&[2.0, 2.0, 2.0]), Some(1));
    }
}
