//! Named figure-error presets: the shipped ones (data/figure_errors.toml, each
//! with how it was obtained and, where a fit estimated it, the parameters'
//! covariance) merged with a scene's `[figure_errors]`, and how a scene names a
//! figure error (a preset or the numbers inline).
//!
//! Data flow: `scene::build` resolves each mirror's figure error here into a
//! [`FigureError`]; the systematics study draws parameter sets from a preset's
//! [`FigureCovariance`].

use super::figure_covariance::FigureCovariance;
use super::figure_error::{FigureError, InvalidFigureError};
use serde::Deserialize;
use std::collections::BTreeMap;

const SHIPPED: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/data/figure_errors.toml"
));

/// Named figure-error presets.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FigureErrorLibrary {
    #[serde(default)]
    pub figure_errors: BTreeMap<String, FigureErrorEntry>,
}

/// A preset: the parameters plus where they came from.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct FigureErrorEntry {
    pub in_plane_narrow: f64,
    pub in_plane_wide: f64,
    pub wide_fraction: f64,
    pub out_of_plane: f64,
    /// How the numbers were obtained (free text; fits write their settings here).
    #[serde(default)]
    pub source: Option<String>,
    /// The fitted parameters' covariance, if the fit estimated it (see
    /// [`super::figure_covariance`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub covariance: Option<FigureCovariance>,
}

impl FigureErrorEntry {
    pub fn parameters(&self) -> FigureError {
        FigureError {
            in_plane_narrow: self.in_plane_narrow,
            in_plane_wide: self.in_plane_wide,
            wide_fraction: self.wide_fraction,
            out_of_plane: self.out_of_plane,
        }
    }
}

/// How a scene names a figure error: a preset, or the numbers inline.
#[derive(Clone, Debug, Deserialize)]
#[serde(untagged)]
pub enum FigureErrorSpec {
    Preset(String),
    Inline(FigureError),
}

impl FigureErrorLibrary {
    /// The presets shipped in data/figure_errors.toml.
    pub fn shipped() -> FigureErrorLibrary {
        toml::from_str(SHIPPED).expect("data/figure_errors.toml is valid (tested)")
    }

    /// This library with `other`'s presets added (`other` wins on equal names).
    pub fn merged(&self, other: &BTreeMap<String, FigureErrorEntry>) -> FigureErrorLibrary {
        let mut out = self.clone();
        out.figure_errors
            .extend(other.iter().map(|(k, v)| (k.clone(), v.clone())));
        out
    }

    /// Resolves a scene's figure error, checked; `None` for a perfect figure.
    pub fn resolve(
        &self,
        spec: &FigureErrorSpec,
    ) -> Result<Option<FigureError>, InvalidFigureError> {
        let f = match spec {
            FigureErrorSpec::Preset(name) => {
                if let Some(c) = self
                    .figure_errors
                    .get(name)
                    .and_then(|e| e.covariance.as_ref())
                {
                    c.checked()
                        .map_err(|e| InvalidFigureError(format!("figure error `{name}`: {e}")))?;
                }
                self.get(name)?
            }
            FigureErrorSpec::Inline(f) => *f,
        };
        f.validate()?;
        Ok((!f.is_perfect()).then_some(f))
    }

    /// The preset `name` with its covariance: refused if it has none, or if the
    /// covariance is not one (what is wrong, by name).
    pub fn with_covariance(
        &self,
        name: &str,
    ) -> Result<(FigureError, FigureCovariance), InvalidFigureError> {
        let f = self.get(name)?;
        let entry = self.figure_errors.get(name);
        let c = entry.and_then(|e| e.covariance.clone()).ok_or_else(|| {
            InvalidFigureError(format!(
                "figure error `{name}` has no covariance: run `traxer fit-figure-error` with --target-error and use its figure_error.toml, or add [figure_errors.{name}.covariance] (docs/telescope.md)"
            ))
        })?;
        c.checked()
            .map_err(|e| InvalidFigureError(format!("figure error `{name}`: {e}")))?;
        Ok((f, c))
    }

    /// The preset `name` (`"none"` is always the perfect figure).
    pub fn get(&self, name: &str) -> Result<FigureError, InvalidFigureError> {
        if name == "none" {
            return Ok(FigureError::NONE);
        }
        self.figure_errors
            .get(name)
            .map(FigureErrorEntry::parameters)
            .ok_or_else(|| {
                let known: Vec<&str> = std::iter::once("none")
                    .chain(self.figure_errors.keys().map(|s| s.as_str()))
                    .collect();
                InvalidFigureError(format!(
                    "unknown figure error `{name}` (known: {})",
                    known.join(", ")
                ))
            })
    }
}
