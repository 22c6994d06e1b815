//! `traxer signal`: the expected X-ray counts of a finished magnet run in a
//! signal region on its sensor, per axion mass, with their spectrum.

use super::InputError;
use std::path::PathBuf;
use traxer::analysis::signal::{signal, Centre, Region, RunSignal, Signal, Size};
use traxer::output::run_read::read_run_signal;
use traxer::output::{write_signal, Provenance, SIGNAL_FILES};

/// Expected X-ray counts in a signal region, per axion mass, from a trace.
///
/// Reads the results folder of a finished `traxer trace` of a Sun scene with
/// its magnet on (images in X-rays per second) and measures, for each axion
/// mass of the run (the scene's, or every mass of a --masses scan), the
/// X-rays per second and per hour of tracking inside a circle on the sensor,
/// and their spectrum in the sensor's energy bands (one band without
/// energy_bins). The circle is placed on the image of one mass: --region-mass,
/// or the run's brightest (a helium setting's resonance, the lightest mass in
/// vacuum); it lies about that image's centroid or about --center, with
/// --radius-mm or the radius holding --fraction of that image's flux; each
/// pixel's flux is spread over its
/// area (no lattice bias). Writes signal.csv, signal_spectrum.csv,
/// signal_spectrum.fits (one SPECTRUM table per mass: ENERG_LO, ENERG_HI in
/// keV, RATE in X-rays/s) and signal.json into --out (default RUN/signal).
#[derive(clap::Args)]
pub struct SignalArgs {
    /// The results folder of the trace.
    pub run: PathBuf,
    #[command(flatten)]
    pub region: RegionArgs,
    #[command(flatten)]
    pub output: super::args::OutputArgs,
}

/// Where the signal region lies on the sensor.
#[derive(clap::Args, Clone, Debug)]
#[group(skip)]
#[command(group(clap::ArgGroup::new("region_size").required(true).multiple(false)))]
pub struct RegionArgs {
    /// The sensor (default: the run's only sensor).
    #[arg(value_name = "NAME", long)]
    pub sensor: Option<String>,
    /// The region's radius (mm on the sensor).
    #[arg(value_name = "MM", long, group = "region_size")]
    pub radius_mm: Option<f64>,
    /// The radius holding this fraction of the flux of the image that places
    /// the region (e.g. 0.8).
    #[arg(value_name = "F", long, group = "region_size")]
    pub fraction: Option<f64>,
    /// The region's centre (mm, x,y in the sensor's frame, as the printed
    /// centroid); default: the centroid of the image that places the region.
    #[arg(
        value_name = "X,Y",
        long = "center",
        alias = "centre",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    pub centre: Vec<f64>,
    /// The axion mass (eV, one of the run's) whose image places the region;
    /// default: the run's brightest.
    #[arg(value_name = "EV", long)]
    pub region_mass: Option<f64>,
}

impl RegionArgs {
    /// The region asked for, checked.
    pub fn region(&self) -> Result<Region, InputError> {
        let centre = match self.centre.as_slice() {
            [] => Centre::Centroid,
            [x, y] if x.is_finite() && y.is_finite() => Centre::At([*x, *y]),
            _ => return Err(InputError("--center X,Y: two finite numbers (mm)".into())),
        };
        let size = match (self.radius_mm, self.fraction) {
            (Some(r), None) => Size::RadiusMm(r),
            (None, Some(f)) => Size::Fraction(f),
            _ => return Err(InputError("give --radius-mm MM or --fraction F".into())),
        };
        Ok(Region {
            centre,
            size,
            on_mass: self.region_mass,
        })
    }

    /// The run in `dir` and its signal in this region.
    pub fn measure(&self, dir: &std::path::Path) -> Result<(RunSignal, Signal), InputError> {
        let run = read_run_signal(dir, self.sensor.as_deref()).map_err(|e| InputError(e.0))?;
        let s = signal(&run, &self.region()?).map_err(|e| InputError(e.0))?;
        Ok((run, s))
    }
}

pub fn run(a: SignalArgs) -> anyhow::Result<()> {
    let (run, s) = a.region.measure(&a.run)?;
    let out = a.output.out.clone().unwrap_or_else(|| a.run.join("signal"));
    let folder = traxer::run::results_folder_reading(&out, &SIGNAL_FILES, &[a.run.as_path()])?;
    let provenance = Provenance::of_table(&super::invocation());
    traxer::run::write_results_folder(folder, |dir| write_signal(dir, &run, &s, &provenance))?;
    say!(
        "signal region on {}: a circle of {} mm about ({:.4}, {:.4}) mm, {} cm², {:.2} % of the flux at m_a = {} eV",
        run.sensor,
        traxer::text::four_decimals(s.radius_mm),
        s.centre_mm[0],
        s.centre_mm[1],
        traxer::text::four_decimals(s.area_cm2),
        100.0 * s.fraction,
        traxer::text::number(s.placed_on_mass_ev)
    );
    say!("{:>12}  {:>12}  {:>14}", "m_a (eV)", "X-rays/s", "per hour");
    for m in &s.masses {
        say!(
            "{:>12}  {:>12.4e}  {:>14.4e}",
            traxer::text::number(m.mass_ev),
            m.rate,
            m.rate * 3600.0
        );
    }
    if !a.output.quiet.quiet {
        tell!("wrote {} to {}", SIGNAL_FILES.join(", "), out.display());
    }
    Ok(())
}
