//! Labels drawn onto a rendered picture (`traxer render --labels`): a dot on
//! the part and its name beside it, dark on a white halo so that it reads on
//! the sky, on metal and on the glowing sensor alike; a label that would cover
//! one placed before moves up or down, with a thin line back to its dot. Where
//! the dots go is the renderer's business (`render::part_labels`); this only
//! places the texts and draws them.

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
    let dots: Vec<(i32, i32)> = labels
        .iter()
        .map(|(_, (c, r))| (*c as i32, *r as i32))
        .collect();
    let sizes: Vec<(i32, i32)> = labels
        .iter()
        .map(|(text, _)| {
            area.estimate_text_size(text, &ink)
                .map(|(a, b)| (a as i32, b as i32))
                .unwrap_or((0, 0))
        })
        .collect();
    let places = place_labels(&sizes, &dots, (w as i32, h as i32), gap);
    // Drawing outside the picture is clipped by plotters, never an error worth
    // losing the render for.
    for (k, &(text, _)) in labels.iter().enumerate() {
        let ((x, y), (tx, ty), (tw, th)) = (dots[k], places[k], sizes[k]);
        if (ty + th / 2 - y).abs() > th {
            // Moved off its dot: a line from the dot to the text's near side.
            let ex = if tx > x { tx } else { tx + tw };
            let line = vec![(x, y), (ex, ty + th / 2)];
            let _ = area.draw(&PathElement::new(line.clone(), WHITE.stroke_width(3)));
            let _ = area.draw(&PathElement::new(line, BLACK.stroke_width(1)));
        }
        let _ = area.draw(&Circle::new((x, y), 3, WHITE.filled()));
        let _ = area.draw(&Circle::new((x, y), 2, BLACK.filled()));
        let _ = haloed(&area, text, (tx, ty), size as u32);
    }
    let _ = area.present();
}

/// Where each label's text goes (its top-left corner), for texts of `sizes`
/// (width, height) at `dots` in a `w` × `h` picture: right of the dot, else
/// left of it, vertically centred; where that would cover a label placed
/// before (or leave the picture), the nearest free place up or down, right or
/// left, up to ten lines away; failing that, right of the dot anyway.
pub fn place_labels(
    sizes: &[(i32, i32)],
    dots: &[(i32, i32)],
    (w, h): (i32, i32),
    gap: i32,
) -> Vec<(i32, i32)> {
    let mut placed: Vec<[i32; 4]> = Vec::new();
    let mut out = Vec::with_capacity(dots.len());
    for (&(x, y), &(tw, th)) in dots.iter().zip(sizes) {
        let clamp_y = |ty: i32| ty.clamp(0, (h - th).max(0));
        let right = x + gap;
        let left = (x - gap - tw).max(0);
        let sides = if right + tw <= w {
            [right, left]
        } else {
            [left, right]
        };
        let free = |(tx, ty): (i32, i32)| {
            let r = [tx - 2, ty - 1, tx + tw + 2, ty + th + 1];
            tx + tw <= w
                && placed
                    .iter()
                    .all(|p| r[2] <= p[0] || p[2] <= r[0] || r[3] <= p[1] || p[3] <= r[1])
        };
        let candidates = (0..=10).flat_map(|k: i32| {
            let shifts = if k == 0 { vec![0] } else { vec![-k, k] };
            shifts
                .into_iter()
                .flat_map(move |s| sides.map(|tx| (tx, clamp_y(y - th / 2 + s * (th + 2)))))
        });
        let mut chosen = (sides[0], clamp_y(y - th / 2));
        for c in candidates {
            if free(c) {
                chosen = c;
                break;
            }
        }
        placed.push([chosen.0, chosen.1, chosen.0 + tw, chosen.1 + th]);
        out.push(chosen);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::place_labels;

    #[test]
    fn labels_of_nearby_parts_do_not_overlap() {
        // Five long names on dots a few pixels apart (the parts of a telescope
        // seen from afar): every text box apart from every other.
        let sizes = vec![(180, 16); 5];
        let dots = vec![(200, 150), (204, 152), (198, 149), (210, 155), (202, 151)];
        let at = place_labels(&sizes, &dots, (480, 300), 6);
        for i in 0..at.len() {
            for j in 0..i {
                let (a, b) = (at[i], at[j]);
                let apart =
                    a.0 + 180 <= b.0 || b.0 + 180 <= a.0 || a.1 + 16 <= b.1 || b.1 + 16 <= a.1;
                assert!(apart, "labels {j} and {i} overlap: {b:?} and {a:?}");
            }
        }
        // A lone label stays beside its dot, vertically centred.
        assert_eq!(
            place_labels(&[(50, 10)], &[(100, 100)], (480, 300), 6),
            [(106, 95)]
        );
    }
}
