//! Labels drawn onto a rendered picture (`traxer render --labels`): a dot on
//! the part and its name beside it, dark on a white halo so that it reads on
//! the sky, on metal and on the glowing sensor alike. Where the labels go is the
//! renderer's business (`render::part_labels`); this only draws them.

use super::image_plot::haloed;
use super::plot::register_font;
use plotters::prelude::*;

/// Draws each (text, (column, row)) label onto `img`.
pub fn draw_labels(img: &mut image::RgbImage, labels: &[(&str, (usize, usize))]) {
    register_font();
    let (w, h) = img.dimensions();
    let size = (h as f64 / 28.0).clamp(11.0, 28.0);
    let backend = BitMapBackend::with_buffer(img, (w, h));
    let area = backend.into_drawing_area();
    let ink = ("sans-serif", size).into_font().color(&BLACK);
    let gap = (size * 0.4) as i32;
    for &(text, (col, row)) in labels {
        let (x, y) = (col as i32, row as i32);
        let (tw, th) = area
            .estimate_text_size(text, &ink)
            .map(|(a, b)| (a as i32, b as i32))
            .unwrap_or((0, 0));
        // Right of the dot, or left of it where the text would leave the picture;
        // vertically centred on it, kept inside.
        let tx = if x + gap + tw < w as i32 {
            x + gap
        } else {
            (x - gap - tw).max(0)
        };
        let ty = (y - th / 2).clamp(0, (h as i32 - th).max(0));
        // Drawing outside the picture is clipped by plotters, never an error
        // worth losing the render for.
        let _ = area.draw(&Circle::new((x, y), 3, WHITE.filled()));
        let _ = area.draw(&Circle::new((x, y), 2, BLACK.filled()));
        let _ = haloed(&area, text, (tx, ty), size as u32);
    }
    let _ = area.present();
}
