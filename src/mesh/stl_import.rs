//! STL import (binary and ASCII) through `stl_io`: what every CAD package
//! exports, and what peer X-ray tools read spiders and baffles from. The file is
//! one [`MeshPart`] named after the file (STL has no parts); its vertices are
//! merged where identical, the triangles' front is their vertex order
//! (counter-clockwise, the right-hand rule, as STL defines it), and the stored
//! facet normals are only checked against it: where they disagree (a common
//! export fault) the import says how many. STL carries no units: its numbers
//! are read as mm, as every mesh's are, and the scene's size check and
//! `traxer inspect` judge the units.

use super::{ImportReport, MeshError, MeshPart, TriangleMesh};
use glam::DVec3;
use std::path::Path;

/// Bytes of a binary STL's header and triangle count, and of each triangle.
const BINARY_HEADER: usize = 84;
const BINARY_TRIANGLE: usize = 50;

pub(super) fn load(path: &Path) -> Result<(Vec<MeshPart>, ImportReport), MeshError> {
    let bytes = std::fs::read(path)
        .map_err(|e| MeshError::invalid(path, format!("cannot read the file: {e}")))?;
    let ascii = bytes.trim_ascii_start().starts_with(b"solid")
        && bytes.iter().take(1024).all(|b| b.is_ascii());
    if !ascii {
        check_binary_size(path, &bytes)?;
    }
    let stl = stl_io::read_stl(&mut std::io::Cursor::new(&bytes)).map_err(|e| {
        let form = if ascii { "ASCII" } else { "binary" };
        MeshError::invalid(path, format!("not a valid {form} STL file: {e}"))
    })?;
    let positions: Vec<DVec3> = stl
        .vertices
        .iter()
        .map(|v| DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64))
        .collect();
    let n = positions.len();
    let mut triangles = Vec::with_capacity(stl.faces.len());
    let mut against = 0;
    for (k, f) in stl.faces.iter().enumerate() {
        if let Some(i) = f.vertices.iter().find(|&&i| i >= n) {
            return Err(MeshError::invalid(
                path,
                format!("triangle {k} uses vertex {i} of {n}"),
            ));
        }
        let [a, b, c] = f.vertices.map(|i| positions[i]);
        let stored = DVec3::new(f.normal[0] as f64, f.normal[1] as f64, f.normal[2] as f64);
        if stored.dot((b - a).cross(c - a)) < 0.0 {
            against += 1;
        }
        triangles.push(f.vertices.map(|i| i as u32));
    }
    let mut mesh = TriangleMesh {
        positions,
        normals: None,
        triangles,
    };
    mesh.normals = Some(mesh.computed_normals());
    let name = path
        .file_stem()
        .map_or("stl".to_string(), |s| s.to_string_lossy().into_owned());
    let mut report = ImportReport::default();
    report.notes.push(format!(
        "STL has no units: its numbers were read as mm ({} triangles); if the file is in metres or inches add a `{{ scale = ... }}` transform step (`traxer inspect` judges the units)",
        mesh.triangles.len()
    ));
    if against > 0 {
        report.notes.push(format!(
            "{against} of {} triangles store a facet normal pointing against their vertex order; traxer takes the vertex order (counter-clockwise seen from the front), as STL defines it",
            mesh.triangles.len()
        ));
    }
    let mut part = MeshPart {
        name: name.clone(),
        aliases: Vec::new(),
        mesh: TriangleMesh::default(),
        primitives: Vec::new(),
    };
    part.push_primitive(format!("solid '{name}'"), mesh, false);
    Ok((vec![part], report))
}

/// A binary STL holds the triangles its header counts, no fewer (a file cut
/// off: a download, a full disk) and no more (a wrong count).
fn check_binary_size(path: &Path, bytes: &[u8]) -> Result<(), MeshError> {
    if bytes.len() < BINARY_HEADER {
        return Err(MeshError::invalid(
            path,
            format!(
                "is not an STL file: {} bytes, less than a binary STL's 84-byte header, and no ASCII `solid` line",
                bytes.len()
            ),
        ));
    }
    let count = u32::from_le_bytes(bytes[80..84].try_into().expect("4 bytes")) as usize;
    let expected = BINARY_HEADER.saturating_add(BINARY_TRIANGLE.saturating_mul(count));
    if bytes.len() < expected {
        return Err(MeshError::invalid(
            path,
            format!(
                "binary STL cut off: its header counts {count} triangles ({expected} bytes), but the file has {} bytes",
                bytes.len()
            ),
        ));
    }
    if bytes.len() > expected {
        // Reading up to the count would drop the rest without a word.
        let extra = bytes.len() - expected;
        return Err(MeshError::invalid(
            path,
            format!(
                "binary STL longer than its header says: the header counts {count} triangles ({expected} bytes), but the file has {} bytes ({} triangles{}); the count is wrong or the file is not one STL",
                bytes.len(),
                (bytes.len() - BINARY_HEADER) / BINARY_TRIANGLE,
                if extra.is_multiple_of(BINARY_TRIANGLE) { String::new() } else { format!(" and {} bytes", (bytes.len() - BINARY_HEADER) % BINARY_TRIANGLE) }
            ),
        ));
    }
    Ok(())
}
