//! Command-line arguments shared by the subcommands, declared once and flattened
//! into each (`#[command(flatten)]`): the scene and its variables, the run
//! settings, the output folder and quietness. Their checks happen here, once, in
//! the conversion to the library's settings ([`RunArgs::config`]); commands with
//! other defaults change them with `mut_arg`.

use super::InputError;
use std::path::PathBuf;
use traxer::trace::RunConfig;

/// More worker threads than this is a typo, not a machine (and would take minutes
/// to start).
pub use traxer::run::MAX_THREADS;

/// Parses `--threads N`: 0 (one per core) to [`MAX_THREADS`].
pub fn parse_threads(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(n) if n <= MAX_THREADS => Ok(n),
        _ => Err(format!(
            "expected 0 (one per core) to {MAX_THREADS} worker threads, got `{s}`"
        )),
    }
}

/// Parses `-D name=value`, checking the shape only (the scene checks the name).
pub fn parse_define(s: &str) -> Result<String, String> {
    match s.split_once('=') {
        Some((k, _)) if !k.trim().is_empty() => Ok(s.to_string()),
        _ => Err(format!("expected name=value, got `{s}`")),
    }
}

/// The scene file and its variables.
#[derive(clap::Args, Clone, Debug)]
pub struct SceneArgs {
    /// Scene file (TOML); see docs/scene-format.md.
    pub scene: PathBuf,
    #[command(flatten)]
    pub vars: DefineArgs,
}

/// `-D name=value` overrides of scene variables.
#[derive(clap::Args, Clone, Debug)]
pub struct DefineArgs {
    /// Override a scene variable declared in [vars]: -D name=value (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    pub define: Vec<String>,
}

/// Random numbers and parallelism.
#[derive(clap::Args, Clone, Debug)]
pub struct SamplingArgs {
    /// Random seed; photon (or pixel) i uses the stream derived from (seed, i), so
    /// results are the same for any --threads.
    #[arg(short, long, value_name = "S", default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (0 = one per core).
    #[arg(short = 'j', long, value_name = "T", default_value_t = 0, value_parser = parse_threads)]
    pub threads: usize,
}

impl SamplingArgs {
    /// A study's sampling block: these with its `photons` per point and `sensor`.
    pub fn block(&self, photons: u64, sensor: &Option<String>) -> traxer::studies::Sampling {
        traxer::studies::Sampling {
            photons,
            seed: self.seed,
            threads: self.threads,
            sensor: sensor.clone(),
        }
    }
}

/// How many photons, with which random numbers, on how many threads.
#[derive(clap::Args, Clone, Debug)]
pub struct RunArgs {
    /// Number of photons to emit (1000000, 1e6 or 1_000_000).
    #[arg(short = 'n', long, value_name = "N", default_value = "1000000", value_parser = parse_count)]
    pub photons: u64,
    #[command(flatten)]
    pub sampling: SamplingArgs,
}

impl RunArgs {
    /// The library's run configuration, checked.
    pub fn config(&self) -> Result<RunConfig, InputError> {
        traxer::run::run_config(
            self.photons,
            self.sampling.seed,
            self.sampling.threads,
            0,
            traxer::run::FrontEnd::Cli,
        )
    }
}

/// Where results go and how much is said.
#[derive(clap::Args, Clone, Debug)]
pub struct OutputArgs {
    /// Output folder, created if missing (default: out/NAME after the scene
    /// file, e.g. out/wolter1_parallel, and out/NAME/focus etc. for studies).
    #[arg(short, long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub quiet: QuietArg,
}

impl OutputArgs {
    /// The output folder: `--out`, else out/`name`.
    pub fn folder(&self, name: &str) -> PathBuf {
        self.out
            .clone()
            .unwrap_or_else(|| PathBuf::from("out").join(name))
    }

    /// The output folder named after `scene` (its file stem) and its `-D`
    /// overrides, with a study's results nested in it (`study`: "focus", ...;
    /// "" for the trace itself): out/cast_axion_image,
    /// out/cast_axion_image@offset_x=2 (a run with other variables is another
    /// run, so it gets its own folder), out/cast_axion_image/focus. A new trace
    /// keeps the studies nested in its folder.
    pub fn scene_folder(&self, scene: &SceneArgs, study: &str) -> PathBuf {
        let stem = scene
            .scene
            .file_stem()
            .map_or("run".into(), |s| s.to_string_lossy().into_owned());
        let name = run_name(&stem, &scene.vars.define);
        match study {
            "" => self.folder(&name),
            study => self.folder(&format!("{name}/{study}")),
        }
    }
}

