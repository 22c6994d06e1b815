//! What the user does in the live window of `traxer view`: the camera they fly
//! ([`Flight`]: moving, turning with the mouse, printing it as a scene-file
//! table) and the help drawn over the picture ([`overlay`]).

use glam::DVec3;
use traxer::render::Camera;

/// The camera the user flies: position, viewing direction, the scene's up.
pub struct Flight {
    pub from: DVec3,
    pub forward: DVec3,
    pub up: DVec3,
    vfov: f64,
    /// Millimetres per second.
    pub speed: f64,
    /// Distance to the look-at point, for printing a camera.
    focus: f64,
}

impl Flight {
    pub fn new(c: &Camera) -> Flight {
        let d = c.look_at - c.look_from;
        Flight {
            from: c.look_from,
            forward: d.normalize(),
            up: c.up.normalize(),
            vfov: c.vfov,
            speed: 0.3 * d.length(),
            focus: d.length(),
        }
    }

    pub fn camera(&self) -> Camera {
        Camera {
            look_from: self.from,
            look_at: self.from + self.forward * self.focus,
            up: self.up,
            vfov: self.vfov,
        }
    }

    /// Turns by `dx`, `dy` pixels of mouse motion (`height` pixels = the field of
    /// view), never looking straight along `up`.
    pub fn look(&mut self, dx: f64, dy: f64, height: f64) {
        let per_pixel = self.vfov.to_radians() / height;
        let right = self.forward.cross(self.up).normalize();
        let yawed = rotate(self.forward, self.up, -dx * per_pixel);
        let pitched = rotate(yawed, right, -dy * per_pixel);
        if pitched.cross(self.up).length() > 0.02 {
            self.forward = pitched.normalize();
        } else {
            self.forward = yawed.normalize();
        }
    }

    /// The camera as a scene-file table.
    pub fn toml(&self) -> String {
        let c = self.camera();
        let v = |p: DVec3| format!("[{:.3}, {:.3}, {:.3}]", p.x, p.y, p.z);
        format!(
            "[cameras.view]\nlook_from = {}\nlook_at = {}\nup = {}\nvfov = {:.2}",
            v(c.look_from),
            v(c.look_at),
            v(c.up),
            c.vfov
        )
    }
}

/// `v` turned by `angle` (rad) about the unit `axis` (Rodrigues).
fn rotate(v: DVec3, axis: DVec3, angle: f64) -> DVec3 {
    let (s, c) = angle.sin_cos();
    v * c + axis.cross(v) * s + axis * axis.dot(v) * (1.0 - c)
}

/// Text lines drawn on a dark box in the top-left corner (8×8 font, doubled in
/// windows 800 pixels wide or more).
pub fn overlay(pixels: &mut [u32], w: usize, h: usize, lines: &[&str]) {
    use font8x8::UnicodeFonts;
    let scale = if w >= 800 { 2 } else { 1 };
    let line_h = 10 * scale;
    let width = lines.iter().map(|l| l.len()).max().unwrap_or(0) * 8 * scale + 16;
    let height = lines.len() * line_h + 12;
    for y in 0..height.min(h) {
        for x in 0..width.min(w) {
            let p = &mut pixels[y * w + x];
            *p = (*p >> 2) & 0x3f3f3f;
        }
    }
    for (i, line) in lines.iter().enumerate() {
        for (j, ch) in line.chars().enumerate() {
            let Some(glyph) = font8x8::BASIC_FONTS.get(ch) else {
                continue;
            };
            for (gy, row) in glyph.iter().enumerate() {
                for gx in 0..8 {
                    if row >> gx & 1 == 0 {
                        continue;
                    }
                    for (sy, sx) in (0..scale).flat_map(|a| (0..scale).map(move |b| (a, b))) {
                        let x = 8 + (j * 8 + gx) * scale + sx;
                        let y = 6 + i * line_h + gy * scale + sy;
                        if x < w && y < h {
                            pixels[y * w + x] = 0xffffff;
                        }
                    }
                }
            }
        }
    }
}
