//! Labels drawn onto a rendered picture (`traxer render --labels`): a dot on
//! the part and its name beside it, dark on a white halo so that it reads on
//! the sky, on metal and on the glowing sensor alike; a label that would cover
//! one placed before moves up or down, with a thin line back to its dot; a
//! name wider than the picture is cut with "…", and a label with no free
//! place anywhere is left out and named to the caller, never drawn over
//! another. Where
//! the dots go is the renderer's business (`render::part_labels`); this only
//! places the texts and draws them.

use super::image_plot::haloed;
use super::plot::register_font;
use plotters::prelude::*;

/// Draws each (text, (column, row)) label onto `img`; returns the texts of
/// those left out because no free place was left for them.
pub fn draw_labels(img: &mut image::RgbImage, labels: &[(&str, (usize, usize))]) -> Vec<String> {
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
    let size_of = |text: &str| {
        area.estimate_text_size(text, &ink)
            .map(|(a, b)| (a as i32, b as i32))
            .unwrap_or((0, 0))
    };
    // A name wider than the picture (less a margin) is cut to fit, with "…".
    let room = (w as i32 - 2 * gap - 4).max(1);
    let texts: Vec<String> = labels
        .iter()
        .map(|(text, _)| {
            let mut t = text.to_string();
            let mut n = t.chars().count();
            while n > 1 && size_of(&t).0 > room {
                n -= 1;
                t = text.chars().take(n).collect::<String>() + "…";
            }
            t
        })
        .collect();
    let sizes: Vec<(i32, i32)> = texts.iter().map(|t| size_of(t)).collect();
    let places = place_labels(&sizes, &dots, (w as i32, h as i32), gap);
    let mut left_out = Vec::new();
    // Drawing outside the picture is clipped by plotters, never an error worth
    // losing the render for.
    for (k, text) in texts.iter().enumerate() {
        let Some((tx, ty)) = places[k] else {
            left_out.push(labels[k].0.to_string());
            continue;
        };
        let ((x, y), (tw, th)) = (dots[k], sizes[k]);
        if (ty + th / 2 - y).abs() > th {
            // Moved off its dot: a line from the dot to the text's near side.
            let end = match (x < tx, x > tx + tw) {
                (true, _) => (tx, ty + th / 2),
                (_, true) => (tx + tw, ty + th / 2),
                // Centred over or under the dot: to its near edge.
                _ => (x, if ty > y { ty } else { ty + th }),
            };
            let line = vec![(x, y), end];
            let _ = area.draw(&PathElement::new(line.clone(), WHITE.stroke_width(3)));
            let _ = area.draw(&PathElement::new(line, BLACK.stroke_width(1)));
        }
        let _ = area.draw(&Circle::new((x, y), 3, WHITE.filled()));
        let _ = area.draw(&Circle::new((x, y), 2, BLACK.filled()));
        let _ = haloed(&area, text, (tx, ty), size as u32);
    }
    let _ = area.present();
    left_out
}

