//! The PSF library's files: `psf.fits`, `psf.npy` and `psf.json`.
//!
//! `psf.fits` follows the layout SIXTE's PSF reader takes (`libsixt/psf.c` of
//! the SIXTE simulator; keywords of OGIP Calibration Memo CAL/GEN/92-027, "The
//! Calibration Requirements for Spatial Point Spread Functions"): every HDU, the
//! primary included, is one 2-D image for one (energy, off-axis angle,
//! azimuth), normalised to a sum of 1, with `ENERGY` [eV], `THETA` [arcmin] and
//! `PHI` [deg]; its axes `DETX`/`DETY` in metres (`CUNIT` m, `CDELT` the pixel
//! pitch) in SIXTE's frame of that azimuth: SIXTE places a pixel at
//! R(φ)·[(f·tan θ, 0) + CRVAL + (pixel − CRPIX)·CDELT], turning the image by φ
//! about the axis. So the reference pixel `CRPIX` is the window's centre,
//! `CRVAL` its place on the sensor (local axes) turned back by φ, less
//! (f·tan θ, 0); and at φ ≠ 0 the image is the sensor's window turned back by
//! φ, resampled bilinearly (`PSFROT`), so that SIXTE's turn puts every pixel
//! where traxer imaged it. At φ = 0 the image is the traced window, pixel for
//! pixel. An alternative WCS `A` gives the sensor's own mm (`X`, `Y`; with
//! the turn in `PCi_jA`), and `PSFFRAC` the window's share of the flux on the
//! sensor (the images are normalised over the window).
//!
//! `psf.npy` holds the traced windows, normalised, as float64 [angle, azimuth,
//! energy, iy, ix] on the sensor's axes (not turned); `psf.json` the grid, each
//! window's place and share, and the provenance.

use super::fits::{provenance_keys, without_primary_extname, write_keys, Keys};
use super::npy::write_npy_f64;
use super::run_files::write_json;
use super::Provenance;
use crate::files::atomic_write;
use crate::studies::psf::{PsfGrid, PsfImage, PsfLibrary};
use fitsio::images::{ImageDescription, ImageType};
use fitsio::FitsFile;
use serde_json::json;
use std::path::Path;

/// The files a PSF library writes.
pub const PSF_FILES: [&str; 3] = ["psf.fits", "psf.npy", "psf.json"];

/// Metres per mm.
const M_PER_MM: f64 = 1e-3;

/// The image normalised to a sum of 1 over its window.
pub fn normalised(image: &PsfImage) -> Vec<f64> {
    let sum: f64 = image.flux.iter().sum();
    image.flux.iter().map(|v| v / sum).collect()
}

/// Writes the library's files into `dir`.
pub fn write_psf_library(
    dir: &Path,
    lib: &PsfLibrary,
    grid: &PsfGrid,
    provenance: &Provenance,
) -> std::io::Result<()> {
    let path = dir.join(PSF_FILES[0]);
    let tmp = tempfile::Builder::new().prefix("traxer-psf-").tempdir()?;
    let tmp_file = tmp.path().join("psf.fits");
    fits_file(&tmp_file, (lib, grid), provenance)
        .map_err(|e| std::io::Error::other(format!("{}: writing FITS: {e}", path.display())))?;
    atomic_write(&path, &without_primary_extname(std::fs::read(&tmp_file)?))?;
    let w = lib.window as u64;
    let shape = [
        grid.angles_arcmin.len() as u64,
        grid.azimuths_deg.len() as u64,
        grid.energies.len() as u64,
        w,
        w,
    ];
    let stack: Vec<f64> = lib.images.iter().flat_map(normalised).collect();
    write_npy_f64(&dir.join(PSF_FILES[1]), &shape, &stack)?;
    write_json(&dir.join(PSF_FILES[2]), &description(lib, grid, provenance))
}

/// `psf.json`: what the files hold.
fn description(lib: &PsfLibrary, grid: &PsfGrid, provenance: &Provenance) -> serde_json::Value {
    json!({
        "provenance": provenance,
        "what": "the image of the scene's parallel beam tilted to each off-axis angle and azimuth at each energy, on the sensor, in a window around its centroid, normalised to a sum of 1 over the window",
        "files": {
            "psf.fits": "one image per HDU (the primary included) in the order of psf.npy, with ENERGY [eV], THETA [arcmin], PHI [deg], DETX/DETY in m in SIXTE's frame of each azimuth (SIXTE turns the image by PHI; CRVAL: the reference pixel's place turned back by PHI, less (f·tan THETA, 0); at PHI ≠ 0 the window turned back by PHI, bilinearly: PSFROT) and WCS A in the sensor's mm; the layout SIXTE's PSF reader takes (OGIP CAL/GEN/92-027 keywords)",
            "psf.npy": "float64 [angle, azimuth, energy, iy, ix], the traced windows on the sensor's axes (not turned), ix along the sensor's local x",
        },
        "sensor": lib.sensor,
        "focal_length_mm": lib.focal_length_mm,
        "pixel_pitch_mm": lib.pitch_mm,
        "sensor_size_mm": lib.size_mm,
        "window_pixels": lib.window,
        "energies_keV": grid.energies,
        "angles_arcmin": grid.angles_arcmin,
        "azimuths_deg": grid.azimuths_deg,
        "photons_per_point": grid.sampling.photons,
        "seed": grid.sampling.seed,
        "seconds": lib.seconds,
        "threads": lib.threads,
        "points": lib.images.iter().map(|i| json!({
            "energy_keV": i.energy_kev,
            "angle_arcmin": i.angle_arcmin,
            "azimuth_deg": i.azimuth_deg,
            "window_corner_pixel": i.corner,
            "centroid_mm": i.centroid_mm,
            "fraction_in_window": i.enclosed(),
            "sensor_flux": i.sensor_flux,
            "photons_recorded": i.photons_recorded,
        })).collect::<Vec<_>>(),
    })
}

