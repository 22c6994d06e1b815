//! The polar vertex grid shared by the tessellations of surfaces of revolution and
//! disks: rows along the axis (or radius), columns around an azimuth range.

use super::AzimuthRange;
use glam::DVec3;

/// Positions and triangles of a grid with `n_rows` + 1 rows and `n_phi` angular
/// steps over `azimuth` (the last column wraps onto the first for a full circle).
/// `vertex(row, phi_radians)` places each vertex. With `apex_first_row` the first
/// row is a single point repeated (a disk's centre), so its quads become triangles.
pub(crate) fn polar_grid(
    azimuth: &AzimuthRange,
    n_phi: usize,
    n_rows: usize,
    apex_first_row: bool,
    mut vertex: impl FnMut(usize, f64) -> DVec3,
) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let span = azimuth.span_deg().min(360.0);
    let cols = if azimuth.is_full() { n_phi } else { n_phi + 1 };
    let mut positions = Vec::with_capacity(cols * (n_rows + 1));
    for j in 0..=n_rows {
        for i in 0..cols {
            let phi = (azimuth.start_deg() + span * i as f64 / n_phi as f64).to_radians();
            positions.push(vertex(j, phi));
        }
    }
    let mut triangles = Vec::with_capacity(2 * n_phi * n_rows);
    for j in 0..n_rows {
        for i in 0..n_phi {
            let i1 = (i + 1) % cols;
            let v00 = (j * cols + i) as u32;
            let v01 = (j * cols + i1) as u32;
            let v10 = ((j + 1) * cols + i) as u32;
            let v11 = ((j + 1) * cols + i1) as u32;
            if !(apex_first_row && j == 0) {
                triangles.push([v00, v01, v11]);
            }
            triangles.push([v00, v11, v10]);
        }
    }
    (positions, triangles)
}
