//! glTF 2.0 import (`.gltf` with external or embedded buffers, `.glb`): the default
//! scene's node hierarchy is walked and every triangle primitive is placed with its
//! node's world matrix. Each node with a mesh becomes one [`MeshPart`], named after
//! the node (aliases: its mesh and its ancestor nodes).

use super::{ImportReport, MeshError, MeshPart, Skipped, TriangleMesh};
use glam::{DMat3, DMat4, DVec3};
use gltf::mesh::Mode;
use std::path::{Path, PathBuf};

/// Required extensions that compress geometry: named in the error so users know to
/// re-export without compression.
const COMPRESSION_EXTENSIONS: [&str; 2] = ["KHR_draco_mesh_compression", "EXT_meshopt_compression"];

pub(super) fn load(path: &Path) -> Result<(Vec<MeshPart>, ImportReport), MeshError> {
    // The gltf crate can panic on malformed files (e.g. an attribute naming an
    // accessor that does not exist makes its validation index past a list).
    super::guard::quietly(|| load_unguarded(path)).unwrap_or_else(|why| {
        Err(MeshError::invalid(
            path,
            format!("malformed glTF: the glTF reader failed on it ({why})"),
        ))
    })
}

fn load_unguarded(path: &Path) -> Result<(Vec<MeshPart>, ImportReport), MeshError> {
    let bad = |m: String| MeshError::invalid(path, m);
    let (document, blob) = read_document(path)?;
    let doc = &document;
    let buffers = load_buffers(path, doc, blob)?;
    let mut parts = Vec::new();
    let mut report = ImportReport {
        normals_from_file: true,
        extensions_used: doc.extensions_used().map(String::from).collect(),
        files: external_buffers(path, doc),
        ..Default::default()
    };
    let roots = root_nodes(doc, &mut report);
    // (node, parent's world matrix, depth, names of the ancestors)
    let mut stack: Vec<(gltf::Node, DMat4, usize, Vec<String>)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, DMat4::IDENTITY, 0, Vec::new()))
        .collect();
    while let Some((node, parent, depth, ancestors)) = stack.pop() {
        if depth > 1000 {
            return Err(bad(
                "node hierarchy deeper than 1000 levels (a cycle?)".into()
            ));
        }
        let local = DMat4::from_cols_array_2d(&node.transform().matrix().map(|c| c.map(f64::from)));
        let world = parent * local;
        let node_name = node
            .name()
            .map(String::from)
            .unwrap_or_else(|| format!("node{}", node.index()));
        for key in node.extensions().into_iter().flat_map(|e| e.keys()) {
            let what = if key == "EXT_mesh_gpu_instancing" {
                ": only the node itself is traced, not its instances"
            } else {
                ""
            };
            report.notes.push(format!(
                "node '{node_name}' carries {key} data, which traxer ignores{what}"
            ));
        }
        if let Some(m) = node.mesh() {
            let mut part = MeshPart {
                name: node_name,
                aliases: m.name().map(String::from).into_iter().collect(),
                mesh: TriangleMesh::default(),
                primitives: Vec::new(),
            };
            part.aliases.extend(ancestors.iter().cloned());
            read_mesh(path, &m, &world, &buffers, &mut part, &mut report)?;
            if !part.mesh.triangles.is_empty() {
                parts.push(part);
            }
        }
        let mut names = ancestors;
        if let Some(n) = node.name() {
            names.push(n.to_string());
        }
        let children: Vec<gltf::Node> = node.children().collect();
        for child in children.into_iter().rev() {
            stack.push((child, world, depth + 1, names.clone()));
        }
    }
    Ok((parts, report))
}

/// The file's document, checked: required extensions are refused by name (read
/// without validation first: the gltf crate's validation rejects any required
/// extension with a bare "Unsupported extension", and the user needs to know
/// which one, where it is used and what to do), then validated.
fn read_document(path: &Path) -> Result<(gltf::Document, Option<Vec<u8>>), MeshError> {
    let bad = |m: String| MeshError::invalid(path, m);
    check_glb_length(path)?;
    let file = std::fs::File::open(path).map_err(|e| bad(format!("cannot read it: {e}")))?;
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_reader_without_validation(std::io::BufReader::new(file))
            .map_err(|e| bad(describe(&e)))?;
    if let Some(ext) = document.extensions_required().next() {
        let why = if COMPRESSION_EXTENSIONS.contains(&ext) {
            "compressed geometry is not supported; export the file without mesh compression"
        } else {
            "traxer does not support this extension"
        };
        let users = primitives_using(&document, ext);
        let users = if users.is_empty() {
            String::new()
        } else {
            format!(" (used by {users})")
        };
        return Err(bad(format!(
            "requires the glTF extension {ext}{users}: {why}"
        )));
    }
    let document =
        gltf::Document::from_json(document.into_json()).map_err(|e| bad(describe(&e)))?;
    Ok((document, blob))
}

