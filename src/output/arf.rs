//! The effective area as OGIP ancillary response files (ARF): one file per
//! off-axis angle of an effective-area sweep, `effective_area_<θ>arcmin.arf`,
//! in the format of OGIP Calibration Memo CAL/GEN/92-002 (George et al., §4,
//! "type I": one response per file): a null primary array and one BINTABLE
//! extension `SPECRESP` with the columns ENERG_LO, ENERG_HI (keV) and SPECRESP
//! (cm²), and the keywords HDUCLASS = 'OGIP', HDUCLAS1 = 'RESPONSE',
//! HDUCLAS2 = 'SPECRESP', HDUVERS = '1.1.0', TELESCOP, INSTRUME, FILTER.
//!
//! Also the sweep's vignetting as a FITS table, `vignetting.fits`: one row per
//! angle and energy with the area, its error and the area over the on-axis
//! area at that energy; and the same vignetting in the layout SIXTE's
//! reader takes (`libsixt/vignetting.c`: OGIP CAL/GEN/92-021's VIGNET
//! table), `vignetting_sixte.fits`: one row whose vector columns ENERG_LO,
//! ENERG_HI (keV), THETA (degrees, where the PSF's THETA is in arcmin), PHI
//! (degrees) and VIGNET, an (energy, θ, φ) array with energy varying fastest,
//! its shape in TDIM5. SIXTE takes the bin whose (ENERG_LO, ENERG_HI] holds
//! the photon's energy, the nearest θ and the first φ, and multiplies the
//! on-axis ARF by it: so VIGNET is the area over the on-axis area.
//!
//! Data flow: `output::effective_area` writes these beside effective_area.csv
//! from the same `AreaResult`; X-ray spectral tools (XSPEC, Sherpa) read them.

use super::fits::{provenance_keys, write_keys, Keys};
use super::Provenance;
use crate::files::atomic_write;
use crate::studies::effective_area::{AngleResult, AreaResult};
use fitsio::tables::{ColumnDataType, ColumnDescription};
use fitsio::FitsFile;
use std::path::Path;

/// The ARF file name of off-axis angle `arcmin`.
pub fn arf_name(arcmin: f64) -> String {
    format!("effective_area_{arcmin}arcmin.arf")
}

/// The energy bins (keV) of a sweep's energies, one per energy: the edges
/// half-way between neighbouring energies, the outer edges half a step beyond
/// the first and last energy (never below half the first). On an even grid
/// each energy is its bin's centre. The bin's response is the area at its
/// energy, not an average over the bin (at an absorption edge inside a bin the
/// two differ). `None` for fewer than two energies: one value has no bin width.
pub fn energy_bins(energies: &[f64]) -> Option<(Vec<f64>, Vec<f64>)> {
    if energies.len() < 2 {
        return None;
    }
    let n = energies.len();
    let mid = |k: usize| 0.5 * (energies[k] + energies[k + 1]);
    let first = (energies[0] - 0.5 * (energies[1] - energies[0])).max(0.5 * energies[0]);
    let last = energies[n - 1] + 0.5 * (energies[n - 1] - energies[n - 2]);
    let lo = (0..n)
        .map(|k| if k == 0 { first } else { mid(k - 1) })
        .collect();
    let hi = (0..n)
        .map(|k| if k + 1 == n { last } else { mid(k) })
        .collect();
    Some((lo, hi))
}

/// Writes the ARFs (TELESCOP: the scene traced) and SIXTE's vignetting file.
pub fn write_responses(dir: &Path, r: &AreaResult, provenance: &Provenance) -> std::io::Result<()> {
    let telescope = provenance
        .scene_path
        .as_deref()
        .and_then(|p| Path::new(p).file_stem())
        .map_or("traxer".to_string(), |s| s.to_string_lossy().into_owned());
    write_arfs(dir, r, &telescope, provenance)?;
    write_sixte_vignetting(dir, r, provenance).map(|_| ())
}

