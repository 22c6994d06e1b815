//! `traxer eef`: encircled energy, HPD, 80 % and 90 % diameters of any `.npy`
//! or FITS image.

use super::InputError;
use anyhow::Context;
use serde_json::json;
use std::path::{Path, PathBuf};
use traxer::analysis::{analyse, ImageGeometry};
use traxer::files::{check_output_file, MANIFEST};
use traxer::output::{
    read_fits_image, read_image, sidecar_path, write_eef_plot, write_sidecar, FitsImage, Provenance,
};

/// Encircled-energy analysis of an image from a trace or from elsewhere.
///
/// Reads a 2-D .npy image [iy][ix] (or 3-D [band][iy][ix], summed over bands), of
/// any numeric type, or a FITS image (.fits, .fit, .fts: the first image HDU).
/// The pixel pitch comes from --pixel-pitch, else from a FITS header's WCS in
/// mm, else, for traxer's own images (NAME.npy, NAME_grid.npy, class images),
/// from the sensor's JSON next to it; the focal length likewise (FOCALLEN, the
/// sensor's). Prints the centroid and the 50/80/90 % diameters (mm, and arcsec
/// with a focal length), with --radius the flux in signal regions (circles
/// about the centroid or --center), and writes the EEF plot with a sidecar (PLOT.json:
/// provenance and the numbers): beside the image, or, for an image in a
/// results folder (which holds one run's results), in the current folder.
#[derive(clap::Args)]
pub struct EefArgs {
    /// The image (.npy or .fits).
    pub image: PathBuf,
    /// Focal length (mm) for diameters in arcseconds: 2·atan(r/f).
    #[arg(value_name = "MM", long)]
    pub focal_length: Option<f64>,
    /// Pixel pitch in mm (x,y or one value for square pixels).
    #[arg(value_name = "MM", long, value_delimiter = ',')]
    pub pixel_pitch: Vec<f64>,
    /// EEF plot to write (default: IMAGE_eef.png next to the image, or in the
    /// current folder if the image lies in a results folder).
    #[arg(value_name = "PNG", long)]
    pub plot: Option<PathBuf>,
    /// Signal regions: the flux within these radii (mm, comma-separated) of
    /// the centroid, or of --center, printed as fractions of the image's flux.
    #[arg(
        value_name = "MM",
        long,
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    pub radius: Vec<f64>,
    /// The signal regions' centre (mm, x,y from the image's centre; the
    /// frame of the printed centroid) instead of the centroid.
    #[arg(
        value_name = "X,Y",
        long,
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    pub center: Vec<f64>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub quiet: super::args::QuietArg,
}

pub fn run(a: EefArgs) -> anyhow::Result<()> {
    let img = read_any_image(&a.image)?;
    let (ny, nx, image) = (img.ny, img.nx, img.summed);
    let focal_length = a.focal_length.or(img.focal_length_mm);
    if image.iter().any(|v| !v.is_finite() || *v < 0.0) {
        return Err(InputError(format!(
            "{}: pixel values must be finite and ≥ 0",
            a.image.display()
        ))
        .into());
    }
    let pitch = pixel_pitch(&a, img.pitch_mm, &img.pitch_from, focal_length)?;
    let g = ImageGeometry {
        nx,
        ny,
        pitch,
        origin_mm: [-0.5 * nx as f64 * pitch[0], -0.5 * ny as f64 * pitch[1]],
    };
    let Some((q, eef)) = analyse(&image, &g, focal_length) else {
        return Err(InputError(format!("{}: the image holds no flux", a.image.display())).into());
    };
    let regions = signal_regions(&a, &image, &g, &q)?;
    let plot = plot_path(&a)?;
    check_output_file(&plot)?;
    check_output_file(&sidecar_path(&plot))?;
    write_eef_plot(
        &plot,
        &format!("{}: encircled energy", a.image.display()),
        &q,
        &eef,
    )
    .with_context(|| format!("cannot write {}", plot.display()))?;
    let details = json!({
        "image": a.image.display().to_string(),
        "pixel_pitch_mm": pitch,
        "image_quality": q,
    });
    write_sidecar(&plot, &Provenance::of_table(&super::invocation()), details)
        .with_context(|| format!("cannot write the sidecar of {}", plot.display()))?;
    if a.json {
        let mut v = serde_json::to_value(&q)?;
        if let Some(r) = &regions {
            v["signal_regions"] = r.json();
        }
        say!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        print_quality(&q);
        if let Some(r) = &regions {
            r.print();
        }
        if !a.quiet.quiet {
            tell!("wrote {}", plot.display());
        }
    }
    Ok(())
}

