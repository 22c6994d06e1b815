//! The files of a trace run: per sensor the images (`NAME.npy` flux,
//! `NAME_counts.npy`), the figures (`NAME.png`, `NAME_log.png`,
//! `NAME_pixels.png`, `NAME_eef.png`), `NAME_projections.csv` and `NAME.json`
//! (named by `sensor::SensorFiles`), with a pixel grid its `NAME_grid.*`, with
//! a gas its conversion depths, per path class and per emission process their
//! images, and with `--fits` the FITS files; the photon list; `summary.json`.
//!
//! Data flow: `run::write_results` (or the live window's save) →
//! [`write_run`] → per sensor `write_sensor` (figures by `sensor_figure`).

use super::conversion::write_conversion;
use super::history::{history_json, write_class_images, write_photon_list, PHOTON_LIST_FILES};
use super::image_plot::SecondaryAxes;
use super::processes::{process_images, write_process_images};
use super::sensor_figure::sensor_figure;
use super::write_eef_plot;
use super::{
    write_csv, write_image_figure, write_npy_f64, write_npy_u64, write_png, Provenance, Scale,
};
use super::{write_grid_fits, write_sensor_fits, FluxUnit, SensorFits};
use crate::analysis::{image_shape, projections, FinishedImage, ImageGeometry};
use crate::files::atomic_write;
use crate::scene::Counted;
use crate::scene::Scene;
use crate::sensor::{fits_file_name, grid_fits_file_name, GridFiles, SensorFiles, SUMMARY_FILE};
use crate::studies::sky::SkyCalibration;
use crate::trace::RunResult;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The optional outputs of a trace, chosen once by the front end.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Outputs {
    /// Each sensor's image as FITS too (`--fits`).
    pub fits: bool,
    /// The photon list (`--photon-list N`, N > 0).
    pub photon_list: bool,
}

/// Every file a trace of `scene` writes: each sensor's and summary.json, the
/// photon list if one is asked for, and each sensor's FITS image with `fits`.
pub fn run_file_names(scene: &Scene, outputs: Outputs) -> Vec<String> {
    let Outputs { fits, photon_list } = outputs;
    let list = photon_list
        .then_some(PHOTON_LIST_FILES)
        .into_iter()
        .flatten();
    scene
        .sensors
        .iter()
        .flat_map(|s| s.file_names())
        .chain([SUMMARY_FILE.to_string()])
        .chain(super::campaign::campaign_file_names(scene))
        .chain(list.map(String::from))
        .chain(scene.sensors.iter().filter(|_| fits).flat_map(|s| {
            let grid = s.pixel_grid.map(|_| grid_fits_file_name(&s.name));
            std::iter::once(fits_file_name(&s.name)).chain(grid)
        }))
        .collect()
}

/// Writes every output of a run into `dir` (created if needed), with each sensor's
/// image as FITS too if `fits` is given: per sensor, where the sky images on it
/// (`studies::sky`, for a Sun scene; `None` otherwise); returns the paths.
pub fn write_run(
    dir: &Path,
    scene: &Scene,
    result: &RunResult,
    provenance: &Provenance,
    fits: Option<&[Option<SkyCalibration>]>,
) -> std::io::Result<Vec<PathBuf>> {
    crate::files::create_dir_all(dir)?;
    let mut written = Vec::new();
    let stats = statistics_json(scene, result);
    let photons = result.stats.photons_emitted;
    let sources = crate::source::sources_json(&scene.sources, photons, scene.magnet.as_deref());
    // A Sun makes images in axions per second (it is then the only source).
    let absolute = scene.rate_per_unit_weight(photons);
    let mut sensor_summaries = Vec::new();
    for (k, (spec, image)) in scene.sensors.iter().zip(&result.images).enumerate() {
        let run = RunJson {
            provenance,
            sources: &sources,
            stats: &stats,
            statistics: &result.stats,
            fits: fits.is_some(),
            sky: fits.and_then(|f| f.get(k)).and_then(Option::as_ref),
        };
        let (summary, files) = write_sensor(dir, scene, spec, image, absolute, &run)?;
        sensor_summaries.push(summary);
        written.extend(files);
    }
    if result.photon_list > 0 {
        written.extend(write_photon_list(
            dir,
            scene,
            &result.photons,
            absolute.unwrap_or(1.0),
        )?);
    }
    let summary = json!({
        "provenance": provenance,
        "sensors": sensor_summaries,
        "sources": sources,
        "statistics": stats,
        "warnings": scene.warnings,
        "magnet": scene.converting_magnet().map(|m| m.assumptions()),
    });
    written.extend(super::campaign::write_campaign(
        dir,
        scene,
        result,
        absolute.unwrap_or(1.0),
    )?);
    let p = dir.join(SUMMARY_FILE);
    write_json(&p, &summary)?;
    written.push(p);
    Ok(written)
}

