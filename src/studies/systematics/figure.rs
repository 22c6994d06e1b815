//! The mirror figure's variations: parameter sets drawn from the covariance
//! the figure-error fit saved with the scene's preset. Parameters the fit left
//! unconstrained are held at the preset's values (the others drawn from their
//! distribution given them): a normal distribution of a parameter the targets
//! do not fix would move the image by whatever its range allows, not by what
//! the measurement says.

use super::plan::{Kind, Request, Variation};
use crate::material::Material;
use crate::scene::Scene;
use crate::xray::figure_covariance::values;

/// The figure draws for `scene`, or why there are none.
pub fn draws(
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
