//! FITS images for astronomers (`trace --fits`): each sensor's flux image as the
//! primary image (float64) of `NAME.fits`, with a header that places it in mm on
//! the sensor and, at the sensor's focal length, in arcseconds; energy-binned
//! sensors as a cube [band, y, x] with an energy axis.
//!
//! Data flow: [`super::write_run`] calls [`write_sensor_fits`] with the same flux
//! array it writes as `NAME.npy`, so the two hold the same numbers.
//!
//! CFITSIO (through the `fitsio` crate) writes the file into a private temporary
//! folder: it takes file names with its own syntax (brackets, `!`, `mem://`), so it
//! is only ever given a plain name of ours; the bytes are then written to the
//! results folder atomically like every other output.
//!
//! The header, in FITS pixel terms (pixel (1, 1) is numpy's `image[0, 0]`, the
//! corner at local (−size_x/2, −size_y/2), +x along the sensor's local x):
//! - WCS (primary): `X`/`Y` in mm on the sensor, the pixel centres exactly
//!   (CRPIX = 1 at the first pixel's centre, CDELT = pitch);
//! - WCS `A` ("FOCAL PLANE ANGLE"): `XANG`/`YANG` in arcsec, the plate scale
//!   206264.806″ / f per mm at the sensor's focal length f (the small-angle
//!   scale: atan(x/f) is smaller by (x/f)²/3 relative, 7e-6 at the edge of a
//!   14 mm sensor at 1.5 m) — a definition, not the sky; only when the sensor
//!   has a focal length;
//! - WCS `S` ("HELIOPROJECTIVE"), for a Sun scene: `HPLN-TAN`/`HPLT-TAN` in
//!   arcsec from the Sun's centre, from the map `studies::sky` measures by
//!   tracing (see [`sky_axes`]);
//! - energy-binned: axis 3 `ENERGY` in keV at the band centres;
//! - BUNIT, E_MIN/E_MAX (keV), and the provenance as keywords (the whole record,
//!   with the command line and the variables, is in `NAME.json`).

use super::Provenance;
use crate::constants::ARCSEC_PER_RAD;
use crate::files::atomic_write;
use crate::sensor::SensorSpec;
use crate::studies::sky::SkyCalibration;
use fitsio::images::{ImageDescription, ImageType};
use fitsio::FitsFile;
use std::path::Path;

/// What the pixel values are: FITS unit string and its explanation.
pub struct FluxUnit {
    pub bunit: &'static str,
    pub comment: &'static str,
}

/// One sensor's image and what its header says about it.
pub struct SensorFits<'a> {
    pub spec: &'a SensorSpec,
    /// [band][iy][ix], the array of `NAME.npy`.
    pub flux: &'a [f64],
    pub unit: FluxUnit,
    /// Energy range of the image (keV): the sensor's bins, or the sources' spectra.
    pub energy_kev: (f64, f64),
    pub provenance: &'a Provenance,
    /// The sensor's JSON file, which holds the whole provenance record.
    pub json_name: &'a str,
    /// Where the sky images on the sensor (a Sun scene), for the WCS `S`.
    pub sky: Option<&'a SkyCalibration>,
    /// The image of each emission process (name, [iy][ix] summed over bands),
    /// written as image extensions named after the process.
    pub processes: &'a [(String, Vec<f64>)],
}

/// An image extension: its name, dimensions (slowest first), data and keys.
pub(super) struct Extension<'a> {
    pub name: String,
    pub dims: Vec<usize>,
    pub data: &'a [f64],
    pub keys: Keys,
}

