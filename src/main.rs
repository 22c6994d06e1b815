//! The `traxer` command line: parses arguments (clap), dispatches to the
//! subcommands in `cli/`, and maps failures to exit codes: 0 success, 1 the run
//! failed, 2 bad input (scene, mesh, arguments), 130 stopped on a signal.

#![forbid(unsafe_code)]

mod cli;

use clap::{CommandFactory, Parser, Subcommand};
use std::process::ExitCode;

/// X-ray raytracer for grazing-incidence telescopes (CAST, BabyIAXO), on Intel Embree.
///
/// Units everywhere: millimetres, keV, degrees. Start where the README does:
/// `traxer trace scenes/panter_al_ka.toml` traces the CAST LLNL telescope at the
/// PANTER test facility (results in out/panter_al_ka; ./scripts/run-example.sh
/// builds traxer and runs it).
#[derive(Parser)]
#[command(name = "traxer", version = concat!(env!("CARGO_PKG_VERSION"), " (", env!("TRAXER_GIT_HASH"), ")"))]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    Trace(cli::trace::TraceArgs),
    Tessellate(cli::tessellate::TessellateArgs),
    Merge(cli::merge::MergeArgs),
    Info(cli::info::InfoArgs),
    Inspect(cli::inspect::InspectArgs),
    Bench(cli::bench::BenchArgs),
    Cache(cli::cache::CacheArgs),
    Reflectivity(cli::reflectivity::ReflectivityArgs),
    Conversion(cli::conversion::ConversionArgs),
    Signal(cli::signal::SignalArgs),
    Reach(cli::reach::ReachArgs),
    Eef(cli::eef::EefArgs),
    Focus(cli::focus::FocusArgs),
    EffectiveArea(cli::effective_area::EffectiveAreaArgs),
    Psf(cli::psf::PsfArgs),
    Systematics(cli::systematics::SystematicsArgs),
    Compare(cli::compare::CompareArgs),
    FitFigureError(cli::fit_figure_error::FitFigureErrorArgs),
    Render(cli::render::RenderArgs),
    SolarFlux(cli::solar_flux::SolarFluxArgs),
    View(cli::view::ViewArgs),
    /// Print every subcommand with all its arguments (docs/scene-format.md).
    #[command(hide = true)]
    Synopsis,
}

impl Command {
    /// `-q`: every command takes it and means the same by it.
    fn quiet(&self) -> bool {
        match self {
            Command::Trace(a) => a.output.quiet.quiet,
            Command::Tessellate(a) => a.quiet.quiet,
            Command::Merge(a) => a.output.quiet.quiet,
            Command::Info(a) => a.quiet.quiet,
            Command::Inspect(a) => a.quiet.quiet,
            Command::Bench(a) => a.quiet.quiet,
            Command::Cache(a) => a.quiet.quiet,
            Command::Reflectivity(a) => a.quiet.quiet,
            Command::Conversion(a) => a.quiet.quiet,
            Command::Signal(a) => a.output.quiet.quiet,
            Command::Reach(a) => a.output.quiet.quiet,
            Command::Eef(a) => a.quiet.quiet,
            Command::Focus(a) => a.output.quiet.quiet,
            Command::EffectiveArea(a) => a.output.quiet.quiet,
            Command::Psf(a) => a.output.quiet.quiet,
            Command::Systematics(a) => a.output.quiet.quiet,
            Command::Compare(a) => a.output.quiet.quiet,
            Command::FitFigureError(a) => a.output.quiet.quiet,
            Command::Render(a) => a.quiet.quiet,
            Command::SolarFlux(a) => a.output.quiet.quiet,
            Command::View(a) => a.quiet.quiet,
            Command::Synopsis => true,
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    cli::signals::stop_cleanly_on_signals();
    if !cli.command.quiet() {
        traxer::progress::set_notice_sink(|m| cli::tell_line(format_args!("note: {m}")));
    }
    if let Err(e) = traxer::environment::check() {
        cli::tell_line(format_args!("error: {e}"));
        return ExitCode::from(2);
    }
    let result = match cli.command {
        Command::Trace(a) => cli::trace::run(a),
        Command::Tessellate(a) => cli::tessellate::run(a),
        Command::Merge(a) => cli::merge::run(a),
        Command::Info(a) => cli::info::run(a),
        Command::Inspect(a) => cli::inspect::run(a),
        Command::Bench(a) => cli::bench::run(a),
        Command::Cache(a) => cli::cache::run(a),
        Command::Reflectivity(a) => cli::reflectivity::run(a),
        Command::Conversion(a) => cli::conversion::run(a),
        Command::Signal(a) => cli::signal::run(a),
        Command::Reach(a) => cli::reach::run(a),
        Command::Eef(a) => cli::eef::run(a),
        Command::Focus(a) => cli::focus::run(a),
        Command::EffectiveArea(a) => cli::effective_area::run(a),
        Command::Psf(a) => cli::psf::run(a),
        Command::Systematics(a) => cli::systematics::run(a),
        Command::Compare(a) => cli::compare::run(a),
        Command::FitFigureError(a) => cli::fit_figure_error::run(a),
        Command::Render(a) => cli::render::run(a),
        Command::SolarFlux(a) => cli::solar_flux::run(a),
        Command::View(a) => cli::view(a),
        Command::Synopsis => cli::synopsis::run(&Cli::command()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if cli::is_stopped(&e) => {
            cli::tell_line(format_args!("{e}"));
            ExitCode::from(130)
        }
        Err(e) => {
            cli::tell_line(format_args!("error: {e:#}"));
            if cli::is_input_error(&e) {
                ExitCode::from(2)
            } else {
                ExitCode::from(1)
            }
        }
    }
}
