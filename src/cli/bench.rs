//! `traxer bench`: photons per second, and raw Embree rays per second on the same
//! rays.

use super::args::{QuietArg, RunArgs, SceneArgs};
use super::{load_xray_scene, progress};

/// Measure tracing speed on a scene and compare it with raw Embree queries.
///
/// Prints photons/s, photons reaching a sensor per second, Embree queries per
/// photon, the raw rtcIntersect1 rate on the very rays of the run, the share of
/// the run spent inside Embree, and the best rate Embree reaches on the same rays
/// sorted (by direction or by origin).
#[derive(clap::Args)]
#[command(mut_arg("photons", |a| a.help("Photons for the timed run").default_value("2000000")))]
pub struct BenchArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub run: RunArgs,
    /// Photons whose queries are replayed for the raw Embree rate.
    #[arg(value_name = "N", long, default_value = "300000", value_parser = super::args::parse_count)]
    pub raw_photons: u64,
    /// Also trace this scene (without the -D overrides), in the same run, and
    /// print the ratio of the two speeds (e.g. --against scenes/panter_al_ka.toml).
    #[arg(long, value_name = "SCENE")]
    pub against: Option<std::path::PathBuf>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub quiet: QuietArg,
}

pub fn run(a: BenchArgs) -> anyhow::Result<()> {
    let cfg = a.run.config()?;
    // Every query of the replayed photons is kept (24 bytes, ~2.5 per photon).
    const MAX_RAW: u64 = 10_000_000;
    if a.raw_photons > MAX_RAW {
        return Err(super::InputError(format!(
            "--raw-photons {} keeps every query in memory: at most {MAX_RAW}",
            a.raw_photons
        ))
        .into());
    }
    let r = measure(&a.scene, &cfg, a.raw_photons, a.quiet.quiet)?;
    let against = match &a.against {
        Some(path) => {
            let other = SceneArgs {
                scene: path.clone(),
                vars: super::args::DefineArgs { define: vec![] },
            };
            Some((
                other.scene.clone(),
                measure(&other, &cfg, a.raw_photons, a.quiet.quiet)?,
            ))
        }
        None => None,
    };
    if a.json {
        match &against {
            None => say!("{}", serde_json::to_string_pretty(&r)?),
            Some((_, o)) => say!(
                "{}",
                serde_json::to_string_pretty(&serde_json::json!({
                    "scene": r,
                    "against": o,
                    "ratio": r.photons_per_second / o.photons_per_second,
                }))?
            ),
        }
        return Ok(());
    }
    print_report(&a.scene.scene, &r);
    if let Some((path, o)) = &against {
        print_report(path, o);
        say!(
            "{} traces {:.2} × as many photons per second as {} (same run, same settings)",
            a.scene.scene.display(),
            r.photons_per_second / o.photons_per_second,
            path.display()
        );
    }
    Ok(())
}

/// Loads a scene and measures it.
fn measure(
    scene: &SceneArgs,
    cfg: &traxer::trace::RunConfig,
    raw_photons: u64,
    quiet: bool,
) -> anyhow::Result<traxer::bench::BenchReport> {
    // The peak memory of this scene alone: from its loading (the reflectivity
    // tables) to the end of the measurement.
    traxer::bench::reset_peak_rss();
    let (_device, scene) = load_xray_scene(scene)?;
    let bar = progress::bar(cfg.photons, "photons", quiet);
    let r = traxer::bench::run(&scene, cfg, raw_photons, &|n| bar.inc(n));
    bar.finish_and_clear();
    Ok(r?)
}

/// One scene's numbers, for people.
fn print_report(path: &std::path::Path, r: &traxer::bench::BenchReport) {
    say!(
        "scene {} ({} triangles, BVH built in {:.2} s), {} threads",
        path.display(),
        r.triangles,
        r.bvh_seconds,
        r.threads
    );
    say!(
        "  traced           {:>12.0} photons/s ({} photons in {:.2} s)",
        r.photons_per_second,
        r.photons,
        r.seconds
    );
    say!(
        "  reaching sensor  {:>12.0} photons/s",
        r.sensor_photons_per_second
    );
    if let Some(mb) = r.peak_rss_mb {
        say!("  peak memory      {mb:>12.0} MB (resident, from loading the scene)");
    }
    say!(
        "  Embree queries   {:>12.3} per photon",
        r.queries_per_photon
    );
    say!(
        "  raw rtcIntersect1{:>12.0} rays/s (same {} rays, no traxer work)",
        r.raw_rays_per_second,
        r.raw_rays
    );
    say!(
        "  photons/s × queries/photon ÷ raw rays/s = {:.2}",
        r.embree_fraction
    );
    say!(
        "  best rtcIntersect1{:>12.0} rays/s (same rays {}); share against it {:.2}",
        r.best_raw_rays_per_second,
        r.best_order.describe(),
        r.photons_per_second * r.queries_per_photon / r.best_raw_rays_per_second
    );
    if let Some(n) = &r.nested_shells {
        say!(
            "  nested-shell search {:>10.0} rays/s against Embree's {:.0} on the same rays ({:.2} ×; {} shells, {:.4} of the answers agree)",
            n.nested_rays_per_second,
            n.embree_rays_per_second,
            n.nested_rays_per_second / n.embree_rays_per_second,
            n.shells,
            n.agreeing_fraction
        );
    }
}
