//! Triangle meshes in f64: what a mesh file imports to, what an analytic shape
//! tessellates to, and what `scene` hands to Embree (as world-space f32).

use super::Transform;
use glam::DVec3;

message_error!(
    /// A mesh the tracer cannot use (no triangles, non-finite coordinates,
    /// indices out of range), with what is wrong.
    InvalidMesh
);

/// A triangle mesh in f64 (Embree receives an f32 copy of the world-space vertices).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    pub positions: Vec<DVec3>,
    /// Unit vertex normals, one per position, when known.
    pub normals: Option<Vec<DVec3>>,
    /// Counter-clockwise (seen from the front) vertex index triples.
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// Checks what the tracer relies on: at least one triangle, finite coordinates
    /// and normals, every index in range, and some triangle with an area.
    pub fn validate(&self) -> Result<(), InvalidMesh> {
        if self.triangles.is_empty() {
            return Err("contains no triangles".into());
        }
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(InvalidMesh::from(format!(
                "vertex {i} has a non-finite coordinate {:?}",
                self.positions[i]
            )));
        }
        let n = self.positions.len();
        if n > u32::MAX as usize {
            return Err(InvalidMesh::from(format!("{n} vertices is more than 2^32")));
        }
        if let Some((i, t)) = self
            .triangles
            .iter()
            .enumerate()
            .find(|(_, t)| t.iter().any(|&k| k as usize >= n))
        {
            return Err(InvalidMesh::from(format!(
                "triangle {i} uses vertex index {:?} but there are only {n} vertices",
                t
            )));
        }
        if let Some(normals) = &self.normals {
            if normals.len() != n {
                return Err(InvalidMesh::from(format!(
                    "{} normals for {n} vertices",
                    normals.len()
                )));
            }
            if let Some(i) = normals.iter().position(|v| !v.is_finite()) {
                return Err(InvalidMesh::from(format!("normal {i} is not finite")));
            }
        }
        // Lines or points exported as triangles: nothing a ray can hit.
        if (0..self.triangles.len()).all(|i| self.face_normal(i) == DVec3::ZERO) {
            return Err(InvalidMesh::from(format!(
                "all its {} triangles have zero area (lines or points exported as triangles?): nothing to trace",
                self.triangles.len()
            )));
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
    /// reversed if the map mirrors), in place: a scene of two million triangles
    /// does not allocate every mesh twice.
    pub fn transformed(mut self, tf: &Transform) -> TriangleMesh {
        for p in &mut self.positions {
            *p = tf.point(*p);
        }
        for n in self.normals.iter_mut().flatten() {
            *n = tf.normal(*n);
        }
        if tf.flips_orientation() {
            for t in &mut self.triangles {
                t.swap(1, 2);
            }
        }
        self
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