/// Writes a sensor's image as the FITS file `path`.
pub fn write_sensor_fits(path: &Path, image: &SensorFits) -> std::io::Result<()> {
    let spec = image.spec;
    let (nx, ny) = (spec.pixels[0] as usize, spec.pixels[1] as usize);
    // fitsio takes the dimensions slowest first, as numpy does.
    let dims: Vec<usize> = match spec.energy_bins {
        Some(_) => vec![spec.bands(), ny, nx],
        None => vec![ny, nx],
    };
    let pitch = spec.pitch();
    let first = [
        -0.5 * spec.size[0] + 0.5 * pitch[0],
        -0.5 * spec.size[1] + 0.5 * pitch[1],
    ];
    let mut keys = Keys::default();
    image_keys(&mut keys, image);
    mm_axes(
        &mut keys,
        first,
        pitch,
        "position on the sensor (local axes)",
    );
    angular_axes(&mut keys, image, first, pitch);
    let frame = PixelFrame {
        origin: first,
        m: [[pitch[0], 0.0], [0.0, pitch[1]]],
    };
    sky_axes(&mut keys, image, &frame);
    if let Some((lo, hi, n)) = spec.energy_bins {
        let width = (hi - lo) / n as f64;
        let axis = LinearAxis {
            ctype: "ENERGY",
            unit: "keV",
            first: lo + 0.5 * width,
            step: width,
        };
        for alt in ["", "A", "S"] {
            if alt.is_empty()
                || (alt == "A" && spec.focal_length.is_some())
                || (alt == "S" && image.sky.is_some())
            {
                keys.axis(3, alt, &axis, "photon energy band");
            }
        }
    }
    provenance_keys(&mut keys, image.provenance, image.json_name);
    let extensions = image
        .processes
        .iter()
        .map(|(name, data)| {
            let mut k = Keys::default();
            image_keys(&mut k, image);
            mm_axes(&mut k, first, pitch, "position on the sensor (local axes)");
            angular_axes(&mut k, image, first, pitch);
            sky_axes(&mut k, image, &frame);
            k.text(
                "PROCESS",
                name,
                "emission process of this image (summed over energy bands)",
            );
            Extension {
                name: name.to_uppercase(),
                dims: vec![ny, nx],
                data,
                keys: k,
            }
        })
        .collect();
    write_fits(path, &dims, image.flux, keys, extensions)
}

/// Writes a sensor's image on its detector pixel grid (`NAME_grid.npy`'s
/// array, summed over bands) as the FITS file `path`: axes in mm from the
/// grid's centre along the grid's axes, and the angles as for the sensor.
pub fn write_grid_fits(
    path: &Path,
    image: &SensorFits,
    grid: &crate::sensor::PixelGrid,
    flux: &[f64],
) -> std::io::Result<()> {
    let (gx, gy) = (grid.pixels[0] as usize, grid.pixels[1] as usize);
    let p = grid.pitch_mm;
    let first = [
        -0.5 * gx as f64 * p + 0.5 * p,
        -0.5 * gy as f64 * p + 0.5 * p,
    ];
    let mut keys = Keys::default();
    image_keys(&mut keys, image);
    mm_axes(&mut keys, first, [p, p], "position from the grid's centre");
    keys.float(
        "GRIDROT",
        grid.rotation_deg,
        "[deg] grid axes from the sensor's, ccw",
    );
    keys.float("GRIDCX", grid.center_mm[0], "[mm] grid centre, sensor x");
    keys.float("GRIDCY", grid.center_mm[1], "[mm] grid centre, sensor y");
    angular_axes(&mut keys, image, first, [p, p]);
    // Grid pixel → sensor-local: the grid's centre plus its turned axes.
    let (s, c) = grid.rotation_deg.to_radians().sin_cos();
    let frame = PixelFrame {
        origin: [
            grid.center_mm[0] + c * first[0] - s * first[1],
            grid.center_mm[1] + s * first[0] + c * first[1],
        ],
        m: [[c * p, -s * p], [s * p, c * p]],
    };
    sky_axes(&mut keys, image, &frame);
    provenance_keys(&mut keys, image.provenance, image.json_name);
    write_fits(path, &[gy, gx], flux, keys, Vec::new())
}

/// The primary WCS: X and Y in mm, `first` the first pixel's centre, `step`
/// the pitch.
pub(super) fn mm_axes(keys: &mut Keys, first: [f64; 2], step: [f64; 2], what: &str) {
    for (i, name) in ["X", "Y"].iter().enumerate() {
        let axis = LinearAxis {
            ctype: name,
            unit: "mm",
            first: first[i],
            step: step[i],
        };
        keys.axis(i + 1, "", &axis, what);
    }
}

/// The cards every image carries: its unit, sensor and energies.
fn image_keys(keys: &mut Keys, image: &SensorFits) {
    keys.text("BUNIT", image.unit.bunit, image.unit.comment);
    keys.text("DETNAME", &image.spec.name, "traxer sensor (object) name");
    keys.float(
        "E_MIN",
        image.energy_kev.0,
        "[keV] lowest energy in the image",
    );
    keys.float(
        "E_MAX",
        image.energy_kev.1,
        "[keV] highest energy in the image",
    );
}

