//! A magnet's field map: B (tesla) on a regular grid of nodes (mm), read from
//! a text file of six columns x y z Bx By Bz (the format of the BabyIAXO map,
//! `data/magnets/`, and of REST-for-Physics' TRestAxionMagneticField), and
//! interpolated trilinearly. Outside the grid the map has no value: the
//! scene's check refuses a bore the map does not cover.
//!
//! Data flow: `scene::magnet` reads the map named by a scene (a shipped one or
//! a file) and places it on the bore; `magnet` samples it along each photon's
//! path.

use glam::DVec3;
use std::collections::BTreeMap;

message_error!(
    /// A field map that cannot be read, with the file, the line and what is
    /// wrong.
    FieldMapError
);

/// The field on a regular grid.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldMap {
    /// The first node (smallest x, y, z), mm.
    pub origin: [f64; 3],
    /// The node spacing along x, y, z, mm.
    pub spacing: [f64; 3],
    /// Nodes along x, y, z.
    pub nodes: [usize; 3],
    /// Bx, By and Bz at each node (T), each component in its own array
    /// (z fastest, then y, then x): a path along the bore (z) reads each
    /// column of nodes in order, and the samples of a run are computed side
    /// by side in the CPU's vectors.
    field: [Vec<f64>; 3],
}

/// The largest map read: 1e8 nodes (2.4 GB as f64 triples).
const MAX_NODES: usize = 100_000_000;