/// The binary buffers (the GLB blob, data URIs, external files); a missing
/// external file is named.
fn load_buffers(
    path: &Path,
    doc: &gltf::Document,
    blob: Option<Vec<u8>>,
) -> Result<Vec<gltf::buffer::Data>, MeshError> {
    let base = path.parent();
    gltf::import_buffers(doc, base, blob).map_err(|e| {
        // The gltf crate's I/O error does not say which file: find it.
        let missing = doc.buffers().find_map(|b| match b.source() {
            gltf::buffer::Source::Uri(uri) if !uri.starts_with("data:") => {
                let file = base.unwrap_or(Path::new(".")).join(uri);
                (!file.exists()).then(|| {
                    format!(
                        "buffer {} refers to {}, which does not exist",
                        b.index(),
                        file.display()
                    )
                })
            }
            _ => None,
        });
        MeshError::invalid(
            path,
            missing.unwrap_or_else(|| format!("cannot load its buffers: {}", describe(&e))),
        )
    })
}

/// The external files the buffers name (not data URIs, not the GLB blob).
fn external_buffers(path: &Path, doc: &gltf::Document) -> Vec<PathBuf> {
    let base = path.parent().unwrap_or(Path::new("."));
    doc.buffers()
        .filter_map(|b| match b.source() {
            gltf::buffer::Source::Uri(uri) if !uri.starts_with("data:") => Some(base.join(uri)),
            _ => None,
        })
        // A percent-encoded name the glTF reader decoded itself is left out.
        .filter(|f| f.is_file())
        .collect()
}

/// The root nodes of the scene that is read (the default one, else the first;
/// a note says so when there are several), or of the node forest if the file has
/// no scene.
fn root_nodes<'a>(doc: &'a gltf::Document, report: &mut ImportReport) -> Vec<gltf::Node<'a>> {
    match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => {
            let count = doc.scenes().count();
            if count > 1 {
                let name = scene.name().map(|n| format!(" '{n}'")).unwrap_or_default();
                report.notes.push(format!(
                    "the file has {count} scenes: only scene {}{name} ({}) is read",
                    scene.index(),
                    if doc.default_scene().is_some() {
                        "the default"
                    } else {
                        "the first; no default is set"
                    }
                ));
            }
            scene.nodes().collect()
        }
        None => {
            // No scene: every node that is nobody's child is a root.
            let children: std::collections::HashSet<usize> = doc
                .nodes()
                .flat_map(|n| n.children().map(|c| c.index()).collect::<Vec<_>>())
                .collect();
            doc.nodes()
                .filter(|n| !children.contains(&n.index()))
                .collect()
        }
    }
}

/// Reads every primitive of mesh `m` (placed by `world`) into `part`; pieces
/// without triangles are skipped with a reason, broken ones are errors.
fn read_mesh(
    path: &Path,
    m: &gltf::Mesh,
    world: &DMat4,
    buffers: &[gltf::buffer::Data],
    part: &mut MeshPart,
    report: &mut ImportReport,
) -> Result<(), MeshError> {
    let bad = |m: String| MeshError::invalid(path, m);
    for prim in m.primitives() {
        let label = primitive_label(m, &prim);
        for key in prim.extensions().into_iter().flat_map(|e| e.keys()) {
            let what = if COMPRESSION_EXTENSIONS.contains(&key.as_str()) {
                ": its uncompressed accessors are read"
            } else {
                ""
            };
            report.notes.push(format!(
                "{label} carries {key} data, which traxer ignores{what}"
            ));
        }
        // Reading accessors walks offsets from the file: a malformed one can make
        // the gltf crate panic.
        let read = super::guard::quietly(|| read_primitive(&prim, buffers, world))
            .map_err(|why| bad(format!("{label}: malformed accessor data ({why})")))?;
        match read {
            Ok((mesh, had_normals)) => {
                report.normals_from_file &= had_normals;
                part.push_primitive(label, mesh, had_normals);
            }
            Err(Unusable::Skip(reason)) => report.skipped.push(Skipped {
                what: label,
                reason,
            }),
            Err(Unusable::Broken(message)) => return Err(bad(format!("{label}: {message}"))),
        }
    }
    Ok(())
}

