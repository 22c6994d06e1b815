//! The sensor table of a scene file (`type = "sensor"` under `[materials]`) and
//! the check of its parameters, next to the [`SensorSpec`] it becomes.

use super::SensorSpec;
use serde::Deserialize;

/// The most pixels (times energy bands) one sensor may have: 2^26 f64 + u64
/// values are 1 GB.
const MAX_PIXELS: u64 = 1 << 26;

/// The most pixels (times energy bands) all sensors of a scene may have together:
/// 2^27 values of flux and counts are 2 GB, allocated once when a run starts.
pub const MAX_TOTAL_PIXELS: u64 = 1 << 27;

/// `energy_bins`: `[min, max, count]`, or `[]` for none.
fn bins_or_none<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Option<(f64, f64, u32)>, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Bins {
        Bands(f64, f64, u32),
        None([f64; 0]),
    }
    match Bins::deserialize(d) {
        Ok(Bins::Bands(lo, hi, n)) => Ok(Some((lo, hi, n))),
        Ok(Bins::None(_)) => Ok(None),
        Err(_) => Err(serde::de::Error::custom(
            "energy_bins = [min, max, count] (keV, keV, a whole number of bands), or [] for none",
        )),
    }
}

message_error!(
    /// A sensor table whose numbers describe no sensor, with what is wrong.
    InvalidSensor
);

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorDesc {
    pub size: [f64; 2],
    pub pixels: [u32; 2],
    /// Optional energy binning `[min, max, count]` (keV): the image gets an energy
    /// axis, one image per band. `[]` is none (a scene variable's default).
    #[serde(default, deserialize_with = "bins_or_none")]
    pub energy_bins: Option<(f64, f64, u32)>,
    /// Focal length (mm) of the optics in front of the sensor: image-quality
    /// diameters are then also given in arcseconds, 2·atan(r/f).
    #[serde(default)]
    pub focal_length: Option<f64>,
    /// A detector pixel grid (default: the GridPix, 256 × 256 pixels of 55 µm)
    /// the image is also written on, flux conserved: NAME_grid.npy, NAME_grid.csv.
    #[serde(default)]
    pub pixel_grid: Option<super::rebin::PixelGridDesc>,
    /// Also write one image per photon path class: NAME_direct.npy,
    /// NAME_front_rear.npy, NAME_front_only.npy, NAME_rear_only.npy, NAME_other.npy.
    #[serde(default)]
    pub history_images: bool,
    /// A gas volume in front of the readout (a gaseous detector): photons are
    /// recorded where they convert, projected along the drift onto the readout.
    #[serde(default)]
    pub gas: Option<crate::xray::gas::GasDesc>,
}

impl SensorDesc {
    /// The sensor of object number `object` named `name`, or what is wrong.
    pub fn spec(&self, name: &str, object: usize) -> Result<SensorSpec, InvalidSensor> {
        if !(self.size.iter().all(|v| v.is_finite() && *v > 0.0)) {
            return Err(InvalidSensor::from(
                "size must be two positive lengths (mm)",
            ));
        }
        let pixels = self.pixels[0] as u64 * self.pixels[1] as u64;
        if self.pixels.contains(&0) || pixels > MAX_PIXELS {
            return Err(InvalidSensor::from(
                "pixels must be positive, at most 2^26 (67 million) in all",
            ));
        }
        if self
            .focal_length
            .is_some_and(|f| !(f.is_finite() && f > 0.0))
        {
            return Err(InvalidSensor::from(
                "focal_length must be a positive length (mm)",
            ));
        }
        if let Some((lo, hi, n)) = self.energy_bins {
            if !(lo.is_finite() && hi.is_finite() && lo < hi && n >= 1)
                || pixels * n as u64 > MAX_PIXELS
            {
                return Err(InvalidSensor::from("energy_bins = [min, max, count] needs min < max (keV), count ≥ 1, and at most 2^26 pixels × bands"));
            }
        }
        let pixel_grid = match &self.pixel_grid {
            None => None,
            Some(g) => Some(g.grid().map_err(InvalidSensor)?),
        };
        let gas = match &self.gas {
            None => None,
            Some(g) => Some(
                crate::xray::gas::DetectorGas::new(g)
                    .map_err(|e| InvalidSensor(format!("gas: {e}")))?,
            ),
        };
        Ok(SensorSpec {
            name: name.to_string(),
            object,
            size: self.size,
            pixels: self.pixels,
            energy_bins: self.energy_bins,
            focal_length: self.focal_length,
            pixel_grid,
            history_images: self.history_images,
            gas,
            processes: Vec::new(),
            masses: Vec::new(),
        })
    }
}