/// With a focal length, the angular WCS `A`: the focal-plane angle (position /
/// focal length, along the image's axes). It is a definition, not the sky: a
/// real telescope's plate scale differs from f·θ (see [`sky_axes`]).
fn angular_axes(keys: &mut Keys, image: &SensorFits, first: [f64; 2], step: [f64; 2]) {
    let Some(f_mm) = image.spec.focal_length else {
        return;
    };
    let scale = ARCSEC_PER_RAD / f_mm;
    keys.text("WCSNAMEA", "FOCAL PLANE ANGLE", "position / focal length");
    for (i, name) in ["XANG", "YANG"].iter().enumerate() {
        let axis = LinearAxis {
            ctype: name,
            unit: "arcsec",
            first: first[i] * scale,
            step: step[i] * scale,
        };
        keys.axis(i + 1, "A", &axis, "focal-plane angle = position / f");
    }
    keys.float("FOCALLEN", f_mm, "[mm] focal length of the angular WCS");
}

/// FITS pixel (1-based) to sensor-local mm: local = origin + m · (p − 1).
struct PixelFrame {
    origin: [f64; 2],
    m: [[f64; 2]; 2],
}

/// The inverse of a 2 × 2 matrix (the callers' matrices are checked regular).
fn inverse(a: [[f64; 2]; 2]) -> [[f64; 2]; 2] {
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    [
        [a[1][1] / det, -a[0][1] / det],
        [-a[1][0] / det, a[0][0] / det],
    ]
}

fn product(a: [[f64; 2]; 2], b: [[f64; 2]; 2]) -> [[f64; 2]; 2] {
    [0, 1].map(|r| [0, 1].map(|c| a[r][0] * b[0][c] + a[r][1] * b[1][c]))
}

/// For a Sun scene, the WCS `S`: helioprojective coordinates (HPLN, HPLT, in
/// arcsec from the Sun's centre, gnomonic) from the map measured by tracing
/// (`studies::sky`): the reference pixel is where the Sun's centre images,
/// and CDELT·PC = J⁻¹·(pixel → mm), J the measured mm per arcsec, so the plate
/// scale, the detector's turn and the image's inversion are all in it. HPLN
/// runs along the scene's `offset_arcmin[0]` axis and HPLT along
/// `offset_arcmin[1]` (a right-handed sky, as seen from the detector): where
/// solar west and north lie depends on the day and hour of an observation,
/// which a scene does not have.
fn sky_axes(keys: &mut Keys, image: &SensorFits, frame: &PixelFrame) {
    let Some(sky) = image.sky else {
        return;
    };
    let to_sky = inverse(sky.mm_per_arcsec);
    let cd = product(to_sky, frame.m);
    let m_inv = inverse(frame.m);
    let d = [
        sky.centre_mm[0] - frame.origin[0],
        sky.centre_mm[1] - frame.origin[1],
    ];
    let crpix = [0, 1].map(|r| 1.0 + m_inv[r][0] * d[0] + m_inv[r][1] * d[1]);
    keys.text(
        "WCSNAMES",
        "HELIOPROJECTIVE",
        "sky from the Sun's centre, measured by tracing",
    );
    for (i, (ctype, what)) in [
        ("HPLN-TAN", "along the scene's offset_arcmin[0] axis"),
        ("HPLT-TAN", "along the scene's offset_arcmin[1] axis"),
    ]
    .iter()
    .enumerate()
    {
        let k = i + 1;
        let cdelt = cd[i][0].hypot(cd[i][1]);
        keys.text(&format!("CTYPE{k}S"), ctype, what);
        keys.text(&format!("CUNIT{k}S"), "arcsec", "");
        keys.float(
            &format!("CRPIX{k}S"),
            crpix[i],
            "where the Sun's centre images",
        );
        keys.float(&format!("CRVAL{k}S"), 0.0, "[arcsec] the Sun's centre");
        keys.float(&format!("CDELT{k}S"), cdelt, "[arcsec] per pixel");
        for (j, value) in cd[i].iter().enumerate() {
            keys.float(
                &format!("PC{k}_{}S", j + 1),
                value / cdelt,
                "measured scale, turn and inversion",
            );
        }
    }
    keys.float(
        "DSUN_OBS",
        sky.sun_distance_mm / 1000.0,
        "[m] distance from the Sun's centre",
    );
    keys.float(
        "SKYSCALE",
        sky.plate_scale_mm_per_arcmin(),
        "[mm/arcmin] measured plate scale (WCS S)",
    );
    keys.float(
        "SKYSCERR",
        sky.plate_scale_error(),
        "[mm/arcmin] its 1 sigma statistical error",
    );
    keys.float(
        "SKYROT",
        sky.rotation_deg(),
        "[deg] image of the sky's +HPLN, ccw from x",
    );
    keys.float(
        "SKYCERR",
        sky.centre_error_mm[0].hypot(sky.centre_error_mm[1]),
        "[mm] 1 sigma error of the Sun centre's image",
    );
    keys.float(
        "SKYSTEP",
        sky.step_arcmin,
        "[arcmin] pointing step of the measurement",
    );
    keys.int(
        "SKYPHOT",
        sky.photons_per_pointing as i64,
        "photons traced per pointing",
    );
}

