//! Nested grazing-incidence telescopes as data: the prescription files of
//! data/telescopes/ (the CAST LLNL optic, XMM-Newton) or a user's file in the
//! same form, parsed and checked. Two shell profiles: `cone` (a conical
//! approximation, per shell R1, R2, R4, R5, as LLNL) and `wolter1` (a true
//! paraboloid + hyperboloid, per shell R3 alone, the surfaces following from
//! R3 and f by `geometry::wolter`).
//!
//! Data flow: `scene::assemblies` reads a [`Telescope`] for every
//! `nested_telescope` assembly, `telescope_parts` expands it into scene
//! objects; tests and studies read the shipped data through [`Telescope::shipped`].

use super::mirror_surface::MirrorSurfaceDesc;
use crate::geometry::wolter::WolterShell;
use serde::Deserialize;

// The telescopes traxer ships, by the name a scene gives (`telescope =
// "llnl"`): every data/telescopes/NAME.toml, compiled in so that an installed
// binary needs no data directory (the list is written by build.rs).
include!(concat!(env!("OUT_DIR"), "/telescopes.rs"));

message_error!(
    /// Telescope data (radii, lengths) that describe no telescope.
    InvalidTelescopeData
);

/// The shape of a shell's two mirrors.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Profile {
    /// Front and rear cones (the conical approximation of LLNL and NuSTAR).
    Cone,
    /// A true Wolter-I shell: paraboloid, then confocal hyperboloid.
    Wolter1,
}

/// One shell. Radii in mm: R1 at the entrance, R2 at the front mirror's other
/// end, R3 at the intersection plane, R4 and R5 at the rear mirror's ends.
/// Cones give R1, R2, R4, R5; Wolter-I shells give R3.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shell {
    #[serde(default)]
    pub r1_mm: Option<f64>,
    #[serde(default)]
    pub r2_mm: Option<f64>,
    #[serde(default)]
    pub r3_mm: Option<f64>,
    #[serde(default)]
    pub r4_mm: Option<f64>,
    #[serde(default)]
    pub r5_mm: Option<f64>,
    /// Wall thickness (mm), perpendicular to the mirror; default the
    /// telescope's `wall_thickness_mm`.
    #[serde(default)]
    pub thickness_mm: Option<f64>,
    /// Both mirrors' surface: coating (data/coatings.toml or the scene's;
    /// default the telescope's `coating`), and figure errors and roughness
    /// where they differ from shell to shell (a scene's replace them).
    #[serde(flatten)]
    pub surface: MirrorSurfaceDesc,
    /// This shell's mirror length (mm); default the telescope's.
    #[serde(default)]
    pub mirror_length_mm: Option<f64>,
    /// This shell's azimuthal extent (degrees); default the telescope's.
    #[serde(default)]
    pub azimuth_span_deg: Option<f64>,
}

/// The entrance spider: `arms` absorbing arms, each `arm_width_deg` wide,
/// evenly spaced in azimuth from `first_arm_deg`, spanning the radii
/// `inner_radius_mm` … `outer_radius_mm` (default: the shells' apertures), a
/// distance in front of the entrance (`distance_mm`, or the scene's
/// `spider_distance`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Spider {
    pub arms: u32,
    pub arm_width_deg: f64,
    #[serde(default)]
    pub first_arm_deg: f64,
    #[serde(default)]
    pub inner_radius_mm: Option<f64>,
    #[serde(default)]
    pub outer_radius_mm: Option<f64>,
    #[serde(default)]
    pub distance_mm: Option<f64>,
}

/// A telescope prescription (a data/telescopes/*.toml file).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Telescope {
    /// What it is, for people (plots, `traxer info`).
    pub name: String,
    pub profile: Profile,
    /// From the intersection plane (the centre plane of a cone telescope).
    pub focal_length_mm: f64,
    /// Each mirror's length: along the slant for cones (the substrate's
    /// length), along the axis for Wolter-I shells (as their tables give it).
    pub mirror_length_mm: f64,
    /// Axial gap between the front and the rear mirrors, centred on the
    /// intersection plane.
    #[serde(default)]
    pub gap_mm: f64,
    /// Each shell's azimuthal extent: 360 (default) for full shells, less for
    /// segments centred on the assembly's `azimuth_center`.
    #[serde(default = "full_circle")]
    pub azimuth_span_deg: f64,
    #[serde(default)]
    pub wall_thickness_mm: Option<f64>,
    #[serde(default)]
    pub coating: Option<String>,
    #[serde(default)]
    pub spider: Option<Spider>,
    pub shells: Vec<Shell>,
}