/// Writes one ARF per angle of `r` into `dir` (nothing for fewer than two
/// energies); returns how many.
pub fn write_arfs(
    dir: &Path,
    r: &AreaResult,
    telescope: &str,
    provenance: &Provenance,
) -> std::io::Result<usize> {
    let energies: Vec<f64> = match r.angles.first() {
        Some(a) => a.points.iter().map(|p| p.energy_kev).collect(),
        None => return Ok(0),
    };
    let Some((lo, hi)) = energy_bins(&energies) else {
        return Ok(0);
    };
    for a in &r.angles {
        let path = dir.join(arf_name(a.off_axis_arcmin));
        let tmp = tempfile::Builder::new().prefix("traxer-arf-").tempdir()?;
        let tmp_file = tmp.path().join("area.arf");
        arf_file(&tmp_file, a, (&lo, &hi), telescope, provenance).map_err(|e| {
            std::io::Error::other(format!("{}: writing the ARF: {e}", path.display()))
        })?;
        atomic_write(&path, &std::fs::read(&tmp_file)?)?;
    }
    Ok(r.angles.len())
}

fn arf_file(
    path: &Path,
    a: &AngleResult,
    (lo, hi): (&[f64], &[f64]),
    telescope: &str,
    provenance: &Provenance,
) -> fitsio::errors::Result<()> {
    let mut f = FitsFile::create(path).open()?;
    let column = |name: &str| {
        ColumnDescription::new(name)
            .with_type(ColumnDataType::Float)
            .create()
    };
    let columns = [
        column("ENERG_LO")?,
        column("ENERG_HI")?,
        column("SPECRESP")?,
    ];
    let hdu = f.create_table("SPECRESP", &columns)?;
    let single = |v: &[f64]| v.iter().map(|&x| x as f32).collect::<Vec<f32>>();
    let area: Vec<f64> = a.points.iter().map(|p| p.area_cm2).collect();
    hdu.write_col(&mut f, "ENERG_LO", &single(lo))?;
    hdu.write_col(&mut f, "ENERG_HI", &single(hi))?;
    hdu.write_col(&mut f, "SPECRESP", &single(&area))?;
    let mut keys = Keys::default();
    keys.text("TUNIT1", "keV", "");
    keys.text("TUNIT2", "keV", "");
    keys.text("TUNIT3", "cm**2", "");
    keys.text("HDUCLASS", "OGIP", "format conforms to OGIP standard");
    keys.text(
        "HDUCLAS1",
        "RESPONSE",
        "dataset relates to spectral response",
    );
    keys.text("HDUCLAS2", "SPECRESP", "dataset is an ancillary response");
    keys.text(
        "HDUVERS",
        "1.1.0",
        "version of the format (OGIP CAL/GEN/92-002a)",
    );
    keys.text("TELESCOP", telescope, "the optic traced");
    keys.text(
        "INSTRUME",
        "traxer",
        "a raytrace, not a measured instrument",
    );
    keys.text("FILTER", "NONE", "");
    keys.float(
        "OFFAXIS",
        a.off_axis_arcmin,
        "[arcmin] off-axis angle of the beam",
    );
    keys.text(
        "EBINS",
        "area at the sweep's energy in each bin",
        "edges half-way between the sweep's energies",
    );
    provenance_keys(&mut keys, provenance, "effective_area.json");
    write_keys(&mut f, &hdu, keys)
}

/// The file of the vignetting as SIXTE reads it.
pub const SIXTE_VIGNETTING: &str = "vignetting_sixte.fits";

/// Why a sweep over these angles gets no SIXTE vignetting file, if it gets
/// none: SIXTE multiplies the on-axis ARF by it, so the sweep must hold the
/// axis, and its off-axis angle θ is ≥ 0 (the side is φ).
pub fn sixte_vignetting_refused(angles_arcmin: &[f64]) -> Option<&'static str> {
    if angles_arcmin.iter().any(|a| *a < 0.0) {
        Some("a negative angle: SIXTE's θ is ≥ 0, the side is the azimuth")
    } else if !angles_arcmin.contains(&0.0) {
        Some("no on-axis angle (0): SIXTE scales the on-axis ARF by it")
    } else {
        None
    }
}

