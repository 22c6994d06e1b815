//! Where a render's part labels go (`traxer render --labels`): one camera ray
//! through each pixel's centre finds which part of the scene the pixel shows; a
//! part's label sits on its visible pixel nearest the middle of those pixels, so
//! it lands on the part even when the part is a ring or half hidden. The Sun's
//! disk is labelled where the sky shows it. Drawing the text is the PNG
//! writer's job (`output::draw_labels`).

use super::camera::Frame;
use crate::raycast::intersect;
use crate::scene::{Camera, Scene};
use rayon::prelude::*;
use std::collections::BTreeMap;

/// A part's name and the pixel (column, row) its label points at.
#[derive(Clone, Debug, PartialEq)]
pub struct PartLabel {
    pub text: String,
    pub pixel: (usize, usize),
}

/// Parts covering fewer pixels than this share of the picture get no label:
/// their label would hide them and crowd the others.
const MIN_SHARE: f64 = 2e-4;

/// The labels of the parts (and the Sun) seen in a `width` × `height` picture.
pub fn part_labels(scene: &Scene, camera: &Camera, width: usize, height: usize) -> Vec<PartLabel> {
    let frame = Frame::new(camera, width as f64 / height as f64);
    // What each pixel shows: a part (borrowed from the scene), or None for the
    // Sun's disk (kept apart, so that an object named "Sun" is not mistaken
    // for it); rows in parallel, as the render's.
    let rows: Vec<Vec<(Option<&str>, usize)>> = (0..height)
        .into_par_iter()
        .map(|row| {
            (0..width)
                .filter_map(|col| {
                    let (origin, dir) = frame.ray(
                        (col as f64 + 0.5) / width as f64,
                        (row as f64 + 0.5) / height as f64,
                    );
                    match intersect(scene, origin, dir, None) {
                        Some(hit) => Some((Some(scene.objects[hit.object].part.as_str()), col)),
                        None => match &scene.sky.sun {
                            Some(sun) if dir.dot(sun.direction) >= sun.cos_radius => {
                                Some((None, col))
                            }
                            _ => None,
                        },
                    }
                })
                .collect()
        })
        .collect();
    let mut seen: BTreeMap<Option<&str>, Vec<(usize, usize)>> = BTreeMap::new();
    for (row, hits) in rows.into_iter().enumerate() {
        for (part, col) in hits {
            seen.entry(part).or_default().push((col, row));
        }
    }
    let min_pixels = (MIN_SHARE * (width * height) as f64).max(1.0);
    seen.into_iter()
        .filter(|(part, pixels)| part.is_none() || pixels.len() as f64 >= min_pixels)
        .map(|(part, pixels)| PartLabel {
            pixel: nearest_to_middle(&pixels),
            text: part.unwrap_or("Sun").to_string(),
        })
        .collect()
}

/// The pixel of the set nearest to the set's mean position.
fn nearest_to_middle(pixels: &[(usize, usize)]) -> (usize, usize) {
    let n = pixels.len() as f64;
    let mx = pixels.iter().map(|p| p.0 as f64).sum::<f64>() / n;
    let my = pixels.iter().map(|p| p.1 as f64).sum::<f64>() / n;
    let d2 = |p: &(usize, usize)| (p.0 as f64 - mx).powi(2) + (p.1 as f64 - my).powi(2);
    *pixels
        .iter()
        .min_by(|a, b| d2(a).total_cmp(&d2(b)))
        .expect("a part is seen in at least one pixel")
}