fn full_circle() -> f64 {
    360.0
}

impl Telescope {
    /// A shipped telescope by name (`llnl`, `xmm_newton`), checked.
    pub fn shipped(name: &str) -> Result<Telescope, InvalidTelescopeData> {
        let (_, text) = SHIPPED.iter().find(|(n, _)| *n == name).ok_or_else(|| {
            let names: Vec<&str> = SHIPPED.iter().map(|(n, _)| *n).collect();
            InvalidTelescopeData::from(format!(
                "no shipped telescope `{name}` (shipped: {}; or give `data = \"FILE.toml\"`)",
                names.join(", ")
            ))
        })?;
        let t: Telescope = toml::from_str(text).expect("shipped telescope data parse (tested)");
        t.validate()?;
        Ok(t)
    }

    pub fn from_toml(text: &str) -> Result<Telescope, toml::de::Error> {
        toml::from_str(text)
    }

    /// Shell i's mirror length (mm): along the slant for cones, the axis for
    /// Wolter-I shells.
    pub fn length(&self, i: usize) -> f64 {
        self.shells[i]
            .mirror_length_mm
            .unwrap_or(self.mirror_length_mm)
    }

    /// Shell i's azimuthal extent (degrees).
    pub fn span(&self, i: usize) -> f64 {
        self.shells[i]
            .azimuth_span_deg
            .unwrap_or(self.azimuth_span_deg)
    }

    /// Shell i's wall thickness (mm).
    pub fn thickness(&self, i: usize) -> f64 {
        self.shells[i]
            .thickness_mm
            .or(self.wall_thickness_mm)
            .expect("validated")
    }

    /// Shell i's coating.
    pub fn coating(&self, i: usize) -> &str {
        self.shells[i]
            .surface
            .coating
            .as_deref()
            .or(self.coating.as_deref())
            .expect("validated")
    }

    /// Cone shell i's radii (R1, R2, R4, R5).
    pub fn cone_radii(&self, i: usize) -> [f64; 4] {
        let s = &self.shells[i];
        [s.r1_mm, s.r2_mm, s.r4_mm, s.r5_mm].map(|r| r.expect("validated cone shell"))
    }

    /// Front (primary) mirror angle of shell i to the axis, radians: the cone
    /// angle asin((R1 − R2)/l), or the paraboloid's α = ¼·atan(R3/f).
    pub fn alpha(&self, i: usize) -> f64 {
        match self.profile {
            Profile::Cone => {
                let [r1, r2, _, _] = self.cone_radii(i);
                ((r1 - r2) / self.length(i)).asin()
            }
            Profile::Wolter1 => self.wolter(i).alpha,
        }
    }

    /// Rear mirror angle of shell i, radians (3α for a Wolter-I shell).
    pub fn alpha_rear(&self, i: usize) -> f64 {
        match self.profile {
            Profile::Cone => {
                let [_, _, r4, r5] = self.cone_radii(i);
                ((r4 - r5) / self.length(i)).asin()
            }
            Profile::Wolter1 => 3.0 * self.wolter(i).alpha,
        }
    }

    /// Wolter-I shell i's surfaces.
    pub fn wolter(&self, i: usize) -> WolterShell {
        let r3 = self.shells[i].r3_mm.expect("validated Wolter-I shell");
        WolterShell::new(self.focal_length_mm, r3).expect("validated")
    }

    /// The smallest radius of shell i's front mirror (mm): inside it, on-axis
    /// X-rays pass the shell without touching it.
    pub fn front_inner_radius(&self, i: usize) -> f64 {
        match self.profile {
            Profile::Cone => self.cone_radii(i)[1],
            Profile::Wolter1 => self.wolter(i).paraboloid_radius(0.5 * self.gap_mm),
        }
    }

    /// How far the predecessor TrAXer puts shell i's cone axis from shell 1's, in
    /// mm, outwards along the segment centre: ((R1 − R2)_i − (R1 − R2)_1)/2, 0 for
    /// shell 1 and 0.72 mm for shell 13 of the LLNL data. TrAXer offsets each shell
    /// by (R1 − R2)/2 from the common axis; the part all shells share only moves the
    /// whole image, so only the difference to shell 1 is applied. The foci of the
    /// shells then no longer coincide and the image grows: with this placement the
    /// perfect-mirror PANTER image reproduces TrAXer's HPD / 80 % / 90 % within 1″
    /// (README, "The solar axion image"); moving the axes inwards instead does not.
    /// Cone segments only.
    pub fn traxer_axis_offset(&self, i: usize) -> f64 {
        let d = |i: usize| {
            let [r1, r2, _, _] = self.cone_radii(i);
            r1 - r2
        };
        0.5 * (d(i) - d(0))
    }

