//! Mesh quality as the tracer sees it: counts, world-space bounds, surface area and
//! the topology faults that make CAD exports leak photons or shade them wrongly
//! (degenerate triangles, open and non-manifold edges, neighbours wound the other
//! way, file normals that contradict the winding).
//!
//! Data flow: `traxer inspect` imports a file with the tracer's own importer
//! ([`super::load_parts`]) and hands each part, each primitive and the whole file to
//! [`analyse`]. Nothing here changes a mesh.
//!
//! Topology is judged after *welding* vertices closer than [`WELD_TOLERANCE`] times
//! the bounding-box diagonal. Files split a vertex wherever the normal or the
//! primitive changes, so edges compared by vertex index would call every crease a
//! hole; edges compared by position do not. A gap wider than the tolerance is a
//! real crack: it is far above f32 resolution (6e-8), so rays can pass through it.

use super::TriangleMesh;
use glam::DVec3;
use std::collections::HashMap;

/// Vertices closer than this fraction of the bounding-box diagonal are one vertex
/// for the topology counts.
pub const WELD_TOLERANCE: f64 = 1e-6;

/// A triangle whose smallest height is below this fraction of its longest side is
/// degenerate: to Embree's f32 arithmetic (relative precision 6e-8) it has no area.
pub const DEGENERATE_HEIGHT: f64 = 1e-7;

/// Neighbouring facets bent by this much or more meet at an intended edge (a
/// crease), not at a step of a tessellated curved surface.
pub const CREASE_DEG: f64 = 30.0;

/// How the triangles use one (welded) edge.
#[derive(Clone, Copy, Default)]
struct EdgeUse {
    triangles: u32,
    /// Uses that run from the lower to the higher vertex index.
    low_to_high: u32,
    /// The first two triangles on the edge.
    first: [u32; 2],
}

/// Axis-aligned bounds in world space (millimetres as the tracer reads them).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Bounds {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Bounds {
    /// Edge lengths of the box.
    pub fn size(&self) -> [f64; 3] {
        [0, 1, 2].map(|i| self.max[i] - self.min[i])
    }

    /// The longest edge of the box.
    pub fn largest_extent(&self) -> f64 {
        self.size().into_iter().fold(0.0, f64::max)
    }
}

/// What [`analyse`] finds in one mesh. The field names are the JSON keys of
/// `traxer inspect --json` (documented in docs/inspect.md): keep them stable.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MeshQuality {
    pub triangles: usize,
    /// Vertices as stored (a file repeats a position once per normal or primitive).
    pub vertices: usize,
    /// Distinct positions after welding.
    pub distinct_positions: usize,
    /// Bounds of the vertices that triangles use.
    pub bounds: Bounds,
    /// Sum of the triangle areas (mm² as the tracer reads the file).
    pub area: f64,
    /// Triangles with (numerically) zero area: see [`DEGENERATE_HEIGHT`].
    pub degenerate_triangles: usize,
    /// Edges with one triangle: the rim of an open surface or of a hole.
    pub boundary_edges: usize,
    /// Edges shared by three or more triangles.
    pub non_manifold_edges: usize,
    /// Edges between two triangles that run along it in the same direction: the
    /// neighbours' windings (hence their front sides) disagree.
    pub inconsistent_winding_edges: usize,
    /// Groups of triangles connected through shared (welded) vertices.
    pub components: usize,
    /// No boundary and no non-manifold edges: the mesh encloses a volume.
    pub closed: bool,
    /// For a closed, consistently wound mesh: the enclosed volume (mm³), positive
    /// when the winding makes the front sides face outwards, negative when the
    /// mesh is inside out.
    pub enclosed_volume: Option<f64>,
    /// Largest bend (degrees) between neighbouring facets below [`CREASE_DEG`]: the
    /// tessellation step of curved surfaces. A flat facet's normal is off the true
    /// surface by up to half of it (use `smooth_normals` on mirrors). `None` when
    /// no two facets meet at less than a crease.
    pub facet_step_deg: Option<f64>,
    /// Edges where facets meet at [`CREASE_DEG`] or more (box edges, rims).
    pub creases: usize,
    /// For vertex normals read from the file: triangles whose normals point
    /// against their winding (the geometric front side); `None` when computed.
    pub normals_against_winding: Option<usize>,
    /// The welding distance used (mm).
    pub weld_distance: f64,
}

