//! The photon-history outputs of a trace: per sensor the flux by path class, by
//! shell (or mirror object) and by path (first → last mirror) for `NAME.json` and
//! `summary.json`; the per-class images; and the photon list (`photons.npy`, a
//! NumPy structured array, and `photons.csv`) of the first recorded photons.

use super::{write_csv, write_npy_f64};
use crate::files::atomic_write;
use crate::history::{PathClass, NO_MIRROR};
use crate::scene::Scene;
use crate::sensor::{class_file_names, SensorImage, SensorSpec, WeightSum};
use crate::trace::RecordedPhoton;
use npyz::WriterBuilder;
use serde_json::{json, Map, Value};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The photon list's files.
pub const PHOTON_LIST_FILES: [&str; 2] = ["photons.npy", "photons.csv"];

/// Name of a mirror object in a history (or "none").
fn mirror_name(scene: &Scene, object: u32) -> String {
    if object == NO_MIRROR {
        "none".into()
    } else {
        scene.objects[object as usize].name.clone()
    }
}

/// The shell a path belongs to: its first mirror's `shell` tag, or the mirror's
/// own name for untagged mirrors (a CAD part), "none" for direct photons.
fn shell_of(scene: &Scene, first: u32) -> String {
    if first == NO_MIRROR {
        return "none".into();
    }
    let o = &scene.objects[first as usize];
    o.shell.clone().unwrap_or_else(|| o.name.clone())
}

/// The flux of one sensor by class, shell and path; `scale` converts weights to
/// the image's units (axions/s for a Sun).
pub fn history_json(scene: &Scene, image: &SensorImage, scale: f64) -> Value {
    let t = &image.paths;
    let class_flux = t.class_flux();
    let total: f64 = class_flux.iter().sum();
    let fraction = |f: f64| if total > 0.0 { f / total } else { 0.0 };
    let classes: Map<String, Value> = PathClass::ALL
        .iter()
        .map(|&c| {
            let (f, n) = (class_flux[c as usize], t.class_counts[c as usize]);
            let v = json!({"flux": f * scale, "fraction": fraction(f), "photons": n});
            (c.name().to_string(), v)
        })
        .collect();
    let mut sums: BTreeMap<String, (WeightSum, u64)> = BTreeMap::new();
    for (&(first, _), &(f, n)) in &t.paths {
        let e = sums.entry(shell_of(scene, first)).or_default();
        e.0.add(f);
        e.1 += n;
    }
    // Shell 2 before shell 10: numbers by value, names after them.
    let mut shells: Vec<(String, (f64, u64))> = sums
        .into_iter()
        .map(|(k, (f, n))| (k, (f.value(), n)))
        .collect();
    shells.sort_by_key(|(k, _)| {
        (
            k.parse::<i64>().map_or(1, |_| 0),
            k.parse::<i64>().ok(),
            k.clone(),
        )
    });
    let shells: Vec<Value> = shells
        .into_iter()
        .map(|(k, (f, n))| {
            json!({"shell": k, "flux": f * scale, "fraction": fraction(f), "photons": n})
        })
        .collect();
    let mut paths: Vec<((u32, u32), (f64, u64))> = t
        .paths
        .iter()
        .map(|(k, (f, n))| (*k, (f.value(), *n)))
        .collect();
    paths.sort_by(|a, b| b.1 .0.total_cmp(&a.1 .0).then(a.0.cmp(&b.0)));
    let paths: Vec<Value> = paths
        .into_iter()
        .map(|((first, last), (f, n))| {
            json!({
                "first_mirror": mirror_name(scene, first),
                "last_mirror": mirror_name(scene, last),
                "flux": f * scale, "fraction": fraction(f), "photons": n,
            })
        })
        .collect();
    json!({
        "classes": classes,
        "shells": shells,
        "paths": paths,
        "explanation": "class of each recorded photon: direct (no reflection), front_rear (exactly two, a front then a rear mirror: the focus), front_only / rear_only (one reflection), other; shells by the first mirror's shell (or its object name); paths by first and last mirror, largest flux first",
    })
}

/// Writes the per-class images of a sensor that asks for them; returns the paths.
pub fn write_class_images(
    dir: &Path,
    spec: &SensorSpec,
    image: &SensorImage,
    scale: f64,
) -> std::io::Result<Vec<PathBuf>> {
    let Some(images) = image.paths.class_images() else {
        return Ok(Vec::new());
    };
    let shape = [spec.pixels[1] as u64, spec.pixels[0] as u64];
    let mut written = Vec::new();
    for (name, img) in class_file_names(&spec.name).iter().zip(&images) {
        let p = dir.join(name);
        let scaled: Vec<f64> = img.iter().map(|v| v * scale).collect();
        write_npy_f64(&p, &shape, &scaled)?;
        written.push(p);
    }
    Ok(written)
}

