//! PNG files: sensor images through the viridis colour map, and the one helper
//! that encodes any RGB picture (plots, montages, renders) and writes it
//! atomically.

use crate::colormap::{max_value, viridis, Scale};
use crate::files::atomic_write;
use std::path::Path;

/// Encodes `img` as PNG and writes it atomically.
pub fn write_rgb_png(path: &Path, img: &image::RgbImage) -> std::io::Result<()> {
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .map_err(std::io::Error::other)?;
    atomic_write(path, &bytes)
}

/// Writes a `nx × ny` image stored row-major with row 0 at the *bottom* (lowest
/// local y), as in the `.npy` files; the PNG shows +y up.
pub fn write_png(
    path: &Path,
    nx: usize,
    ny: usize,
    data: &[f64],
    scale: Scale,
) -> std::io::Result<()> {
    let max = max_value(data);
    let mut img = image::RgbImage::new(nx as u32, ny as u32);
    for iy in 0..ny {
        for ix in 0..nx {
            let c = viridis(data[iy * nx + ix], max, scale);
            img.put_pixel(ix as u32, (ny - 1 - iy) as u32, image::Rgb(c));
        }
    }
    write_rgb_png(path, &img)
}