impl FieldMap {
    /// Reads a map from `text` (`name` for messages): rows of six numbers,
    /// `#` comments and blank lines skipped, the rows in any order; every node
    /// of the grid exactly once.
    pub fn parse(name: &str, text: &str) -> Result<FieldMap, FieldMapError> {
        let mut rows: Vec<([f64; 3], [f64; 3], usize)> = Vec::new();
        for (i, line) in text.lines().enumerate() {
            let line_no = i + 1;
            let t = line.trim();
            if t.is_empty() || t.starts_with('#') {
                continue;
            }
            let cols: Vec<&str> = t.split_whitespace().collect();
            if cols.len() != 6 {
                return Err(format!(
                    "{name}:{line_no}: {} columns; a field map's rows are x y z (mm) Bx By Bz (T)",
                    cols.len()
                )
                .into());
            }
            let mut v = [0.0; 6];
            for (k, c) in cols.iter().enumerate() {
                v[k] = c
                    .parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| {
                        format!(
                            "{name}:{line_no}: column {} is `{c}`, not a finite number",
                            k + 1
                        )
                    })?;
            }
            rows.push(([v[0], v[1], v[2]], [v[3], v[4], v[5]], line_no));
            if rows.len() > MAX_NODES {
                return Err(format!("{name}: more than {MAX_NODES} rows").into());
            }
        }
        if rows.is_empty() {
            return Err(format!("{name}: no rows (x y z Bx By Bz)").into());
        }
        let mut origin = [0.0; 3];
        let mut spacing = [0.0; 3];
        let mut nodes = [0usize; 3];
        for axis in 0..3 {
            let (o, s, n) = axis_grid(name, &rows, axis)?;
            (origin[axis], spacing[axis], nodes[axis]) = (o, s, n);
        }
        let total = nodes[0].saturating_mul(nodes[1]).saturating_mul(nodes[2]);
        if total > 2 * rows.len() {
            return Err(format!(
                "{name}: the rows' coordinates span a grid of {} × {} × {} nodes, but the file has {} rows: most nodes are missing",
                nodes[0], nodes[1], nodes[2], rows.len()
            )
            .into());
        }
        let mut field = vec![[f64::NAN; 3]; total];
        let mut seen = vec![0usize; total];
        for (p, b, line_no) in &rows {
            let mut index = [0usize; 3];
            for axis in 0..3 {
                index[axis] = ((p[axis] - origin[axis]) / spacing[axis]).round() as usize;
            }
            let k = index[2] + nodes[2] * (index[1] + nodes[1] * index[0]);
            if seen[k] != 0 {
                return Err(format!(
                    "{name}:{line_no}: the node ({}, {}, {}) mm is also on line {}",
                    p[0], p[1], p[2], seen[k]
                )
                .into());
            }
            seen[k] = *line_no;
            field[k] = *b;
        }
        if let Some(k) = seen.iter().position(|&l| l == 0) {
            let missing = seen.iter().filter(|&&l| l == 0).count();
            let (iz, iy, ix) = (
                k % nodes[2],
                (k / nodes[2]) % nodes[1],
                k / (nodes[2] * nodes[1]),
            );
            let at = |axis: usize, i: usize| origin[axis] + i as f64 * spacing[axis];
            return Err(format!(
                "{name}: {missing} of the grid's {total} nodes ({} × {} × {}) are missing, the first at ({}, {}, {}) mm",
                nodes[0], nodes[1], nodes[2], at(0, ix), at(1, iy), at(2, iz)
            )
            .into());
        }
        let field = std::array::from_fn(|c| field.iter().map(|b| b[c]).collect());
        Ok(FieldMap {
            origin,
            spacing,
            nodes,
            field,
        })
    }

    /// The finest node spacing (mm): the default step of a path through it.
    pub fn finest_spacing(&self) -> f64 {
        self.spacing.iter().copied().fold(f64::INFINITY, f64::min)
    }

    /// The strongest field at any node (T): with trilinear interpolation, the
    /// strongest anywhere in the map.
    pub fn peak_tesla(&self) -> f64 {
        let [x, y, z] = &self.field;
        (x.iter().zip(y).zip(z))
            .map(|((x, y), z)| DVec3::new(*x, *y, *z).length())
            .fold(0.0, f64::max)
    }

    /// The largest field component at any node (T): what a message names
    /// when |B| itself overflows.
    pub fn peak_component_tesla(&self) -> f64 {
        self.field
            .iter()
            .flatten()
            .map(|c| c.abs())
            .fold(0.0, f64::max)
    }

    /// The grid's far corner (largest x, y, z), mm.
    pub fn end(&self) -> [f64; 3] {
        std::array::from_fn(|a| self.origin[a] + (self.nodes[a] - 1) as f64 * self.spacing[a])
    }

    /// B (T) at `p` (mm, the map's frame), trilinear between the nodes; `None`
    /// outside the grid.
    #[inline]
    pub fn at(&self, p: [f64; 3]) -> Option<[f64; 3]> {
        self.at_grid(self.to_grid(p))
    }

    /// `p` (mm) in grid units: node i of each axis at i.
    #[inline]
    pub fn to_grid(&self, p: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|a| (p[a] - self.origin[a]) / self.spacing[a])
    }

    /// A vector (mm) in grid units.
    #[inline]
    pub fn vector_to_grid(&self, v: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|a| v[a] / self.spacing[a])
    }

    /// B (T) at the point `u` in grid units (a path steps through them
    /// without a division per sample); `None` outside the grid.
    #[inline]
    pub fn at_grid(&self, u: [f64; 3]) -> Option<[f64; 3]> {
        let mut cell = [0usize; 3];
        let mut f = [0.0; 3];
        for a in 0..3 {
            let last = (self.nodes[a] - 1) as f64;
            // A point on the grid's face, computed a rounding error outside
            // (a path's last sample on the bore's end plane), is on it.
            let raw = u[a];
            if !(raw >= -1e-9 && raw <= last + 1e-9) {
                return None;
            }
            let u = raw.clamp(0.0, last);
            let i = (u as usize).min(self.nodes[a] - 2);
            cell[a] = i;
            f[a] = u - i as f64;
        }
        // Strides: z 1, y nz, x nz·ny.
        let (sy, sx) = (self.nodes[2], self.nodes[2] * self.nodes[1]);
        let k = cell[2] + sy * cell[1] + sx * cell[0];
        let mut b = [0.0; 3];
        for (v, out) in self.field.iter().zip(&mut b) {
            let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
            let z00 = lerp(v[k], v[k + 1], f[2]);
            let z10 = lerp(v[k + sy], v[k + sy + 1], f[2]);
            let z01 = lerp(v[k + sx], v[k + sx + 1], f[2]);
            let z11 = lerp(v[k + sx + sy], v[k + sx + sy + 1], f[2]);
            *out = lerp(lerp(z00, z10, f[1]), lerp(z01, z11, f[1]), f[0]);
        }
        Some(b)
    }
}

/// The first sample after `k` (at most `n`) whose grid coordinate
/// u0 + j du has left the cell [i, i + 1] it starts in.
fn run_end(k: usize, n: usize, (u0, du): (f64, f64), i: usize) -> usize {
    let edge = match du.partial_cmp(&0.0) {
        Some(std::cmp::Ordering::Greater) => (i as f64 + 1.0 - u0) / du,
        Some(std::cmp::Ordering::Less) => (i as f64 - u0) / du,
        _ => return n,
    };
    // Samples j < edge lie inside; one exactly on the far side is in the
    // next cell (either cell interpolates it alike).
    let last_inside = edge.ceil().max(k as f64 + 1.0);
    (last_inside.min(n as f64)) as usize
}

