//! `traxer.reflectivity` (R of a coating, as `traxer reflectivity`) and
//! `traxer.eef` (encircled energy and diameters of any image, as `traxer eef`).

use crate::convert::{array, to_json};
use crate::errors::{input, lib};
use crate::units::{numbers, optional, plain, Unit};
use numpy::{AllowTypeChange, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use traxer::analysis::{analyse, ImageGeometry};
use traxer::xray::coating_from_spec;

/// Reflectivity R(E, θ) of a mirror coating.
///
/// reflectivity(coating, energies_keV, angles_deg, polarisation="unpolarised", optical_constants="henke")
///
/// `coating`: a coating of data/coatings.toml (e.g. "llnl_recipe_3", "gold"), or
/// "FILE" / "FILE:NAME" for a TOML file with [materials] and [coatings].
/// `energies_keV` and `angles_deg` (grazing angles) broadcast against each other
/// like numpy arguments: two arrays of one length give R at each pair,
/// `E[:, None]` and `theta[None, :]` give the grid. `polarisation`:
/// "unpolarised", "s" or "p"; `optical_constants`: the layers' table of
/// scattering factors, "henke" or "chantler" (a second opinion). Returns a float64 array of the broadcast shape.
/// Plain numbers are keV and degrees (0–90); astropy Quantities convert (an
/// angle in arcmin, an energy in eV, a wavelength in Å).
#[pyfunction]
#[pyo3(signature = (coating, energies_keV, angles_deg, polarisation = "unpolarised", optical_constants = "henke"))]
#[allow(non_snake_case)]
pub fn reflectivity<'py>(
    py: Python<'py>,
    coating: &str,
    energies_keV: &Bound<'py, PyAny>,
    angles_deg: &Bound<'py, PyAny>,
    polarisation: &str,
    optical_constants: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let constants = traxer::xray::elements::OpticalConstants::parse(optical_constants)
        .map_err(|e| input(format!("optical_constants={optical_constants:?}: {e}")))?;
    let pick: fn(&traxer::xray::parratt::Reflectance) -> f64 = match polarisation {
        "unpolarised" | "unpolarized" => |r| r.unpolarised(),
        "s" => |r| r.s,
        "p" => |r| r.p,
        other => {
            return Err(input(format!(
                "polarisation={other:?}: expected \"unpolarised\", \"s\" or \"p\""
            )))
        }
    };
    let coating = coating_from_spec(coating, constants).map_err(lib)?;
    let energies_keV = plain("energies_keV", energies_keV, Unit::KeV)?;
    let angles_deg = plain("angles_deg", angles_deg, Unit::Degree)?;
    let numpy = py.import("numpy")?;
    let pair = numpy.call_method1("broadcast_arrays", (energies_keV, angles_deg))?;
    let as_f64 = |i: usize| -> PyResult<Vec<f64>> {
        let a = numpy.call_method1("ravel", (pair.get_item(i)?,))?;
        let a = numpy.call_method1("asarray", (a, "float64"))?;
        a.extract::<Vec<f64>>()
    };
    let (energies, angles) = (as_f64(0)?, as_f64(1)?);
    let shape: Vec<usize> = pair.get_item(0)?.getattr("shape")?.extract()?;
    let values = py.detach(|| {
        energies
            .iter()
            .zip(&angles)
            .map(|(&e, &th)| {
                if !(0.0..=90.0).contains(&th) {
                    return Err(format!(
                        "angles_deg={th}: a grazing angle is 0° to 90° (from the surface, in degrees)"
                    ));
                }
                coating
                    .reflectance(e, th.to_radians())
                    .map(|r| pick(&r))
                    .map_err(|err| err.to_string())
            })
            .collect::<Result<Vec<f64>, String>>()
    });
    array(py, &shape, values.map_err(input)?)
}

/// Encircled energy of an image, as `traxer eef`.
///
/// eef(image, pixel_pitch_mm, focal_length_mm=None)
///
/// `image`: [iy, ix] (or [band, iy, ix], summed over bands), any numeric type,
/// values finite and ≥ 0; pixel (0, 0) has its corner at (-nx/2, -ny/2) pitches.
/// `pixel_pitch_mm`: one number or (x, y); it and `focal_length_mm` may be
/// astropy Quantities (the image's own unit does not matter). Returns a dict: centroid_mm,
/// total_flux, hpd_mm, d80_mm, d90_mm (diameters around the centroid holding 50,
/// 80 and 90 % of the flux), their *_arcsec with a focal length (2·atan(r/f)),
/// and the curve as radius_mm and fraction arrays.
#[pyfunction]
#[pyo3(signature = (image, pixel_pitch_mm, focal_length_mm = None))]
pub fn eef<'py>(
    py: Python<'py>,
    image: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    pixel_pitch_mm: &Bound<'py, PyAny>,
    focal_length_mm: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let focal_length_mm = optional("focal_length_mm", focal_length_mm, Unit::Mm)?;
    let shape = image.shape().to_vec();
    let (ny, nx) = match shape[..] {
        [ny, nx] | [_, ny, nx] => (ny, nx),
        _ => {
            return Err(input(format!(
                "image: expected a 2-D [iy, ix] or 3-D [band, iy, ix] array, got shape {shape:?}"
            )))
        }
    };
    let values: Vec<f64> = image.as_array().iter().copied().collect();
    if values.iter().any(|v| !v.is_finite() || *v < 0.0) {
        return Err(input("image: pixel values must be finite and ≥ 0"));
    }
    let pitch = match numbers("pixel_pitch_mm", pixel_pitch_mm, Unit::Mm)?[..] {
        [p] => [p, p],
        [x, y] => [x, y],
        _ => return Err(input("pixel_pitch_mm: expected one number or (x, y) in mm")),
    };
    if !pitch.iter().all(|p| p.is_finite() && *p > 0.0)
        || focal_length_mm.is_some_and(|f| !(f.is_finite() && f > 0.0))
    {
        return Err(input("pixel pitch and focal length must be positive (mm)"));
    }
    let summed = traxer::sensor::sum_bands(&values, nx * ny);
    let g = ImageGeometry {
        nx,
        ny,
        pitch,
        origin_mm: [-0.5 * nx as f64 * pitch[0], -0.5 * ny as f64 * pitch[1]],
    };
    let Some((q, curve)) = py.detach(|| analyse(&summed, &g, focal_length_mm)) else {
        return Err(input("image: holds no flux"));
    };
    let out = to_json(py, &q)?;
    let dict = out.cast::<PyDict>()?;
    let n = curve.radius_mm.len();
    dict.set_item("radius_mm", array(py, &[n], curve.radius_mm)?)?;
    dict.set_item("fraction", array(py, &[n], curve.fraction)?)?;
    Ok(out)
}