/// Where each label's text goes (its top-left corner), for texts of `sizes`
/// (width, height) at `dots` in a `w` × `h` picture: right of the dot, else
/// left of it, vertically centred; where that would cover a label placed
/// before, its own dot, or leave the picture, the nearest free place up or
/// down — right, left, or centred over the dot — as far as the picture goes;
/// failing that, `None`: the label is left out rather than drawn over another.
pub fn place_labels(
    sizes: &[(i32, i32)],
    dots: &[(i32, i32)],
    (w, h): (i32, i32),
    gap: i32,
) -> Vec<Option<(i32, i32)>> {
    let mut placed: Vec<[i32; 4]> = Vec::new();
    let mut out = Vec::with_capacity(dots.len());
    for (&(x, y), &(tw, th)) in dots.iter().zip(sizes) {
        let clamp_y = |ty: i32| ty.clamp(0, (h - th).max(0));
        // Right of the dot, left of it, or (a name too long for either side)
        // centred over it on another line, with its leader line.
        let (right, left) = (x + gap, x - gap - tw);
        let centred = (x - tw / 2).clamp(0, (w - tw).max(0));
        let sides = [right, left, centred];
        let free = |(tx, ty): (i32, i32)| {
            let r = [tx - 2, ty - 1, tx + tw + 2, ty + th + 1];
            // The text itself over the dot (radius 2), not its padding.
            let covers_dot = tx < x + 2 && x - 2 < tx + tw && ty < y + 2 && y - 2 < ty + th;
            tx >= 0
                && tx + tw <= w
                && !covers_dot
                && placed
                    .iter()
                    .all(|p| r[2] <= p[0] || p[2] <= r[0] || r[3] <= p[1] || p[3] <= r[1])
        };
        let lines = h / (th + 2).max(1) + 1;
        let candidates = (0..=lines).flat_map(|k: i32| {
            let shifts = if k == 0 { vec![0] } else { vec![-k, k] };
            shifts
                .into_iter()
                .flat_map(move |s| sides.map(|tx| (tx, clamp_y(y - th / 2 + s * (th + 2)))))
        });
        let chosen = candidates.into_iter().find(|&c| free(c));
        if let Some(c) = chosen {
            placed.push([c.0, c.1, c.0 + tw, c.1 + th]);
        }
        out.push(chosen);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::place_labels;

    /// Every placed box apart from every other.
    fn assert_apart(at: &[Option<(i32, i32)>], sizes: &[(i32, i32)]) {
        for i in 0..at.len() {
            for j in 0..i {
                let (Some(a), Some(b)) = (at[i], at[j]) else {
                    continue;
                };
                let ((aw, ah), (bw, bh)) = (sizes[i], sizes[j]);
                let apart =
                    a.0 + aw <= b.0 || b.0 + bw <= a.0 || a.1 + ah <= b.1 || b.1 + bh <= a.1;
                assert!(apart, "labels {j} and {i} overlap: {b:?} and {a:?}");
            }
        }
    }

    #[test]
    fn labels_of_nearby_parts_do_not_overlap() {
        // Five long names on dots a few pixels apart (the parts of a telescope
        // seen from afar): every text box apart from every other.
        let sizes = vec![(180, 16); 5];
        let dots = vec![(200, 150), (204, 152), (198, 149), (210, 155), (202, 151)];
        let at = place_labels(&sizes, &dots, (480, 300), 6);
        assert!(at.iter().all(Option::is_some));
        assert_apart(&at, &sizes);
        // A lone label stays beside its dot, vertically centred.
        assert_eq!(
            place_labels(&[(50, 10)], &[(100, 100)], (480, 300), 6),
            [Some((106, 95))]
        );
    }

    #[test]
    fn a_name_too_long_for_either_side_goes_above_or_below_its_dot_not_over_it() {
        // It used to be pushed against the left edge, over its own dot.
        let (x, y) = (290, 49);
        let at = place_labels(&[(460, 16)], &[(x, y)], (480, 300), 4);
        let (tx, ty) = at[0].expect("placed");
        assert!(tx >= 0 && tx + 460 <= 480, "{tx}");
        assert!(ty + 16 <= y - 2 || ty >= y + 2, "{ty}: over the dot at {y}");
    }

    #[test]
    fn labels_that_cannot_all_fit_are_left_out_not_drawn_over_each_other() {
        // Issue 59 §4: 40 long names on one spot of a 480 × 300 picture once
        // fell back to "right of the dot anyway", on top of each other. The
        // picture holds 2 columns × 16 lines of them at most.
        let sizes = vec![(200, 16); 40];
        let dots = vec![(240, 150); 40];
        let at = place_labels(&sizes, &dots, (480, 300), 6);
        assert_apart(&at, &sizes);
        let placed = at.iter().filter(|p| p.is_some()).count();
        assert!((16..=34).contains(&placed), "{placed} placed");
        assert!(at.iter().any(Option::is_none));
    }
}
