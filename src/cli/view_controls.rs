//! What the user does in the live window of `traxer view`: the camera they fly
//! ([`Flight`]: moving, turning with the mouse, printing it as a scene-file
//! table) and the help drawn over the picture ([`overlay`]).

use glam::DVec3;
use minifb::{InputCallback, Key, MouseButton, MouseMode, Window};
use std::cell::RefCell;
use std::rc::Rc;
use std::time::{Duration, Instant};
use traxer::render::Camera;

/// The help shown on screen (H or F1) and in `--help`.
pub const HELP: [&str; 11] = [
    "mouse drag   look around",
    "W A S D      move (or the arrow keys)",
    "E / Q        up / down",
    "PgUp / PgDn  speed x2 / /2",
    "R            back to the camera",
    "C            next camera of the scene",
    "F2           save sensor images + frame",
    "P            print the camera (TOML)",
    "L            name the parts",
    "H / F1       this help",
    "Esc          quit",
];
/// Every key press as it happens: a tap shorter than a frame (which polling the
/// key state between frames would miss) still counts.
struct Presses(Rc<RefCell<Vec<Key>>>);

impl InputCallback for Presses {
    fn add_char(&mut self, _: u32) {}

    fn set_key_state(&mut self, key: Key, down: bool) {
        if down {
            self.0.borrow_mut().push(key);
        }
    }
}

/// What the keys asked for besides flying.
pub struct Asked {
    pub save: bool,
    pub quit: bool,
}

/// The state of the user's input between frames.
pub struct Controls {
    pub flight: Flight,
    /// Which of the scene's cameras R returns to.
    which: usize,
    pub help: bool,
    /// Part labels on the picture (L).
    pub labels: bool,
    last_mouse: Option<(f32, f32)>,
    last_frame: Instant,
    moved_at: Instant,
    presses: Rc<RefCell<Vec<Key>>>,
}

impl Controls {
    /// Starts at `camera`, listening to `window`'s key presses.
    pub fn new(window: &mut Window, camera: &Camera, help: bool) -> Controls {
        let presses = Rc::new(RefCell::new(Vec::new()));
        window.set_input_callback(Box::new(Presses(presses.clone())));
        Controls {
            flight: Flight::new(camera),
            which: 0,
            help,
            labels: false,
            last_mouse: None,
            last_frame: Instant::now(),
            moved_at: Instant::now() - Duration::from_secs(1),
            presses,
        }
    }

    /// The camera moved in the last 150 ms (the picture is then drawn coarse).
    pub fn moving(&self) -> bool {
        self.moved_at.elapsed() < Duration::from_millis(150)
    }

    /// Reads the mouse and the keys since the last frame: flies, switches
    /// cameras, toggles the help, prints the camera; returns what else was asked.
    pub fn poll(&mut self, window: &Window, cams: &[Camera], height: usize) -> Asked {
        let dt = self.last_frame.elapsed().as_secs_f64().min(0.25);
        self.last_frame = Instant::now();
        let f = &mut self.flight;
        let mut moved = false;
        // Looking: drag with the left button.
        let mouse = window.get_mouse_pos(MouseMode::Pass);
        if window.get_mouse_down(MouseButton::Left) {
            if let (Some((x0, y0)), Some((x, y))) = (self.last_mouse, mouse) {
                if (x, y) != (x0, y0) {
                    f.look((x - x0) as f64, (y - y0) as f64, height as f64);
                    moved = true;
                }
            }
            self.last_mouse = mouse;
        } else {
            self.last_mouse = None;
        }
        // Moving: while keys are held.
        let right = f.forward.cross(f.up).normalize();
        let down = |keys: &[Key]| keys.iter().any(|k| window.is_key_down(*k));
        for (keys, dir) in [
            (&[Key::W, Key::Up][..], f.forward),
            (&[Key::S, Key::Down][..], -f.forward),
            (&[Key::D, Key::Right][..], right),
            (&[Key::A, Key::Left][..], -right),
            (&[Key::E][..], f.up),
            (&[Key::Q][..], -f.up),
        ] {
            if down(keys) {
                f.from += dir * f.speed * dt;
                moved = true;
            }
        }
        // One-shot keys: every press since the last frame.
        let presses: Vec<Key> = self.presses.borrow_mut().drain(..).collect();
        let pressed = |k: Key| presses.contains(&k);
        if pressed(Key::PageUp) {
            f.speed *= 2.0;
        }
        if pressed(Key::PageDown) {
            f.speed /= 2.0;
        }
        if pressed(Key::C) {
            self.which = (self.which + 1) % cams.len();
        }
        if pressed(Key::R) || pressed(Key::C) {
            self.flight = Flight::new(&cams[self.which]);
            moved = true;
        }
        if pressed(Key::H) || pressed(Key::F1) {
            self.help = !self.help;
        }
        if pressed(Key::L) {
            self.labels = !self.labels;
        }
        if pressed(Key::P) {
            say!("{}", self.flight.toml());
        }
        if moved {
            self.moved_at = Instant::now();
        }
        Asked {
            save: pressed(Key::F2),
            quit: pressed(Key::Escape) || window.is_key_down(Key::Escape),
        }
    }
}

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
    overlay_at(pixels, w, h, lines, false)
}