/// "primitive 2 of mesh 'rails'" (or "of mesh #3" when the mesh has no name).
fn primitive_label(m: &gltf::Mesh, prim: &gltf::Primitive) -> String {
    let mesh = m
        .name()
        .map(|n| format!("'{n}'"))
        .unwrap_or(format!("#{}", m.index()));
    format!("primitive {} of mesh {mesh}", prim.index())
}

/// The primitives that carry data of extension `ext`, for the refusal message.
fn primitives_using(doc: &gltf::Document, ext: &str) -> String {
    let users: Vec<String> = doc
        .meshes()
        .flat_map(|m| {
            m.primitives()
                .filter(|p| p.extensions().is_some_and(|e| e.contains_key(ext)))
                .map(|p| primitive_label(&m, &p))
                .collect::<Vec<_>>()
        })
        .collect();
    match users.len() {
        0..=3 => users.join(", "),
        n => format!("{}, ... ({n} primitives in all)", users[..3].join(", ")),
    }
}

/// Why a primitive adds no triangles: left out with a warning, or a broken file.
enum Unusable {
    Skip(String),
    Broken(String),
}

fn read_primitive(
    prim: &gltf::Primitive,
    buffers: &[gltf::buffer::Data],
    world: &DMat4,
) -> Result<(TriangleMesh, bool), Unusable> {
    let mode = prim.mode();
    if !matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    ) {
        return Err(Unusable::Skip(format!("mode {mode:?} has no triangles")));
    }
    let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let position_accessor = prim
        .get(&gltf::Semantic::Positions)
        .ok_or_else(|| Unusable::Skip("no POSITION attribute".into()))?;
    check_accessor_types(prim, &position_accessor)?;
    let positions: Vec<DVec3> = reader
        .read_positions()
        .ok_or_else(|| unreadable("POSITION", &position_accessor))?
        .map(|p| world.transform_point3(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)))
        .collect();
    // Never fewer elements than declared: a truncated export must not lose
    // triangles silently.
    complete("POSITION", &position_accessor, positions.len())?;
    let indices: Vec<u32> = match (reader.read_indices(), prim.indices()) {
        (Some(ix), Some(accessor)) => {
            let ix: Vec<u32> = ix.into_u32().collect();
            complete("indices", &accessor, ix.len())?;
            ix
        }
        (None, Some(accessor)) => return Err(unreadable("indices", &accessor)),
        _ => (0..positions.len() as u32).collect(),
    };
    let mut triangles = assemble_triangles(mode, &indices);
    // glTF: a node matrix with negative determinant reverses the winding.
    let linear = DMat3::from_mat4(*world);
    if linear.determinant() < 0.0 {
        for t in &mut triangles {
            t.swap(1, 2);
        }
    }
    let normal_matrix = linear.inverse().transpose();
    let file_normals: Option<Vec<DVec3>> = reader.read_normals().map(|ns| {
        ns.map(|n| {
            (normal_matrix * DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64))
                .try_normalize()
                .unwrap_or(DVec3::NAN)
        })
        .collect()
    });
    let mut mesh = TriangleMesh {
        positions,
        normals: None,
        triangles,
    };
    match (&file_normals, prim.get(&gltf::Semantic::Normals)) {
        (Some(normals), Some(accessor)) => {
            complete("NORMAL", &accessor, normals.len())?;
            if normals.len() != mesh.positions.len() {
                return Err(Unusable::Broken(format!(
                    "its NORMAL accessor {} has {} elements for {} positions (glTF requires one per vertex)",
                    accessor.index(),
                    normals.len(),
                    mesh.positions.len()
                )));
            }
        }
        (None, Some(accessor)) => return Err(unreadable("NORMAL", &accessor)),
        _ => {}
    }
    let had_normals = matches!(&file_normals, Some(n) if n.len() == mesh.positions.len());
    // An index past this primitive's vertices would silently point into the next
    // primitive once the part is assembled: refuse the file.
    let n = mesh.positions.len();
    if let Some((i, t)) = mesh
        .triangles
        .iter()
        .enumerate()
        .find(|(_, t)| t.iter().any(|&k| k as usize >= n))
    {
        return Err(Unusable::Broken(format!(
            "triangle {i} uses vertex index {t:?} but the primitive has only {n} vertices"
        )));
    }
    mesh.normals = if had_normals {
        file_normals
    } else {
        Some(mesh.computed_normals())
    };
    Ok((mesh, had_normals))
}

