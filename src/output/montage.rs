//! Side-by-side pictures: PNG tiles (sensor images, plots) scaled to one size,
//! laid out in a grid with a caption above each, written as one PNG. Used for
//! comparisons such as perfect vs figure-error mirrors.

use super::plot::register_font;
use super::write_rgb_png;
use plotters::prelude::*;
use std::path::Path;

/// One tile: caption and the PNG file to show.
pub struct Tile<'a> {
    pub caption: String,
    pub png: &'a Path,
}

const CAPTION_HEIGHT: u32 = 28;

/// Writes `tiles` row by row, `columns` per row, each scaled to `tile_width` ×
/// `tile_height` pixels (aspect ratio kept, centred on white) under its caption.
pub fn write_montage(
    path: &Path,
    tiles: &[Tile],
    columns: usize,
    tile_width: u32,
    tile_height: u32,
) -> std::io::Result<()> {
    let columns = columns.max(1);
    let rows = tiles.len().div_ceil(columns) as u32;
    let cell_h = tile_height + CAPTION_HEIGHT;
    let (w, h) = (tile_width * columns as u32, cell_h * rows);
    let mut canvas = image::RgbImage::from_pixel(w, h, image::Rgb([255, 255, 255]));
    for (k, t) in tiles.iter().enumerate() {
        let img = image::open(t.png)
            .map_err(|e| std::io::Error::other(format!("{}: {e}", t.png.display())))?
            .to_rgb8();
        let scaled = image::imageops::resize(
            &img,
            tile_width,
            tile_height,
            image::imageops::FilterType::Triangle,
        );
        // `resize` fills the box exactly; keep the aspect ratio instead.
        let (iw, ih) = img.dimensions();
        let f = (tile_width as f64 / iw as f64).min(tile_height as f64 / ih as f64);
        let (sw, sh) = (
            ((iw as f64 * f).round() as u32).max(1),
            ((ih as f64 * f).round() as u32).max(1),
        );
        let scaled = if (sw, sh) == scaled.dimensions() {
            scaled
        } else {
            image::imageops::resize(&img, sw, sh, image::imageops::FilterType::Triangle)
        };
        let x = (k % columns) as u32 * tile_width + (tile_width - sw) / 2;
        let y = (k / columns) as u32 * cell_h + CAPTION_HEIGHT + (tile_height - sh) / 2;
        image::imageops::replace(&mut canvas, &scaled, x as i64, y as i64);
    }
    register_font();
    {
        let mut buf = canvas.into_raw();
        {
            let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
            let style = ("sans-serif", 18).into_font().color(&BLACK);
            for (k, t) in tiles.iter().enumerate() {
                let x = (k % columns) as i32 * tile_width as i32 + 8;
                let y = (k / columns) as i32 * cell_h as i32 + 5;
                root.draw(&Text::new(t.caption.clone(), (x, y), style.clone()))
                    .map_err(|e| std::io::Error::other(format!("caption: {e}")))?;
            }
            root.present()
                .map_err(|e| std::io::Error::other(format!("caption: {e}")))?;
        }
        canvas = image::RgbImage::from_raw(w, h, buf).expect("buffer of the right size");
    }
    write_rgb_png(path, &canvas)
}
