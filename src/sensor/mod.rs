//! Image sensors: a pixel grid in an object's local x–y plane that absorbs photons
//! and accumulates their weights ("flux") and their number ("counts"), exactly
//! ([`exact`]), with the tallies a physicist asks of it: by photon path
//! ([`paths`]), by emission process, per axion mass of a magnet's mass scan
//! ([`masses`]), by conversion depth in a gas detector ([`conversion`]), and
//! the image rebinned onto the detector's pixel grid ([`rebin`]). `files` names
//! every file a sensor writes.
//!
//! Data flow: the scene build checks each object's sensor material ([`SensorDesc`])
//! and creates a [`SensorSpec`] for it; `trace` maps hits to pixels with
//! [`SensorSpec::pixel`] and adds each chunk's records to a [`SensorImage`] in any
//! order (the sums are exact); `analysis` measures it and `output` writes it. With energy
//! binning the image has an energy axis: [band][iy][ix].

pub mod campaign;
pub mod conversion;
mod desc;
pub mod exact;
mod files;
pub mod masses;
pub mod paths;
mod pixel_sums;
mod processes;
pub mod rebin;

pub use desc::{SensorDesc, MAX_TOTAL_PIXELS};
pub use exact::WeightSum;
pub use files::{
    check_file_names, class_file_names, file_stem, fits_file_name, grid_fits_file_name,
    mass_file_names, process_file_names, ConversionFiles, GridFiles, SensorFiles,
    MAX_FILE_NAME_BYTES, SUMMARY_FILE,
};
pub use paths::PathTally;
pub use pixel_sums::PixelSums;
pub use processes::ProcessTally;
pub use rebin::{rebin, PixelGrid, Rebinned};

use crate::history::PathClass;
use crate::xray::gas::DetectorGas;
use conversion::{ConversionRecord, ConversionTally};
use glam::DVec3;

/// Geometry of one sensor. Pixel (0, 0) is at local (−w/2, −h/2); ix grows with
/// local x, iy with local y. Images are stored row-major as [iy][ix].
#[derive(Clone, Debug, serde::Serialize)]
pub struct SensorSpec {
    /// Name of the object carrying the sensor (also the output file stem).
    pub name: String,
    /// Index of that object in the scene.
    pub object: usize,
    /// Active area (mm) along local x and y.
    pub size: [f64; 2],
    /// Pixels along local x and y.
    pub pixels: [u32; 2],
    /// Energy bands (keV): `min`, `max`, `count` equal bands; `None` = one image.
    pub energy_bins: Option<(f64, f64, u32)>,
    /// Focal length (mm) for angular image-quality numbers.
    pub focal_length: Option<f64>,
    /// A detector pixel grid the image is also rebinned to.
    pub pixel_grid: Option<PixelGrid>,
    /// Write one image per photon path class (NAME_front_rear.npy, ...).
    pub history_images: bool,
    /// The detector gas in front of the readout, if the sensor is a gaseous
    /// detector (the gas lies on the side the sensor's normal points to).
    #[serde(skip)]
    pub gas: Option<DetectorGas>,
    /// The source's processes (a Sun with Primakoff and ABC: "primakoff",
    /// "abc"), each recorded as an image of its own beside the total; empty
    /// for a source of one process.
    pub processes: Vec<String>,
    /// The axion masses (eV) of a magnet's mass scan, each recorded as an
    /// image of its own beside the total ([`masses`]); empty without a scan.
    pub masses: Vec<f64>,
}

impl SensorSpec {
    /// Every file a trace writes for this sensor.
    pub fn file_names(&self) -> Vec<String> {
        let owned = |files: &[&str]| files.iter().map(|f| f.to_string()).collect::<Vec<_>>();
        let mut names = owned(&SensorFiles::of(&self.name).all());
        if self.pixel_grid.is_some() {
            names.extend(owned(&GridFiles::of(&self.name).all()));
        }
        if self.history_images {
            names.extend(class_file_names(&self.name));
        }
        if self.gas.is_some() {
            names.extend(owned(&ConversionFiles::of(&self.name).all()));
        }
        names.extend(process_file_names(&self.name, &self.processes));
        if !self.masses.is_empty() {
            names.extend(mass_file_names(&self.name, !self.processes.is_empty()));
        }
        names
    }

