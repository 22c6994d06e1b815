//! `traxer inspect`: what the tracer will see in a mesh file, before trusting a
//! trace through it. The file goes through the tracer's own importer
//! (`mesh::load_parts` and `mesh::select_parts`, as a scene's `mesh` shape does);
//! each part, each primitive and the whole file are analysed by `mesh::quality`,
//! and the bounding box by `mesh::units`. The JSON keys are documented in
//! docs/inspect.md.

use super::InputError;
use serde::Serialize;
use std::path::{Path, PathBuf};
use traxer::mesh::quality::{analyse, MeshQuality};
use traxer::mesh::units::{hint, UnitsHint};
use traxer::mesh::{self, MeshError, MeshPart, Skipped};

/// Check mesh files (glTF .gltf/.glb, OBJ) before tracing them.
///
/// Reports, per part (glTF node with a mesh, OBJ object), per primitive and for the
/// whole file: triangles, vertices, world-space bounding box, surface area,
/// degenerate triangles, boundary (open) and non-manifold edges, neighbours wound
/// the other way, normals, the tessellation step of curved surfaces, skipped and
/// refused pieces, and whether the units look like millimetres. Exit code 0 when every file imports, 2 when one cannot (with
/// the error the tracer would give).
#[derive(clap::Args)]
pub struct InspectArgs {
    /// Mesh files (.gltf, .glb, .obj, .stl).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Print JSON (keys documented in docs/inspect.md) instead of text.
    #[arg(long)]
    pub json: bool,
    /// The size in millimetres you expect the largest extent of each file to have
    /// (e.g. 450 for a telescope): the units hint then names the unit that fits.
    #[arg(long, value_name = "MM")]
    pub expect_size: Option<f64>,
    #[command(flatten)]
    pub quiet: super::args::QuietArg,
}

/// Version of the JSON layout: raised when a key changes meaning or disappears.
const JSON_VERSION: u32 = 1;

#[derive(Serialize)]
struct Report {
    traxer_inspect: u32,
    files: Vec<FileReport>,
}

#[derive(Serialize)]
struct FileReport {
    file: String,
    format: &'static str,
    imported: bool,
    /// The importer's error (the tracer's message) when `imported` is false.
    error: Option<String>,
    total: Option<Total>,
    parts: Vec<PartReport>,
    skipped: Vec<Skipped>,
    notes: Vec<String>,
    extensions_used: Vec<String>,
    units: Option<UnitsHint>,
}

#[derive(Serialize)]
struct Total {
    parts: usize,
    normals: &'static str,
    #[serde(flatten)]
    quality: MeshQuality,
}

#[derive(Serialize)]
struct PartReport {
    name: String,
    aliases: Vec<String>,
    normals: &'static str,
    #[serde(flatten)]
    quality: MeshQuality,
    primitives: Vec<PrimitiveReport>,
}

#[derive(Serialize)]
struct PrimitiveReport {
    label: String,
    normals: &'static str,
    #[serde(flatten)]
    quality: MeshQuality,
}

pub fn run(a: InspectArgs) -> anyhow::Result<()> {
    if let Some(s) = a.expect_size {
        if !(s.is_finite() && s > 0.0) {
            return Err(InputError(format!(
                "--expect-size {s}: expected a positive size in millimetres"
            ))
            .into());
        }
    }
    let mut failures: Vec<MeshError> = Vec::new();
    let mut files = Vec::new();
    for path in &a.files {
        let (report, error) = inspect_file(path, a.expect_size);
        if !a.json {
            print_text(&report);
        }
        files.push(report);
        failures.extend(error);
    }
    if a.json {
        let report = Report {
            traxer_inspect: JSON_VERSION,
            files,
        };
        say!("{}", serde_json::to_string_pretty(&report)?);
    }
    match failures.len() {
        0 => Ok(()),
        1 => Err(failures.remove(0).into()),
        n => {
            for e in &failures {
                tell!("error: {e}");
            }
            Err(InputError(format!(
                "{n} of {} files cannot be imported (see above)",
                a.files.len()
            ))
            .into())
        }
    }
}

