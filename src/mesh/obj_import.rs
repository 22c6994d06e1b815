//! Wavefront OBJ import through `tobj`: polygons are triangulated, each object
//! (or group) of the file is one [`MeshPart`]; material libraries are ignored.

use super::{ImportReport, MeshError, MeshPart, TriangleMesh};
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
            report
                .warnings
                .push(format!("object '{}' skipped: no faces", model.name));
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
        let indices_ok = part
            .triangles
            .iter()
            .all(|t| t.iter().all(|&k| (k as usize) < n));
        if m.normals.len() == 3 * n && n > 0 {
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
            part.normals = Some(if indices_ok {
                part.computed_normals()
            } else {
                vec![DVec3::Z; n]
            });
        }
        parts.push(MeshPart {
            name: model.name.clone(),
            aliases: Vec::new(),
            mesh: part,
        });
    }
    Ok((parts, report))
}