    /// Checks the numbers make a telescope, naming the shell and key at fault.
    pub fn validate(&self) -> Result<(), InvalidTelescopeData> {
        let pos = |x: f64| x.is_finite() && x > 0.0;
        if !(pos(self.focal_length_mm) && pos(self.mirror_length_mm)) {
            return Err("focal_length_mm and mirror_length_mm must be > 0"
                .to_string()
                .into());
        }
        if !(self.gap_mm.is_finite() && self.gap_mm >= 0.0) {
            return Err("gap_mm must be ≥ 0".to_string().into());
        }
        if !(self.azimuth_span_deg > 0.0 && self.azimuth_span_deg <= 360.0) {
            return Err("azimuth_span_deg must lie in (0, 360]".to_string().into());
        }
        if self.wall_thickness_mm.is_some_and(|t| !pos(t)) {
            return Err("wall_thickness_mm must be > 0".to_string().into());
        }
        if self.shells.is_empty() {
            return Err("no shells".to_string().into());
        }
        if self.shells.len() > MAX_SHELLS {
            return Err(format!(
                "{} shells: at most {MAX_SHELLS} (the most nested X-ray optics have a few hundred; each shell is about a dozen objects and a MB of the scene's memory)",
                self.shells.len()
            )
            .into());
        }
        for (key, value) in [
            ("focal_length_mm", self.focal_length_mm),
            ("mirror_length_mm", self.mirror_length_mm),
            ("gap_mm", self.gap_mm),
        ] {
            if value > MAX_LENGTH_MM {
                return Err(format!(
                    "{key} = {} mm: beyond any telescope (at most {} mm)",
                    crate::text::number(value),
                    crate::text::number(MAX_LENGTH_MM)
                )
                .into());
            }
        }
        for i in 0..self.shells.len() {
            self.validate_shell(i)
                .map_err(|m| InvalidTelescopeData::from(format!("shell {}: {m}", i + 1)))?;
        }
        self.check_nesting().map_err(InvalidTelescopeData::from)?;
        self.check_spider_radii()?;
        if let Some(s) = &self.spider {
            let ok = s.arms > 0
                && s.arm_width_deg > 0.0
                && s.arm_width_deg * s.arms as f64 <= 360.0
                && s.first_arm_deg.is_finite()
                && s.inner_radius_mm.is_none_or(|r| r.is_finite() && r >= 0.0)
                && s.outer_radius_mm.is_none_or(pos)
                && s.distance_mm.is_none_or(|d| d.is_finite() && d >= 0.0);
            if !ok {
                return Err("spider: need arms ≥ 1, arm_width_deg > 0 with arms × width ≤ 360, radii and distance_mm ≥ 0".to_string().into());
            }
        }
        Ok(())
    }

    /// The spider's arms must span radii from inner to outer: the defaults (the
    /// innermost shell's opening, the outermost wall) where not given.
    fn check_spider_radii(&self) -> Result<(), InvalidTelescopeData> {
        let Some(s) = &self.spider else {
            return Ok(());
        };
        let inner = s
            .inner_radius_mm
            .unwrap_or_else(|| self.front_inner_radius(0));
        let outer = s.outer_radius_mm.unwrap_or_else(|| self.outer_radius());
        if inner < outer {
            return Ok(());
        }
        let said = |given: Option<f64>, key: &str, value: f64, default: &str| match given {
            Some(_) => format!("{key} = {}", crate::text::number(value)),
            None => format!(
                "{} ({key} not given: {default})",
                crate::text::number((value * 1e3).round() / 1e3)
            ),
        };
        Err(format!(
            "spider: its arms would reach from {} to {} mm: the inner radius must be below the outer one",
            said(s.inner_radius_mm, "inner_radius_mm", inner, "the innermost shell's opening"),
            said(s.outer_radius_mm, "outer_radius_mm", outer, "the outermost wall")
        )
        .into())
    }