/// Writes SIXTE's vignetting file into `dir` when the sweep allows one
/// ([`sixte_vignetting_refused`], and two energies or more for the bins);
/// returns whether it did.
pub fn write_sixte_vignetting(
    dir: &Path,
    r: &AreaResult,
    provenance: &Provenance,
) -> std::io::Result<bool> {
    let angles: Vec<f64> = r.angles.iter().map(|a| a.off_axis_arcmin).collect();
    let energies: Vec<f64> = match r.angles.first() {
        Some(a) => a.points.iter().map(|p| p.energy_kev).collect(),
        None => return Ok(false),
    };
    let Some(bins) = energy_bins(&energies) else {
        return Ok(false);
    };
    if sixte_vignetting_refused(&angles).is_some() {
        return Ok(false);
    }
    let path = dir.join(SIXTE_VIGNETTING);
    let tmp = tempfile::Builder::new().prefix("traxer-vig-").tempdir()?;
    let tmp_file = tmp.path().join(SIXTE_VIGNETTING);
    sixte_vignetting_file(&tmp_file, r, bins, provenance).map_err(|e| {
        std::io::Error::other(format!(
            "{}: writing SIXTE's vignetting table: {e}",
            path.display()
        ))
    })?;
    atomic_write(&path, &std::fs::read(&tmp_file)?)?;
    Ok(true)
}

fn sixte_vignetting_file(
    path: &Path,
    r: &AreaResult,
    (lo, hi): (Vec<f64>, Vec<f64>),
    provenance: &Provenance,
) -> fitsio::errors::Result<()> {
    let on_axis = r
        .angles
        .iter()
        .find(|a| a.off_axis_arcmin == 0.0)
        .expect("checked: the sweep holds the axis");
    let (n_e, n_theta) = (lo.len(), r.angles.len());
    // SIXTE interpolates in THETA, which must rise: the angles in order,
    // however the sweep was given.
    let mut angles: Vec<_> = r.angles.iter().collect();
    angles.sort_by(|a, b| a.off_axis_arcmin.total_cmp(&b.off_axis_arcmin));
    // [φ][θ][E] in memory is FITS's (E, θ, φ) with E varying fastest.
    let mut vignet = Vec::with_capacity(n_e * n_theta);
    for a in &angles {
        for (p, axis) in a.points.iter().zip(&on_axis.points) {
            // Where nothing reaches the sensor on axis the ARF is 0, and so is
            // SIXTE's product whatever VIGNET says: 0 rather than NaN.
            vignet.push(match axis.area_cm2 > 0.0 {
                true => p.area_cm2 / axis.area_cm2,
                false => 0.0,
            });
        }
    }
    let theta_deg: Vec<f64> = angles.iter().map(|a| a.off_axis_arcmin / 60.0).collect();
    let columns: [(&str, Vec<f64>, &str); 5] = [
        ("ENERG_LO", lo, "keV"),
        ("ENERG_HI", hi, "keV"),
        ("THETA", theta_deg, "deg"),
        ("PHI", vec![r.azimuth_deg], "deg"),
        ("VIGNET", vignet, ""),
    ];
    let mut f = FitsFile::create(path).open()?;
    let descriptions = columns
        .iter()
        .map(|(name, values, _)| {
            ColumnDescription::new(*name)
                .with_type(ColumnDataType::Float)
                .that_repeats(values.len())
                .create()
        })
        .collect::<Result<Vec<_>, _>>()?;
    let hdu = f.create_table("VIGNET", &descriptions)?;
    for (name, values, _) in &columns {
        let single: Vec<f32> = values.iter().map(|v| *v as f32).collect();
        hdu.write_col(&mut f, *name, &single)?;
    }
    let mut keys = Keys::default();
    for (k, (_, _, unit)) in columns.iter().enumerate() {
        if !unit.is_empty() {
            keys.text(&format!("TUNIT{}", k + 1), unit, "");
        }
    }
    keys.text(
        "TDIM5",
        &format!("({n_e},{n_theta},1)"),
        "VIGNET[phi][theta][energy]",
    );
    keys.text("HDUCLASS", "OGIP", "format conforms to OGIP standard");
    keys.text("HDUDOC", "CAL/GEN/92-021", "OGIP memo on spatial responses");
    keys.text("HDUCLAS1", "RESPONSE", "");
    keys.text("HDUCLAS2", "VIGNET", "");
    keys.text("HDUVERS", "1.0.0", "version of the format");
    keys.text(
        "VIGNDEF",
        "AREA(E, THETA) / AREA(E, 0)",
        "scales the on-axis ARF",
    );
    keys.text("COUNTS", &r.counts, "what the area counts");
    provenance_keys(&mut keys, provenance, "effective_area.json");
    write_keys(&mut f, &hdu, keys)
}

