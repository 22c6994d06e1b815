//! Which variations of the scene a systematics study traces: from the sources
//! of uncertainty asked for (or every one the scene supports) and the scene's
//! variables, the list of variations, each a set of `-D` overrides and, for
//! the mirror figure, a parameter set drawn from the preset's covariance.

use super::super::StudyError;
use crate::material::Material;
use crate::scene::Scene;
use crate::xray::elements::OpticalConstants;
use crate::xray::figure_covariance::{values, PARAMETERS as FIGURE_PARAMETERS};
use crate::xray::FigureError;
use serde::Serialize;

/// How a source's variations give its standard deviation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// Random draws: their sample standard deviation.
    Draws,
    /// A low and a high value, taken as ±1σ: the root mean square of their
    /// differences to the nominal value.
    Range,
    /// One alternative (another solar model): its difference to the nominal
    /// image, taken as 1σ.
    Alternative,
}

/// One source of uncertainty.
#[derive(Clone, Debug, Serialize)]
pub struct SourcePlan {
    /// Its name in the table (`figure`, `solar_model`, `pointing_x`, ...).
    pub name: String,
    pub kind: Kind,
    /// What is varied, in words, with the values.
    pub what: String,
}

/// One traced variation of the scene.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Variation {
    /// The source it belongs to (`nominal` for the unchanged scene).
    pub source: String,
    /// Which variation of it (`+1′`, `draw 3`, `b16_gs98`).
    pub label: String,
    /// The `-D NAME=VALUE` overrides it adds to the study's own.
    pub defines: Vec<String>,
    /// The mirrors' figure error, for a figure draw.
    pub figure: Option<FigureError>,
}

/// The study's plan: its sources and the variations, the nominal first.
#[derive(Clone, Debug, Serialize)]
pub struct Plan {
    pub sources: Vec<SourcePlan>,
    pub variations: Vec<Variation>,
    /// Sources the scene cannot vary (not asked for by name), with the reason.
    pub skipped: Vec<(String, String)>,
    /// Notes on the figure draws (held parameters, draws moved onto the
    /// parameters' domain).
    pub notes: Vec<String>,
}

/// What to vary.
#[derive(Clone, Debug)]
pub struct Request {
    /// Sources by name; `None`: every one the scene supports.
    pub sources: Option<Vec<String>>,
    /// Parameter sets drawn from the figure-error covariance.
    pub figure_draws: usize,
    /// The figure-error preset (default: the scene variable `figure_error`).
    pub figure_preset: Option<String>,
    /// Figure parameters held at the preset's values (the others drawn from
    /// their distribution given them); `None`: the preset's `unconstrained`.
    pub figure_hold: Option<Vec<String>>,
    /// The Sun's centre moved by ± this (arcmin) in x and in y.
    pub pointing_arcmin: f64,
    /// The telescope's axis tilted by ± this (arcmin) towards x and towards y.
    pub tilt_arcmin: f64,
    /// The alternative solar model.
    pub solar_model: String,
    /// The gas pressure's range (mbar); `None`: nominal ± 50 mbar.
    pub gas_pressure_mbar: Option<[f64; 2]>,
    /// The gas temperature's range (K); `None`: nominal ± 10 K.
    pub gas_temperature_k: Option<[f64; 2]>,
    /// Other scene variables with their ranges.
    pub vary: Vec<(String, [f64; 2])>,
    /// Seed of the figure draws.
    pub seed: u64,
}

/// The sources a study can vary, in the order of its table.
pub const SOURCES: [&str; 9] = [
    "figure",
    "optical_constants",
    "solar_model",
    "pointing_x",
    "pointing_y",
    "tilt_x",
    "tilt_y",
    "gas_pressure",
    "gas_temperature",
];

/// Default gas ranges around the scene's values: ± 50 mbar, ± 10 K.
pub const GAS_PRESSURE_SPAN_MBAR: f64 = 50.0;
pub const GAS_TEMPERATURE_SPAN_K: f64 = 10.0;

/// The option that sets a built-in source's range or alternative.
fn option_of(source: &str) -> Option<&'static str> {
    Some(match source {
        "solar_model" => "--solar-model",
        "pointing_x" | "pointing_y" => "--pointing",
        "tilt_x" | "tilt_y" => "--tilt",
        "gas_pressure" => "--gas-pressure",
        "gas_temperature" => "--gas-temperature",
        _ => return None,
    })
}