/// Imports one file exactly as a scene's `mesh = { file = ... }` does, and
/// analyses what came out.
fn inspect_file(path: &Path, expect_size: Option<f64>) -> (FileReport, Option<MeshError>) {
    let mut report = FileReport {
        file: path.display().to_string(),
        format: format_of(path),
        imported: false,
        error: None,
        total: None,
        parts: Vec::new(),
        skipped: Vec::new(),
        notes: Vec::new(),
        extensions_used: Vec::new(),
        units: None,
    };
    let (parts, import) = match mesh::load_parts(path) {
        Ok(loaded) => loaded,
        Err(e) => {
            report.error = Some(e.to_string());
            return (report, Some(e));
        }
    };
    report.skipped = import.skipped.clone();
    report.notes = import.notes.clone();
    report.extensions_used = import.extensions_used.clone();
    // The whole file, checked as the tracer checks a `mesh` shape without `part`.
    let whole = match mesh::select_parts(path, &parts, None) {
        Ok(m) => m,
        Err(e) => {
            report.error = Some(e.to_string());
            return (report, Some(e));
        }
    };
    report.imported = true;
    report.parts = parts.iter().map(part_report).collect();
    let all_file = parts.iter().all(MeshPart::normals_from_file);
    let normals = normals_label(
        all_file,
        parts
            .iter()
            .any(|p| p.primitives.iter().any(|q| q.normals_from_file)),
    );
    // One part is the whole file: do not analyse a large mesh twice.
    let quality = match report.parts.as_slice() {
        [only] => only.quality.clone(),
        _ => analyse(&whole, all_file),
    };
    report.units = Some(hint(quality.bounds.largest_extent(), expect_size));
    report.total = Some(Total {
        parts: parts.len(),
        normals,
        quality,
    });
    (report, None)
}

fn part_report(part: &MeshPart) -> PartReport {
    let all = part.normals_from_file();
    let quality = analyse(&part.mesh, all);
    let primitives = part
        .primitives
        .iter()
        .map(|p| PrimitiveReport {
            label: p.label.clone(),
            normals: normals_label(p.normals_from_file, p.normals_from_file),
            // A part of one primitive is that primitive.
            quality: if part.primitives.len() == 1 {
                quality.clone()
            } else {
                analyse(&part.primitive_mesh(p), p.normals_from_file)
            },
        })
        .collect();
    PartReport {
        name: part.name.clone(),
        aliases: part.aliases.clone(),
        normals: normals_label(all, part.primitives.iter().any(|p| p.normals_from_file)),
        quality,
        primitives,
    }
}

/// "file": every vertex normal from the file; "computed": none (the tracer
/// computes area-weighted ones); "mixed": some primitives have them.
fn normals_label(all_from_file: bool, any_from_file: bool) -> &'static str {
    match (all_from_file, any_from_file) {
        (true, _) => "file",
        (false, true) => "mixed",
        (false, false) => "computed",
    }
}

fn format_of(path: &Path) -> &'static str {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .as_deref()
    {
        Some("gltf") => "gltf",
        Some("glb") => "glb",
        Some("obj") => "obj",
        _ => "unknown",
    }
}

fn print_text(r: &FileReport) {
    say!("{} ({})", r.file, r.format);
    for s in &r.skipped {
        say!("  skipped: {}: {}", s.what, s.reason);
    }
    for n in &r.notes {
        say!("  note: {n}");
    }
    if !r.extensions_used.is_empty() {
        say!("  glTF extensions used: {}", r.extensions_used.join(", "));
    }
    if let Some(e) = &r.error {
        say!("  CANNOT BE IMPORTED: {e}");
        say!("");
        return;
    }
    let (Some(t), Some(u)) = (&r.total, &r.units) else {
        return;
    };
    let q = &t.quality;
    say!(
        "  {} part{}, {} triangles, {} vertices ({} distinct positions), normals: {}",
        t.parts,
        if t.parts == 1 { "" } else { "s" },
        q.triangles,
        q.vertices,
        q.distinct_positions,
        describe_normals(t.normals, q.normals_against_winding)
    );
    say!("  bounds (mm): {}", bounds_text(q));
    say!(
        "  size (mm): {} x {} x {}; area {} mm^2",
        sig(q.bounds.size()[0]),
        sig(q.bounds.size()[1]),
        sig(q.bounds.size()[2]),
        sig(q.area)
    );
    say!("  topology: {}", topology_text(q));
    say!("  facets: {}", facet_text(q));
    say!("  units: {}", u.message);
    say!("  parts:");
    say!(
        "    {:<24} {:>9} {:>9} {:>12} {:>6} {:>8} {:>8} {:>9} {:>9} {:>8}  bounds (mm)",
        "name",
        "triangles",
        "vertices",
        "area/mm^2",
        "degen",
        "boundary",
        "non-man.",
        "mis-wound",
        "step/deg",
        "normals"
    );
    for p in &r.parts {
        part_row(&p.name, p.normals, &p.quality);
        if p.primitives.len() > 1 {
            for q in &p.primitives {
                part_row(&format!("  {}", q.label), q.normals, &q.quality);
            }
        }
    }
    say!("");
}

