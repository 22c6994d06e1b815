//! Units hint for imported meshes. traxer reads every coordinate as a millimetre,
//! but CAD exports often come in metres (glTF's own convention) or inches, and a
//! telescope 0.45 units long traces as a 0.45 mm toy without any error.
//!
//! Data flow: `traxer inspect` passes the largest extent of a file's bounding box
//! (and, if the user gave it, the size they expect) to [`hint`], which names the
//! suspected unit and the `{ scale = s }` transform step that fixes it.

/// A length unit a CAD file may be written in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unit {
    /// Symbol used in messages and JSON: "m", "in", ...
    pub symbol: &'static str,
    pub name: &'static str,
    /// Millimetres per unit: the scale to apply in the scene file.
    pub millimetres: f64,
}

/// The units considered, smallest first.
pub const UNITS: [Unit; 6] = [
    Unit {
        symbol: "um",
        name: "micrometres",
        millimetres: 0.001,
    },
    Unit {
        symbol: "mm",
        name: "millimetres",
        millimetres: 1.0,
    },
    Unit {
        symbol: "cm",
        name: "centimetres",
        millimetres: 10.0,
    },
    Unit {
        symbol: "in",
        name: "inches",
        millimetres: 25.4,
    },
    Unit {
        symbol: "ft",
        name: "feet",
        millimetres: 304.8,
    },
    Unit {
        symbol: "m",
        name: "metres",
        millimetres: 1000.0,
    },
];

/// Below this largest extent (in file units) nothing in a helioscope beamline is
/// plausible in millimetres: the smallest parts traced as whole files (sensor
/// chips, windows) are over a centimetre; in metres or inches they are below 5.
pub const SMALLEST_PLAUSIBLE_MM: f64 = 5.0;

/// Above this largest extent nothing is plausible in millimetres: the longest
/// helioscope magnet (IAXO) is about 20 m.
pub const LARGEST_PLAUSIBLE_MM: f64 = 30_000.0;

/// An expected size matches a unit when it lies within this factor of the file's
/// extent converted by the unit.
pub const MATCH_FACTOR: f64 = 1.5;

/// What [`hint`] concludes. Field names are JSON keys of `traxer inspect --json`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct UnitsHint {
    /// Longest edge of the bounding box, in file units.
    pub largest_extent: f64,
    /// The unit the file is probably in ("mm" when it looks right), if any.
    pub suspected_unit: Option<&'static str>,
    /// Scale to put first in the object's `transform` (`{ scale = s }`) so that the
    /// file becomes millimetres; `None` when no unit is suspected or it is mm.
    pub scale: Option<f64>,
    /// The same in words, for the text report.
    pub message: String,
}

/// Judges the units from the largest extent of the bounding box (file units) and,
/// optionally, the size in millimetres the user expects that extent to have.
pub fn hint(largest_extent: f64, expected_mm: Option<f64>) -> UnitsHint {
    let l = largest_extent;
    let (metres, inches) = (unit("m"), unit("in"));
    let as_mm = |u: Unit| format!("{} mm", round(l * u.millimetres));
    let fix = |u: Unit| {
        format!(
            "add `{{ scale = {:?} }}` as the first step of the object's `transform`",
            u.millimetres
        )
    };
    let suspect = |u: Unit, message: String| UnitsHint {
        largest_extent: l,
        suspected_unit: Some(u.symbol),
        scale: (u.symbol != "mm").then_some(u.millimetres),
        message,
    };
    let unsure = |message: String| UnitsHint {
        largest_extent: l,
        suspected_unit: None,
        scale: None,
        message,
    };
    if !(l.is_finite() && l > 0.0) {
        return unsure(format!("largest extent {l}: no size to judge the units by"));
    }
    if let Some(want) = expected_mm {
        let ratio = want / l;
        let best = UNITS
            .into_iter()
            .min_by(|a, b| {
                let d = |u: &Unit| (ratio / u.millimetres).ln().abs();
                d(a).total_cmp(&d(b))
            })
            .expect("UNITS is not empty");
        return if (ratio / best.millimetres).ln().abs() <= MATCH_FACTOR.ln() {
            if best.symbol == "mm" {
                suspect(best, format!("largest extent {} mm matches the expected {} mm: the file is in millimetres", round(l), round(want)))
            } else {
                suspect(
                    best,
                    format!(
                        "largest extent {} units, expected {} mm: the file is in {}, which makes it {}: {}",
                        round(l),
                        round(want),
                        best.name,
                        as_mm(best),
                        fix(best)
                    ),
                )
            }
        } else {
            unsure(format!(
                "largest extent {} units, expected {} mm: a factor {} that matches no common unit (mm, cm, in, ft, m, um); check the export, or scale by {}",
                round(l), round(want), round(ratio), round(ratio)
            ))
        };
    }
    if l < SMALLEST_PLAUSIBLE_MM {
        suspect(
            metres,
            format!(
                "largest extent {} units: read as millimetres (as traxer does) that is too small for a telescope, magnet or detector part. \
                 The file is probably in metres (glTF's convention, and a common CAD export unit), which makes it {}: {}. (In inches it would be {}: scale 25.4.)",
                round(l),
                as_mm(metres),
                fix(metres),
                as_mm(inches)
            ),
        )
    } else if l > LARGEST_PLAUSIBLE_MM {
        suspect(
            unit("um"),
            format!(
                "largest extent {} units: read as millimetres that is {} m, larger than any helioscope. \
                 The file may be in micrometres: {}; {}.",
                round(l),
                round(l / 1000.0),
                as_mm(unit("um")),
                fix(unit("um"))
            ),
        )
    } else {
        UnitsHint {
            largest_extent: l,
            suspected_unit: Some("mm"),
            scale: None,
            message: format!(
                "largest extent {} mm: plausible in millimetres (in inches it would be {}, in metres {}; \
                 --expect-size MM checks against the size you expect)",
                round(l),
                as_mm(inches),
                as_mm(metres)
            ),
        }
    }
}

fn unit(symbol: &str) -> Unit {
    UNITS
        .into_iter()
        .find(|u| u.symbol == symbol)
        .expect("a unit of UNITS")
}

/// Four significant digits, without exponent noise for everyday sizes.
fn round(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = (3 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.digits$}")
}
