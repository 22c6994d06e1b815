//! `traxer conversion`: the axion–photon conversion probability P(E) of a
//! magnet for lists of energies and axion masses, without tracing — a scene's
//! magnet, or one given by options — along an axial line of the bore or
//! averaged over its cross-section (`traxer::magnet::probe`).

use super::args::{parse_values, DefineArgs};
use super::InputError;
use std::path::PathBuf;
use traxer::files::{atomic_write, check_output_file};
use traxer::magnet::buffer_gas::BufferGasDesc;
use traxer::magnet::probe::{self, Where};
use traxer::magnet::{Field, Magnet};
use traxer::output::csv_text;
use traxer::scene::magnet::{standalone, MagnetDesc};

/// The axion–photon conversion probability P(E) of a magnet, as CSV.
///
/// The magnet is a scene's `[magnet]` (SCENE, with -D), or given here: a
/// uniform field (--field-t, --length-m) or a field map (--field-map: a
/// shipped one such as bykovskiy_201906, BabyIAXO's, or a FILE of rows x y z
/// Bx By Bz in mm and T), with an optional buffer gas (--gas, --pressure-mbar,
/// --temperature-k). P is taken along the bore's axis, along the axial line
/// through --at X,Y (mm), or averaged over the bore's cross-section
/// (--bore-average). Columns: energy_keV, axion_mass_eV, probability. Example
/// (CAST's vacuum number, 1.70e-17):
///   traxer conversion --field-t 9 --length-m 9.26 --g-agamma 1e-10 --energies 1,4,8
#[derive(clap::Args)]
pub struct ConversionArgs {
    /// A scene whose [magnet] to take (its field, gas, mass and coupling).
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub vars: DefineArgs,
    /// A uniform transverse field, T.
    #[arg(long, value_name = "T", conflicts_with_all = ["scene", "field_map"])]
    pub field_t: Option<f64>,
    /// With --field-t: the magnet's length, m.
    #[arg(long, value_name = "M", requires = "field_t")]
    pub length_m: Option<f64>,
    /// A field map: a shipped one (bykovskiy_201906) or a FILE.
    #[arg(long, value_name = "NAME|FILE", conflicts_with = "scene")]
    pub field_map: Option<String>,
    /// A buffer gas in the bore: a formula (He for helium-3 or -4, which are
    /// alike at the same pressure and temperature).
    #[arg(long, value_name = "FORMULA", conflicts_with = "scene", requires_all = ["pressure_mbar", "temperature_k"])]
    pub gas: Option<String>,
    #[arg(long, value_name = "MBAR", requires = "gas")]
    pub pressure_mbar: Option<f64>,
    #[arg(long, value_name = "K", requires = "gas")]
    pub temperature_k: Option<f64>,
    /// g_aγ in GeV⁻¹ [default: the scene's, else 1e-10].
    #[arg(long, value_name = "G")]
    pub g_agamma: Option<f64>,
    /// Photon energies, keV (a,b,c or start:stop:step).
    #[arg(long, value_name = "LIST")]
    pub energies: String,
    /// Axion masses, eV [default: the scene's, else 0].
    #[arg(long, value_name = "LIST")]
    pub masses: Option<String>,
    /// The axial line through this point of the bore's cross-section, mm
    /// [default: the axis].
    #[arg(long, value_name = "X,Y", conflicts_with = "bore_average", allow_hyphen_values = true, value_parser = super::args::parse_pair)]
    pub at: Option<[f64; 2]>,
    /// Average P over the bore's cross-section (8 192 axial lines, each for
    /// an equal area: converged to 2e-4 through BabyIAXO's map).
    #[arg(long)]
    pub bore_average: bool,
    /// The path integral's step through a map, mm [default: the scene's, else
    /// the map's node spacing].
    #[arg(long, value_name = "MM")]
    pub step_mm: Option<f64>,
    /// Also write the CSV to this file (atomically).
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    #[command(flatten)]
    pub quiet: super::args::QuietArg,
}

