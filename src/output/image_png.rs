//! PNG pictures of sensor images through the viridis colour map.

use crate::files::atomic_write;
use std::path::Path;

/// How values map to colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    /// 0 → dark end of viridis, the maximum → bright end.
    Linear,
    /// log10, spanning `decades` below the maximum; zero pixels are dark.
    Log { decades: u32 },
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
    let max = data.iter().cloned().fold(0.0, f64::max);
    let mut img = image::RgbImage::new(nx as u32, ny as u32);
    for iy in 0..ny {
        for ix in 0..nx {
            let v = data[iy * nx + ix];
            let t = if max <= 0.0 || v <= 0.0 {
                0.0
            } else {
                match scale {
                    Scale::Linear => v / max,
                    Scale::Log { decades } => {
                        let d = decades.max(1) as f64;
                        ((v / max).log10() + d) / d
                    }
                }
            };
            let c = colorous::VIRIDIS.eval_continuous(t.clamp(0.0, 1.0));
            img.put_pixel(ix as u32, (ny - 1 - iy) as u32, image::Rgb([c.r, c.g, c.b]));
        }
    }
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .map_err(std::io::Error::other)?;
    atomic_write(path, &bytes)
}