/// What every sensor's JSON repeats about the run.
pub(super) struct RunJson<'a> {
    pub(super) provenance: &'a Provenance,
    sources: &'a Value,
    stats: &'a Value,
    /// The same, as counted (for the figures' notes).
    pub(super) statistics: &'a crate::trace::Statistics,
    /// Also write the image as FITS.
    fits: bool,
    /// Where the sky images on this sensor (FITS WCS `S`), for a Sun scene.
    sky: Option<&'a SkyCalibration>,
}

impl RunJson<'_> {
    /// What a sensor's figure says of the run: photons traced, what stopped them.
    fn figure_facts(&self) -> (&Provenance, &crate::trace::Statistics) {
        (self.provenance, self.statistics)
    }
}

/// Writes one sensor's files (flux and counts `.npy`, PNGs, EEF plot,
/// projections, grid, per-class images, `NAME.json`); returns its summary entry
/// and the paths written. `absolute` converts weights to axions/s (a Sun).
fn write_sensor(
    dir: &Path,
    scene: &Scene,
    spec: &crate::sensor::SensorSpec,
    image: &crate::sensor::SensorImage,
    absolute: Option<f64>,
    run: &RunJson,
) -> std::io::Result<(Value, Vec<PathBuf>)> {
    let mut written = Vec::new();
    let (nx, ny) = (spec.pixels[0] as usize, spec.pixels[1] as usize);
    // [band][iy][ix] with energy bins, [iy][ix] without.
    let shape: Vec<u64> = image_shape(spec).iter().map(|&n| n as u64).collect();
    let files = SensorFiles::of(&spec.name);
    let path = |name: &str| dir.join(name);
    write_npy_u64(&path(&files.counts_npy), &shape, &image.counts.to_vec())?; // gone before the flux is made
    let finished = FinishedImage::of(spec, image, absolute);
    let (flux, summed) = (&finished.flux[..], finished.summed());
    write_npy_f64(&path(&files.flux_npy), &shape, flux)?;
    let on_grid = finished.on_grid(spec);
    let scale = absolute.unwrap_or(1.0);
    if run.fits {
        // FITS holds every process image in one file.
        let processes = process_images(spec, image, scale);
        let fits = SensorFits {
            spec,
            flux,
            unit: flux_unit(scene.counted()),
            energy_kev: scene.image_energy_range(spec),
            provenance: run.provenance,
            json_name: &files.json,
            sky: run.sky,
            processes: &processes,
        };
        written.extend(write_fits_files(dir, &fits, on_grid.as_ref())?);
    }
    let figure = |scale| sensor_figure(scene, spec, &finished, run.figure_facts(), scale);
    write_image_figure(&path(&files.figure_png), &figure(Scale::Linear))?;
    write_image_figure(
        &path(&files.figure_log_png),
        &figure(Scale::Log { decades: 5 }),
    )?;
    write_png(&path(&files.pixels_png), nx, ny, summed, Scale::Linear)?;
    let (geometry, quality) = (&finished.geometry, &finished.quality);
    if let Some((q, eef)) = quality {
        write_eef_plot(
            &path(&files.eef_png),
            &format!("{}: encircled energy", spec.name),
            q,
            eef,
        )?;
    }
    write_projections(&path(&files.projections_csv), summed, geometry)?;
    let grid = write_grid_files(dir, scene, spec, on_grid, &finished, run, &mut written)?;
    written.extend(write_class_images(dir, spec, image, scale)?);
    let (processes, masses) = write_tallies(dir, (scene, spec, image), scale, &mut written)?;
    let conversion = write_conversion_files(dir, scene, spec, image, absolute, &mut written)?;
    let sensor = json!({
        "name": spec.name,
        "object": spec.object,
        "size_mm": spec.size,
        "pixels": spec.pixels,
        "pixel_pitch_mm": spec.pitch(),
        "layout": "image[iy, ix] (numpy row-major), or image[band, iy, ix] with energy bins; ix along the sensor's local x, iy along local y; pixel (0, 0) has its corner at local (-size_x/2, -size_y/2); PNGs show the sum over bands, +y up",
        "energy_band_edges_keV": spec.band_edges(),
        "units": {
            "lengths": "mm",
            "flux": flux_units(scene.counted(), spec.gas.is_some()),
            "counts": "number of photons per pixel",
        },
        "total_flux": finished.total_flux(),
        // With a magnet, the expected X-rays per hour of tracking (total_flux
        // is per second).
        "x_rays_per_hour_of_tracking": (scene.counted() == Counted::XRays)
            .then(|| finished.total_flux() * 3600.0),
        "image_quality": finished.image_quality(),
        "total_counts": image.total_counts(),
        "pixel_grid": grid,
        "sky_wcs": run.sky.map(sky_wcs_json),
        "conversion": conversion,
        "history": history_json(scene, image, scale),
        "by_process": processes,
        "by_mass": masses,
        "files": files_json(spec, &files, quality.is_some(), run.fits),
    });
    let doc = json!({
        "provenance": run.provenance,
        "sensor": sensor,
        "sources": run.sources,
        "statistics": run.stats,
    });
    write_json(&path(&files.json), &doc)?;
    written.extend(
        files
            .all()
            .into_iter()
            .filter(|f| *f != files.eef_png || quality.is_some())
            .map(path),
    );
    Ok((sensor, written))
}