/// Writes `data` of `dims` (slowest first) with `keys` as the FITS file `path`,
/// followed by the image `extensions`, atomically.
pub(super) fn write_fits(
    path: &Path,
    dims: &[usize],
    data: &[f64],
    keys: Keys,
    extensions: Vec<Extension>,
) -> std::io::Result<()> {
    let tmp = tempfile::Builder::new().prefix("traxer-fits-").tempdir()?;
    let tmp_file = tmp.path().join("image.fits");
    fits_file(&tmp_file, dims, data, keys, extensions)
        .map_err(|e| std::io::Error::other(format!("{}: writing FITS: {e}", path.display())))?;
    let bytes = without_primary_extname(std::fs::read(&tmp_file)?);
    atomic_write(path, &bytes)
}

fn fits_file(
    tmp_file: &Path,
    dims: &[usize],
    data: &[f64],
    keys: Keys,
    extensions: Vec<Extension>,
) -> fitsio::errors::Result<()> {
    let description = ImageDescription {
        data_type: ImageType::Double,
        dimensions: dims,
    };
    let mut f = FitsFile::create(tmp_file)
        .with_custom_primary(&description)
        .open()?;
    let hdu = f.primary_hdu()?;
    hdu.write_image(&mut f, data)?;
    write_keys(&mut f, &hdu, keys)?;
    for e in extensions {
        let description = ImageDescription {
            data_type: ImageType::Double,
            dimensions: &e.dims,
        };
        let hdu = f.create_image(e.name, &description)?;
        hdu.write_image(&mut f, e.data)?;
        write_keys(&mut f, &hdu, e.keys)?;
    }
    Ok(())
}

/// Writes `keys` into the header of `hdu`, in order.
pub(super) fn write_keys(
    f: &mut FitsFile,
    hdu: &fitsio::hdu::FitsHdu,
    keys: Keys,
) -> fitsio::errors::Result<()> {
    for (name, value) in keys.0 {
        match value {
            Value::Text(v, c) => hdu.write_key(f, &name, (v.as_str(), c.as_str()))?,
            Value::Float(v, c) => hdu.write_key(f, &name, (v, c.as_str()))?,
            Value::Int(v, c) => hdu.write_key(f, &name, (v, c.as_str()))?,
        }
    }
    Ok(())
}

/// The file without the `EXTNAME = '_PRIMARY'` card the fitsio crate puts in
/// a custom primary header (a primary HDU has no extension name; ds9 and
/// astropy show it). The card is cut out and the header's padding after END
/// grows by one card, so every offset after the header stays where it was.
pub(super) fn without_primary_extname(mut bytes: Vec<u8>) -> Vec<u8> {
    const CARD: usize = 80;
    let cards = bytes.len() / CARD;
    let end = (0..cards).find(|&i| bytes[i * CARD..].starts_with(b"END     "));
    let extname = (0..cards)
        .take_while(|&i| end.is_none_or(|e| i < e))
        .find(|&i| {
            let card = &bytes[i * CARD..(i + 1) * CARD];
            card.starts_with(b"EXTNAME =") && card.windows(10).any(|w| w == b"'_PRIMARY'")
        });
    if let (Some(x), Some(e)) = (extname, end) {
        // Cards x+1 ..= e (END) move up one; the freed card becomes padding.
        bytes.copy_within((x + 1) * CARD..(e + 1) * CARD, x * CARD);
        bytes[e * CARD..(e + 1) * CARD].fill(b' ');
    }
    bytes
}