/// The scene variables a source sets (none for a `--vary` source, which the
/// variable names itself).
fn variables(source: &str) -> &'static [&'static str] {
    match source {
        "figure" => &[],
        "optical_constants" => &["mirror_optical_constants"],
        "solar_model" => &["solar_model"],
        "pointing_x" => &["offset_x"],
        "pointing_y" => &["offset_y"],
        "tilt_x" => &["telescope_tilt_x"],
        "tilt_y" => &["telescope_tilt_y"],
        "gas_pressure" => &["gas_pressure_mbar"],
        "gas_temperature" => &["gas_temperature_k"],
        _ => &[],
    }
}

/// The plan for `scene` (the nominal scene, loaded with the study's own
/// overrides).
pub fn plan(scene: &Scene, r: &Request) -> Result<Plan, StudyError> {
    let bad = |m: String| Err(StudyError::Input(m));
    if let Some(names) = &r.sources {
        if let Some(n) = names.iter().find(|n| !SOURCES.contains(&n.as_str())) {
            return bad(format!(
                "unknown source of uncertainty `{n}` (known: {}); vary any scene variable with --vary NAME=LOW:HIGH",
                SOURCES.join(", ")
            ));
        }
    }
    if r.figure_draws < 2
        && r.sources
            .as_ref()
            .is_none_or(|s| s.iter().any(|n| n == "figure"))
    {
        return bad(format!(
            "--figure-draws {}: the figure's standard deviation needs at least 2 draws (20 or more for a useful one); to leave the figure out, name the other sources with --sources",
            r.figure_draws
        ));
    }
    // An option that only one source reads names that source: a misspelt
    // --figure-preset must be refused, not the figure quietly skipped.
    let named_by_option = |source: &str| match source {
        "figure" => [
            ("--figure-preset", r.figure_preset.is_some()),
            ("--figure-hold", r.figure_hold.is_some()),
        ]
        .into_iter()
        .find(|(_, given)| *given)
        .map(|(o, _)| o),
        "gas_pressure" => r.gas_pressure_mbar.map(|_| "--gas-pressure"),
        "gas_temperature" => r.gas_temperature_k.map(|_| "--gas-temperature"),
        _ => None,
    };
    let mut p = Plan {
        sources: Vec::new(),
        variations: vec![Variation {
            source: "nominal".into(),
            label: "nominal".into(),
            defines: Vec::new(),
            figure: None,
        }],
        skipped: Vec::new(),
        notes: Vec::new(),
    };
    for source in SOURCES {
        let mut asked = r.sources.as_ref().map(|s| s.iter().any(|n| n == source));
        if let Some(option) = named_by_option(source) {
            if asked == Some(false) {
                return bad(format!(
                    "{option} is given but {source} is not among --sources: add it, or drop {option}"
                ));
            }
            asked = Some(true);
        }
        if asked == Some(false) {
            continue;
        }
        match variations_of(scene, r, source, &mut p.notes) {
            Ok((what, kind, vs)) => {
                p.sources.push(SourcePlan {
                    name: source.into(),
                    kind,
                    what,
                });
                p.variations.extend(vs);
            }
            Err(reason) if asked.is_none() => p.skipped.push((source.into(), reason)),
            Err(reason) => return bad(format!("cannot vary {source}: {reason}")),
        }
    }
    check_vary(r, &p.sources)?;
    for (name, range) in &r.vary {
        let (what, vs) = range_of(scene, name, *range, &format!("vary:{name}"), "")?;
        p.sources.push(SourcePlan {
            name: format!("vary:{name}"),
            kind: Kind::Range,
            what,
        });
        p.variations.extend(vs);
    }
    if p.sources.is_empty() {
        return bad("no source of uncertainty to vary: the scene supports none of those asked for (give --vary NAME=LOW:HIGH)".into());
    }
    Ok(p)
}

/// Refuses a `--vary` given twice or of a variable a planned source already
/// varies.
fn check_vary(r: &Request, sources: &[SourcePlan]) -> Result<(), StudyError> {
    let bad = |m: String| Err(StudyError::Input(m));
    for (k, (name, _)) in r.vary.iter().enumerate() {
        if r.vary[..k].iter().any(|(n, _)| n == name) {
            return bad(format!(
                "--vary {name} is given twice: one range per variable"
            ));
        }
        // Varied twice, the variable's effect would enter the total twice
        // (σ √2 too big where the two ranges agree).
        if let Some(src) = sources
            .iter()
            .find(|src| variables(&src.name).contains(&name.as_str()))
        {
            return bad(format!(
                "--vary {name}: the source {0} already varies `{name}`, and its effect would be counted twice; set {0}'s range with its own option{1}, or leave {0} out with --sources",
                src.name,
                option_of(&src.name).map_or(String::new(), |o| format!(" ({o})"))
            ));
        }
    }
    Ok(())
}

