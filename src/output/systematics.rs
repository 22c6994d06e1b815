//! The files of a systematics study (`studies::systematics`): the table of
//! every variation (`systematics.csv`), each source's effect and the study's
//! description (`systematics.json`), the maps as npy (`map_*.npy`) and FITS
//! (`systematics.fits`: the mean image, then the nominal one, the total σ and
//! each source's σ as extensions), and the mean and σ images as PNG.

use super::fits_maps::{write_maps_fits, Map};
use super::image_plot::{write_image_figure, ImageFigure, SecondaryAxes};
use super::npy::write_npy_f64;
use super::run_files::{flux_unit, write_json};
use super::{write_csv, Provenance};
use crate::colormap::Scale;
use crate::studies::systematics::{summary::metrics, Systematics, METRICS};
use serde_json::json;
use std::path::Path;

/// The files a systematics study writes, by what they hold.
#[derive(Clone, Copy, Debug)]
pub struct SystematicsFiles {
    /// Every variation's metrics.
    pub table_csv: &'static str,
    /// Each source's effect and the study's description.
    pub description_json: &'static str,
    /// The mean, nominal, σ and per-source σ maps as FITS images.
    pub maps_fits: &'static str,
    pub nominal_npy: &'static str,
    pub mean_npy: &'static str,
    pub sigma_npy: &'static str,
    /// One σ map per source, stacked.
    pub sigma_by_source_npy: &'static str,
    /// Every variation's image, stacked.
    pub variations_npy: &'static str,
    pub mean_png: &'static str,
    pub sigma_png: &'static str,
    /// σ over the nominal image, pixel by pixel.
    pub sigma_relative_npy: &'static str,
    /// The Monte Carlo noise of a variation's image (NaN where not measured).
    pub sigma_noise_npy: &'static str,
}

/// The files a systematics study writes.
pub const SYSTEMATICS_FILES: SystematicsFiles = SystematicsFiles {
    table_csv: "systematics.csv",
    description_json: "systematics.json",
    maps_fits: "systematics.fits",
    nominal_npy: "map_nominal.npy",
    mean_npy: "map_mean.npy",
    sigma_npy: "map_sigma.npy",
    sigma_by_source_npy: "map_sigma_by_source.npy",
    variations_npy: "map_variations.npy",
    mean_png: "map_mean.png",
    sigma_png: "map_sigma.png",
    sigma_relative_npy: "map_sigma_relative.npy",
    sigma_noise_npy: "map_sigma_noise.npy",
};

impl SystematicsFiles {
    /// Every name, in the order above.
    pub fn all(&self) -> [&'static str; 12] {
        [
            self.table_csv,
            self.description_json,
            self.maps_fits,
            self.nominal_npy,
            self.mean_npy,
            self.sigma_npy,
            self.sigma_by_source_npy,
            self.variations_npy,
            self.mean_png,
            self.sigma_png,
            self.sigma_relative_npy,
            self.sigma_noise_npy,
        ]
    }
}