    /// Linear pixel index of a local-frame point, or `None` outside the active area.
    #[inline]
    pub fn pixel(&self, local: DVec3) -> Option<u32> {
        let fx = (local.x / self.size[0] + 0.5) * self.pixels[0] as f64;
        let fy = (local.y / self.size[1] + 0.5) * self.pixels[1] as f64;
        if !(fx >= 0.0 && fy >= 0.0) {
            return None; // also rejects NaN
        }
        let (ix, iy) = (fx as u64, fy as u64);
        if ix >= self.pixels[0] as u64 || iy >= self.pixels[1] as u64 {
            return None;
        }
        Some((iy * self.pixels[0] as u64 + ix) as u32)
    }

    /// Pixel pitch (mm) along x and y.
    pub fn pitch(&self) -> [f64; 2] {
        [
            self.size[0] / self.pixels[0] as f64,
            self.size[1] / self.pixels[1] as f64,
        ]
    }

    /// Pixels of one image (one energy band).
    pub fn pixel_count(&self) -> usize {
        self.pixels[0] as usize * self.pixels[1] as usize
    }

    /// The image values a run holds for this sensor, toward the scene's cap
    /// [`MAX_TOTAL_PIXELS`]: pixels × bands, one image per path class with
    /// `history_images`, one per process of the source, its pixel grid's
    /// pixels × bands (made when written), and per mass of a mass scan the
    /// pixels × bands and one image per process.
    pub fn image_values(&self) -> u64 {
        let pixels = self.pixel_count() as u64;
        let bands = self.bands() as u64;
        let classes = if self.history_images {
            PathClass::ALL.len() as u64 * pixels
        } else {
            0
        };
        let grid = self
            .pixel_grid
            .as_ref()
            .map_or(0, |g| g.pixels[0] as u64 * g.pixels[1] as u64 * bands);
        let processes = self.processes.len() as u64 * pixels;
        let masses = self.masses.len() as u64 * (pixels * bands + processes);
        pixels * bands + classes + grid + processes + masses
    }

    /// Number of energy bands (1 without binning).
    pub fn bands(&self) -> usize {
        self.energy_bins.map_or(1, |b| b.2 as usize)
    }

    /// Index of the band holding `energy_kev` (0 without binning), or `None` if
    /// the energy is outside the binned range.
    #[inline]
    pub fn band(&self, energy_kev: f64) -> Option<u32> {
        let Some((lo, hi, n)) = self.energy_bins else {
            return Some(0);
        };
        if !(energy_kev >= lo && energy_kev <= hi) {
            return None;
        }
        Some((((energy_kev - lo) / (hi - lo) * n as f64) as u32).min(n - 1))
    }

    /// Band edges (keV), `count + 1` values, when binned.
    pub fn band_edges(&self) -> Option<Vec<f64>> {
        self.energy_bins.map(|(lo, hi, n)| {
            (0..=n)
                .map(|i| lo + (hi - lo) * i as f64 / n as f64)
                .collect()
        })
    }
}

/// An image stack [band][pixel] (`plane` pixels per band) summed over the bands,
/// band by band in order (so the sum is the same wherever it is computed).
pub fn sum_bands(stack: &[f64], plane: usize) -> Vec<f64> {
    let mut out = vec![0.0; plane];
    for band in stack.chunks_exact(plane.max(1)) {
        for (o, v) in out.iter_mut().zip(band) {
            *o += v;
        }
    }
    out
}

/// Accumulated image of one sensor.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SensorImage {
    /// Sum of photon weights per pixel, exact (see [`exact`]); [`SensorImage::flux`]
    /// gives it as floating-point numbers.
    pub flux_sum: PixelSums<WeightSum>,
    /// Number of photons per pixel.
    pub counts: PixelSums<u64>,
    /// The flux by photon path.
    pub paths: PathTally,
    /// Where the photons converted, for a sensor with a gas.
    pub conversion: Option<ConversionTally>,
    /// The flux by emission process ([`SensorSpec::processes`]).
    #[serde(default)]
    pub processes: ProcessTally,
    /// The flux for each mass of a mass scan ([`SensorSpec::masses`]).
    #[serde(default)]
    pub masses: masses::MassTally,
    /// Pixels per band plane.
    plane: usize,
}