/// The whole grid in the first HDU's header: how many energies, angles and
/// azimuths, and each value (`PSFE1`… in keV, `PSFT1`… in arcmin, `PSFP1`… in
/// degrees; up to 999 per axis, as keyword names hold 8 characters), the HDUs
/// following in the order angle, azimuth, energy.
fn grid_keys(keys: &mut Keys, grid: &PsfGrid) {
    keys.int(
        "NPSFIMG",
        crate::studies::psf::points(grid).len() as i64,
        "PSF images in this file, one per HDU",
    );
    keys.text(
        "PSFORDER",
        "THETA,PHI,ENERGY",
        "HDU order: energy varies fastest",
    );
    for (count, prefix, values, unit) in [
        ("NPSFE", "PSFE", &grid.energies, "[keV] energy"),
        (
            "NPSFT",
            "PSFT",
            &grid.angles_arcmin,
            "[arcmin] off-axis angle",
        ),
        ("NPSFP", "PSFP", &grid.azimuths_deg, "[deg] azimuth"),
    ] {
        keys.int(count, values.len() as i64, "values in the grid");
        for (k, v) in values.iter().enumerate().filter(|_| values.len() <= 999) {
            keys.float(&format!("{prefix}{}", k + 1), *v, unit);
        }
    }
}

fn fits_file(
    path: &Path,
    (lib, grid): (&PsfLibrary, &PsfGrid),
    provenance: &Provenance,
) -> fitsio::errors::Result<()> {
    let w = lib.window as usize;
    let description = ImageDescription {
        data_type: ImageType::Double,
        dimensions: &[w, w],
    };
    let mut f = FitsFile::create(path)
        .with_custom_primary(&description)
        .open()?;
    for (k, image) in lib.images.iter().enumerate() {
        let hdu = match k {
            0 => f.primary_hdu()?,
            _ => f.create_image("PSF".to_string(), &description)?,
        };
        hdu.write_image(&mut f, &in_sixte_frame(image, lib))?;
        let mut keys = keys(lib, image, k, provenance);
        if k == 0 {
            grid_keys(&mut keys, grid);
        }
        write_keys(&mut f, &hdu, keys)?;
    }
    Ok(())
}