/// A source's variations, or why the scene cannot vary it.
fn variations_of(
    scene: &Scene,
    r: &Request,
    source: &str,
    notes: &mut Vec<String>,
) -> Result<(String, Kind, Vec<Variation>), String> {
    if let Some(v) = variables(source)
        .iter()
        .find(|v| !scene.vars.contains_key(**v))
    {
        return Err(format!("the scene has no variable `{v}`"));
    }
    let number = |v: &str| scene_number(scene, v);
    let around = |v: &str, d: f64| -> Result<[f64; 2], String> {
        let x = number(v)?;
        Ok([x - d, x + d])
    };
    let range = |var: &str, lh: [f64; 2], unit: &str| {
        range_of(scene, var, lh, source, unit)
            .map(|(w, vs)| (w, Kind::Range, vs))
            .map_err(|e| e.to_string())
    };
    match source {
        "figure" => figure_draws(scene, r, notes),
        "solar_model" | "optical_constants" => alternative(scene, r, source),
        "pointing_x" | "pointing_y" => {
            let var = variables(source)[0];
            // ±1′ is a placeholder, not a measured number: said where it is used.
            range(var, around(var, r.pointing_arcmin)?, "′").map(|(w, k, vs)| {
                (
                    format!(
                        "{w}; --pointing {}′: set it to your tracking's 1σ accuracy",
                        r.pointing_arcmin
                    ),
                    k,
                    vs,
                )
            })
        }
        "tilt_x" | "tilt_y" => {
            // The scene's tilt variables are in degrees.
            let var = variables(source)[0];
            range(var, around(var, r.tilt_arcmin / 60.0)?, "°").map(|(_, k, vs)| {
                (
                    format!(
                        "{var} ± {}′ (± {:.5}°); --tilt: set it to your alignment's 1σ",
                        r.tilt_arcmin,
                        r.tilt_arcmin / 60.0
                    ),
                    k,
                    vs,
                )
            })
        }
        "gas_pressure" => {
            let var = variables(source)[0];
            let lh = match r.gas_pressure_mbar {
                Some(lh) => lh,
                None => around(var, GAS_PRESSURE_SPAN_MBAR)?,
            };
            range(var, lh, " mbar")
        }
        _ => {
            let var = variables(source)[0];
            let lh = match r.gas_temperature_k {
                Some(lh) => lh,
                None => around(var, GAS_TEMPERATURE_SPAN_K)?,
            };
            range(var, lh, " K")
        }
    }
}

/// A source with one alternative: the solar model (`--solar-model`) or the
/// mirrors' optical constants (the other of the two tables).
fn alternative(
    scene: &Scene,
    r: &Request,
    source: &str,
) -> Result<(String, Kind, Vec<Variation>), String> {
    let var = variables(source)[0];
    let nominal = scene.vars[var].as_str().unwrap_or_default();
    let (other, what) = if source == "solar_model" {
        if nominal == r.solar_model {
            return Err(format!(
                "the scene already uses solar model `{nominal}`: nothing to compare"
            ));
        }
        let what = format!("solar model {} instead of {nominal}", r.solar_model);
        (r.solar_model.clone(), what)
    } else {
        // Two tables exist; the other one is the alternative. Henke against
        // Chantler moves the XMM module's area by −2 to +4 % over 1–10 keV
        // (docs/cast.md).
        let other = match OpticalConstants::parse(nominal) {
            Ok(OpticalConstants::Henke) => OpticalConstants::Chantler,
            Ok(OpticalConstants::Chantler) => OpticalConstants::Henke,
            Err(e) => return Err(format!("variable `{var}`: {e}")),
        };
        let what = format!(
            "the mirrors' optical constants (f1, f2) from {} instead of {nominal}",
            other.name()
        );
        (other.name().to_string(), what)
    };
    Ok((
        what,
        Kind::Alternative,
        vec![Variation {
            source: source.into(),
            label: other.clone(),
            defines: vec![format!("{var}={other}")],
            figure: None,
        }],
    ))
}

/// A scene variable's value as a number.
fn scene_number(scene: &Scene, var: &str) -> Result<f64, String> {
    match scene.vars.get(var) {
        Some(toml::Value::Float(x)) => Ok(*x),
        Some(toml::Value::Integer(i)) => Ok(*i as f64),
        Some(v) => Err(format!("variable `{var}` is {v}, not a number")),
        None => Err(format!("the scene has no variable `{var}`")),
    }
}