impl SensorImage {
    /// Zeroed image with `bands()` × `pixel_count()` entries ([band][iy][ix]).
    pub fn new(spec: &SensorSpec) -> SensorImage {
        let n = spec.pixel_count() * spec.bands();
        SensorImage {
            flux_sum: PixelSums::new(n),
            counts: PixelSums::new(n),
            paths: PathTally::new(spec.history_images, spec.pixel_count()),
            conversion: spec.gas.as_ref().map(|g| ConversionTally::new(&g.desc)),
            processes: ProcessTally::new(spec.processes.len(), spec.pixel_count()),
            masses: masses::MassTally::new(
                spec.masses.len(),
                n,
                spec.processes.len(),
                spec.pixel_count(),
            ),
            plane: spec.pixel_count(),
        }
    }

    /// Sum of photon weights per pixel ([band][iy][ix]).
    pub fn flux(&self) -> Vec<f64> {
        self.flux_sum.iter().map(WeightSum::value).collect()
    }

    /// The image summed over energy bands.
    pub fn flux_summed(&self, spec: &SensorSpec) -> Vec<f64> {
        sum_bands(&self.flux(), spec.pixel_count())
    }

    // A photon is recorded in three parts, which a chunk's photons pass
    // through one part at a time (`trace::Tally::add_records`): each part is
    // a short loop, so the processor keeps many pixels' memory in flight at
    // once, where one long loop body waited for each. The sums are exact
    // integers: their order does not change a bit.

    /// A photon's part in the image and counts: its pixel (band included)
    /// and weight.
    #[inline]
    pub fn record_flux(&mut self, pixel: u32, weight: f64) {
        self.flux_sum
            .get_mut(pixel as usize)
            .add(WeightSum::of(weight));
        *self.counts.get_mut(pixel as usize) += 1;
    }

    /// A photon's part in the process and mass images: its shares among the
    /// processes and its weight factor per mass.
    #[inline]
    pub fn record_split(
        &mut self,
        (pixel, weight): (u32, f64),
        shares: &crate::source::ProcessWeights,
        mass_factors: &[f64],
    ) {
        let in_plane = pixel as usize % self.plane.max(1);
        self.processes
            .record(in_plane, (weight, WeightSum::of(weight)), shares);
        self.masses
            .record((pixel as usize, in_plane), weight, mass_factors, shares);
    }

    /// A photon's part in the path tallies (its class and first and last
    /// mirror) and, for a gas detector, the conversions (its energy and
    /// conversion).
    #[inline]
    pub fn record_path(
        &mut self,
        (pixel, weight): (u32, f64),
        (class, first, last): (PathClass, u32, u32),
        (energy_kev, conversion): (f64, Option<&ConversionRecord>),
    ) {
        if let (Some(tally), Some(c)) = (&mut self.conversion, conversion) {
            tally.record(weight, energy_kev, c);
        }
        let in_plane = pixel as usize % self.plane.max(1);
        self.paths
            .record(in_plane, WeightSum::of(weight), class, (first, last));
    }

    /// Adds the image of another part of the same run (exact, in any order).
    pub fn add(&mut self, other: &SensorImage) {
        self.flux_sum.add_with(&other.flux_sum, |a, b| a.add(b));
        self.counts.add_with(&other.counts, |a, b| *a += b);
        self.paths.add(&other.paths);
        self.processes.add(&other.processes);
        self.masses.add(&other.masses);
        if let (Some(a), Some(b)) = (&mut self.conversion, &other.conversion) {
            a.add(b);
        }
    }

    /// Total flux, summed exactly.
    pub fn total_flux(&self) -> f64 {
        let mut total = WeightSum::ZERO;
        for (_, s) in self.flux_sum.allocated() {
            total.add(s);
        }
        total.value()
    }

    pub fn total_counts(&self) -> u64 {
        self.counts.allocated().map(|(_, c)| c).sum()
    }
}