/// Writes the study's files into `dir`; `scene_name` titles the pictures.
pub fn write_systematics(
    dir: &Path,
    s: &Systematics,
    scene_name: &str,
    provenance: &Provenance,
) -> std::io::Result<()> {
    let f = SYSTEMATICS_FILES;
    write_table(&dir.join(f.table_csv), s)?;
    write_json(&dir.join(f.description_json), &description(s, provenance))?;
    let [nx, ny] = s.frame.pixels;
    let unit = flux_unit(s.facts.counted);
    let mut maps = vec![
        Map {
            name: String::new(),
            data: &s.mean_map,
            what: "mean image: nominal plus each source's mean shift".into(),
        },
        Map {
            name: "NOMINAL".into(),
            data: &s.nominal_map,
            what: "the nominal scene's image".into(),
        },
        Map {
            name: "SIGMA".into(),
            data: &s.sigma_map,
            what: "total systematic sigma: the sources' in quadrature".into(),
        },
    ];
    for (e, m) in s.sources.iter().zip(&s.sigma_maps) {
        maps.push(Map {
            name: format!("SIGMA_{}", e.name.to_uppercase().replace(':', "_")),
            data: m,
            what: format!("sigma of {}", e.name),
        });
    }
    let frame = if s.frame.grid.is_some() {
        "position from the detector grid's centre"
    } else {
        "position on the sensor"
    };
    write_maps_fits(
        &dir.join(f.maps_fits),
        [ny, nx],
        (s.frame.first_mm, s.frame.step_mm, frame),
        &unit,
        &maps,
        (provenance, f.description_json),
    )?;
    let dims = [ny as u64, nx as u64];
    write_npy_f64(&dir.join(f.nominal_npy), &dims, &s.nominal_map)?;
    write_npy_f64(&dir.join(f.mean_npy), &dims, &s.mean_map)?;
    write_npy_f64(&dir.join(f.sigma_npy), &dims, &s.sigma_map)?;
    write_npy_f64(
        &dir.join(f.sigma_relative_npy),
        &dims,
        &s.relative_sigma_map,
    )?;
    let unknown = vec![f64::NAN; s.sigma_map.len()];
    write_npy_f64(
        &dir.join(f.sigma_noise_npy),
        &dims,
        s.noise_map.as_ref().unwrap_or(&unknown),
    )?;
    let stack = |v: Vec<&Vec<f64>>| -> (Vec<u64>, Vec<f64>) {
        let shape = vec![v.len() as u64, ny as u64, nx as u64];
        (shape, v.into_iter().flatten().copied().collect())
    };
    let (shape, data) = stack(s.sigma_maps.iter().collect());
    write_npy_f64(&dir.join(f.sigma_by_source_npy), &shape, &data)?;
    let (shape, data) = stack(s.outcomes.iter().map(|o| &o.map).collect());
    write_npy_f64(&dir.join(f.variations_npy), &shape, &data)?;
    // Both framed as the sensor figures are, on the nominal image's flux: a
    // 15 mm image is not lost on a 60 mm detector.
    let g = map_geometry(s);
    let quality = crate::analysis::analyse(&s.nominal_map, &g, None);
    for (file, values, what) in [
        (f.mean_png, &s.mean_map, "mean image"),
        (f.sigma_png, &s.sigma_map, "systematic σ (all sources)"),
    ] {
        let mut fig = figure(s, values, (scene_name, what));
        if let Some((q, _)) = &quality {
            if super::sensor_figure::frame_figure(
                &mut fig,
                values,
                &g,
                (q.centroid_mm, 0.5 * q.d90_mm),
            ) {
                fig.orientation.push_str(&format!(
                    "; framed: ±2 × the nominal image's 90 % radius ({}: all of it)",
                    f.mean_npy
                ));
            }
        }
        write_image_figure(&dir.join(file), &fig)?;
    }
    Ok(())
}

/// The maps' pixel geometry, for the analysis that frames their figures.
fn map_geometry(s: &Systematics) -> crate::analysis::ImageGeometry {
    let fr = &s.frame;
    crate::analysis::ImageGeometry {
        nx: fr.pixels[0],
        ny: fr.pixels[1],
        pitch: fr.step_mm,
        origin_mm: std::array::from_fn(|k| fr.first_mm[k] - 0.5 * fr.step_mm[k]),
    }
}

/// The PNG of one map.
fn figure<'a>(s: &Systematics, values: &'a [f64], (scene, what): (&str, &str)) -> ImageFigure<'a> {
    let fr = &s.frame;
    let extent = std::array::from_fn(|k| {
        let a = fr.first_mm[k] - 0.5 * fr.step_mm[k];
        [a, a + fr.pixels[k] as f64 * fr.step_mm[k]]
    });
    let names: Vec<&str> = s.sources.iter().map(|e| e.name.as_str()).collect();
    let on_grid = fr.grid.is_some();
    ImageFigure {
        title: format!("{scene}: {what}, sensor {}", s.facts.sensor),
        subtitle: format!(
            "{} variations · sources: {}",
            s.outcomes.len(),
            names.join(", ")
        ),
        values: std::borrow::Cow::Borrowed(values),
        pixels: fr.pixels,
        extent_mm: extent,
        // On the detector's grid, its pixel indices too.
        secondary: on_grid
            .then(|| SecondaryAxes::pixel_index(fr.step_mm[0], [extent[0][0], extent[1][0]])),
        unit: format!(
            "{} per {}",
            match s.facts.counted.particles() {
                "" => "weight".to_string(),
                p => format!("{p} s⁻¹"),
            },
            if on_grid {
                "detector pixel"
            } else {
                "map pixel"
            }
        ),
        scale: Scale::Linear,
        axes: if on_grid {
            ["grid x".into(), "grid y".into()]
        } else {
            ["sensor x".into(), "sensor y".into()]
        },
        orientation: if on_grid {
            "axes of the detector pixel grid, from its centre".into()
        } else {
            "the sensor's local axes, from its centre".into()
        },
        overlay: Default::default(),
        note: None,
        top: None,
    }
}