/// The per-process and per-mass images and their JSON entries.
fn write_tallies(
    dir: &Path,
    (scene, spec, image): (
        &Scene,
        &crate::sensor::SensorSpec,
        &crate::sensor::SensorImage,
    ),
    scale: f64,
    written: &mut Vec<PathBuf>,
) -> std::io::Result<(Value, Value)> {
    let magnet = scene.counted() == Counted::XRays;
    Ok((
        write_process_images(dir, (spec, image, magnet), scale, written)?,
        super::masses::write_mass_images(dir, spec, image, scale, written)?,
    ))
}

/// The `files` entry of a sensor's JSON: each file by what it holds.
fn files_json(
    spec: &crate::sensor::SensorSpec,
    files: &SensorFiles,
    eef: bool,
    fits: bool,
) -> Value {
    json!({
        "flux_npy": files.flux_npy, "counts_npy": files.counts_npy,
        "png_linear": files.figure_png, "png_log": files.figure_log_png,
        "png_pixels": files.pixels_png,
        "eef_png": eef.then_some(&files.eef_png),
        "projections_csv": files.projections_csv,
        "fits": fits.then(|| fits_file_name(&spec.name)),
        "class_images_npy": spec.history_images.then(|| crate::sensor::class_file_names(&spec.name)),
    })
}

/// A sensor's FITS files (`--fits`): its image and, with a pixel grid, the
/// grid's image; returns their paths.
fn write_fits_files(
    dir: &Path,
    fits: &SensorFits,
    on_grid: Option<&(crate::sensor::PixelGrid, crate::sensor::Rebinned)>,
) -> std::io::Result<Vec<PathBuf>> {
    let path = dir.join(fits_file_name(&fits.spec.name));
    write_sensor_fits(&path, fits)?;
    let mut written = vec![path];
    if let Some((g, r)) = on_grid {
        let path = dir.join(grid_fits_file_name(&fits.spec.name));
        write_grid_fits(&path, fits, g, &r.flux)?;
        written.push(path);
    }
    Ok(written)
}

/// Where the sky images on a sensor, for `NAME.json` (the FITS WCS `S`).
fn sky_wcs_json(c: &SkyCalibration) -> Value {
    json!({
        "what": "where the sky images on this sensor, measured by tracing the scene's Sun at its offset and ±step along each axis (the FITS WCS S, helioprojective: HPLN along the scene's offset_arcmin[0] axis, HPLT along offset_arcmin[1], origin at the Sun's centre); errors are 1σ statistical (even vs odd photon chunks)",
        "calibration": c,
        "plate_scale_mm_per_arcmin": c.plate_scale_mm_per_arcmin(),
        "plate_scale_error_mm_per_arcmin": c.plate_scale_error(),
        "rotation_deg": c.rotation_deg(),
    })
}

/// What a sensor's pixel values are, in words, for `NAME.json`.
fn flux_units(counted: Counted, gas: bool) -> &'static str {
    match (counted, gas) {
        (Counted::Axions, false) => "axions per second per pixel reaching the sensor (before the conversion probability in the magnet: the scene has none), for the coupling in sources[].coupling",
        (Counted::Axions, true) => "axions per second per pixel whose X-ray converts in the detector gas over that pixel (before the conversion probability in the magnet: the scene has none), for the coupling in sources[].coupling",
        (Counted::XRays, false) => "X-ray photons per second per pixel reaching the sensor: axions converted in the magnet (see magnet), for the couplings in sources[].coupling and magnet.g_agamma_per_gev",
        (Counted::XRays, true) => "X-ray photons per second per pixel converting in the detector gas over that pixel: axions converted in the magnet (see magnet), for the couplings in sources[].coupling and magnet.g_agamma_per_gev",
        (Counted::Weights, false) => "sum of photon weights per pixel (see sources[].weight)",
        (Counted::Weights, true) => "sum of photon weights per pixel, each times its probability of converting in the detector gas (see sources[].weight)",
    }
}