/// Whether `dir` is a traxer results folder (it holds the list of one run's
/// files).
fn is_results_folder(dir: &Path) -> bool {
    dir.join(MANIFEST).is_file()
}

/// Where the EEF plot goes: --plot, else IMAGE_eef.png beside the image, or
/// in the current folder when the image lies in a results folder. A results
/// folder holds one run's results: `NAME_eef.png` there is the trace's own
/// plot, which an analysis of the image must not silently replace.
fn plot_path(a: &EefArgs) -> Result<PathBuf, InputError> {
    let folder = |p: &Path| {
        p.parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."))
            .to_path_buf()
    };
    let refuse = |plot: &Path| {
        InputError(format!(
            "{}: {} is a traxer results folder, which holds one run's results (its own plots among them): give --plot a place outside it",
            plot.display(),
            folder(plot).display()
        ))
    };
    if let Some(p) = &a.plot {
        return match is_results_folder(&folder(p)) {
            true => Err(refuse(p)),
            false => Ok(p.clone()),
        };
    }
    let stem = a
        .image
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let name = format!("{stem}_eef.png");
    let beside = a.image.with_file_name(&name);
    if !is_results_folder(&folder(&beside)) {
        return Ok(beside);
    }
    let here = PathBuf::from(&name);
    match is_results_folder(Path::new(".")) {
        true => Err(refuse(&here)),
        false => Ok(here),
    }
}

/// The flux within circles about one centre.
struct SignalRegions {
    centre_mm: [f64; 2],
    /// Whether the centre is the centroid (else --center).
    about_centroid: bool,
    radii_mm: Vec<f64>,
    flux: Vec<f64>,
    total: f64,
}

impl SignalRegions {
    fn json(&self) -> serde_json::Value {
        json!({
            "center_mm": self.centre_mm,
            "about": if self.about_centroid { "the centroid" } else { "--center" },
            "regions": self.radii_mm.iter().zip(&self.flux).map(|(r, f)| json!({
                "radius_mm": r,
                "flux": f,
                "fraction": f / self.total,
            })).collect::<Vec<_>>(),
        })
    }

    fn print(&self) {
        let about = match self.about_centroid {
            true => "the centroid",
            false => "the given centre",
        };
        for (r, f) in self.radii_mm.iter().zip(&self.flux) {
            say!(
                "within {} mm of {about} ({:.4}, {:.4}): {:.2} % of the flux ({f:.6e} of {:.6e})",
                traxer::text::number(*r),
                self.centre_mm[0],
                self.centre_mm[1],
                100.0 * f / self.total,
                self.total
            );
        }
    }
}

/// The flux within --radius of the centroid or --center, if asked.
fn signal_regions(
    a: &EefArgs,
    image: &[f64],
    g: &ImageGeometry,
    q: &traxer::analysis::ImageQuality,
) -> Result<Option<SignalRegions>, InputError> {
    if a.radius.is_empty() {
        if !a.center.is_empty() {
            return Err(InputError(
                "--center is the centre of the --radius circles: give --radius too".into(),
            ));
        }
        return Ok(None);
    }
    if let Some(r) = a.radius.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
        return Err(InputError(format!(
            "--radius {}: expected positive radii in mm",
            traxer::text::number(*r)
        )));
    }
    let centre_mm = match a.center.as_slice() {
        [] => q.centroid_mm,
        [x, y] if x.is_finite() && y.is_finite() => [*x, *y],
        _ => {
            return Err(InputError(
                "--center takes two numbers, x,y in mm from the image's centre".into(),
            ))
        }
    };
    Ok(Some(SignalRegions {
        centre_mm,
        about_centroid: a.center.is_empty(),
        flux: traxer::analysis::flux_within(image, g, centre_mm, &a.radius),
        radii_mm: a.radius.clone(),
        total: q.total_flux,
    }))
}

/// The image, its pitch and focal length where the file or its sensor's JSON
/// say them.
fn read_any_image(path: &Path) -> Result<FitsImage, InputError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if matches!(ext.as_deref(), Some("fits" | "fit" | "fts")) {
        return read_fits_image(path).map_err(InputError);
    }
    let img = read_image(path).map_err(|e| InputError(e.to_string()))?;
    let sensor = sensor_of(path);
    Ok(FitsImage {
        nx: img.nx,
        ny: img.ny,
        summed: img.summed,
        pitch_mm: sensor.as_ref().map(|s| s.pitch_mm),
        pitch_from: sensor.as_ref().map_or(String::new(), |s| s.from.clone()),
        focal_length_mm: sensor.and_then(|s| s.focal_length_mm),
    })
}

