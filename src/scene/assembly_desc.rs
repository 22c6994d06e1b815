//! The `[[assemblies]]` tables of a scene file: one entry that stands for many
//! objects (today a nested telescope). Read with the rest of the description
//! (`desc`), expanded into objects by `assemblies`.

use super::mirror_surface::MirrorSurfaceDesc;
use super::placement::TransformStep;
use super::shapes::TessellateDesc;
use serde::Deserialize;

/// Built-in assemblies: many objects from one entry.
///
/// ```toml
/// [[assemblies]]
/// type = "nested_telescope"      # shells as data (data/telescopes/NAME.toml)
/// telescope = "xmm_newton"       # a shipped telescope ("llnl", "xmm_newton"), or a FILE.toml
/// data = "my_telescope.toml"     # or: a prescription file in the same form
/// name = "xmm"                   # prefix of its objects' names (default: the telescope's key)
/// azimuth_center = 0.0           # degrees: direction of segments' centre (LLNL's 30°)
/// coating = "perfect"            # optional: one coating for every shell
///                                # ("as_built", the default: each shell's own)
/// figure_error = "llnl_panter"   # optional: figure errors of every mirror
/// shell_axes = "coaxial"         # or "traxer": each segment's axis where TrAXer puts it
/// spider = true                  # the data's entrance spider (default: when it has one)
/// spider_distance = 20.0         # mm in front of the entrance (when the data gives none)
/// central_stop = false           # an absorbing disk filling the innermost opening
/// omit = ["rear_7"]              # optional: parts left out (stray-light studies):
///                                # a mirror with its wall, or one part ("rear_7_back")
/// tessellate = { segments = 500, rings = 20 }   # optional: meshes with smooth normals
/// mesh = "../meshes/llnl_telescope.glb"          # optional: the parts from a mesh file
/// transform = [ { translate = [0, 0, 0] } ]     # placement of the telescope frame
/// ```
///
/// `type = "llnl_telescope"` is the same with `telescope = "llnl"` and `name =
/// "llnl"` by default.
#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum AssemblyDesc {
    NestedTelescope(NestedTelescopeDesc),
    LlnlTelescope(NestedTelescopeDesc),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NestedTelescopeDesc {
    #[serde(default)]
    pub name: Option<String>,
    /// A shipped telescope (`telescope::SHIPPED`), or a prescription file
    /// (a name ending in `.toml`, relative to the scene) as `data`.
    #[serde(default)]
    pub telescope: Option<String>,
    /// A prescription file, relative to the scene.
    #[serde(default)]
    pub data: Option<String>,
    #[serde(default)]
    pub azimuth_center: f64,
    /// The surface of every mirror: one coating for every shell (or
    /// "as_built": each shell's own), and figure errors and roughness that
    /// replace the shells' own where the data gives them.
    #[serde(flatten)]
    pub surface: MirrorSurfaceDesc,
    /// Where each shell's cone axis lies (see [`ShellAxes`]).
    #[serde(default)]
    pub shell_axes: ShellAxes,
    /// Whether the data's entrance spider is built (default: when it has one).
    #[serde(default)]
    pub spider: Option<bool>,
    /// The spider's distance in front of the entrance (mm); replaces the data's.
    #[serde(default)]
    pub spider_distance: Option<f64>,
    #[serde(default)]
    pub central_stop: bool,
    /// Parts left out, by their name without the assembly's prefix: "rear_7" is
    /// that mirror with its wall (back and edges), "rear_7_back" that part alone.
    #[serde(default)]
    pub omit: Vec<String>,
    #[serde(default)]
    pub tessellate: Option<TessellateDesc>,
    /// A mesh file holding the parts, named `<name>_<part>` as `traxer tessellate`
    /// writes them (meshes/llnl_telescope.glb), tessellated at azimuth_center 0.
    #[serde(default)]
    pub mesh: Option<String>,
    #[serde(default)]
    pub transform: Vec<TransformStep>,
}

/// Where the shells' cone axes lie.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case")]
pub enum ShellAxes {
    /// On one common optical axis, as designed.
    #[default]
    Coaxial,
    /// As the predecessor TrAXer built the telescope: shell i's axis moved by
    /// `Telescope::traxer_axis_offset` along the segment centre, so the
    /// shells' foci no longer coincide. For comparing with TrAXer's images.
    /// Cone segments only.
    Traxer,
}
