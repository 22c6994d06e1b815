//! Wavefront OBJ import through `tobj`: polygons are triangulated, each object
//! (or group) of the file is one [`MeshPart`]; material libraries are ignored.

use super::{ImportReport, MeshError, MeshPart, Skipped, TriangleMesh};
use glam::DVec3;
use std::path::Path;

pub(super) fn load(path: &Path) -> Result<(Vec<MeshPart>, ImportReport), MeshError> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, _materials) = tobj::load_obj(path, &options).map_err(|e| {
        MeshError::invalid(
            path,
            match e {
                tobj::LoadError::OpenFileFailed => "cannot open the file".to_string(),
                tobj::LoadError::ReadError => "cannot read the file".to_string(),
                other => format!("not a valid OBJ file: {other}"),
            },
        )
    })?;
    let mut parts = Vec::new();
    let mut report = ImportReport {
        normals_from_file: true,
        ..Default::default()
    };
    for model in models {
        let m = &model.mesh;
        if m.indices.is_empty() {
            report.skipped.push(Skipped {
                what: format!("object '{}'", model.name),
                reason: "no faces (points or lines only)".into(),
            });
            continue;
        }
        let positions: Vec<DVec3> = m
            .positions
            .chunks_exact(3)
            .map(|p| DVec3::new(p[0], p[1], p[2]))
            .collect();
        let triangles: Vec<[u32; 3]> = m
            .indices
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        let mut part = TriangleMesh {
            positions,
            normals: None,
            triangles,
        };
        let n = part.positions.len();
        if let Some((i, t)) = part
            .triangles
            .iter()
            .enumerate()
            .find(|(_, t)| t.iter().any(|&k| k as usize >= n))
        {
            return Err(MeshError::invalid(
                path,
                format!(
                    "object '{}': triangle {i} uses vertex index {t:?} but the object has only {n} vertices",
                    model.name
                ),
            ));
        }
        let had_normals = m.normals.len() == 3 * n && n > 0;
        if had_normals {
            part.normals = Some(
                m.normals
                    .chunks_exact(3)
                    .map(|v| {
                        DVec3::new(v[0], v[1], v[2])
                            .try_normalize()
                            .unwrap_or(DVec3::NAN)
                    })
                    .collect(),
            );
        } else {
            report.normals_from_file = false;
            part.normals = Some(part.computed_normals());
        }
        let mut piece = MeshPart {
            name: model.name.clone(),
            aliases: Vec::new(),
            mesh: TriangleMesh::default(),
            primitives: Vec::new(),
        };
        piece.push_primitive(format!("object '{}'", model.name), part, had_normals);
        parts.push(piece);
    }
    Ok((parts, report))
}