/// `overlay` in the top-left corner, or the bottom-left one with `bottom`.
pub fn overlay_at(pixels: &mut [u32], w: usize, h: usize, lines: &[&str], bottom: bool) {
    let scale = if w >= 800 { 2 } else { 1 };
    let height = lines.len() * 10 * scale + 12;
    let top = if bottom { h.saturating_sub(height) } else { 0 };
    text_box(pixels, (w, h), lines, (0, top), scale, 8);
}

/// The parts' names, each on a small dark box beside a white dot, the boxes
/// placed apart.
pub fn labels(pixels: &mut [u32], w: usize, h: usize, labels: &[(&str, (usize, usize))]) {
    // The boxes' sizes (8 × 8 font, 4 pixels of padding) and where they go:
    // apart from each other, as a render's labels (`output::place_labels`).
    let sizes: Vec<(i32, i32)> = labels
        .iter()
        .map(|(t, _)| ((t.len() * 8 + 8) as i32, 16))
        .collect();
    let dots: Vec<(i32, i32)> = labels
        .iter()
        .map(|(_, (x, y))| (*x as i32, *y as i32))
        .collect();
    let places = traxer::output::place_labels(&sizes, &dots, (w as i32, h as i32), 4);
    // A label with no free place is left out (the window has no room to say so).
    let placed = labels
        .iter()
        .zip(places)
        .filter_map(|(l, p)| p.map(|p| (l, p)));
    for (&(text, (x, y)), (left, top)) in placed {
        for (dx, dy) in (0..3).flat_map(|a| (0..3).map(move |b| (a, b))) {
            let (px, py) = ((x + dx).saturating_sub(1), (y + dy).saturating_sub(1));
            if px < w && py < h {
                pixels[py * w + px] = 0xffffff;
            }
        }
        text_box(
            pixels,
            (w, h),
            &[text],
            (left.max(0) as usize, top.max(0) as usize),
            1,
            4,
        );
    }
}

/// White text on a darkened box with its top-left corner at `(left, top)`, the
/// 8×8 font drawn `scale` times larger, `pad` pixels from the box's edges.
fn text_box(
    pixels: &mut [u32],
    (w, h): (usize, usize),
    lines: &[&str],
    (left, top): (usize, usize),
    scale: usize,
    pad: usize,
) {
    use font8x8::UnicodeFonts;
    let line_h = 10 * scale;
    let width = lines.iter().map(|l| l.len()).max().unwrap_or(0) * 8 * scale + 2 * pad;
    let height = lines.len() * line_h + pad + pad / 2;
    for y in top..(top + height).min(h) {
        for x in left..(left + width).min(w) {
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
                        let x = left + pad + (j * 8 + gx) * scale + sx;
                        let y = top + pad * 3 / 4 + i * line_h + gy * scale + sy;
                        if x < w && y < h {
                            pixels[y * w + x] = 0xffffff;
                        }
                    }
                }
            }
        }
    }
}