/// The image as SIXTE's frame of its azimuth holds it, normalised: the
/// traced window itself at φ = 0 (mod 360°); else the window turned back by
/// φ about its centre pixel, each output pixel's centre looked up in the
/// traced window by bilinear interpolation (zero beyond it).
fn in_sixte_frame(image: &PsfImage, lib: &PsfLibrary) -> Vec<f64> {
    let traced = normalised(image);
    let (sin, cos) = image.azimuth_deg.to_radians().sin_cos();
    if image.azimuth_deg.rem_euclid(360.0) == 0.0 {
        return traced;
    }
    let w = lib.window as usize;
    let c = 0.5 * (w as f64 - 1.0);
    let [px, py] = lib.pitch_mm;
    let at = |ix: isize, iy: isize| -> f64 {
        let inside = (0..w as isize).contains(&ix) && (0..w as isize).contains(&iy);
        if inside {
            traced[iy as usize * w + ix as usize]
        } else {
            0.0
        }
    };
    let mut out = vec![0.0; w * w];
    for j in 0..w {
        for i in 0..w {
            // The pixel's offset from the centre (mm) in SIXTE's frame, turned
            // by φ onto the sensor, in the traced window's pixels.
            let (u, v) = ((i as f64 - c) * px, (j as f64 - c) * py);
            let x = c + (u * cos - v * sin) / px;
            let y = c + (u * sin + v * cos) / py;
            let (x0, y0) = (x.floor(), y.floor());
            let (fx, fy) = (x - x0, y - y0);
            let (x0, y0) = (x0 as isize, y0 as isize);
            out[j * w + i] = (1.0 - fy) * ((1.0 - fx) * at(x0, y0) + fx * at(x0 + 1, y0))
                + fy * ((1.0 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
        }
    }
    let sum: f64 = out.iter().sum();
    out.iter().map(|v| v / sum).collect()
}

/// The keywords of image `k`.
fn keys(lib: &PsfLibrary, image: &PsfImage, k: usize, provenance: &Provenance) -> Keys {
    let mut keys = Keys::default();
    if k > 0 {
        keys.int(
            "EXTVER",
            k as i64,
            "number of this PSF image among the PSF HDUs",
        );
    }
    keys.text("HDUCLASS", "OGIP", "format conforms to OGIP standard");
    keys.text("HDUDOC", "CAL/GEN/92-027", "OGIP memo on spatial PSFs");
    keys.text("HDUVERS", "1.0.0", "version of the format");
    keys.text("HDUCLAS1", "IMAGE", "");
    keys.text("HDUCLAS2", "PSF", "");
    keys.text("HDUCLAS3", "PREDICTED", "a raytrace");
    keys.text("HDUCLAS4", "NET", "normalised to a sum of 1 over the image");
    keys.text(
        "TELESCOP",
        &provenance_scene(provenance),
        "the scene traced",
    );
    keys.text("INSTRUME", &lib.sensor, "the sensor");
    keys.float("ENERGY", image.energy_kev * 1e3, "[eV] photon energy");
    keys.float("ENERG_LO", image.energy_kev, "[keV]");
    keys.float("ENERG_HI", image.energy_kev, "[keV]");
    keys.float("THETA", image.angle_arcmin, "[arcmin] off-axis angle");
    keys.float("PHI", image.azimuth_deg, "[deg] azimuth of the tilt");
    keys.float(
        "FOCALLEN",
        lib.focal_length_mm * M_PER_MM,
        "[m] focal length",
    );
    let w = lib.window as f64;
    let centre = 0.5 * (w + 1.0);
    let (theta, phi) = (
        (image.angle_arcmin / 60.0).to_radians(),
        image.azimuth_deg.to_radians(),
    );
    // The window's centre pixel on the sensor (local mm): sensor pixel i
    // (from 0) has its centre at (i + 0.5)·pitch − size/2, and the window's
    // pixel `centre` (from 1) is sensor pixel corner + centre − 1.
    let at: [f64; 2] = std::array::from_fn(|axis| {
        (image.corner[axis] as f64 + centre - 0.5) * lib.pitch_mm[axis] - 0.5 * lib.size_mm[axis]
    });
    // In SIXTE's frame of azimuth φ: turned back by φ, less (f·tan θ, 0).
    let (sin, cos) = phi.sin_cos();
    let turned = [cos * at[0] + sin * at[1], -sin * at[0] + cos * at[1]];
    let offset = [turned[0] - lib.focal_length_mm * theta.tan(), turned[1]];
    turn_keys(&mut keys, image.azimuth_deg);
    for (axis, name) in [(0usize, "X"), (1, "Y")] {
        let n = axis + 1;
        let pitch = lib.pitch_mm[axis];
        let at = at[axis];
        keys.text(
            &format!("CTYPE{n}"),
            &format!("DET{name}"),
            "detector coordinates",
        );
        keys.text(&format!("CUNIT{n}"), "m", "");
        keys.float(&format!("CRPIX{n}"), centre, "the window's centre pixel");
        keys.float(
            &format!("CRVAL{n}"),
            offset[axis] * M_PER_MM,
            "[m] SIXTE frame: offset from (f tan THETA, 0)",
        );
        keys.float(&format!("CDELT{n}"), pitch * M_PER_MM, "[m] pixel pitch");
        keys.text(
            &format!("CTYPE{n}A"),
            name,
            "position on the sensor (local axes)",
        );
        keys.text(&format!("CUNIT{n}A"), "mm", "");
        keys.float(&format!("CRPIX{n}A"), centre, "");
        keys.float(
            &format!("CRVAL{n}A"),
            at,
            "[mm] the centre pixel on the sensor",
        );
        keys.float(&format!("CDELT{n}A"), pitch, "[mm]");
    }
    keys.float(
        "PSFFRAC",
        image.enclosed(),
        "share of the sensor's flux in this window",
    );
    keys.int(
        "PSFPHOT",
        image.photons_recorded as i64,
        "photons recorded on the sensor",
    );
    provenance_keys(&mut keys, provenance, PSF_FILES[2]);
    keys
}

/// At φ ≠ 0 the image is turned back by φ: said (PSFROT) and undone in the
/// sensor's WCS A (its PC matrix turns by φ).
fn turn_keys(keys: &mut Keys, azimuth_deg: f64) {
    if azimuth_deg.rem_euclid(360.0) == 0.0 {
        return;
    }
    let (sin, cos) = azimuth_deg.to_radians().sin_cos();
    keys.float(
        "PSFROT",
        azimuth_deg,
        "[deg] window turned back by PHI, bilinear",
    );
    for (name, value) in [
        ("PC1_1A", cos),
        ("PC1_2A", -sin),
        ("PC2_1A", sin),
        ("PC2_2A", cos),
    ] {
        keys.float(name, value, "the turn by PHI onto the sensor");
    }
}

/// The scene's file stem, for TELESCOP.
fn provenance_scene(p: &Provenance) -> String {
    p.scene_path
        .as_deref()
        .and_then(|s| Path::new(s).file_stem())
        .map_or("traxer".to_string(), |s| s.to_string_lossy().into_owned())
}
