//! The centre of an image that its edges cannot pull: the centroid within a
//! disk, the disk moved onto that centroid until it stays put. A plain
//! centroid follows whatever the sensor's edge cuts off the image's wings;
//! this one moves with the image as a whole (shift it, and the centre shifts
//! by as much, while the disk stays inside the sensor), which is what a
//! plate scale measured from image shifts needs.
//!
//! Data flow: `studies::sky` measures where the sky images with it; tests
//! measure traced images with it (from `NAME.npy` via [`image_points`]).

use super::ImageGeometry;

/// Iterations at most; the disk stops moving long before (a few).
const ITERATIONS: usize = 100;

/// The centroid of the weighted points `(x, y, w)` within `radius` of itself,
/// found from the plain centroid; `None` without weight.
pub fn windowed_centroid(points: &[(f64, f64, f64)], radius: f64) -> Option<[f64; 2]> {
    let centroid = |inside: &dyn Fn(f64, f64) -> bool| {
        let (mut sw, mut sx, mut sy) = (0.0, 0.0, 0.0);
        for &(x, y, w) in points {
            if inside(x, y) {
                sw += w;
                sx += w * x;
                sy += w * y;
            }
        }
        (sw > 0.0).then(|| [sx / sw, sy / sw])
    };
    let mut c = centroid(&|_, _| true)?;
    for _ in 0..ITERATIONS {
        let r2 = radius * radius;
        let next = centroid(&|x, y| (x - c[0]).powi(2) + (y - c[1]).powi(2) <= r2)?;
        let moved = (next[0] - c[0]).hypot(next[1] - c[1]);
        c = next;
        if moved <= 1e-12 * radius {
            break;
        }
    }
    Some(c)
}

/// The pixels of `image` that hold flux, as points at their centres.
pub fn image_points(image: &[f64], g: &ImageGeometry) -> Vec<(f64, f64, f64)> {
    image
        .iter()
        .enumerate()
        .filter(|(_, &v)| v > 0.0)
        .map(|(k, &v)| {
            let (x, y) = g.center(k % g.nx, k / g.nx);
            (x, y, v)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A symmetric blob with a far, lopsided wing: the plain centroid is pulled
    /// by the wing, the windowed one finds the blob's centre; shifting every
    /// point shifts it by as much.
    #[test]
    fn the_windowed_centroid_ignores_a_far_wing_and_moves_with_the_image() {
        let mut pts: Vec<(f64, f64, f64)> = Vec::new();
        for i in -10..=10 {
            for j in -10..=10 {
                let (x, y) = (0.1 * i as f64, 0.1 * j as f64);
                pts.push((x + 1.0, y - 0.5, (-(x * x + y * y)).exp()));
            }
        }
        pts.push((6.0, 0.0, 5.0));
        let c = windowed_centroid(&pts, 2.0).unwrap();
        assert!(
            (c[0] - 1.0).abs() < 1e-12 && (c[1] + 0.5).abs() < 1e-12,
            "{c:?}"
        );
        let shifted: Vec<_> = pts.iter().map(|&(x, y, w)| (x + 0.3, y - 0.2, w)).collect();
        let s = windowed_centroid(&shifted, 2.0).unwrap();
        assert!(
            (s[0] - 1.3).abs() < 1e-12 && (s[1] + 0.7).abs() < 1e-12,
            "{s:?}"
        );
    }
}
