//! Reading a FITS image for `traxer eef`: the first image HDU with data (the
//! primary, or the first extension holding an image), summed over a third
//! axis, with the pixel pitch from a linear WCS in mm (CDELT1/2 with CUNIT
//! "mm", as traxer writes) and the focal length from FOCALLEN if present.
//!
//! The file is copied into a private temporary folder first: CFITSIO reads
//! brackets, `!` and `+` in file names as its own syntax, so it only ever sees a
//! plain name of ours.

use fitsio::hdu::HduInfo;
use fitsio::FitsFile;
use std::path::Path;

/// An image read from FITS.
pub struct FitsImage {
    pub nx: usize,
    pub ny: usize,
    /// [iy][ix], summed over bands for a cube.
    pub summed: Vec<f64>,
    /// (x, y) pitch in mm, when the header has a WCS in mm.
    pub pitch_mm: Option<[f64; 2]>,
    /// Where `pitch_mm` was read (file and key), for messages.
    pub pitch_from: String,
    pub focal_length_mm: Option<f64>,
}

/// Reads the image of `path`; the error says what is wrong with the file.
pub fn read_fits_image(path: &Path) -> Result<FitsImage, String> {
    let shown = path.display();
    let tmp = tempfile::Builder::new()
        .prefix("traxer-fits-")
        .tempdir()
        .map_err(|e| format!("{shown}: {e}"))?;
    let plain = tmp.path().join("image.fits");
    std::fs::copy(path, &plain).map_err(|e| format!("{shown}: {e}"))?;
    let mut f = FitsFile::open(&plain).map_err(|e| format!("{shown}: not a FITS file ({e})"))?;
    let hdus = f.iter().count();
    for i in 0..hdus {
        let hdu = f.hdu(i).map_err(|e| format!("{shown}: HDU {i}: {e}"))?;
        let HduInfo::ImageInfo { shape, .. } = &hdu.info else {
            continue;
        };
        let (ny, nx) = match shape[..] {
            [ny, nx] | [_, ny, nx] => (ny, nx),
            [] => continue,
            _ => {
                return Err(format!(
                    "{shown}: HDU {i} has {} axes: expected an image of 2 (or 3, summed)",
                    shape.len()
                ))
            }
        };
        // A header can claim any size: check it against the file before
        // allocating (a few bytes of header must not ask for terabytes).
        let elements = shape
            .iter()
            .try_fold(1u64, |n, &k| n.checked_mul(k as u64))
            .unwrap_or(u64::MAX);
        let bytes = elements.saturating_mul(bytes_per_value(&hdu.info));
        let size = std::fs::metadata(&plain).map_or(0, |m| m.len());
        if bytes > size {
            let dims: Vec<String> = shape.iter().rev().map(|k| k.to_string()).collect();
            return Err(format!(
                "{shown}: HDU {i}'s header (NAXISn) claims an image of {} values, {bytes} bytes, but the file holds only {size} bytes: truncated or damaged",
                dims.join(" × ")
            ));
        }
        let data: Vec<f64> = hdu
            .read_image(&mut f)
            .map_err(|e| format!("{shown}: HDU {i}: {e}"))?;
        let mut key = |name: &str| hdu.read_key::<f64>(&mut f, name).ok();
        let (dx, dy) = (key("CDELT1"), key("CDELT2"));
        let focal_length_mm = key("FOCALLEN").filter(|v| v.is_finite() && *v > 0.0);
        let unit = |k: &str, f: &mut FitsFile| hdu.read_key::<String>(f, k).ok();
        let in_mm = unit("CUNIT1", &mut f).is_some_and(|u| u.trim() == "mm")
            && unit("CUNIT2", &mut f).is_some_and(|u| u.trim() == "mm");
        let pitch_mm = match (dx, dy) {
            (Some(x), Some(y)) if in_mm => Some([x.abs(), y.abs()]),
            _ => None,
        };
        return Ok(FitsImage {
            nx,
            ny,
            summed: crate::sensor::sum_bands(&data, nx * ny),
            pitch_mm,
            pitch_from: format!("{shown}: HDU {i}'s header keys CDELT1/CDELT2"),
            focal_length_mm,
        });
    }
    Err(format!("{shown}: no image HDU with data"))
}

/// Bytes per pixel value of an image HDU (BITPIX / 8).
fn bytes_per_value(info: &HduInfo) -> u64 {
    use fitsio::images::ImageType::*;
    match info {
        HduInfo::ImageInfo { image_type, .. } => match image_type {
            UnsignedByte | Byte => 1,
            Short | UnsignedShort => 2,
            Long | UnsignedLong | Float => 4,
            LongLong | Double => 8,
        },
        _ => 1,
    }
}