/// `systematics.csv`: one row per variation.
fn write_table(path: &Path, s: &Systematics) -> std::io::Result<()> {
    let mut header = vec!["source", "variation", "settings"];
    header.extend(METRICS);
    header.push("photons_on_sensor");
    let rows = s.outcomes.iter().zip(&s.plan.variations).map(|(o, v)| {
        let mut row = vec![o.source.clone(), o.label.clone(), settings(v)];
        row.extend(metrics(o).iter().map(|x| match x.is_nan() {
            true => String::new(),
            false => format!("{x:e}"),
        }));
        row.push(o.photons_recorded.to_string());
        row
    });
    write_csv(path, &header, rows)
}

/// A variation's settings in words: its overrides, or its figure parameters.
fn settings(v: &crate::studies::systematics::Variation) -> String {
    match v.figure {
        Some(f) => format!(
            "in_plane_narrow={} in_plane_wide={} wide_fraction={} out_of_plane={}",
            f.in_plane_narrow, f.in_plane_wide, f.wide_fraction, f.out_of_plane
        ),
        None => v.defines.join(" "),
    }
}

/// `systematics.json`: each source's effect, the nominal values, the total,
/// the map's frame and what the files hold.
pub fn description(s: &Systematics, provenance: &Provenance) -> serde_json::Value {
    let effects: Vec<_> = s
        .sources
        .iter()
        .map(|e| {
            let by: serde_json::Map<String, serde_json::Value> = METRICS
                .iter()
                .zip(&e.effects)
                .map(|(m, x)| (m.to_string(), json!({"sigma": x.sigma, "shift": x.shift})))
                .collect();
            json!({"name": e.name, "kind": e.kind, "what": e.what, "variations": e.variations, "effects": by})
        })
        .collect();
    let nominal = metrics(&s.outcomes[0]);
    json!({
        "provenance": provenance,
        "what": "the image's systematic uncertainty: the scene traced under each source of uncertainty with the same photons (common random numbers); each source's standard deviation sigma (draws: their sample standard deviation; a low and a high value taken as ±1σ: the root mean square of their differences to the nominal; an alternative model: its difference to the nominal) and mean shift (draws: their mean minus the nominal; a range: the mean of low and high minus the nominal; an alternative: it minus the nominal), the sources combined in quadrature",
        "units": {
            "flux": if s.facts.absolute { format!("{} per second on the sensor", s.facts.counted.particles()) } else { "summed photon weights on the sensor".into() },
            "central_flux": format!("the same in the central {} around the sensor's centre", crate::studies::systematics::central_words(s.facts.central_mm, s.facts.central_circle)),
            "diameters": "arcsec (HPD, 80 %, 90 % encircled flux)",
            "centroid": "mm on the sensor",
        },
        "sensor": s.facts.sensor,
        "central_mm": s.facts.central_mm,
        "maps": {
            "map_sigma_relative.npy": "the total sigma over the mean image, per pixel (NaN where the mean is not positive)",
            "map_sigma_noise.npy": "the Monte Carlo noise of map_sigma.npy, per pixel: half the difference of the total sigma computed from each half of the photons (two independent estimates; NaN when not kept)",
            "noise_to_sigma": s.noise_to_sigma,
            "noise_to_sigma_means": "sqrt(sum of noise^2 / sum of sigma^2) over the map: well below 1 when the sigma map shows the sources, not the photons' noise; near 1 or above, trace more photons",
        },
        "central_region": if s.facts.central_circle { "circle (central_mm its radius)" } else { "square (central_mm its side)" },
        "nominal": METRICS.iter().zip(nominal).map(|(m, x)| (m.to_string(), json!(x))).collect::<serde_json::Map<_, _>>(),
        "sources": effects,
        "total_sigma": METRICS.iter().zip(&s.total_sigma).map(|(m, x)| (m.to_string(), json!(x))).collect::<serde_json::Map<_, _>>(),
        "skipped": s.plan.skipped.iter().map(|(n, r)| json!({"source": n, "reason": r})).collect::<Vec<_>>(),
        "notes": s.plan.notes,
        "map": s.frame,
        "files": {
            "systematics.csv": "one row per traced variation: its source, settings and quantities",
            "systematics.fits": "primary: the mean image; extensions NOMINAL, SIGMA (total) and SIGMA_<SOURCE>; WCS in mm on the map's frame",
            "map_nominal.npy": "float64 [iy, ix]: the nominal image on the map",
            "map_mean.npy": "float64 [iy, ix]: the nominal image plus each source's mean shift",
            "map_sigma.npy": "float64 [iy, ix]: the total systematic sigma per pixel",
            "map_sigma_by_source.npy": "float64 [source, iy, ix] in the order of sources",
            "map_variations.npy": "float64 [variation, iy, ix]: every traced variation's image, in the order of systematics.csv",
        },
        "seconds": s.facts.seconds,
        "threads": s.facts.threads,
    })
}
