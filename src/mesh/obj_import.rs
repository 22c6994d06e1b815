//! Wavefront OBJ import through `tobj`: each object (or group) of the file is
//! one [`MeshPart`]; polygon faces are triangulated by ear clipping (a concave
//! face keeps its area); line (`l`) and point (`p`) elements are left out and
//! reported; material libraries are ignored.

use super::{ImportReport, MeshError, MeshPart, Skipped, TriangleMesh};
use glam::DVec3;
use std::path::Path;

pub(super) fn load(path: &Path) -> Result<(Vec<MeshPart>, ImportReport), MeshError> {
    let options = tobj::LoadOptions {
        triangulate: false,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let text = std::fs::read(path)
        .map_err(|e| MeshError::invalid(path, format!("cannot read the file: {e}")))?;
    let encoding_note = check_text(path, &text)?;
    let text = match encoding_note {
        None => text,
        Some(_) => String::from_utf8_lossy(&text).into_owned().into_bytes(),
    };
    // tobj reads a line element of three or more vertices as a polygon face:
    // line elements are taken out here, and counted.
    let (faces_only, lines) = without_line_elements(&text);
    let loaded = tobj::load_obj_buf(&mut &faces_only[..], &options, |_| {
        Ok((Vec::new(), Default::default()))
    });
    let (models, _materials) = loaded.map_err(|e| {
        MeshError::invalid(
            path,
            match e {
                tobj::LoadError::OpenFileFailed => "cannot open the file".to_string(),
                tobj::LoadError::ReadError => "cannot read the file".to_string(),
                other => match first_bad_line(&faces_only, &other) {
                    Some((line, text)) => {
                        format!("not a valid OBJ file: line {line}: {other}: `{text}`")
                    }
                    None => format!("not a valid OBJ file: {other}"),
                },
            },
        )
    })?;
    let mut parts = Vec::new();
    let mut report = ImportReport {
        normals_from_file: true,
        ..Default::default()
    };
    report.notes.extend(encoding_note);
    if lines > 0 {
        report.skipped.push(Skipped {
            what: format!("{lines} line element(s) (`l`)"),
            reason: "lines have no area to trace".into(),
        });
    }
    for model in models {
        let m = &model.mesh;
        if m.indices.is_empty() {
            report.skipped.push(Skipped {
                what: format!("object '{}'", model.name),
                reason: "no faces (points or lines only)".into(),
            });
            continue;
        }
        let (part, had_normals, folded) = model_mesh(path, &model)?;
        if let Some(note) = folded_note(&model.name, &folded) {
            report.notes.push(note);
        }
        report.normals_from_file &= had_normals;
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

/// An OBJ file is text: a binary file (a .glb, an STL, a CAD format renamed)
/// is named as such rather than reported as unreadable. Text that is not UTF-8
/// (Latin-1 comments or names from older exporters) is read with those bytes
/// replaced; the returned note says where.
fn check_text(path: &Path, bytes: &[u8]) -> Result<Option<String>, MeshError> {
    let line_of = |at: usize| bytes[..at].iter().filter(|&&b| b == b'\n').count() + 1;
    // NUL and control characters other than tab, line feed, carriage return
    // and form feed do not occur in text.
    let control = |b: u8| b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r' | 0x0c);
    if let Some(at) = bytes.iter().position(|&b| control(b)) {
        return Err(MeshError::invalid(
            path,
            format!(
                "is not a text OBJ file: line {} holds binary data (byte {at} is 0x{:02x}); an OBJ file is text of `v` and `f` lines, and a binary glTF must be named .glb",
                line_of(at),
                bytes[at]
            ),
        ));
    }
    Ok(std::str::from_utf8(bytes).err().map(|e| {
        format!(
            "line {} is not UTF-8 text (byte 0x{:02x}): such bytes were read as the replacement character � (names may show it)",
            line_of(e.valid_up_to()),
            bytes[e.valid_up_to()]
        )
    }))
}

/// The note for an object's quads that are not flat, split along their better
/// diagonal: how many, which faces and how far folded.
fn folded_note(object: &str, folded: &[(usize, f64)]) -> Option<String> {
    let most = folded
        .iter()
        .map(|f| f.1)
        .fold(None, |m: Option<f64>, f| Some(m.map_or(f, |m| m.max(f))))?;
    let listed: Vec<String> = folded
        .iter()
        .take(5)
        .map(|(face, fold)| format!("{face} ({fold:.1}°)"))
        .collect();
    Some(format!(
        "object '{object}': {} quad(s) not flat enough to triangulate in one plane were split along the diagonal that folds them least (faces {}{}; the most folded by {most:.1}° between its two triangles)",
        folded.len(),
        listed.join(", "),
        if folded.len() > 5 { ", ..." } else { "" }
    ))
}

/// Quads split along their better diagonal: (face number, fold in degrees).
type Folded = Vec<(usize, f64)>;

/// One OBJ object as a checked mesh, whether the file gave its normals, and
/// its quads split along their better diagonal.
type ModelMesh = (TriangleMesh, bool, Folded);

fn model_mesh(path: &Path, model: &tobj::Model) -> Result<ModelMesh, MeshError> {
    let m = &model.mesh;
    let positions: Vec<DVec3> = m
        .positions
        .chunks_exact(3)
        .map(|p| DVec3::new(p[0], p[1], p[2]))
        .collect();
    let (triangles, folded) = faces_to_triangles(&m.indices, &m.face_arities, &positions)
        .map_err(|why| MeshError::invalid(path, format!("object '{}': {why}", model.name)))?;
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
    part.normals = Some(if had_normals {
        m.normals
            .chunks_exact(3)
            .map(|v| {
                DVec3::new(v[0], v[1], v[2])
                    .try_normalize()
                    .unwrap_or(DVec3::NAN)
            })
            .collect()
    } else {
        part.computed_normals()
    });
    Ok((part, had_normals, folded))
}

/// The file without its line elements (`l ...`, with any `\` continuation
/// lines), and how many there were.
fn without_line_elements(text: &[u8]) -> (Vec<u8>, usize) {
    let mut out = Vec::with_capacity(text.len());
    let (mut count, mut continuing) = (0, false);
    for line in text.split_inclusive(|&b| b == b'\n') {
        let trimmed = line.trim_ascii();
        let is_line = continuing
            || trimmed.first() == Some(&b'l')
                && trimmed.get(1).is_none_or(|c| c.is_ascii_whitespace());
        if is_line {
            count += usize::from(!continuing);
            continuing = trimmed.ends_with(b"\\");
            out.push(b'\n'); // keeps the line numbers of tobj's messages
        } else {
            out.extend_from_slice(line);
        }
    }
    (out, count)
}

/// Triangles of the faces given as `indices` with `arities` corners each (no
/// arities: all triangles); polygons with their true area (`polygon`), or the
/// face that cannot be triangulated and why. Also the quads that are not flat
/// and were split along their better diagonal: (face number, fold in degrees).
fn faces_to_triangles(
    indices: &[u32],
    arities: &[u32],
    positions: &[DVec3],
) -> Result<(Vec<[u32; 3]>, Folded), String> {
    if arities.is_empty() {
        let triangles = indices
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        return Ok((triangles, Vec::new()));
    }
    let mut folded = Vec::new();
    let mut out = Vec::with_capacity(indices.len());
    let mut start = 0;
    for (number, &a) in arities.iter().enumerate() {
        let face = &indices[start..start + a as usize];
        start += a as usize;
        if face.len() < 3 {
            continue;
        }
        // Out-of-range indices are reported by the caller; treat them as the origin here.
        let corners: Vec<DVec3> = face
            .iter()
            .map(|&k| positions.get(k as usize).copied().unwrap_or(DVec3::ZERO))
            .collect();
        let triangulation = super::polygon::triangulate(&corners).map_err(|why| {
            let c = corners[0];
            format!(
                "face {} ({} corners, the first at ({}, {}, {})): {why}",
                number + 1,
                face.len(),
                c.x,
                c.y,
                c.z
            )
        })?;
        if let Some(fold) = triangulation.folded_deg {
            folded.push((number + 1, fold));
        }
        out.extend(
            triangulation
                .triangles
                .into_iter()
                .map(|t| t.map(|i| face[i])),
        );
    }
    Ok((out, folded))
}

/// The first line (1-based, with its text cut to 80 characters) of the kind an
/// OBJ error is about that does not parse: `v` or `vn` without three numbers, `vt`
/// without one, `f` with fewer than three corners or a corner that is not a
/// vertex index of the file. `None` if no such line is found.
fn first_bad_line(text: &[u8], error: &tobj::LoadError) -> Option<(usize, String)> {
    use tobj::LoadError as E;
    let text = String::from_utf8_lossy(text);
    let mut vertices: i64 = 0;
    for (i, line) in text.lines().enumerate() {
        let mut tokens = line.split_whitespace();
        let keyword = tokens.next().unwrap_or("");
        let rest: Vec<&str> = tokens.collect();
        let numbers =
            |n: usize| rest.len() >= n && rest[..n].iter().all(|t| t.parse::<f64>().is_ok());
        let bad = match (keyword, error) {
            ("v", _) => {
                vertices += 1;
                matches!(error, E::PositionParseError) && !numbers(3)
            }
            ("vn", E::NormalParseError) => !numbers(3),
            ("vt", E::TexcoordParseError) => !numbers(1),
            (
                "f",
                E::FaceParseError
                | E::InvalidPolygon
                | E::FaceVertexOutOfBounds
                | E::GenericFailure,
            ) => {
                rest.len() < 3
                    || rest.iter().any(|c| {
                        let index = c.split('/').next().unwrap_or("").parse::<i64>();
                        // 1-based, or negative counting back from the last vertex.
                        index.is_err()
                            || index.is_ok_and(|k| k == 0 || k > vertices || -k > vertices)
                    })
            }
            _ => false,
        };
        if bad {
            let shown: String = line.chars().take(80).collect();
            let cut = if line.chars().count() > 80 { "…" } else { "" };
            return Some((i + 1, format!("{}{cut}", shown.trim_end())));
        }
    }
    None
}