/// The default results folder's name for scene `stem` with the overrides
/// `defines` ("NAME=VALUE"): the stem alone without overrides, else the stem,
/// `@` and the overrides sorted by name and joined by commas, characters a
/// file name should not hold replaced by `_` (offset_x=2,window_nm=0); when
/// that grows beyond 100 characters (inline tables, long paths), the first 12
/// hex digits of the overrides' SHA-256 stand for them.
pub fn run_name(stem: &str, defines: &[String]) -> String {
    if defines.is_empty() {
        return stem.to_string();
    }
    let mut sorted: Vec<String> = defines.iter().map(|d| d.trim().to_string()).collect();
    sorted.sort();
    let joined = sorted.join(",");
    let safe: String = joined
        .chars()
        .map(|c| match c {
            'a'..='z' | 'A'..='Z' | '0'..='9' | '.' | '_' | '-' | '+' | '=' | ',' => c,
            _ => '_',
        })
        .collect();
    if safe.len() <= 100 {
        format!("{stem}@{safe}")
    } else {
        let hash = traxer::files::sha256_hex(joined.as_bytes());
        format!("{stem}@{}", &hash[..12])
    }
}

/// `--quiet`.
#[derive(clap::Args, Clone, Copy, Debug)]
pub struct QuietArg {
    /// Quiet: no progress bar and no notes on stderr (errors and warnings still
    /// appear); stdout carries only the result (nothing for trace and render).
    /// The same for every command.
    #[arg(short, long)]
    pub quiet: bool,
}

/// A count of photons as a physicist writes it: 1000000, 1e6, 2.5e5 or
/// 1_000_000 (a whole number, at most 2^63).
pub fn parse_count(s: &str) -> Result<u64, String> {
    let text = s.trim().replace('_', "");
    if let Ok(n) = text.parse::<u64>() {
        return Ok(n);
    }
    match text.parse::<f64>() {
        Ok(x) if x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x <= 2f64.powi(63) => {
            Ok(x as u64)
        }
        Ok(x) if x.is_finite() && x >= 0.0 && x <= 2f64.powi(63) => {
            Err(format!("{s} is not a whole number of photons"))
        }
        _ => Err(format!(
            "expected a whole number such as 1000000 or 1e6, not `{s}`"
        )),
    }
}

/// Parses "a,b,c" or "start:stop:step" (inclusive of stop).
/// The values start, start + step, … up to stop (with a tolerance of 1e-9
/// steps), each the number a person would write: where start and step have
/// at most 12 decimals, value i is (A + i·S) / 10^d in integers, so that
/// 0.1:30:0.1 ends at 30 (not 30.000000000000004, beyond the Henke tables)
/// and its third value is 0.3 (not 0.30000000000000004 in file names).
fn decimal_range(a: f64, b: f64, step: f64) -> Vec<f64> {
    let count = ((b - a) / step + 1e-9).floor() as usize;
    let decimals = |x: f64| {
        (0..=12).find(|&d| {
            let scale = 10f64.powi(d);
            let n = (x * scale).round();
            n.abs() < 2f64.powi(52) && n / scale == x
        })
    };
    match (decimals(a), decimals(step)) {
        (Some(da), Some(ds)) => {
            let scale = 10f64.powi(da.max(ds));
            let (start, inc) = ((a * scale).round(), (step * scale).round());
            (0..=count)
                .map(|i| (start + inc * i as f64) / scale)
                .collect()
        }
        _ => (0..=count).map(|i| a + step * i as f64).collect(),
    }
}

pub fn parse_values(what: &str, s: &str) -> Result<Vec<f64>, super::InputError> {
    let bad = || {
        super::InputError(format!(
            "--{what} {s}: expected numbers a,b,c or a range start:stop:step"
        ))
    };
    let parts: Vec<&str> = s.split(':').collect();
    let values = if parts.len() == 3 {
        let n: Vec<f64> = parts
            .iter()
            .map(|p| p.trim().parse().map_err(|_| bad()))
            .collect::<Result<_, _>>()?;
        let (a, b, step) = (n[0], n[1], n[2]);
        if !(step > 0.0 && b >= a) || (b - a) / step > 1e6 {
            return Err(super::InputError(format!(
                "--{what} {s}: need stop ≥ start, step > 0 and at most a million values"
            )));
        }
        decimal_range(a, b, step)
    } else if parts.len() == 1 {
        s.split(',')
            .map(|p| p.trim().parse().map_err(|_| bad()))
            .collect::<Result<Vec<f64>, _>>()?
    } else {
        return Err(bad());
    };
    if values.is_empty() || values.iter().any(|v| !v.is_finite()) {
        return Err(bad());
    }
    Ok(values)
}

/// Two numbers `X,Y`.
pub fn parse_pair(s: &str) -> Result<[f64; 2], String> {
    let v: Vec<Option<f64>> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect();
    match v.as_slice() {
        [Some(x), Some(y)] => Ok([*x, *y]),
        _ => Err(format!("`{s}`: expected two numbers X,Y")),
    }
}

#[cfg(test)]
mod range_tests {
    #[test]
    fn ranges_hold_the_numbers_a_person_writes() {
        let v = super::decimal_range(0.1, 30.0, 0.1);
        assert_eq!(v.len(), 300);
        assert_eq!(v[2], 0.3);
        assert_eq!(v[119], 12.0);
        assert_eq!(*v.last().unwrap(), 30.0);
        assert_eq!(
            super::decimal_range(0.0, 1.0, 0.25),
            [0.0, 0.25, 0.5, 0.75, 1.0]
        );
        // Not decimal: as before.
        let third = 1.0 / 3.0;
        assert_eq!(super::decimal_range(0.0, 1.0, third).len(), 4);
    }
}