/// Analyses a mesh whose indices are in range (as every imported mesh is).
/// `normals_from_file` says whether `mesh.normals` came from the file, which is
/// when their agreement with the winding is worth checking.
pub fn analyse(mesh: &TriangleMesh, normals_from_file: bool) -> MeshQuality {
    let used = used_vertices(mesh);
    let bounds = used.iter().zip(&mesh.positions).filter(|(u, _)| **u).fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), (_, &p)| (lo.min(p), hi.max(p)),
    );
    let (lo, hi) = if mesh.triangles.is_empty() {
        (DVec3::ZERO, DVec3::ZERO)
    } else {
        bounds
    };
    let weld_distance = WELD_TOLERANCE * (hi - lo).length();
    let (welded, distinct_positions) = weld(&mesh.positions, &used, weld_distance);
    let corners = |t: &[u32; 3]| t.map(|k| mesh.positions[k as usize]);

    let (area, degenerate_triangles, facet_normals) = facets(mesh, &welded);
    let (edges, mut components) = welded_edges(mesh, &welded, distinct_positions);
    let boundary_edges = edges.values().filter(|e| e.triangles == 1).count();
    let non_manifold_edges = edges.values().filter(|e| e.triangles > 2).count();
    let inconsistent_winding_edges = edges
        .values()
        .filter(|e| e.triangles == 2 && e.low_to_high != 1)
        .count();
    let (facet_step_deg, creases) = facet_bends(&edges, &facet_normals);
    let mut roots: Vec<u32> = mesh
        .triangles
        .iter()
        .map(|t| components.root(welded[t[0] as usize]))
        .collect();
    roots.sort_unstable();
    roots.dedup();

    let closed = !mesh.triangles.is_empty() && boundary_edges == 0 && non_manifold_edges == 0;
    let enclosed_volume = (closed && inconsistent_winding_edges == 0).then(|| {
        // Divergence theorem about the box centre (keeps the sum well conditioned).
        let o = 0.5 * (lo + hi);
        mesh.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = corners(t).map(|p| p - o);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    });
    let normals_against_winding = match (&mesh.normals, normals_from_file) {
        (Some(normals), true) => Some(
            (0..mesh.triangles.len())
                .filter(|&i| {
                    let vertex_normals: DVec3 =
                        mesh.triangles[i].iter().map(|&k| normals[k as usize]).sum();
                    mesh.face_normal(i).dot(vertex_normals) < 0.0
                })
                .count(),
        ),
        _ => None,
    };
    MeshQuality {
        triangles: mesh.triangles.len(),
        vertices: mesh.positions.len(),
        distinct_positions,
        bounds: Bounds {
            min: lo.to_array(),
            max: hi.to_array(),
        },
        area,
        degenerate_triangles,
        boundary_edges,
        non_manifold_edges,
        inconsistent_winding_edges,
        facet_step_deg,
        creases,
        components: roots.len(),
        closed,
        enclosed_volume,
        normals_against_winding,
        weld_distance,
    }
}

/// Total area, the number of degenerate triangles, and each triangle's unit
/// normal (`None` for degenerate ones, whose normal is noise).
fn facets(mesh: &TriangleMesh, welded: &[u32]) -> (f64, usize, Vec<Option<DVec3>>) {
    let mut area = 0.0;
    let mut degenerate_triangles = 0;
    let mut facet_normals: Vec<Option<DVec3>> = Vec::with_capacity(mesh.triangles.len());
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|k| mesh.positions[k as usize]);
        let cross = (b - a).cross(c - a);
        let twice_area = cross.length();
        area += 0.5 * twice_area;
        let w = t.map(|k| welded[k as usize]);
        let longest = (b - a)
            .length_squared()
            .max((c - b).length_squared())
            .max((a - c).length_squared());
        // height = 2A / longest side ≤ DEGENERATE_HEIGHT · longest side
        if w[0] == w[1] || w[1] == w[2] || w[2] == w[0] || twice_area <= DEGENERATE_HEIGHT * longest
        {
            degenerate_triangles += 1;
            facet_normals.push(None);
        } else {
            facet_normals.push(Some(cross / twice_area));
        }
    }
    (area, degenerate_triangles, facet_normals)
}