/// The pixel pitch (mm): given, or from the image's file or sensor; checked
/// with the focal length.
fn pixel_pitch(
    a: &EefArgs,
    found: Option<[f64; 2]>,
    found_in: &str,
    focal_length: Option<f64>,
) -> Result<[f64; 2], InputError> {
    let pitch = match a.pixel_pitch.as_slice() {
        [p] => [*p, *p],
        [px, py] => [*px, *py],
        [] => found.ok_or_else(|| {
            InputError(format!(
                "{}: give --pixel-pitch (neither a FITS WCS in mm nor a traxer sensor JSON beside it says it)",
                a.image.display()
            ))
        })?,
        _ => {
            return Err(InputError(
                "--pixel-pitch takes one or two values (mm)".into(),
            ))
        }
    };
    if !pitch.iter().all(|p| p.is_finite() && *p > 0.0) {
        let from = match a.pixel_pitch.is_empty() {
            true => found_in.to_string(),
            false => "--pixel-pitch".into(),
        };
        return Err(InputError(format!(
            "{from}: pixel pitch {:e} × {:e} mm: expected positive lengths (mm); give --pixel-pitch",
            pitch[0], pitch[1]
        )));
    }
    if let Some(f) = focal_length.filter(|f| !(f.is_finite() && *f > 0.0)) {
        return Err(InputError(format!(
            "focal length {f:e} mm (--focal-length, or the image's FOCALLEN / sensor JSON): expected a positive length"
        )));
    }
    Ok(pitch)
}

/// Centroid and diameters on stdout.
fn print_quality(q: &traxer::analysis::ImageQuality) {
    say!(
        "centroid: ({:.4}, {:.4}) mm",
        q.centroid_mm[0],
        q.centroid_mm[1]
    );
    for (name, d, s) in [
        ("HPD (50 %)", q.hpd_mm, q.hpd_arcsec),
        ("80 %", q.d80_mm, q.d80_arcsec),
        ("90 %", q.d90_mm, q.d90_arcsec),
    ] {
        match s {
            Some(s) => say!("{name:>11}: {d:.4} mm = {s:.1} arcsec"),
            None => say!("{name:>11}: {d:.4} mm"),
        }
    }
}

/// What a traxer sensor JSON beside an image says about it.
struct SensorInfo {
    pitch_mm: [f64; 2],
    /// The JSON file and key the pitch comes from.
    from: String,
    focal_length_mm: Option<f64>,
}

/// The pitch and focal length of a traxer image, from the JSON of the sensor
/// that lists the file among its files (NAME.json lists NAME.npy, its class
/// images and, under pixel_grid, NAME_grid.npy with the grid's pitch).
fn sensor_of(image: &Path) -> Option<SensorInfo> {
    let name = image.file_name()?.to_string_lossy().into_owned();
    let dir = image
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let lists = |files: Option<&serde_json::Value>| {
        files.and_then(|f| f.as_object()).is_some_and(|f| {
            f.values().any(|v| {
                v.as_str() == Some(&name)
                    || v.as_array()
                        .is_some_and(|a| a.iter().any(|x| x.as_str() == Some(&name)))
            })
        })
    };
    for entry in std::fs::read_dir(dir).ok()?.flatten() {
        let path = entry.path();
        if path.extension().and_then(|e| e.to_str()) != Some("json") {
            continue;
        }
        let Some(v) = std::fs::read_to_string(&path)
            .ok()
            .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        else {
            continue;
        };
        let Some(sensor) = v.get("sensor") else {
            continue;
        };
        let focal_length_mm = sensor
            .get("image_quality")
            .and_then(|q| q.get("focal_length_mm"))
            .and_then(|f| f.as_f64());
        let grid = sensor.get("pixel_grid").filter(|g| !g.is_null());
        if let Some(g) = grid.filter(|g| lists(g.get("files"))) {
            let p = g.get("pitch_mm")?.as_f64()?;
            return Some(SensorInfo {
                pitch_mm: [p, p],
                from: format!("{}: key sensor.pixel_grid.pitch_mm", path.display()),
                focal_length_mm,
            });
        }
        // The per-process images (NAME_primakoff.npy, ...) are listed under
        // by_process, on the sensor's pixels.
        let process_image = sensor
            .get("by_process")
            .and_then(|b| b.get("processes"))
            .and_then(|p| p.as_array())
            .is_some_and(|p| {
                p.iter()
                    .any(|e| e.get("file").and_then(|f| f.as_str()) == Some(&name))
            });
        if lists(sensor.get("files")) || process_image {
            let p = sensor.get("pixel_pitch_mm")?;
            let pitch_mm = [p.get(0)?.as_f64()?, p.get(1)?.as_f64()?];
            return Some(SensorInfo {
                pitch_mm,
                from: format!("{}: key sensor.pixel_pitch_mm", path.display()),
                focal_length_mm,
            });
        }
    }
    None
}
