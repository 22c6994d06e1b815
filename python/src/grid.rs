//! `traxer.GridImage`: a sensor's image rebinned onto its detector pixel grid
//! (the GridPix's 256 × 256 pixels of 55 µm), flux conserved, as the CLI writes
//! NAME_grid.npy and NAME_grid.csv; reached as `SensorImage.grid`.

use crate::convert::array;
use pyo3::prelude::*;
use traxer::sensor::{PixelGrid, Rebinned};

/// A sensor's image on its detector pixel grid (the scene's `pixel_grid`),
/// summed over energy bands, flux conserved by overlap area. Equal to
/// NAME_grid.npy.
#[pyclass(module = "traxer", frozen, get_all)]
pub struct GridImage {
    /// Flux per grid pixel [iy, ix], in the sensor image's unit.
    pub flux: Py<PyAny>,
    /// (nx, ny) grid pixels.
    pub pixels: (u32, u32),
    /// The grid's pixel pitch, mm (square pixels).
    pub pitch_mm: f64,
    /// Degrees, counter-clockwise from the sensor's x axis to the grid's.
    pub rotation_deg: f64,
    /// The grid's centre on the sensor (local x, y), mm.
    pub center_mm: (f64, f64),
    /// Sensor x (mm) of each grid pixel's centre, [iy, ix] (a turned grid's
    /// centres are not a product of two axes).
    pub x_mm: Py<PyAny>,
    /// Sensor y (mm) of each grid pixel's centre, [iy, ix].
    pub y_mm: Py<PyAny>,
    /// The flux landing on the grid.
    pub flux_on_grid: f64,
    /// The flux of the sensor image outside the grid (never negative).
    pub flux_outside_grid: f64,
}

impl GridImage {
    pub fn new(py: Python<'_>, g: &PixelGrid, r: Rebinned) -> PyResult<GridImage> {
        let (gx, gy) = (g.pixels[0] as usize, g.pixels[1] as usize);
        let centres: Vec<[f64; 2]> = (0..gx * gy)
            .map(|k| g.pixel_center(k % gx, k / gx))
            .collect();
        let axis = |i: usize| centres.iter().map(|c| c[i]).collect::<Vec<f64>>();
        Ok(GridImage {
            flux_on_grid: r.flux.iter().sum(),
            flux_outside_grid: r.outside,
            flux: array(py, &[gy, gx], r.flux)?.unbind(),
            pixels: (g.pixels[0], g.pixels[1]),
            pitch_mm: g.pitch_mm,
            rotation_deg: g.rotation_deg,
            center_mm: (g.center_mm[0], g.center_mm[1]),
            x_mm: array(py, &[gy, gx], axis(0))?.unbind(),
            y_mm: array(py, &[gy, gx], axis(1))?.unbind(),
        })
    }
}

#[pymethods]
impl GridImage {
    fn __repr__(&self) -> String {
        format!(
            "traxer.GridImage({}×{} pixels of {} mm, flux on grid {:.6e}, outside {:.6e})",
            self.pixels.0, self.pixels.1, self.pitch_mm, self.flux_on_grid, self.flux_outside_grid
        )
    }
}