/// Writes the vignetting table to `path` (a sweep's `vignetting.fits`): the BINTABLE `VIGNETTING` with the
/// columns OFFAXIS (arcmin), ENERGY (keV), AREA and AREA_ERR (cm²) and VIGNET,
/// the area over the area at the reference angle `VIGREF` (the on-axis one, or
/// the sweep's angle nearest the axis) at the same energy.
pub fn write_vignetting(
    path: &Path,
    r: &AreaResult,
    provenance: &Provenance,
) -> std::io::Result<()> {
    let tmp = tempfile::Builder::new().prefix("traxer-vig-").tempdir()?;
    let tmp_file = tmp.path().join("vignetting.fits");
    vignetting_file(&tmp_file, r, provenance).map_err(|e| {
        std::io::Error::other(format!(
            "{}: writing the vignetting table: {e}",
            path.display()
        ))
    })?;
    atomic_write(path, &std::fs::read(&tmp_file)?)
}

fn vignetting_file(
    path: &Path,
    r: &AreaResult,
    provenance: &Provenance,
) -> fitsio::errors::Result<()> {
    let reference = r
        .angles
        .iter()
        .min_by(|a, b| a.off_axis_arcmin.abs().total_cmp(&b.off_axis_arcmin.abs()));
    let mut columns: [Vec<f64>; 5] = Default::default();
    for a in &r.angles {
        for (k, p) in a.points.iter().enumerate() {
            let on_axis = reference.map_or(f64::NAN, |r| r.points[k].area_cm2);
            let row = [
                a.off_axis_arcmin,
                p.energy_kev,
                p.area_cm2,
                p.error_cm2,
                p.area_cm2 / on_axis,
            ];
            for (c, v) in columns.iter_mut().zip(row) {
                c.push(v);
            }
        }
    }
    let names = ["OFFAXIS", "ENERGY", "AREA", "AREA_ERR", "VIGNET"];
    let mut f = FitsFile::create(path).open()?;
    let descriptions = names
        .iter()
        .map(|n| {
            ColumnDescription::new(*n)
                .with_type(ColumnDataType::Double)
                .create()
        })
        .collect::<Result<Vec<_>, _>>()?;
    let hdu = f.create_table("VIGNETTING", &descriptions)?;
    for (name, data) in names.iter().zip(&columns) {
        hdu.write_col(&mut f, *name, data)?;
    }
    let mut keys = Keys::default();
    for (k, unit) in ["arcmin", "keV", "cm**2", "cm**2", ""].iter().enumerate() {
        if !unit.is_empty() {
            keys.text(&format!("TUNIT{}", k + 1), unit, "");
        }
    }
    keys.float(
        "VIGREF",
        reference.map_or(f64::NAN, |r| r.off_axis_arcmin),
        "[arcmin] VIGNET = AREA / AREA at this angle",
    );
    keys.text("COUNTS", &r.counts, "what the area counts");
    provenance_keys(&mut keys, provenance, "effective_area.json");
    write_keys(&mut f, &hdu, keys)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_are_contiguous_with_edges_half_way_between_the_energies() {
        let (lo, hi) = energy_bins(&[1.0, 1.5, 2.5]).unwrap();
        assert_eq!(lo, [0.75, 1.25, 2.0]);
        assert_eq!(hi, [1.25, 2.0, 3.0]);
        // The first edge never reaches zero or below.
        let (lo, _) = energy_bins(&[0.1, 1.0]).unwrap();
        assert_eq!(lo[0], 0.05);
        assert!(energy_bins(&[1.0]).is_none());
    }
}
