//! `traxer compare`: one scene traced with its analytic objects exact and
//! tessellated at several resolutions (and, optionally, other scene files such
//! as one built from exported meshes), with the image quality, the photons
//! reaching the sensor and the speed of each, relative to the analytic run
//! (`traxer::studies::compare`).

use super::args::{OutputArgs, RunArgs, SceneArgs};
use super::Warnings;
use std::path::PathBuf;
use traxer::embree::Device;
use traxer::geometry::Resolution;
use traxer::output::compare_markdown;
use traxer::scene::{Representation, Scene};
use traxer::studies::compare::{variants, CompareStudy};
use traxer::studies::StudyError;

/// Compare the analytic scene with meshes of it: HPD / 80 % / 90 %, photons on the
/// sensor and photons per second.
///
/// Every analytic object (the LLNL telescope's shells, backs and edges included)
/// is traced exact, then tessellated at each --resolutions entry SEGMENTSxRINGS
/// (mirrors with smooth normals). All runs use the same seed, so differences are
/// not Monte Carlo noise. --also adds other scene files (e.g. one that loads the
/// shipped meshes) as extra rows. Prints a Markdown table; writes compare.csv and
/// compare.json into --out. Example:
///   traxer compare scenes/panter_al_ka.toml --resolutions 8x1,30x1,120x2
#[derive(clap::Args)]
#[command(mut_arg("photons", |a| a.help("Photons per run").default_value("2000000")))]
pub struct CompareArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Tessellations to compare, SEGMENTSxRINGS (comma separated).
    #[arg(value_name = "SxR", long, value_delimiter = ',', value_parser = str::parse::<Resolution>,
          default_value = traxer::studies::compare::DEFAULT_RESOLUTIONS)]
    pub resolutions: Vec<Resolution>,
    /// Other scene files to trace and compare (repeatable), e.g. a scene built
    /// from exported meshes; they get the same -D overrides.
    #[arg(value_name = "SCENE", long)]
    pub also: Vec<PathBuf>,
    /// Sensor to measure (default: the scene's only sensor).
    #[arg(value_name = "NAME", long)]
    pub sensor: Option<String>,
    #[command(flatten)]
    pub run: RunArgs,
    #[command(flatten)]
    pub output: OutputArgs,
    /// Continue a stopped comparison in --out: the variants it recorded
    /// (compare_checkpoint.jsonl) are taken, the rest traced.
    #[arg(long)]
    pub resume: bool,
}

pub fn run(a: CompareArgs) -> anyhow::Result<()> {
    let cfg = a.run.config()?;
    let device = Device::new()?;
    let defines = &a.scene.vars.define;
    let warnings = std::sync::Mutex::new(Warnings::default());
    let load = |path: &std::path::Path, repr| -> Result<Scene, StudyError> {
        let scene = Scene::load_as(&device, path, defines, repr)?;
        if let Ok(mut w) = warnings.lock() {
            w.show(&scene);
        }
        Ok(scene)
    };
    let analytic = load(&a.scene.scene, Representation::Analytic)?;
    traxer::studies::require_sources(&analytic)?;
    let runs = variants(&a.scene.scene, &a.resolutions, &a.also);
    let sampling = traxer::studies::Sampling {
        photons: cfg.photons,
        seed: cfg.seed,
        threads: cfg.threads,
        sensor: a.sensor.clone(),
    };
    let study = CompareStudy::new(runs, sampling, &load);
    let places = (&a.scene, &a.output);
    let (rows, out) = super::study::run_loaded(&study, (&device, &analytic), places, a.resume)?;
    say!("{}", compare_markdown(&rows));
    if !a.output.quiet.quiet {
        say!(
            "{} photons per run, seed {}; Δ relative to the analytic run; wrote compare.csv and compare.json to {}",
            cfg.photons,
            cfg.seed,
            out.display()
        );
    }
    Ok(())
}