fn part_row(name: &str, normals: &str, q: &MeshQuality) {
    say!(
        "    {:<24} {:>9} {:>9} {:>12} {:>6} {:>8} {:>8} {:>9} {:>9} {:>8}  {}",
        name,
        q.triangles,
        q.vertices,
        sig(q.area),
        q.degenerate_triangles,
        q.boundary_edges,
        q.non_manifold_edges,
        q.inconsistent_winding_edges,
        q.facet_step_deg
            .map_or("-".to_string(), |d| format!("{d:.4}")),
        normals,
        bounds_text(q)
    );
}

fn bounds_text(q: &MeshQuality) -> String {
    let b = &q.bounds;
    format!(
        "x [{}, {}]  y [{}, {}]  z [{}, {}]",
        sig(b.min[0]),
        sig(b.max[0]),
        sig(b.min[1]),
        sig(b.max[1]),
        sig(b.min[2]),
        sig(b.max[2])
    )
}

fn facet_text(q: &MeshQuality) -> String {
    let step = match q.facet_step_deg {
        Some(d) if d < 1e-6 => "neighbours below a crease lie in one plane".to_string(),
        Some(d) => format!(
            "neighbours bend by up to {}° ({}″) on curved surfaces",
            sig(d),
            sig(d * 3600.0)
        ),
        None => "no curved surfaces".to_string(),
    };
    format!(
        "{step}; {} creases (bends of {}° or more)",
        q.creases,
        traxer::mesh::quality::CREASE_DEG
    )
}

fn describe_normals(label: &str, against: Option<usize>) -> String {
    match (label, against) {
        ("computed", _) => "none in the file (computed from the geometry)".into(),
        (l, Some(0)) => format!("{l} (all agree with the winding)"),
        (l, Some(n)) => format!("{l} ({n} triangles' normals point against their winding)"),
        (l, None) => l.to_string(),
    }
}

fn topology_text(q: &MeshQuality) -> String {
    let mut s = format!(
        "{} component{}; {} degenerate triangles; {} boundary edges; {} non-manifold edges; {} edges between neighbours wound the other way",
        q.components,
        if q.components == 1 { "" } else { "s" },
        q.degenerate_triangles,
        q.boundary_edges,
        q.non_manifold_edges,
        q.inconsistent_winding_edges
    );
    match (q.closed, q.enclosed_volume) {
        (true, Some(v)) if v < 0.0 => s.push_str(&format!(
            ". Closed but INSIDE OUT: enclosed volume {} mm^3 with the front sides facing inwards",
            sig(v)
        )),
        (true, Some(v)) => s.push_str(&format!(". Closed: encloses {} mm^3", sig(v))),
        (true, None) => s.push_str(". Closed, but the winding is inconsistent"),
        (false, _) => {
            s.push_str(". Open surface (fine for thin mirror shells; a solid must be closed)")
        }
    }
    s.push_str(&format!(
        " [vertices within {} mm welded]",
        sig(q.weld_distance)
    ));
    s
}

/// Six significant digits, plain notation for everyday sizes.
fn sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let mag = x.abs().log10().floor() as i32;
    if !(-4..9).contains(&mag) {
        return format!("{x:.5e}");
    }
    let digits = (5 - mag).max(0) as usize;
    let s = format!("{x:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}