    fn validate_shell(&self, i: usize) -> Result<(), String> {
        let s = &self.shells[i];
        let pos = |x: f64| x.is_finite() && x > 0.0;
        for (key, value) in [
            ("r1_mm", s.r1_mm),
            ("r2_mm", s.r2_mm),
            ("r3_mm", s.r3_mm),
            ("r4_mm", s.r4_mm),
            ("r5_mm", s.r5_mm),
            ("mirror_length_mm", s.mirror_length_mm),
            ("thickness_mm", s.thickness_mm),
        ] {
            if let Some(v) = value.filter(|v| *v > MAX_LENGTH_MM) {
                return Err(format!(
                    "{key} = {} mm: beyond any telescope (at most {} mm)",
                    crate::text::number(v),
                    crate::text::number(MAX_LENGTH_MM)
                ));
            }
        }
        if !pos(self.length(i)) {
            return Err("mirror_length_mm must be > 0".into());
        }
        if !(self.span(i) > 0.0 && self.span(i) <= 360.0) {
            return Err("azimuth_span_deg must lie in (0, 360]".into());
        }
        if s.thickness_mm
            .or(self.wall_thickness_mm)
            .is_none_or(|t| !pos(t))
        {
            return Err(
                "give a wall thickness > 0 (thickness_mm, or the telescope's wall_thickness_mm)"
                    .into(),
            );
        }
        if s.surface.coating.is_none() && self.coating.is_none() {
            return Err("give a coating (coating, or the telescope's coating = \"NAME\")".into());
        }
        match self.profile {
            Profile::Cone => {
                if s.r3_mm.is_some() {
                    return Err("a cone shell gives r1_mm, r2_mm, r4_mm, r5_mm, not r3_mm".into());
                }
                let [r1, r2, r4, r5] = [s.r1_mm, s.r2_mm, s.r4_mm, s.r5_mm];
                let (Some(r1), Some(r2), Some(r4), Some(r5)) = (r1, r2, r4, r5) else {
                    return Err("a cone shell needs r1_mm, r2_mm, r4_mm and r5_mm".into());
                };
                let l = self.length(i);
                if !([r1, r2, r4, r5].into_iter().all(pos) && r1 > r2 && r4 > r5)
                    || r1 - r2 >= l
                    || r4 - r5 >= l
                {
                    return Err(
                        "need r1 > r2 > 0 and r4 > r5 > 0 with differences below the mirror length"
                            .into(),
                    );
                }
            }
            Profile::Wolter1 => {
                if [s.r1_mm, s.r2_mm, s.r4_mm, s.r5_mm]
                    .iter()
                    .any(Option::is_some)
                {
                    return Err(
                        "a Wolter-I shell gives r3_mm alone (the other radii follow from it and f)"
                            .into(),
                    );
                }
                let Some(r3) = s.r3_mm else {
                    return Err("a Wolter-I shell needs r3_mm".into());
                };
                // The hyperboloid must stay on its branch over the whole mirror.
                let w = WolterShell::new(self.focal_length_mm, r3)?;
                let z_end = -(0.5 * self.gap_mm + self.length(i));
                if z_end - w.hyperboloid_centre <= w.a {
                    return Err(format!(
                        "a hyperboloid {} mm long does not fit in front of the focus of this shell",
                        crate::text::number(self.length(i))
                    ));
                }
            }
        }
        // A mirror steeper than a few degrees reflects no X-rays: such a shell
        // is a unit mistake (R3 in cm, f in m) or R3 ≥ f, not a design.
        for (mirror, angle) in [("front", self.alpha(i)), ("rear", self.alpha_rear(i))] {
            if angle.to_degrees() > MAX_GRAZING_DEG {
                return Err(format!(
                    "its {mirror} mirror meets the axis at {:.2}°, not at a grazing angle (X-ray mirrors reflect below about 2°, and traxer refuses more than {MAX_GRAZING_DEG}°): are the radii and focal_length_mm = {} both in mm{}?",
                    angle.to_degrees(),
                    crate::text::number(self.focal_length_mm),
                    if self.profile == Profile::Wolter1 { ", and R3 much smaller than f" } else { "" }
                ));
            }
        }
        Ok(())
    }
}

/// The most shells a prescription may have.
const MAX_SHELLS: usize = 1000;

/// The longest length (mm) a prescription may give: 10 km.
const MAX_LENGTH_MM: f64 = 1e7;

/// The steepest mirror a prescription may have, degrees to the axis.
const MAX_GRAZING_DEG: f64 = 5.0;
