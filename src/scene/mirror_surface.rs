//! A mirror's surface as a scene or a prescription declares it: its coating,
//! figure errors and microroughness. One type, flattened into the three places
//! that declare mirrors: a `[materials]` mirror, a nested telescope (for every
//! mirror: its choices replace the shells' own) and a prescription's shell (its
//! own, where shells differ). `materials` turns it into the traced
//! `Material::Mirror` (reflectivity table, figure error, roughness).

use crate::xray::figure_presets::FigureErrorSpec;
use crate::xray::roughness::RoughnessSpec;
use serde::Deserialize;

/// Coating, figure errors and microroughness of a mirror; each optional.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MirrorSurfaceDesc {
    /// Name of a coating (data/coatings.toml or the scene's `[coatings]`);
    /// without one a mirror is perfect (R = 1).
    #[serde(default)]
    pub coating: Option<String>,
    /// Figure errors: a preset name (data/figure_errors.toml or the scene's
    /// `[figure_errors]`, "none") or the parameters inline; default none.
    #[serde(default)]
    pub figure_error: Option<FigureErrorSpec>,
    /// Scatter from microroughness: a PSD over a band of spatial frequencies
    /// (`xray::roughness`), or "none"; default none.
    #[serde(default)]
    pub roughness: Option<RoughnessSpec>,
}

/// A surface's keys, as they appear in every table it is flattened into.
pub const SURFACE_KEYS: [&str; 3] = ["coating", "figure_error", "roughness"];

/// The keys of a mirror material (`materials::MirrorDesc`) besides its surface's.
pub const MIRROR_KEYS: [&str; 1] = ["side"];

/// The keys of a nested telescope (`assembly_desc::NestedTelescopeDesc`) besides
/// its surface's.
pub const NESTED_TELESCOPE_KEYS: [&str; 12] = [
    "name",
    "telescope",
    "data",
    "azimuth_center",
    "shell_axes",
    "spider",
    "spider_distance",
    "central_stop",
    "omit",
    "tessellate",
    "mesh",
    "transform",
];

/// The keys of a prescription's shell (`telescope::Shell`) besides its
/// surface's.
pub const SHELL_KEYS: [&str; 8] = [
    "r1_mm",
    "r2_mm",
    "r3_mm",
    "r4_mm",
    "r5_mm",
    "thickness_mm",
    "mirror_length_mm",
    "azimuth_span_deg",
];

/// The keys of the tables that flatten a surface in: serde cannot list them
/// when it refuses an unknown key (it names the key alone), so the scene's
/// error names them from here, by where the table is. `tests` keeps each
/// list equal to its struct's fields.
pub fn keys_of_table_with_surface(table: &str) -> Option<Vec<&'static str>> {
    let indexed = |prefix: &str| {
        table
            .strip_prefix(prefix)
            .and_then(|r| r.strip_prefix('['))
            .and_then(|r| r.strip_suffix(']'))
            .is_some_and(|i| i.chars().all(|c| c.is_ascii_digit()))
    };
    let own: &[&'static str] = if indexed("assemblies") {
        &NESTED_TELESCOPE_KEYS
    } else if indexed("shells") {
        &SHELL_KEYS
    } else if table.starts_with("materials.") {
        &MIRROR_KEYS
    } else {
        return None;
    };
    Some(own.iter().chain(&SURFACE_KEYS).copied().collect())
}

impl MirrorSurfaceDesc {
    /// This surface (a shell's own) with the figure errors and roughness that
    /// `over` (the telescope's, for every mirror) chooses in place of its own.
    /// The coating stays this surface's: a telescope's coating is resolved
    /// with the shells' before.
    pub fn under(&self, over: &MirrorSurfaceDesc) -> MirrorSurfaceDesc {
        MirrorSurfaceDesc {
            coating: self.coating.clone(),
            figure_error: over.figure_error.clone().or(self.figure_error.clone()),
            roughness: over.roughness.clone().or(self.roughness.clone()),
        }
    }

    /// Whether this shell's own figure errors or roughness stay under `over`
    /// (its mirrors then need a material of their own).
    pub fn keeps_own_under(&self, over: &MirrorSurfaceDesc) -> bool {
        (over.figure_error.is_none() && self.figure_error.is_some())
            || (over.roughness.is_none() && self.roughness.is_some())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The field names a value's `Debug` shows (the surface's among them,
    /// the flattened `surface` itself left out).
    fn fields(debug: &str) -> Vec<String> {
        let mut names: Vec<String> = debug
            .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == ':'))
            .filter_map(|w| w.strip_suffix(':'))
            .filter(|w| !w.is_empty() && *w != "surface")
            .map(str::to_string)
            .collect();
        names.sort();
        names.dedup();
        names
    }

    fn listed(table: &str) -> Vec<String> {
        let mut keys: Vec<String> = keys_of_table_with_surface(table)
            .unwrap()
            .iter()
            .map(|k| k.to_string())
            .collect();
        keys.sort();
        keys
    }

    #[test]
    fn the_key_lists_are_the_structs_fields() {
        let mirror: super::super::materials::MaterialDesc =
            toml::from_str("type = \"mirror\"").unwrap();
        assert_eq!(fields(&format!("{mirror:?}")), listed("materials.m"));
        let telescope: super::super::assembly_desc::AssemblyDesc =
            toml::from_str("type = \"nested_telescope\"").unwrap();
        let mut got = fields(&format!("{telescope:?}"));
        // The transform's steps and the omit list print no field names of
        // their own when empty; ShellAxes prints as a unit variant.
        got.retain(|f| !f.is_empty());
        assert_eq!(got, listed("assemblies[0]"));
        let shell: super::super::telescope::Shell = toml::from_str("").unwrap();
        assert_eq!(fields(&format!("{shell:?}")), listed("shells[3]"));
        assert!(keys_of_table_with_surface("sources[0]").is_none());
        assert!(keys_of_table_with_surface("assemblies[x]").is_none());
    }

    #[test]
    fn a_telescope_replaces_a_shells_figure_errors_and_roughness_not_its_coating() {
        let shell: MirrorSurfaceDesc =
            toml::from_str("coating = \"gold\"\nroughness = \"slumped_glass_limit\"").unwrap();
        let telescope: MirrorSurfaceDesc =
            toml::from_str("coating = \"perfect\"\nfigure_error = \"llnl_panter\"").unwrap();
        let both = shell.under(&telescope);
        assert_eq!(both.coating.as_deref(), Some("gold"));
        assert!(both.figure_error.is_some() && both.roughness.is_some());
        assert!(shell.keeps_own_under(&telescope), "its own roughness stays");
        let smooth: MirrorSurfaceDesc = toml::from_str("roughness = \"none\"").unwrap();
        assert!(!shell.keeps_own_under(&smooth));
        assert!(shell.under(&smooth).roughness == smooth.roughness);
    }
}