/// One run of a line's samples inside one x–y cell, on consecutive z node
/// planes: the grid coordinates step linearly with the sample's number j,
/// x = x.0 + x.1 j, the fraction into the cell is x − x.2 (the cell's first
/// node), and each sample is bilinear between
/// the cell's four z columns.
struct Run {
    x: (f64, f64, f64),
    y: (f64, f64, f64),
    rows: [[f64; 3]; 2],
}

impl Run {
    /// Fills `out` with the projected field on the columns' planes in their
    /// order: sample t of `out` is the path's sample j = j0 + sign t
    /// (`sign` −1 for a path stepping down z; the caller then reverses the
    /// run). The columns are slices of `out`'s length and the loop carries no
    /// index checks and runs forward in memory, so that the compiler computes
    /// samples side by side: it is the whole cost of a path through a map.
    #[inline(always)]
    fn sample(&self, columns: [[&[f64]; 4]; 3], (j0, sign): (f64, f64), out: &mut [[f64; 2]]) {
        let n = out.len();
        let [[x00, x01, x10, x11], [y00, y01, y10, y11], [z00, z01, z10, z11]] = columns;
        let (x00, x01, x10, x11) = (&x00[..n], &x01[..n], &x10[..n], &x11[..n]);
        let (y00, y01, y10, y11) = (&y00[..n], &y01[..n], &y10[..n], &y11[..n]);
        let (z00, z01, z10, z11) = (&z00[..n], &z01[..n], &z10[..n], &z11[..n]);
        let (numbers, out) = (&PLANE_NUMBERS[..n], &mut out[..n]);
        let [r0, r1] = self.rows;
        for t in 0..n {
            let j = j0 + sign * numbers[t];
            let fx = self.x.0 + self.x.1 * j - self.x.2;
            let fy = self.y.0 + self.y.1 * j - self.y.2;
            let (w00, w01, w10, w11) = (
                (1.0 - fx) * (1.0 - fy),
                (1.0 - fx) * fy,
                fx * (1.0 - fy),
                fx * fy,
            );
            let bx = w00 * x00[t] + w01 * x01[t] + w10 * x10[t] + w11 * x11[t];
            let by = w00 * y00[t] + w01 * y01[t] + w10 * y10[t] + w11 * y11[t];
            let bz = w00 * z00[t] + w01 * z01[t] + w10 * z10[t] + w11 * z11[t];
            out[t] = [
                r0[0] * bx + r0[1] * by + r0[2] * bz,
                r1[0] * bx + r1[1] * by + r1[2] * bz,
            ];
        }
    }
}

/// 0, 1, 2, … as floats: the sample numbers of a run, read rather than
/// converted from integers so that the run's loop has nothing but
/// arithmetic on arrays. A run is at most this long (a longer one is cut).
static PLANE_NUMBERS: [f64; 512] = {
    let mut n = [0.0; 512];
    let mut i = 0;
    while i < 512 {
        n[i] = i as f64;
        i += 1;
    }
    n
};