/// Writes the sensor's image on its detector pixel grid, if it has one; returns
/// its `NAME.json` entry (null without a grid) and adds the paths to `written`.
fn write_grid_files(
    dir: &Path,
    scene: &Scene,
    spec: &crate::sensor::SensorSpec,
    on_grid: Option<(crate::sensor::PixelGrid, crate::sensor::Rebinned)>,
    finished: &FinishedImage,
    run: &RunJson,
    written: &mut Vec<PathBuf>,
) -> std::io::Result<Value> {
    let Some((g, r)) = on_grid else {
        return Ok(Value::Null);
    };
    let g = &g;
    let names = GridFiles::of(&spec.name);
    let [npy, csv, png] = names.all().map(|n| dir.join(n));
    write_grid((&npy, &csv), &r, g)?;
    let mut figure = sensor_figure(scene, spec, finished, run.figure_facts(), Scale::Linear);
    let half = [
        g.pixels[0] as f64 * g.pitch_mm / 2.0,
        g.pixels[1] as f64 * g.pitch_mm / 2.0,
    ];
    figure.title = format!(
        "{} on its {}×{} pixel grid",
        figure.title, g.pixels[0], g.pixels[1]
    );
    figure.values = std::borrow::Cow::Borrowed(&r.flux);
    figure.overlay = Default::default();
    figure.pixels = [g.pixels[0] as usize, g.pixels[1] as usize];
    figure.extent_mm = [[-half[0], half[0]], [-half[1], half[1]]];
    figure.secondary = Some(SecondaryAxes::pixel_index(g.pitch_mm, [-half[0], -half[1]]));
    figure.axes = [
        "grid x from its centre".into(),
        "grid y from its centre".into(),
    ];
    figure.unit = figure.unit.replace("per pixel", "per grid pixel");
    figure.orientation = format!(
        "Grid axes turned {}° counter-clockwise from the sensor's, centred at ({}, {}) mm on it; {} row 0 is the bottom row. Flux outside the grid: {}.",
        g.rotation_deg,
        g.center_mm[0],
        g.center_mm[1],
        names.npy,
        if r.outside > 0.0 { format!("{:.4e}", r.outside) } else { "none".into() }
    );
    write_image_figure(&png, &figure)?;
    written.extend([npy, csv, png]);
    Ok(json!({
        "pixels": g.pixels, "pitch_mm": g.pitch_mm, "rotation_deg": g.rotation_deg,
        "center_mm": g.center_mm,
        "flux_on_grid": r.flux.iter().sum::<f64>(), "flux_outside_grid": r.outside,
        "layout": "grid[iy, ix]; pixel (ix, iy) centred at x_mm, y_mm of the sensor (grid_csv); flux shared by overlap area",
        "files": {
            "grid_npy": names.npy, "grid_csv": names.csv, "grid_png": names.png,
            "grid_fits": run.fits.then(|| grid_fits_file_name(&spec.name)),
        },
    }))
}

/// Writes a gas detector's conversion files; returns their `NAME.json` entry
/// (null for other sensors) and adds the paths to `written`.
fn write_conversion_files(
    dir: &Path,
    scene: &Scene,
    spec: &crate::sensor::SensorSpec,
    image: &crate::sensor::SensorImage,
    absolute: Option<f64>,
    written: &mut Vec<PathBuf>,
) -> std::io::Result<Value> {
    let Some(tally) = &image.conversion else {
        return Ok(Value::Null);
    };
    let to_world = &scene.objects[spec.object].transform.to_world;
    let (entry, files) = write_conversion(dir, spec, tally, to_world, absolute.unwrap_or(1.0))?;
    written.extend(files);
    Ok(entry)
}