pub fn run(a: ConversionArgs) -> anyhow::Result<()> {
    if let Some(csv) = &a.csv {
        check_output_file(csv)?;
    }
    let magnet = magnet(&a)?;
    let energies = parse_values("energies", &a.energies)?;
    if let Some(e) = energies.iter().find(|e| !(0.03..=30.0).contains(*e)) {
        return Err(InputError(format!(
            "--energies: {e} keV is outside 0.03–30 keV (the X-ray tables' range)"
        ))
        .into());
    }
    let masses = match &a.masses {
        Some(m) => parse_values("masses", m)?,
        None => vec![magnet.axion_mass_ev],
    };
    traxer::scene::magnet::check_probe_masses(&magnet, "--masses", &masses).map_err(InputError)?;
    let at = match (a.bore_average, a.at) {
        (true, _) => Where::BoreAverage {
            rings: traxer::magnet::probe::BORE_AVERAGE_RINGS,
        },
        (false, p) => Where::Line(p.unwrap_or([0.0, 0.0])),
    };
    if !a.quiet.quiet {
        eprintln!("{}", describe(&magnet, at));
    }
    let rows = probe::table(&magnet, at, &energies, &masses);
    let csv = csv_text(
        &["energy_keV", "axion_mass_eV", "probability"],
        rows.iter().map(|r| {
            vec![
                r.energy_kev.to_string(),
                r.mass_ev.to_string(),
                format!("{:e}", r.probability),
            ]
        }),
    );
    print!("{csv}");
    if let Some(path) = &a.csv {
        atomic_write(path, csv.as_bytes())?;
    }
    Ok(())
}

/// The scene's magnet, or the one the options describe.
fn magnet(a: &ConversionArgs) -> anyhow::Result<Magnet> {
    let mut m = match &a.scene {
        Some(scene) => {
            let device = traxer::embree::Device::new()?;
            let s = traxer::scene::Scene::load(&device, scene, &a.vars.define)?;
            let Some(m) = s.magnet.as_deref() else {
                return Err(InputError(format!(
                    "{}: the scene has no [magnet] (or it is not enabled: a scene variable such as -D magnet=true may switch it on)",
                    scene.display()
                ))
                .into());
            };
            m.clone()
        }
        None => {
            let gas = a.gas.as_ref().map(|f| BufferGasDesc {
                mixture: [(f.clone(), 1.0)].into(),
                pressure_mbar: a.pressure_mbar.unwrap_or_default(),
                temperature_k: a.temperature_k.unwrap_or_default(),
            });
            let desc = MagnetDesc {
                enabled: true,
                bore: "bore".into(),
                field_t: a.field_t,
                field_direction: None,
                field_map: a.field_map.clone(),
                field_map_transform: Vec::new(),
                step_mm: a.step_mm,
                axion_mass_ev: 0.0,
                masses_ev: Vec::new(),
                g_agamma: a.g_agamma.unwrap_or(1e-10),
                gas,
                campaign: None,
            };
            if a.field_t.is_none() && a.field_map.is_none() {
                return Err(InputError("give a SCENE with a [magnet], or the field: --field-t T --length-m M, or --field-map NAME|FILE".into()).into());
            }
            standalone(&desc, a.length_m.map(|l| l * 1000.0)).map_err(InputError)?
        }
    };
    // The options given replace the scene's, checked as the scene's are.
    if a.g_agamma.is_some() || a.step_mm.is_some() {
        m = traxer::scene::magnet::revised(&m, a.g_agamma, a.step_mm).map_err(InputError)?;
    }
    Ok(m)
}

/// One line on what is computed.
fn describe(m: &Magnet, at: Where) -> String {
    let field = match &m.field {
        Field::Uniform { tesla, .. } => format!("uniform {tesla} T"),
        Field::Map { name, .. } => format!("field map {name} (step {} mm)", m.step_mm),
    };
    let gas = match &m.gas {
        None => "vacuum".to_string(),
        Some(g) => format!(
            "gas {:?} at {} mbar, {} K (m_γ = {:.4} eV)",
            g.desc.mixture.keys().collect::<Vec<_>>(),
            g.desc.pressure_mbar,
            g.desc.temperature_k,
            g.photon_mass_ev()
        ),
    };
    let place = match at {
        Where::Line([x, y]) => format!("along the axial line through ({x}, {y}) mm"),
        Where::BoreAverage { .. } => format!("averaged over the bore (radius {} mm)", m.radius_mm),
    };
    format!(
        "P(a→γ): {field} over {} m, {gas}, g_aγ = {:e} GeV⁻¹, {place}",
        2.0 * m.half_length_mm / 1000.0,
        m.g_agamma_gev
    )
}
