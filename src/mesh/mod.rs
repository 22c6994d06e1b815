//! Mesh files: import from glTF 2.0, Wavefront OBJ and STL into
//! [`TriangleMesh`]es (the in-memory form lives in `geometry`), export of
//! tessellated shapes, and inspection.
//!
//! Data flow: `scene::build` calls [`load`] for every `mesh` shape of a scene file
//! (and `geometry::Shape::tessellate` produces the same [`TriangleMesh`] for
//! tessellated analytic shapes); the mesh is transformed to world space and handed
//! to Embree. `traxer tessellate` writes meshes with [`export`]; `traxer inspect`
//! reports on imported files with [`quality`] and [`units`].

mod export;
mod gltf_import;
mod guard;
mod obj_import;
mod polygon;
pub mod quality;
mod stl_import;
pub mod units;

pub use crate::geometry::TriangleMesh;
pub use export::{write_gltf, write_mesh, write_mesh_parts, write_obj};

use std::ops::Range;
use std::path::{Path, PathBuf};

/// What an import found besides the triangles.
#[derive(Clone, Debug, Default)]
pub struct ImportReport {
    /// Pieces of the file that hold no usable triangles (a glTF primitive of lines
    /// or points, an OBJ object without faces), with the reason.
    pub skipped: Vec<Skipped>,
    /// Other things the user should know (e.g. extension data that was ignored).
    pub notes: Vec<String>,
    /// Whether the file provided vertex normals for every triangle (otherwise the
    /// missing ones were computed from the geometry).
    pub normals_from_file: bool,
    /// The glTF extensions the file declares it uses (none for OBJ).
    pub extensions_used: Vec<String>,
    /// Other files read besides the mesh file (a glTF's external buffers).
    pub files: Vec<PathBuf>,
}

/// A piece of a mesh file that the importer left out (its fields are JSON keys of
/// `traxer inspect --json`).
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Skipped {
    /// Which piece, e.g. "primitive 2 of mesh 'rails'" or "object 'axis'".
    pub what: String,
    /// Why, e.g. "mode Lines has no triangles".
    pub reason: String,
}

impl ImportReport {
    /// Everything worth a warning, one line each (skipped pieces, then notes).
    pub fn warnings(&self) -> Vec<String> {
        self.skipped
            .iter()
            .map(|s| format!("{} skipped: {}", s.what, s.reason))
            .chain(self.notes.iter().cloned())
            .collect()
    }
}

/// Why a mesh file cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    #[error("mesh file {path}: {message}")]
    Invalid { path: PathBuf, message: String },
    #[error("mesh file {path}: unsupported file type (expected .gltf, .glb, .obj or .stl)")]
    UnknownFormat { path: PathBuf },
}

impl MeshError {
    pub(crate) fn invalid(path: &Path, message: impl Into<String>) -> MeshError {
        MeshError::Invalid {
            path: path.to_path_buf(),
            message: message.into(),
        }
    }
}

/// One named piece of a mesh file: a glTF node with a mesh, or an OBJ object.
#[derive(Clone, Debug)]
pub struct MeshPart {
    /// The node's (object's) name, or `node<index>` for an unnamed glTF node.
    pub name: String,
    /// Other names that select this part: its glTF mesh and its ancestor nodes
    /// (so that a CAD sub-assembly can be picked as a whole).
    pub aliases: Vec<String>,
    pub mesh: TriangleMesh,
    /// Where each glTF primitive (or the OBJ object) sits in `mesh`, in file order.
    pub primitives: Vec<Primitive>,
}

/// One glTF primitive (one OBJ object) of a [`MeshPart`]: its triangles and
/// vertices are contiguous ranges of the part's mesh.
#[derive(Clone, Debug)]
pub struct Primitive {
    /// e.g. "primitive 0 of mesh 'shell_1'" or "object 'bore'".
    pub label: String,
    pub triangles: Range<usize>,
    pub vertices: Range<usize>,
    /// Whether the file gave this primitive vertex normals (else they were computed).
    pub normals_from_file: bool,
}

impl MeshPart {
    /// Whether `name` selects this part.
    pub fn is_named(&self, name: &str) -> bool {
        self.name == name || self.aliases.iter().any(|a| a == name)
    }

    /// Whether every primitive of the part came with normals from the file.
    pub fn normals_from_file(&self) -> bool {
        self.primitives.iter().all(|p| p.normals_from_file)
    }

    /// One primitive as a mesh of its own (indices renumbered from 0).
    pub fn primitive_mesh(&self, p: &Primitive) -> TriangleMesh {
        let base = p.vertices.start as u32;
        TriangleMesh {
            positions: self.mesh.positions[p.vertices.clone()].to_vec(),
            normals: self
                .mesh
                .normals
                .as_ref()
                .map(|n| n[p.vertices.clone()].to_vec()),
            triangles: self.mesh.triangles[p.triangles.clone()]
                .iter()
                .map(|t| t.map(|k| k.wrapping_sub(base)))
                .collect(),
        }
    }

    /// Appends one imported primitive to the part, recording where it went.
    pub(crate) fn push_primitive(
        &mut self,
        label: String,
        mesh: TriangleMesh,
        normals_from_file: bool,
    ) {
        let triangles = self.mesh.triangles.len()..self.mesh.triangles.len() + mesh.triangles.len();
        let vertices = self.mesh.positions.len()..self.mesh.positions.len() + mesh.positions.len();
        self.mesh.append(mesh);
        self.primitives.push(Primitive {
            label,
            triangles,
            vertices,
            normals_from_file,
        });
    }
}

/// Loads a `.gltf`, `.glb`, `.obj` or `.stl` file, applying glTF node transforms, and
/// checks it ([`TriangleMesh::validate`]). Vertex normals are always present in the
/// result: from the file where it has them, computed otherwise.
pub fn load(path: &Path) -> Result<(TriangleMesh, ImportReport), MeshError> {
    let (parts, report) = load_parts(path)?;
    Ok((select_parts(path, &parts, None)?, report))
}

/// The parts of a mesh file, unchecked (see [`select_parts`]).
pub fn load_parts(path: &Path) -> Result<(Vec<MeshPart>, ImportReport), MeshError> {
    if path.is_dir() {
        return Err(MeshError::invalid(
            path,
            "is a folder, not a mesh file (.gltf, .glb, .obj or .stl)",
        ));
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "gltf" | "glb" => gltf_import::load(path),
        "obj" => obj_import::load(path),
        "stl" => stl_import::load(path),
        _ => Err(MeshError::UnknownFormat {
            path: path.to_path_buf(),
        }),
    }
}

/// The parts selected by `name` (every part for `None`) as one checked mesh.
pub fn select_parts(
    path: &Path,
    parts: &[MeshPart],
    name: Option<&str>,
) -> Result<TriangleMesh, MeshError> {
    let mut mesh = TriangleMesh::default();
    for p in parts.iter().filter(|p| name.is_none_or(|n| p.is_named(n))) {
        mesh.append(p.mesh.clone());
    }
    if let (Some(n), true) = (name, mesh.triangles.is_empty()) {
        let names: Vec<&str> = parts.iter().map(|p| p.name.as_str()).collect();
        let shown = names.len().min(12);
        return Err(MeshError::invalid(
            path,
            format!(
                "has no part named `{n}` (its {} parts: {}{})",
                names.len(),
                names[..shown].join(", "),
                if shown < names.len() { ", ..." } else { "" }
            ),
        ));
    }
    mesh.validate().map_err(|m| MeshError::invalid(path, m.0))?;
    Ok(mesh)
}