/// What a sensor's pixel values are (as FITS BUNIT): photons per pixel, weighted
/// as each source says (`sources[].weight` in the sensor's JSON), or axions (or,
/// with a magnet, converted X-rays) per second with a Sun.
pub fn flux_unit(counted: Counted) -> FluxUnit {
    match counted {
        Counted::Axions => FluxUnit {
            bunit: "s-1",
            comment: "axions per second per pixel reaching the sensor",
        },
        Counted::XRays => FluxUnit {
            bunit: "s-1",
            comment: "X-rays per second per pixel (axions converted in the magnet)",
        },
        Counted::Weights => FluxUnit {
            bunit: "ph",
            comment: "weighted photons per pixel (see sources[].weight)",
        },
    }
}

/// The image's x and y projections as CSV (the shorter axis' columns end empty).
fn write_projections(path: &Path, image: &[f64], g: &ImageGeometry) -> std::io::Result<()> {
    let (px, py) = projections(image, g);
    let column = |i: usize, v: &[f64], origin: f64, pitch: f64| match v.get(i) {
        Some(f) => [
            (origin + (i as f64 + 0.5) * pitch).to_string(),
            f.to_string(),
        ],
        None => [String::new(), String::new()],
    };
    write_csv(
        path,
        &["index", "x_mm", "flux_vs_x", "y_mm", "flux_vs_y"],
        (0..g.nx.max(g.ny)).map(|i| {
            let [xm, fx] = column(i, &px, g.origin_mm[0], g.pitch[0]);
            let [ym, fy] = column(i, &py, g.origin_mm[1], g.pitch[1]);
            vec![i.to_string(), xm, fx, ym, fy]
        }),
    )
}

/// The image rebinned to the sensor's detector grid, as `.npy` [iy][ix] and as CSV
/// (pixel indices, pixel-centre positions on the sensor, flux).
fn write_grid(
    (npy, csv): (&Path, &Path),
    r: &crate::sensor::Rebinned,
    g: &crate::sensor::PixelGrid,
) -> std::io::Result<()> {
    let (gx, gy) = (g.pixels[0] as usize, g.pixels[1] as usize);
    write_npy_f64(npy, &[gy as u64, gx as u64], &r.flux)?;
    write_csv(
        csv,
        &["ix", "iy", "x_mm", "y_mm", "flux"],
        (0..gx * gy).map(|k| {
            let (ix, iy) = (k % gx, k / gx);
            let [x, y] = g.pixel_center(ix, iy);
            vec![
                ix.to_string(),
                iy.to_string(),
                format!("{x:.6}"),
                format!("{y:.6}"),
                r.flux[k].to_string(),
            ]
        }),
    )
}

/// Pretty JSON, written atomically.
pub fn write_json(path: &Path, v: &Value) -> std::io::Result<()> {
    let mut text = serde_json::to_string_pretty(v).expect("JSON of plain values");
    text.push('\n');
    atomic_write(path, text.as_bytes())
}

/// The run's statistics as `summary.json` gives them.
pub fn statistics_json(scene: &Scene, r: &RunResult) -> Value {
    let s = &r.stats;
    let per_object: serde_json::Map<String, Value> = scene
        .objects
        .iter()
        .zip(&s.hits_per_object)
        .map(|(o, n)| (o.name.clone(), json!(n)))
        .collect();
    let stopped: serde_json::Map<String, Value> = scene
        .objects
        .iter()
        .zip(&s.stopped_after_reflection)
        .filter(|(_, n)| **n > 0)
        .map(|(o, n)| (o.name.clone(), json!(n)))
        .collect();
    let per_sensor: serde_json::Map<String, Value> = scene
        .sensors
        .iter()
        .zip(&s.recorded_per_sensor)
        .map(|(o, n)| (o.name.clone(), json!(n)))
        .collect();
    json!({
        "photons_emitted": s.photons_emitted,
        "reached_sensor": s.reached_sensor,
        "absorbed": s.absorbed,
        "absorbed_mirror_back": s.absorbed_mirror_back,
        "reflected_into_surface": s.reflected_into_surface,
        "scattered_below_surface": s.scattered_below_surface,
        "sensor_outside_area": s.sensor_outside_area,
        "sensor_outside_energy_range": s.sensor_outside_energy_range,
        "escaped": s.escaped,
        "max_interactions_reached": s.max_interactions_reached,
        "embree_queries": s.embree_queries,
        "queries_per_photon": s.embree_queries as f64 / s.photons_emitted.max(1) as f64,
        "hits_per_object": per_object,
        "stopped_after_reflection": stopped,
        "recorded_per_sensor": per_sensor,
        "seconds": r.seconds,
        "threads": r.threads,
        "photons_per_second": s.photons_emitted as f64 / r.seconds.max(1e-9),
        "sensor_photons_per_second": s.reached_sensor as f64 / r.seconds.max(1e-9),
    })
}