/// One row of `photons.npy`: the field names are the dtype's, `energy_keV`
/// as in every other file and Python name (the derive's generated code needs
/// the allowance at module level).
mod row {
    #![allow(non_snake_case)]
    #[derive(npyz::Serialize, npyz::AutoSerialize, Clone, Copy)]
    pub struct PhotonRow {
        pub index: u64,
        pub sensor: u32,
        pub x_mm: f64,
        pub y_mm: f64,
        pub dir_x: f64,
        pub dir_y: f64,
        pub dir_z: f64,
        pub energy_keV: f64,
        pub weight: f64,
        pub reflections: u16,
        pub first_mirror: i32,
        pub last_mirror: i32,
        pub class: u8,
    }
}
use row::PhotonRow;

fn mirror_index(m: u32) -> i32 {
    if m == NO_MIRROR {
        -1
    } else {
        m as i32
    }
}

/// The photon list's rows, weights in the images' units (`scale`).
fn photon_rows(photons: &[RecordedPhoton], scale: f64) -> Vec<PhotonRow> {
    photons
        .iter()
        .map(|p| {
            let r = &p.record;
            PhotonRow {
                index: p.index,
                sensor: r.sensor,
                x_mm: p.local.x,
                y_mm: p.local.y,
                dir_x: p.dir.x,
                dir_y: p.dir.y,
                dir_z: p.dir.z,
                energy_keV: r.energy,
                weight: r.weight * scale,
                reflections: r.history.reflections,
                first_mirror: mirror_index(r.history.first_mirror),
                last_mirror: mirror_index(r.history.last_mirror),
                class: r.history.class() as u8,
            }
        })
        .collect()
}

/// `photons.npy` as bytes: a structured array with the fields of [`PhotonRow`].
fn npy_bytes(rows: &[PhotonRow]) -> std::io::Result<Vec<u8>> {
    let mut buf = Vec::new();
    {
        let mut w = npyz::WriteOptions::new()
            .default_dtype()
            .shape(&[rows.len() as u64])
            .writer(&mut buf)
            .begin_nd()?;
        w.extend(rows.iter().copied())?;
        w.finish()?;
    }
    Ok(buf)
}

/// The photon list as the bytes of `photons.npy` (see [`write_photon_list`]);
/// the Python module hands them to numpy.
pub fn photon_list_npy(photons: &[RecordedPhoton], scale: f64) -> std::io::Result<Vec<u8>> {
    npy_bytes(&photon_rows(photons, scale))
}

/// Writes the photon list: `photons.npy` (structured: index, sensor, x_mm, y_mm
/// on the sensor, dir_x/y/z, energy_keV, weight, reflections, first_mirror,
/// last_mirror (object indices, −1 = none), class (0 direct, 1 front_rear,
/// 2 front_only, 3 rear_only, 4 other)) and `photons.csv` with names instead of
/// indices. Weights are in the images' units (`scale`).
pub fn write_photon_list(
    dir: &Path,
    scene: &Scene,
    photons: &[RecordedPhoton],
    scale: f64,
) -> std::io::Result<Vec<PathBuf>> {
    let rows = photon_rows(photons, scale);
    let buf = npy_bytes(&rows)?;
    let npy = dir.join(PHOTON_LIST_FILES[0]);
    atomic_write(&npy, &buf)?;
    let csv = dir.join(PHOTON_LIST_FILES[1]);
    write_csv(
        &csv,
        &[
            "index",
            "sensor",
            "x_mm",
            "y_mm",
            "dir_x",
            "dir_y",
            "dir_z",
            "energy_keV",
            "weight",
            "reflections",
            "first_mirror",
            "last_mirror",
            "class",
        ],
        photons.iter().zip(&rows).map(|(p, r)| {
            vec![
                r.index.to_string(),
                scene.sensors[r.sensor as usize].name.clone(),
                r.x_mm.to_string(),
                r.y_mm.to_string(),
                r.dir_x.to_string(),
                r.dir_y.to_string(),
                r.dir_z.to_string(),
                r.energy_keV.to_string(),
                r.weight.to_string(),
                r.reflections.to_string(),
                mirror_name(scene, p.record.history.first_mirror),
                mirror_name(scene, p.record.history.last_mirror),
                PathClass::from_index(r.class).name().to_string(),
            ]
        }),
    )?;
    Ok(vec![npy, csv])
}
