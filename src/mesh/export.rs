//! Mesh export: glTF 2.0 (`.gltf` with the buffer embedded as a data URI, or binary
//! `.glb`) and Wavefront OBJ. Files are written atomically.

use super::TriangleMesh;
use crate::output::atomic_write;
use base64::Engine;
use glam::DVec3;
use serde_json::json;
use std::fmt::Write as _;
use std::path::Path;

/// Writes `.gltf`, `.glb` or `.obj`, chosen by the file extension.
pub fn write_mesh(path: &Path, mesh: &TriangleMesh, name: &str) -> std::io::Result<()> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .as_deref()
    {
        Some("obj") => write_obj(path, mesh, name),
        Some("gltf") | Some("glb") => write_gltf(path, mesh, name),
        _ => Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "{}: unknown mesh extension (use .gltf, .glb or .obj)",
                path.display()
            ),
        )),
    }
}

/// glTF 2.0 with POSITION, NORMAL (when present) and u32 indices, in one buffer.
/// Coordinates are written as they are (traxer's unit is the millimetre).
pub fn write_gltf(path: &Path, mesh: &TriangleMesh, name: &str) -> std::io::Result<()> {
    let mut bin: Vec<u8> = Vec::new();
    for t in &mesh.triangles {
        for &k in t {
            bin.extend_from_slice(&k.to_le_bytes());
        }
    }
    let idx_len = bin.len();
    let pos_off = bin.len();
    let (lo, hi) = mesh.bounds();
    push_vec3s(&mut bin, &mesh.positions);
    let pos_len = bin.len() - pos_off;
    let nrm_off = bin.len();
    if let Some(n) = &mesh.normals {
        push_vec3s(&mut bin, n);
    }
    let nrm_len = bin.len() - nrm_off;

    let glb = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    let mut buffer = json!({ "byteLength": bin.len() });
    if !glb {
        let data = base64::engine::general_purpose::STANDARD.encode(&bin);
        buffer["uri"] = json!(format!("data:application/octet-stream;base64,{data}"));
    }
    let f32s = |v: DVec3| json!([v.x as f32, v.y as f32, v.z as f32]);
    let mut attributes = json!({ "POSITION": 1 });
    let mut buffer_views = vec![
        json!({ "buffer": 0, "byteOffset": 0, "byteLength": idx_len, "target": 34963 }),
        json!({ "buffer": 0, "byteOffset": pos_off, "byteLength": pos_len, "target": 34962 }),
    ];
    let mut accessors = vec![
        json!({ "bufferView": 0, "componentType": 5125, "count": 3 * mesh.triangles.len(), "type": "SCALAR" }),
        json!({ "bufferView": 1, "componentType": 5126, "count": mesh.positions.len(), "type": "VEC3",
                "min": f32s(lo), "max": f32s(hi) }),
    ];
    if mesh.normals.is_some() {
        buffer_views.push(
            json!({ "buffer": 0, "byteOffset": nrm_off, "byteLength": nrm_len, "target": 34962 }),
        );
        accessors.push(json!({ "bufferView": 2, "componentType": 5126, "count": mesh.positions.len(), "type": "VEC3" }));
        attributes["NORMAL"] = json!(2);
    }
    let doc = json!({
        "asset": { "version": "2.0", "generator": format!("traxer {}", env!("CARGO_PKG_VERSION")) },
        "scene": 0,
        "scenes": [ { "nodes": [0] } ],
        "nodes": [ { "mesh": 0, "name": name } ],
        "meshes": [ { "name": name, "primitives": [ { "attributes": attributes, "indices": 0, "mode": 4 } ] } ],
        "buffers": [ buffer ],
        "bufferViews": buffer_views,
        "accessors": accessors,
    });
    let text = serde_json::to_string(&doc).expect("JSON of plain values");
    if !glb {
        return atomic_write(path, text.as_bytes());
    }
    // GLB: 12-byte header, JSON chunk (space padded), BIN chunk (zero padded).
    let mut json_chunk = text.into_bytes();
    while json_chunk.len() % 4 != 0 {
        json_chunk.push(b' ');
    }
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let total = 12 + 8 + json_chunk.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_chunk.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json_chunk);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    atomic_write(path, &out)
}

fn push_vec3s(bin: &mut Vec<u8>, v: &[DVec3]) {
    for p in v {
        for c in [p.x, p.y, p.z] {
            bin.extend_from_slice(&(c as f32).to_le_bytes());
        }
    }
}

/// Wavefront OBJ with `v`, `vn` (when present) and `f` lines; full f64 precision.
pub fn write_obj(path: &Path, mesh: &TriangleMesh, name: &str) -> std::io::Result<()> {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# traxer {} tessellation, units: mm",
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(s, "o {name}");
    for p in &mesh.positions {
        let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
    }
    if let Some(ns) = &mesh.normals {
        for n in ns {
            let _ = writeln!(s, "vn {} {} {}", n.x, n.y, n.z);
        }
    }
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|k| k + 1);
        if mesh.normals.is_some() {
            let _ = writeln!(s, "f {a}//{a} {b}//{b} {c}//{c}");
        } else {
            let _ = writeln!(s, "f {a} {b} {c}");
        }
    }
    atomic_write(path, s.as_bytes())
}
