//! A coating named the way users name one (`traxer reflectivity --coating`, and
//! `traxer.reflectivity` in Python): a shipped coating of data/coatings.toml, or
//! FILE / FILE:NAME for a TOML file with `[materials]` and `[coatings]` tables.
//!
//! Data flow: user text → [`coating_from_spec`] → a built [`Coating`] whose
//! R(E, θ) the caller evaluates; scene files resolve their coatings themselves
//! (`scene::build`).

use super::elements::OpticalConstants;
use super::{Coating, CoatingLibrary};
use std::path::Path;

message_error!(
    /// Why a coating given by name or file cannot be built: the message names the
    /// argument (and the file and line of a bad coatings file).
    CoatingSpecError
);

/// The coating `spec` names: a shipped coating (e.g. `llnl_recipe_3`, `gold`),
/// or `FILE` (a coatings file defining one coating) or `FILE:NAME`, its layers
/// on the table of optical constants `constants`.
pub fn coating_from_spec(
    spec: &str,
    constants: OpticalConstants,
) -> Result<Coating, CoatingSpecError> {
    let mut shipped = CoatingLibrary::shipped();
    shipped.mirror_constants = constants;
    if shipped.is_perfect(spec) {
        return Err(format!("coating {spec}: R = 1 everywhere, nothing to compute").into());
    }
    if shipped.coatings.contains_key(spec) {
        return shipped
            .coating(spec)
            .map_err(|e| CoatingSpecError(e.to_string()));
    }
    let (file, name) = match spec.rsplit_once(':') {
        Some((f, n)) if Path::new(f).is_file() => (f, Some(n)),
        _ => (spec, None),
    };
    if !Path::new(file).is_file() {
        return Err(format!(
            "coating {spec}: not a shipped coating (have: {}) and not a file",
            shipped
                .coatings
                .keys()
                .cloned()
                .collect::<Vec<_>>()
                .join(", ")
        )
        .into());
    }
    let text = std::fs::read_to_string(file).map_err(|e| format!("{file}: {e}"))?;
    let mut lib: CoatingLibrary = toml::from_str(&text).map_err(|e| {
        let line = e
            .span()
            .map(|s| text[..s.start].lines().count().max(1))
            .unwrap_or(0);
        format!("{file}:{line}: {}", e.message())
    })?;
    let name = match name {
        Some(n) => n.to_string(),
        None if lib.coatings.len() == 1 => lib.coatings.keys().next().expect("one").clone(),
        None => {
            return Err(format!(
                "{file} defines {} coatings; choose one as {file}:NAME",
                lib.coatings.len()
            )
            .into())
        }
    };
    lib.mirror_constants = constants;
    shipped
        .merged(&lib)
        .coating(&name)
        .map_err(|e| CoatingSpecError(format!("{file}: {e}")))
}