/// The run's provenance as keywords (FITS strings hold 68 characters: longer
/// values are cut, and `PROVFILE` names the JSON file with all of it).
pub(super) fn provenance_keys(keys: &mut Keys, p: &Provenance, json_name: &str) {
    keys.text("ORIGIN", "traxer", "X-ray raytracer for axion helioscopes");
    keys.text(
        "CREATOR",
        &format!("traxer {} ({})", p.traxer_version, p.git_hash),
        "program and commit",
    );
    if let Some(e) = &p.embree_version {
        keys.text("EMBREE", e, "ray-intersection library");
    }
    keys.text(
        "DATE",
        &iso_date(p.finished_unix_s),
        "UTC when the run finished",
    );
    if let Some(path) = &p.scene_path {
        let name = Path::new(path)
            .file_name()
            .map_or(path.clone(), |n| n.to_string_lossy().into_owned());
        keys.text("SCENE", &name, "scene file");
    }
    if let Some(h) = &p.scene_sha256 {
        keys.text("SCENESHA", h, "SHA-256 of the scene file");
    }
    if !p.overrides.is_empty() {
        keys.text(
            "OVERRIDE",
            &p.overrides.join(" "),
            "-D overrides of scene variables",
        );
    }
    if let Some(s) = p.seed {
        keys.int("SEED", s as i64, "random seed");
    }
    if let Some(n) = p.photons {
        keys.int("PHOTONS", n as i64, "photons traced");
    }
    if let Some(first) = p.first_photon {
        keys.int("FIRSTPH", first as i64, "index of the first photon traced");
    }
    keys.text("PROVFILE", json_name, "complete provenance (JSON sidecar)");
}

/// A header card's value and comment.
enum Value {
    Text(String, String),
    Float(f64, String),
    Int(i64, String),
}

/// A linear WCS axis: its type and unit, the world coordinate of the first
/// pixel's centre (FITS pixel 1) and the step per pixel.
struct LinearAxis<'a> {
    ctype: &'a str,
    unit: &'a str,
    first: f64,
    step: f64,
}

/// Cards in the order they are written.
#[derive(Default)]
pub(super) struct Keys(Vec<(String, Value)>);

impl Keys {
    pub(super) fn text(&mut self, name: &str, value: &str, comment: &str) {
        self.0.push((
            name.into(),
            Value::Text(fits_string(value), fits_string(comment)),
        ));
    }
    pub(super) fn float(&mut self, name: &str, value: f64, comment: &str) {
        self.0
            .push((name.into(), Value::Float(value, fits_string(comment))));
    }
    /// The cards of axis `k` of the WCS with letter `alt` ("" for the primary).
    fn axis(&mut self, k: usize, alt: &str, a: &LinearAxis, what: &str) {
        let unit = a.unit;
        self.text(&format!("CTYPE{k}{alt}"), a.ctype, what);
        self.text(&format!("CUNIT{k}{alt}"), unit, "");
        self.float(&format!("CRPIX{k}{alt}"), 1.0, "the first pixel's centre");
        self.float(
            &format!("CRVAL{k}{alt}"),
            a.first,
            &format!("[{unit}] there"),
        );
        self.float(
            &format!("CDELT{k}{alt}"),
            a.step,
            &format!("[{unit}] per pixel"),
        );
    }

    pub(super) fn int(&mut self, name: &str, value: i64, comment: &str) {
        self.0
            .push((name.into(), Value::Int(value, fits_string(comment))));
    }
}

/// A FITS header string: printable ASCII only (anything else becomes `?`), at
/// most 68 characters (what one card holds).
fn fits_string(s: &str) -> String {
    s.chars()
        .map(|c| if (' '..='~').contains(&c) { c } else { '?' })
        .take(68)
        .collect()
}

/// `YYYY-MM-DDThh:mm:ss` (UTC) of a Unix time, the FITS DATE format; civil date
/// from the day count by the proleptic Gregorian calendar's 400-year cycle.
fn iso_date(unix_s: u64) -> String {
    let days = (unix_s / 86_400) as i64;
    let secs = unix_s % 86_400;
    // Days since 0000-03-01, so that leap days end a year.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}",
        secs / 3600,
        secs / 60 % 60,
        secs % 60
    )
}

#[cfg(test)]
mod tests {
    use super::{fits_string, iso_date};

    /// Dates checked against `date -u -d @SECONDS` (GNU coreutils).
    #[test]
    fn iso_dates_of_unix_times() {
        assert_eq!(iso_date(0), "1970-01-01T00:00:00");
        assert_eq!(iso_date(951_782_400), "2000-02-29T00:00:00");
        assert_eq!(iso_date(1_795_000_000), "2026-11-18T11:06:40");
        assert_eq!(iso_date(4_107_542_399), "2100-02-28T23:59:59");
        assert_eq!(iso_date(4_107_542_400), "2100-03-01T00:00:00");
    }

    #[test]
    fn header_strings_are_printable_ascii_and_fit_a_card() {
        assert_eq!(fits_string("Al Kα"), "Al K?");
        assert_eq!(fits_string(&"x".repeat(100)).len(), 68);
    }
}