/// Undirected welded edges with their uses, and the connected components of the
/// welded vertices.
fn welded_edges(
    mesh: &TriangleMesh,
    welded: &[u32],
    distinct_positions: usize,
) -> (HashMap<(u32, u32), EdgeUse>, UnionFind) {
    let mut edges: HashMap<(u32, u32), EdgeUse> = HashMap::with_capacity(mesh.triangles.len() * 2);
    let mut components = UnionFind::new(distinct_positions);
    for (i, t) in mesh.triangles.iter().enumerate() {
        let w = t.map(|k| welded[k as usize]);
        if w[0] == w[1] || w[1] == w[2] || w[2] == w[0] {
            continue; // its edges have no length
        }
        for (a, b) in [(w[0], w[1]), (w[1], w[2]), (w[2], w[0])] {
            let e = edges.entry((a.min(b), a.max(b))).or_default();
            if e.triangles < 2 {
                e.first[e.triangles as usize] = i as u32;
            }
            e.triangles += 1;
            e.low_to_high += u32::from(a < b);
            components.join(a, b);
        }
    }
    (edges, components)
}

/// The largest bend below [`CREASE_DEG`] between neighbouring facets, as
/// unoriented planes (a winding fault is reported elsewhere), and the number of
/// creases (bends at or above it).
fn facet_bends(
    edges: &HashMap<(u32, u32), EdgeUse>,
    facet_normals: &[Option<DVec3>],
) -> (Option<f64>, usize) {
    let mut facet_step_deg: Option<f64> = None;
    let mut creases = 0;
    for e in edges.values().filter(|e| e.triangles == 2) {
        let (Some(n1), Some(n2)) = (
            facet_normals[e.first[0] as usize],
            facet_normals[e.first[1] as usize],
        ) else {
            continue;
        };
        let cos = n1.dot(n2).abs().min(1.0);
        let angle = n1.cross(n2).length().atan2(cos).to_degrees();
        if angle >= CREASE_DEG {
            creases += 1;
        } else {
            facet_step_deg = Some(facet_step_deg.unwrap_or(0.0).max(angle));
        }
    }
    (facet_step_deg, creases)
}

/// Which vertices some triangle uses.
fn used_vertices(mesh: &TriangleMesh) -> Vec<bool> {
    let mut used = vec![false; mesh.positions.len()];
    for t in &mesh.triangles {
        for &k in t {
            used[k as usize] = true;
        }
    }
    used
}

/// Maps every used vertex to a representative index (0..count) such that vertices
/// within `distance` of a representative share it. Grid hashing with cells of the
/// welding distance: a match can only lie in the 27 cells around a vertex.
fn weld(positions: &[DVec3], used: &[bool], distance: f64) -> (Vec<u32>, usize) {
    let mut welded = vec![u32::MAX; positions.len()];
    let mut representatives: Vec<DVec3> = Vec::new();
    if distance > 0.0 {
        let cell = |p: DVec3| (p / distance).floor().to_array().map(|c| c as i64);
        let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        for (i, &p) in positions.iter().enumerate().filter(|(i, _)| used[*i]) {
            let c = cell(p);
            let mut found = None;
            'search: for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let key = [
                            c[0].saturating_add(dx),
                            c[1].saturating_add(dy),
                            c[2].saturating_add(dz),
                        ];
                        if let Some(list) = grid.get(&key) {
                            if let Some(&r) = list
                                .iter()
                                .find(|&&r| representatives[r as usize].distance(p) <= distance)
                            {
                                found = Some(r);
                                break 'search;
                            }
                        }
                    }
                }
            }
            welded[i] = found.unwrap_or_else(|| {
                let r = representatives.len() as u32;
                representatives.push(p);
                grid.entry(c).or_default().push(r);
                r
            });
        }
    } else {
        // A single point (or no triangles): weld identical coordinates only.
        let mut seen: HashMap<[u64; 3], u32> = HashMap::new();
        for (i, p) in positions.iter().enumerate().filter(|(i, _)| used[*i]) {
            let key = p.to_array().map(|c| (c + 0.0).to_bits()); // -0.0 → 0.0
            let next = seen.len() as u32;
            welded[i] = *seen.entry(key).or_insert(next);
        }
        representatives.resize(seen.len(), DVec3::ZERO);
    }
    (welded, representatives.len())
}

/// Disjoint sets over welded vertices, for counting connected components.
struct UnionFind {
    parent: Vec<u32>,
}

impl UnionFind {
    fn new(n: usize) -> Self {
        UnionFind {
            parent: (0..n as u32).collect(),
        }
    }

    fn root(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let up = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = up; // path halving
            x = up;
        }
        x
    }

    fn join(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.root(a), self.root(b));
        if ra != rb {
            self.parent[ra.max(rb) as usize] = ra.min(rb);
        }
    }
}
