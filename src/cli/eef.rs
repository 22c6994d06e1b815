//! `traxer eef`: encircled energy, HPD, 80 % and 90 % diameters of any `.npy` image.

use super::InputError;
use anyhow::Context;
use serde_json::json;
use std::path::{Path, PathBuf};
use traxer::analysis::{analyse, ImageGeometry};
use traxer::files::check_output_file;
use traxer::output::{read_image, sidecar_path, write_eef_plot, write_sidecar, Provenance};

/// Encircled-energy analysis of an image from a trace or from elsewhere.
///
/// Reads a 2-D .npy image [iy][ix] (or 3-D [band][iy][ix], summed over bands), of
/// any numeric type. The pixel pitch comes from --pixel-pitch or, for traxer's own
/// images, from the JSON sidecar next to it (NAME.json). Prints the centroid and
/// the 50/80/90 % diameters (mm, and arcsec with --focal-length) and writes the EEF
/// plot with a sidecar (PLOT.json: provenance and the numbers).
#[derive(clap::Args)]
pub struct EefArgs {
    /// The image (.npy).
    pub image: PathBuf,
    /// Focal length (mm) for diameters in arcseconds: 2·atan(r/f).
    #[arg(value_name = "MM", long)]
    pub focal_length: Option<f64>,
    /// Pixel pitch in mm (x,y or one value for square pixels).
    #[arg(value_name = "MM", long, value_delimiter = ',')]
    pub pixel_pitch: Vec<f64>,
    /// EEF plot to write (default: IMAGE_eef.png next to the image).
    #[arg(value_name = "PNG", long)]
    pub plot: Option<PathBuf>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub quiet: super::args::QuietArg,
}

pub fn run(a: EefArgs) -> anyhow::Result<()> {
    let img = read_image(&a.image)?;
    let (ny, nx, image) = (img.ny, img.nx, img.summed);
    if image.iter().any(|v| !v.is_finite() || *v < 0.0) {
        return Err(InputError(format!(
            "{}: pixel values must be finite and ≥ 0",
            a.image.display()
        ))
        .into());
    }
    let pitch = pixel_pitch(&a)?;
    let g = ImageGeometry {
        nx,
        ny,
        pitch,
        origin_mm: [-0.5 * nx as f64 * pitch[0], -0.5 * ny as f64 * pitch[1]],
    };
    let Some((q, eef)) = analyse(&image, &g, a.focal_length) else {
        return Err(InputError(format!("{}: the image holds no flux", a.image.display())).into());
    };
    let plot = a.plot.clone().unwrap_or_else(|| {
        let stem = a
            .image
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        a.image.with_file_name(format!("{stem}_eef.png"))
    });
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
    write_sidecar(&plot, &Provenance::new(&super::invocation(), None), details)
        .with_context(|| format!("cannot write the sidecar of {}", plot.display()))?;
    if a.json {
        say!("{}", serde_json::to_string_pretty(&q)?);
    } else {
        print_quality(&q);
        if !a.quiet.quiet {
            tell!("wrote {}", plot.display());
        }
    }
    Ok(())
}

/// The pixel pitch (mm): given, or from the sidecar next to the image; checked
/// with the focal length.
fn pixel_pitch(a: &EefArgs) -> Result<[f64; 2], InputError> {
    let pitch = match a.pixel_pitch.as_slice() {
        [p] => [*p, *p],
        [px, py] => [*px, *py],
        [] => pitch_from_sidecar(&a.image).ok_or_else(|| {
            InputError(format!(
                "{}: give --pixel-pitch (no traxer sidecar JSON next to it)",
                a.image.display()
            ))
        })?,
        _ => {
            return Err(InputError(
                "--pixel-pitch takes one or two values (mm)".into(),
            ))
        }
    };
    if !pitch.iter().all(|p| p.is_finite() && *p > 0.0)
        || a.focal_length.is_some_and(|f| !(f.is_finite() && f > 0.0))
    {
        return Err(InputError(
            "pixel pitch and focal length must be positive (mm)".into(),
        ));
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

/// Pixel pitch from traxer's sidecar NAME.json next to NAME.npy.
fn pitch_from_sidecar(image: &Path) -> Option<[f64; 2]> {
    let text = std::fs::read_to_string(image.with_extension("json")).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    let p = v.get("sensor")?.get("pixel_pitch_mm")?;
    Some([p.get(0)?.as_f64()?, p.get(1)?.as_f64()?])
}