impl FieldMap {
    /// B (T) projected on the two map-frame vectors `rows` (B · rows[0],
    /// B · rows[1]) at the `n` points u0 + k du (grid units, k = 0 … n − 1),
    /// appended to `out`; a point outside the grid counts as no field.
    ///
    /// A line that steps from node plane to node plane along z (|du_z| = 1,
    /// u0 on a plane: a path along the bore's axis sampled at the map's
    /// spacing, BabyIAXO's case) needs no z interpolation: each sample is
    /// bilinear in x, y between four of the map's z columns, exactly what the
    /// trilinear interpolation gives there, at half its cost.
    pub fn sample_line(
        &self,
        (u0, du): ([f64; 3], [f64; 3]),
        n: usize,
        rows: [[f64; 3]; 2],
        out: &mut Vec<[f64; 2]>,
    ) {
        let project = |b: [f64; 3]| {
            [
                rows[0][0] * b[0] + rows[0][1] * b[1] + rows[0][2] * b[2],
                rows[1][0] * b[0] + rows[1][1] * b[1] + rows[1][2] * b[2],
            ]
        };
        let on_planes = (du[2].abs() - 1.0).abs() < 1e-9 && (u0[2] - u0[2].round()).abs() < 1e-9;
        if !on_planes {
            out.extend((0..n).map(|k| {
                let u = std::array::from_fn(|a| u0[a] + du[a] * k as f64);
                self.at_grid(u).map_or([0.0; 2], project)
            }));
            return;
        }
        let (nz, ny) = (self.nodes[2], self.nodes[1]);
        let z0 = u0[2].round() as i64;
        let dz = du[2].signum() as i64;
        out.reserve(n);
        // The samples come in runs within one x–y cell (a path nearly along
        // z crosses few cells' sides): the cell is found once per run, the
        // fractions step linearly within it.
        let mut k = 0;
        while k < n {
            let kf = k as f64;
            let z = z0 + dz * k as i64;
            let (cx, cy) = (
                self.cell(0, u0[0] + du[0] * kf),
                self.cell(1, u0[1] + du[1] * kf),
            );
            let (Some((ix, _)), Some((iy, _)), true) = (cx, cy, (0..nz as i64).contains(&z)) else {
                out.push([0.0; 2]);
                k += 1;
                continue;
            };
            let end = run_end(k, n, (u0[0], du[0]), ix)
                .min(run_end(k, n, (u0[1], du[1]), iy))
                .min(match dz > 0 {
                    true => (nz as i64 - z0).max(0) as usize,
                    false => (z0 + 1).max(0) as usize,
                });
            let end = end.max(k + 1).min(k + PLANE_NUMBERS.len());
            let base = nz * (iy + ny * ix);
            // The four z columns of the cell's corners over the run's planes,
            // walked in the path's direction.
            let (za, zb) = match dz > 0 {
                true => (z as usize, z as usize + (end - k)),
                false => (z as usize + 1 - (end - k), z as usize + 1),
            };
            let corners = [base, base + nz, base + nz * ny, base + nz * ny + nz];
            let columns = self
                .field
                .each_ref()
                .map(|v| corners.map(|c| &v[c + za..c + zb]));
            let start = out.len();
            out.resize(start + (end - k), [0.0; 2]);
            let run = Run {
                x: (u0[0], du[0], ix as f64),
                y: (u0[1], du[1], iy as f64),
                rows,
            };
            let samples = &mut out[start..];
            if dz > 0 {
                run.sample(columns, (k as f64, 1.0), samples);
            } else {
                run.sample(columns, ((end - 1) as f64, -1.0), samples);
                samples.reverse();
            }
            k = end;
        }
    }

    /// The cell along `axis` holding the grid coordinate `u` and the fraction
    /// into it, as [`FieldMap::at_grid`] takes them; `None` outside.
    #[inline]
    fn cell(&self, axis: usize, u: f64) -> Option<(usize, f64)> {
        let last = (self.nodes[axis] - 1) as f64;
        if !(u >= -1e-9 && u <= last + 1e-9) {
            return None;
        }
        let u = u.clamp(0.0, last);
        let i = (u as usize).min(self.nodes[axis] - 2);
        Some((i, u - i as f64))
    }
}

/// One axis of the grid: its first node, spacing and node count, from the
/// rows' coordinates; refuses coordinates off a regular grid (naming a row).
fn axis_grid(
    name: &str,
    rows: &[([f64; 3], [f64; 3], usize)],
    axis: usize,
) -> Result<(f64, f64, usize), FieldMapError> {
    const XYZ: [&str; 3] = ["x", "y", "z"];
    // Distinct values (to 1e-9 mm) with the first line each appears on.
    let mut values: BTreeMap<i64, (f64, usize)> = BTreeMap::new();
    for (p, _, line_no) in rows {
        values
            .entry((p[axis] * 1e9).round() as i64)
            .or_insert((p[axis], *line_no));
    }
    let v: Vec<(f64, usize)> = values.into_values().collect();
    if v.len() == 1 {
        return Err(format!(
            "{name}: every row has {} = {} mm: a field map is a 3-D grid with at least 2 nodes along x, y and z",
            XYZ[axis], v[0].0
        )
        .into());
    }
    // The spacing is the commonest gap between neighbouring values (the
    // smallest of the commonest): one stray value then stands out as off it.
    let mut gaps: BTreeMap<i64, (usize, f64)> = BTreeMap::new();
    for w in v.windows(2) {
        let gap = w[1].0 - w[0].0;
        gaps.entry((gap * 1e6).round() as i64).or_insert((0, gap)).0 += 1;
    }
    let most = gaps.values().map(|g| g.0).max().unwrap_or(0);
    let spacing = gaps.values().find(|g| g.0 == most).map_or(1.0, |g| g.1);
    let origin = v[0].0;
    for &(x, line_no) in &v {
        let k = (x - origin) / spacing;
        if (k - k.round()).abs() > 1e-6 {
            return Err(format!(
                "{name}:{line_no}: {} = {x} mm is off the regular grid of the file's other {} values (from {origin} mm every {spacing} mm): a field map must be a regular grid",
                XYZ[axis], XYZ[axis]
            )
            .into());
        }
    }
    let nodes = ((v[v.len() - 1].0 - origin) / spacing).round() as usize + 1;
    Ok((origin, spacing, nodes))
}
