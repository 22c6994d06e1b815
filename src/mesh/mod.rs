//! Triangle meshes: the in-memory form, import from glTF 2.0 and Wavefront OBJ,
//! and export of tessellated shapes.
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
pub mod quality;
pub mod units;

pub use export::{write_gltf, write_mesh, write_mesh_parts, write_obj};

use glam::DVec3;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// A triangle mesh in f64 (Embree receives an f32 copy of the world-space vertices).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    pub positions: Vec<DVec3>,
    /// Unit vertex normals, one per position, when known.
    pub normals: Option<Vec<DVec3>>,
    /// Counter-clockwise (seen from the front) vertex index triples.
    pub triangles: Vec<[u32; 3]>,
}

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
    #[error("mesh file {path}: unsupported file type (expected .gltf, .glb or .obj)")]
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

/// Loads a `.gltf`, `.glb` or `.obj` file, applying glTF node transforms, and
/// checks it ([`TriangleMesh::validate`]). Vertex normals are always present in the
/// result: from the file where it has them, computed otherwise.
pub fn load(path: &Path) -> Result<(TriangleMesh, ImportReport), MeshError> {
    let (parts, report) = load_parts(path)?;
    Ok((select_parts(path, &parts, None)?, report))
}

/// The parts of a mesh file, unchecked (see [`select_parts`]).
pub fn load_parts(path: &Path) -> Result<(Vec<MeshPart>, ImportReport), MeshError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "gltf" | "glb" => gltf_import::load(path),
        "obj" => obj_import::load(path),
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
    mesh.validate().map_err(|m| MeshError::invalid(path, m))?;
    Ok(mesh)
}

impl TriangleMesh {
    /// Checks what the tracer relies on: at least one triangle, finite coordinates
    /// and normals, every index in range.
    pub fn validate(&self) -> Result<(), String> {
        if self.triangles.is_empty() {
            return Err("contains no triangles".into());
        }
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(format!(
                "vertex {i} has a non-finite coordinate {:?}",
                self.positions[i]
            ));
        }
        let n = self.positions.len();
        if n > u32::MAX as usize {
            return Err(format!("{n} vertices is more than 2^32"));
        }
        if let Some((i, t)) = self
            .triangles
            .iter()
            .enumerate()
            .find(|(_, t)| t.iter().any(|&k| k as usize >= n))
        {
            return Err(format!(
                "triangle {i} uses vertex index {:?} but there are only {n} vertices",
                t
            ));
        }
        if let Some(normals) = &self.normals {
            if normals.len() != n {
                return Err(format!("{} normals for {n} vertices", normals.len()));
            }
            if let Some(i) = normals.iter().position(|v| !v.is_finite()) {
                return Err(format!("normal {i} is not finite"));
            }
        }
        Ok(())
    }

    /// Geometric (unnormalised, length = 2 × area) normal of triangle `i`.
    #[inline]
    pub fn face_normal(&self, i: usize) -> DVec3 {
        let [a, b, c] = self.triangles[i];
        let (a, b, c) = (
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        );
        (b - a).cross(c - a)
    }

    /// Area-weighted vertex normals from the geometry (used when a file has none).
    pub fn computed_normals(&self) -> Vec<DVec3> {
        let mut acc = vec![DVec3::ZERO; self.positions.len()];
        for (i, t) in self.triangles.iter().enumerate() {
            let n = self.face_normal(i);
            for &k in t {
                acc[k as usize] += n;
            }
        }
        acc.into_iter()
            .map(|n| n.try_normalize().unwrap_or(DVec3::Z))
            .collect()
    }

    /// Reverses triangles whose winding disagrees with their vertex normals, so
    /// that the geometric normal and the shading normal agree (tessellation helper).
    pub fn orient_to_normals(&mut self) {
        let Some(normals) = &self.normals else { return };
        for i in 0..self.triangles.len() {
            let t = self.triangles[i];
            let avg: DVec3 = t.iter().map(|&k| normals[k as usize]).sum();
            if self.face_normal(i).dot(avg) < 0.0 {
                self.triangles[i] = [t[0], t[2], t[1]];
            }
        }
    }

    /// Appends another mesh (normals are kept only if both have them).
    pub fn append(&mut self, other: TriangleMesh) {
        let base = self.positions.len() as u32;
        self.normals = match (self.normals.take(), other.normals) {
            (Some(mut a), Some(b)) => {
                a.extend(b);
                Some(a)
            }
            (None, Some(b)) if self.positions.is_empty() => Some(b),
            _ => None,
        };
        self.positions.extend(other.positions);
        self.triangles.extend(
            other
                .triangles
                .iter()
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
    }

    /// The mesh mapped by a transform (normals by its inverse transpose; winding
    /// reversed if the map mirrors).
    pub fn transformed(&self, tf: &crate::geometry::Transform) -> TriangleMesh {
        let flip = tf.flips_orientation();
        TriangleMesh {
            positions: self.positions.iter().map(|&p| tf.point(p)).collect(),
            normals: self
                .normals
                .as_ref()
                .map(|ns| ns.iter().map(|&n| tf.normal(n)).collect()),
            triangles: if flip {
                self.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect()
            } else {
                self.triangles.clone()
            },
        }
    }

    /// Axis-aligned bounds (lower, upper).
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.positions.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        )
    }

    /// Total surface area.
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|i| 0.5 * self.face_normal(i).length())
            .sum()
    }
}