/// The two variations of `var` at `low` and `high`.
fn range_of(
    scene: &Scene,
    var: &str,
    [low, high]: [f64; 2],
    source: &str,
    unit: &str,
) -> Result<(String, Vec<Variation>), StudyError> {
    let nominal = scene_number(scene, var).map_err(|e| {
        let known: Vec<&str> = scene.vars.keys().map(String::as_str).collect();
        StudyError::Input(format!("{e} (the scene's variables: {})", known.join(", ")))
    })?;
    if !(low.is_finite() && high.is_finite() && low < high) {
        return Err(StudyError::Input(format!(
            "{var}: the range {low}:{high} must be LOW:HIGH with LOW < HIGH"
        )));
    }
    let at = |x: f64| Variation {
        source: source.into(),
        label: format!("{var} = {x}"),
        defines: vec![format!("{var}={x:?}")],
        figure: None,
    };
    Ok((
        format!("{var} from {low} to {high}{unit} (nominal {nominal})"),
        vec![at(low), at(high)],
    ))
}

/// The figure parameters' names, for messages.
pub fn figure_parameter_names() -> String {
    FIGURE_PARAMETERS.join(", ")
}

// The mirror figure's variations: parameter sets drawn from the covariance
// the figure-error fit saved with the scene's preset. Parameters the fit left
// unconstrained are held at the preset's values (the others drawn from their
// distribution given them): a normal distribution of a parameter the targets
// do not fix would move the image by whatever its range allows, not by what
// the measurement says.

/// The figure draws for `scene`, or why there are none.
fn figure_draws(
    scene: &Scene,
    r: &Request,
    notes: &mut Vec<String>,
) -> Result<(String, Kind, Vec<Variation>), String> {
    let preset = match (&r.figure_preset, scene.vars.get("figure_error")) {
        (Some(p), _) => p.clone(),
        (None, Some(toml::Value::String(p))) => p.clone(),
        _ => return Err(
            "the scene has no variable `figure_error` naming its preset: give --figure-preset NAME"
                .into(),
        ),
    };
    let (nominal, cov) = scene
        .figure_errors
        .with_covariance(&preset)
        .map_err(|e| e.to_string())?;
    let used = scene.objects.iter().any(|o| {
        matches!(&o.material, Material::Mirror { figure_error: Some(f), .. } if values(f) == values(&nominal))
    });
    if !used {
        return Err(format!(
            "no mirror of the scene has the figure error of preset `{preset}` (as loaded: set figure_error = \"{preset}\")"
        ));
    }
    if r.figure_draws < 2 {
        return Err(format!(
            "{} figure draws: a standard deviation needs at least 2 (20 or more for a useful one)",
            r.figure_draws
        ));
    }
    let held = r
        .figure_hold
        .clone()
        .unwrap_or_else(|| cov.unconstrained.clone());
    let Some(given) = cov.given(&held)? else {
        return Err(format!(
            "every parameter of preset `{preset}`'s covariance is held ({}): nothing to draw",
            held.join(", ")
        ));
    };
    let (sets, clipped) = given.draw(&nominal, r.figure_draws, r.seed)?;
    if !held.is_empty() {
        notes.push(format!(
            "figure: {} held at the preset's values{}; {} drawn given them",
            held.join(", "),
            match r.figure_hold {
                None => " (the fit found them unconstrained)",
                Some(_) => "",
            },
            given.parameters.join(", ")
        ));
    }
    if clipped > 0 {
        notes.push(format!(
            "figure: {clipped} of {} draws fell outside the parameters' domain and were moved onto its edge",
            r.figure_draws
        ));
    }
    let sd: Vec<String> = given
        .parameters
        .iter()
        .zip(0..)
        .map(|(p, k)| format!("{p} ± {:.3}", given.matrix[k][k].max(0.0).sqrt()))
        .collect();
    let variations = sets
        .into_iter()
        .enumerate()
        .map(|(k, f)| Variation {
            source: "figure".into(),
            label: format!("draw {}", k + 1),
            defines: Vec::new(),
            figure: Some(f),
        })
        .collect();
    Ok((
        format!(
            "{} parameter sets of preset `{preset}` drawn from its covariance ({})",
            r.figure_draws,
            sd.join(", ")
        ),
        Kind::Draws,
        variations,
    ))
}