/// Checks the accessor types glTF allows (without extensions, which are refused
/// when required): the gltf crate would misread or panic on others.
fn check_accessor_types(
    prim: &gltf::Primitive,
    positions: &gltf::Accessor,
) -> Result<(), Unusable> {
    use gltf::accessor::{DataType, Dimensions};
    expect_type("POSITION", positions, Dimensions::Vec3, &[DataType::F32])?;
    if let Some(a) = prim.get(&gltf::Semantic::Normals) {
        expect_type("NORMAL", &a, Dimensions::Vec3, &[DataType::F32])?;
    }
    if let Some(a) = prim.indices() {
        expect_type(
            "indices",
            &a,
            Dimensions::Scalar,
            &[DataType::U8, DataType::U16, DataType::U32],
        )?;
    }
    Ok(())
}

/// Triangles from the index list of a triangle list, strip or fan (glTF's
/// winding rules for strips).
fn assemble_triangles(mode: Mode, indices: &[u32]) -> Vec<[u32; 3]> {
    match mode {
        Mode::Triangles => indices
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect(),
        Mode::TriangleStrip => (2..indices.len())
            .map(|i| {
                if i % 2 == 0 {
                    [indices[i - 2], indices[i - 1], indices[i]]
                } else {
                    [indices[i - 1], indices[i - 2], indices[i]]
                }
            })
            .collect(),
        _ => (2..indices.len())
            .map(|i| [indices[0], indices[i - 1], indices[i]])
            .collect(),
    }
}

/// Checks that all `count` elements an accessor declares were read.
fn complete(what: &str, accessor: &gltf::Accessor, read: usize) -> Result<(), Unusable> {
    if read == accessor.count() {
        Ok(())
    } else {
        Err(Unusable::Broken(format!(
            "its {what} accessor {} declares {} elements but its buffer view holds only {read}",
            accessor.index(),
            accessor.count()
        )))
    }
}

/// Checks an accessor's element type against what glTF allows for its use.
fn expect_type(
    what: &str,
    accessor: &gltf::Accessor,
    dimensions: gltf::accessor::Dimensions,
    types: &[gltf::accessor::DataType],
) -> Result<(), Unusable> {
    if accessor.dimensions() == dimensions && types.contains(&accessor.data_type()) {
        Ok(())
    } else {
        Err(Unusable::Broken(format!(
            "its {what} accessor {} holds {:?} of {:?}; glTF requires {dimensions:?} of {}",
            accessor.index(),
            accessor.dimensions(),
            accessor.data_type(),
            types
                .iter()
                .map(|t| format!("{t:?}"))
                .collect::<Vec<_>>()
                .join(" or ")
        )))
    }
}

/// An accessor the gltf crate cannot read: no buffer view, or a view (or buffer)
/// too short for the elements it declares.
fn unreadable(what: &str, accessor: &gltf::Accessor) -> Unusable {
    Unusable::Broken(format!(
        "its {what} accessor {} declares {} elements that its buffer view does not hold (view too short, or none)",
        accessor.index(),
        accessor.count()
    ))
}

/// A binary glTF (GLB) file declares its length in its 12-byte header: a file
/// shorter than that was cut off (an interrupted copy or download).
fn check_glb_length(path: &Path) -> Result<(), MeshError> {
    use std::io::Read;
    let Ok(mut f) = std::fs::File::open(path) else {
        return Ok(()); // the reader says why
    };
    let mut header = Vec::with_capacity(12);
    let _ = f.by_ref().take(12).read_to_end(&mut header);
    if header.len() < 4 || &header[..4] != b"glTF" {
        return Ok(());
    }
    let size = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    if header.len() < 12 {
        return Err(MeshError::invalid(
            path,
            format!(
                "is truncated: a GLB file starts with a 12-byte header, this one has {size} bytes"
            ),
        ));
    }
    let declared = u32::from_le_bytes([header[8], header[9], header[10], header[11]]) as u64;
    if size < declared {
        return Err(MeshError::invalid(
            path,
            format!("is truncated: its header declares {declared} bytes, the file has {size}"),
        ));
    }
    Ok(())
}

/// The gltf crate's errors, in words a user can act on.
fn describe(e: &gltf::Error) -> String {
    match e {
        gltf::Error::Io(io) => format!("cannot read it: {io}"),
        gltf::Error::Deserialize(d) => format!("not valid glTF JSON: {d}"),
        gltf::Error::Validation(list) => {
            let items: Vec<String> = list
                .iter()
                .take(5)
                .map(|(path, err)| format!("{}: {err}", path.as_str()))
                .collect();
            format!("invalid glTF: {}", items.join("; "))
        }
        other => other.to_string(),
    }
}
