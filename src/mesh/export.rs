//! Mesh export: glTF 2.0 (`.gltf` with the buffer embedded as a data URI, or binary
//! `.glb`) and Wavefront OBJ. Files are written atomically.

use super::TriangleMesh;
use crate::files::atomic_write;
use base64::Engine;
use glam::DVec3;
use serde_json::json;
use std::fmt::Write as _;
use std::path::Path;

/// Writes `.gltf`, `.glb` or `.obj`, chosen by the file extension.
pub fn write_mesh(path: &Path, mesh: &TriangleMesh, name: &str) -> std::io::Result<()> {
    write_mesh_parts(path, &[(name, mesh)])
}

/// Writes several named meshes into one `.gltf`, `.glb` or `.obj` file: one glTF
/// node (and mesh) or one OBJ object per part, so that a scene can pick parts by
/// name (`shape = { type = "mesh", file = ..., part = "name" }`).
pub fn write_mesh_parts(path: &Path, parts: &[(&str, &TriangleMesh)]) -> std::io::Result<()> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .as_deref()
    {
        Some("obj") => write_obj(path, parts),
        Some("gltf") | Some("glb") => write_gltf(path, parts),
        _ => Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "{}: unknown mesh extension (use .gltf, .glb or .obj)",
                path.display()
            ),
        )),
    }
}

/// glTF 2.0 with POSITION, NORMAL (when present) and u32 indices, all parts in
/// one buffer. Coordinates are written as they are (traxer's unit is the
/// millimetre).
pub fn write_gltf(path: &Path, parts: &[(&str, &TriangleMesh)]) -> std::io::Result<()> {
    let mut bin: Vec<u8> = Vec::new();
    let mut buffer_views = Vec::new();
    let mut accessors = Vec::new();
    let mut meshes = Vec::new();
    let mut nodes = Vec::new();
    let f32s = |v: DVec3| json!([v.x as f32, v.y as f32, v.z as f32]);
    // Appends one buffer view and returns its index.
    let mut view = |bin: &mut Vec<u8>, data: Vec<u8>, target: u32| -> usize {
        let offset = bin.len();
        bin.extend_from_slice(&data);
        buffer_views.push(json!({ "buffer": 0, "byteOffset": offset, "byteLength": data.len(), "target": target }));
        buffer_views.len() - 1
    };
    for (k, (name, mesh)) in parts.iter().enumerate() {
        let idx: Vec<u8> = mesh
            .triangles
            .iter()
            .flat_map(|t| t.iter().flat_map(|k| k.to_le_bytes()))
            .collect();
        let v = view(&mut bin, idx, 34963);
        accessors.push(json!({ "bufferView": v, "componentType": 5125, "count": 3 * mesh.triangles.len(), "type": "SCALAR" }));
        let indices = accessors.len() - 1;
        let (lo, hi) = mesh.bounds();
        let v = view(&mut bin, vec3_bytes(&mesh.positions), 34962);
        accessors.push(json!({ "bufferView": v, "componentType": 5126, "count": mesh.positions.len(), "type": "VEC3",
                "min": f32s(lo), "max": f32s(hi) }));
        let mut attributes = json!({ "POSITION": accessors.len() - 1 });
        if let Some(n) = &mesh.normals {
            let v = view(&mut bin, vec3_bytes(n), 34962);
            accessors.push(json!({ "bufferView": v, "componentType": 5126, "count": mesh.positions.len(), "type": "VEC3" }));
            attributes["NORMAL"] = json!(accessors.len() - 1);
        }
        meshes.push(json!({ "name": name, "primitives": [ { "attributes": attributes, "indices": indices, "mode": 4 } ] }));
        nodes.push(json!({ "mesh": k, "name": name }));
    }

    let glb = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    let mut buffer = json!({ "byteLength": bin.len() });
    if !glb {
        let data = base64::engine::general_purpose::STANDARD.encode(&bin);
        buffer["uri"] = json!(format!("data:application/octet-stream;base64,{data}"));
    }
    let doc = json!({
        "asset": { "version": "2.0", "generator": format!("traxer {}", env!("CARGO_PKG_VERSION")) },
        "scene": 0,
        "scenes": [ { "nodes": (0..parts.len()).collect::<Vec<_>>() } ],
        "nodes": nodes,
        "meshes": meshes,
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
    while !json_chunk.len().is_multiple_of(4) {
        json_chunk.push(b' ');
    }
    while !bin.len().is_multiple_of(4) {
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

fn vec3_bytes(v: &[DVec3]) -> Vec<u8> {
    v.iter()
        .flat_map(|p| [p.x, p.y, p.z])
        .flat_map(|c| (c as f32).to_le_bytes())
        .collect()
}

/// Wavefront OBJ with one `o` object per part, `v`, `vn` (when present) and `f`
/// lines; full f64 precision.
pub fn write_obj(path: &Path, parts: &[(&str, &TriangleMesh)]) -> std::io::Result<()> {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# traxer {} tessellation, units: mm",
        env!("CARGO_PKG_VERSION")
    );
    // OBJ indices count from 1 over the whole file, vertices and normals apart.
    let (mut v0, mut n0) = (1u32, 1u32);
    for (name, mesh) in parts {
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
            let [a, b, c] = t.map(|k| k + v0);
            if mesh.normals.is_some() {
                let [na, nb, nc] = t.map(|k| k + n0);
                let _ = writeln!(s, "f {a}//{na} {b}//{nb} {c}//{nc}");
            } else {
                let _ = writeln!(s, "f {a} {b} {c}");
            }
        }
        v0 += mesh.positions.len() as u32;
        if let Some(ns) = &mesh.normals {
            n0 += ns.len() as u32;
        }
    }
    atomic_write(path, s.as_bytes())
}
