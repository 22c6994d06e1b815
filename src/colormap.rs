//! The viridis colour map and how values map onto it: shared by the sensor PNGs
//! (`output`) and by the sensor glow of visible-light renders (`render`), so both
//! show an image alike. A leaf: it depends on no other module.

/// How values map to colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    /// 0 → dark end of viridis, the maximum → bright end.
    Linear,
    /// log10, spanning `decades` below the maximum; zero pixels are dark.
    Log { decades: u32 },
}

/// Position (0–1) of `v` on the colour map of an image whose largest value is
/// `max`; 0 for zero, negative or NaN values and for an empty image.
pub fn position(v: f64, max: f64, scale: Scale) -> f64 {
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
    t.clamp(0.0, 1.0)
}

/// The sRGB colour of `v` (see [`position`]).
pub fn viridis(v: f64, max: f64, scale: Scale) -> [u8; 3] {
    let c = colorous::VIRIDIS.eval_continuous(position(v, max, scale));
    [c.r, c.g, c.b]
}

/// The largest value of an image (0 for an empty or all-negative one).
pub fn max_value(values: &[f64]) -> f64 {
    values.iter().cloned().fold(0.0, f64::max)
}
