//! The grid of a reflectivity table, sized to its coating: the nodes in energy
//! and the step in x = E sin θ are refined until interpolating between them
//! reproduces the exact Parratt value within [`CHECK_TOLERANCE`] at the middle
//! of every cell, and no finer. `table.rs` calls [`build_grid`] and keeps the
//! result.
//!
//! Why x = E sin θ (keV; the momentum transfer is q = 4π x / hc) and not θ: a
//! coating's features sit at fixed q, not at fixed angle. The critical knee is
//! at x_c = E √(2δ), nearly the same at every energy away from absorption edges
//! (δ ∝ λ²), and the Kiessig and Bragg fringes of a stack of thickness D repeat
//! every hc / 2D in x at every energy. So on an (E, x) grid, R changes along E
//! only as the optical constants do (smoothly between the tables' nodes), and
//! each row takes the x step its own energy needs; an (E, θ) grid needs fine
//! angles at high energies (narrow fringes) times fine energies at large angles
//! (fringes in energy) everywhere. XMM's 250 nm of gold over 0.1–15 keV took
//! 17 000 angles × 6 800 energies (470 MB) under the old fixed rule in θ; this
//! grid takes 2.2 MB, each LLNL multilayer 7–8 MB.
//!
//! * x: each row has its own uniform step (a lookup is a division, not a
//!   search), from x_c / 15 halved until Catmull–Rom between the nodes is within
//!   the tolerance at every cell's middle. A halving reuses the middles just
//!   computed as the new nodes. Row i covers x up to E_i · [`ROW_REACH`] ·
//!   sin θ_max, and consecutive energies differ by less than that factor, so
//!   both rows around any energy in the table cover every x ≤ E sin θ_max.
//! * Energies: the scattering-factor tables' own energy nodes are nodes (the
//!   optical constants bend there and jump at absorption edges; a node on each
//!   side of an edge makes the edge exact), with a geometric start between
//!   them; then each cell is checked at its middle (a whole row) and halved
//!   until linear interpolation holds there. Between the optical nodes R is
//!   smooth in E, so a middle that holds speaks for its cell.
//!
//! Checking at the middles of cells in both directions bounds the error between
//! the nodes in practice: the random-point test in tests/it/xray.rs holds every
//! shipped coating to 1e-4 over whole tables.

use super::coating::Coating;
use super::elements::scattering_table;
use super::optical::EnergyOutOfRange;
use super::parratt::reflectance;
use rayon::prelude::*;

/// The largest |R_interpolated − R_exact| the middle of a row's cell may show.
pub const CHECK_TOLERANCE: f64 = 3e-5;

/// The largest error of interpolating in energy at the middle of an energy
/// cell, measured at the nodes of the exact middle row (so it includes both
/// neighbours' interpolation in x): with the row's own 3e-5 between its nodes,
/// below the 1e-4 the tables promise.
pub const ENERGY_TOLERANCE: f64 = 6e-5;

/// How far beyond its own E sin θ_max each row reaches, and the largest ratio
/// of consecutive energy nodes.
pub const ROW_REACH: f64 = 1.25;

/// Cells narrower than this (keV) are not split at their middle: R is smooth
/// between the scattering tables' nodes, so only a failure of the refinement
/// itself would get here.
const MIN_CELL_KEV: f64 = 1e-6;

/// Halvings of the x step at most (x_c / 15 / 2¹⁴: far below any fringe of a
/// coating thinner than 10 µm).
const MAX_HALVINGS: u32 = 14;

/// One energy's row: R at x = 0, step, 2·step, … .
#[derive(Clone, Debug)]
pub struct Row {
    pub x_step: f64,
    pub values: Vec<f32>,
}

impl Row {
    /// R at `x` (keV) by Catmull–Rom between the nodes; `x` within the row.
    #[inline]
    pub fn at(values: &[f32], x_step: f64, x: f64) -> f64 {
        let fx = x / x_step;
        // Rows cover every x of their cells; the clamp only guards rounding.
        let j = (fx as usize).min(values.len() - 2);
        interpolate_in_x(values, j, fx - j as f64)
    }

    /// The largest x (keV) the row holds.
    fn reach(&self) -> f64 {
        (self.values.len() - 1) as f64 * self.x_step
    }
}

/// A table's grid and its values.
pub struct Grid {
    pub energies: Vec<f64>,
    pub rows: Vec<Row>,
}

/// R of one coating along rows of x at fixed energy.
struct Rows<'a> {
    coating: &'a Coating,
    sin_theta_max: f64,
    /// The coarsest x step a row starts from (keV).
    first_step: f64,
}

impl Rows<'_> {
    /// R at x = `first`, `first + 2`, … (in units of `half_step`), `count`
    /// values: the nodes (first = 0, half_step = step/2) or the middles of the
    /// cells (first = 1) of a grid with step 2·half_step. Both spell x as an odd
    /// or even multiple of the half step, so that the middles become nodes of
    /// the halved grid with the same bits.
    fn at(&self, e: f64, first: usize, count: usize, half_step: f64) -> Vec<f64> {
        let (layers, sub) = self.coating.layers_at(e).expect("range checked");
        let sigma = self.coating.stack.substrate_roughness_nm;
        (0..count)
            .map(|j| {
                let theta = ((first + 2 * j) as f64 * half_step / e).asin();
                reflectance(e, theta, &layers, sub, sigma).unpolarised()
            })
            .collect()
    }

    /// The row at energy `e`, out to x = e · ROW_REACH · sin θ_max, its step
    /// halved until Catmull–Rom holds at every cell's middle (each halving
    /// takes the middles just computed as its new nodes).
    fn row(&self, e: f64) -> Row {
        let mut step = self.first_step;
        let n = (e * ROW_REACH * self.sin_theta_max / step).ceil() as usize + 2;
        let mut values: Vec<f32> = self
            .at(e, 0, n, 0.5 * step)
            .into_iter()
            .map(|r| r as f32)
            .collect();
        for _ in 0..MAX_HALVINGS {
            let middles = self.at(e, 1, values.len() - 1, 0.5 * step);
            let worst = middles
                .iter()
                .enumerate()
                .map(|(j, &m)| (interpolate_in_x(&values, j, 0.5) - m).abs())
                .fold(0.0, f64::max);
            if worst <= CHECK_TOLERANCE {
                break;
            }
            let mut finer = Vec::with_capacity(2 * values.len() - 1);
            for (j, &r) in values.iter().enumerate() {
                finer.push(r);
                if let Some(&m) = middles.get(j) {
                    finer.push(m as f32);
                }
            }
            values = finer;
            step *= 0.5;
        }
        Row {
            x_step: step,
            values,
        }
    }
}

/// R between nodes j and j + 1 of `row` at fraction `t`: Catmull–Rom through
/// nodes j − 1 … j + 2, linear in the first and last cells. The one formula of
/// both the lookup and the check.
#[inline]
pub fn interpolate_in_x(row: &[f32], j: usize, t: f64) -> f64 {
    let (p1, p2) = (row[j] as f64, row[j + 1] as f64);
    if j == 0 || j + 2 >= row.len() {
        return p1 + (p2 - p1) * t;
    }
    let (p0, p3) = (row[j - 1] as f64, row[j + 2] as f64);
    let (t2, t3) = (t * t, t * t * t);
    0.5 * (2.0 * p1
        + (p2 - p0) * t
        + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2
        + (3.0 * p1 - p0 - 3.0 * p2 + p3) * t3)
}

/// The grid of `coating` for energies e_min … e_max (keV) and grazing angles
/// 0 … θ_max.
pub fn build_grid(
    coating: &Coating,
    e_min: f64,
    e_max: f64,
    theta_max: f64,
) -> Result<Grid, EnergyOutOfRange> {
    let rows = Rows {
        coating,
        sin_theta_max: theta_max.sin(),
        first_step: critical_x(coating, e_min, e_max)? / 15.0,
    };
    assert!(
        ROW_REACH * rows.sin_theta_max < 1.0,
        "θ_max {theta_max} rad: rows would reach beyond normal incidence"
    );
    // The optical constants' own nodes are nodes too: R bends sharply there
    // (and jumps at absorption edges), which a check at a cell's middle can miss.
    let mut start = geometric(e_min, e_max, 16);
    if start.len() > 1 {
        start.extend(optical_nodes(coating, e_min, e_max));
        start.sort_by(f64::total_cmp);
        start.dedup();
    }
    let mut nodes: Vec<(f64, Row)> = start.par_iter().map(|&e| (e, rows.row(e))).collect();
    let mut pending: Vec<(f64, f64)> = start.windows(2).map(|w| (w[0], w[1])).collect();
    while !pending.is_empty() {
        let row_of = |e: f64| &nodes[nodes.partition_point(|(x, _)| *x < e)].1;
        // Each pending cell's middle row, exact, against the interpolation; a
        // cell that fails is split there (its middle row becomes a node), and
        // its halves are checked next. Between the optical constants' nodes R
        // is smooth in E, so a cell whose middle holds is whole.
        let splits: Vec<Option<(f64, Row)>> = pending
            .par_iter()
            .map(|&(lo, hi)| {
                let mid = 0.5 * (lo + hi);
                let exact = rows.row(mid);
                let worst = energy_error(row_of(lo), row_of(hi), (mid - lo) / (hi - lo), &exact);
                if worst <= ENERGY_TOLERANCE {
                    return None;
                }
                (hi - lo > MIN_CELL_KEV).then_some((mid, exact))
            })
            .collect();
        let mut next = Vec::new();
        for (&(lo, hi), split) in pending.iter().zip(splits) {
            if let Some((e, row)) = split {
                next.push((lo, e));
                next.push((e, hi));
                nodes.push((e, row));
            }
        }
        nodes.sort_by(|a, b| a.0.total_cmp(&b.0));
        pending = next;
    }
    let (energies, rows) = nodes.into_iter().unzip();
    Ok(Grid { energies, rows })
}

/// The worst |interpolated − exact| at the nodes of the row `exact` (in the
/// reach of the lower row `a`), interpolating between rows `a` and `b` with
/// weight `w` on `b`.
fn energy_error(a: &Row, b: &Row, w: f64, exact: &Row) -> f64 {
    let reach = a.reach();
    exact
        .values
        .iter()
        .enumerate()
        .map(|(j, &r)| (j as f64 * exact.x_step, r as f64))
        .take_while(|&(x, _)| x <= reach)
        .map(|(x, r)| {
            let lerp =
                Row::at(&a.values, a.x_step, x) * (1.0 - w) + Row::at(&b.values, b.x_step, x) * w;
            (lerp - r).abs()
        })
        .fold(0.0, f64::max)
}

/// `cells + 1` energies from e_min to e_max in equal ratios (never more than
/// [`ROW_REACH`] apart), or e_min alone for a line.
fn geometric(e_min: f64, e_max: f64, cells: usize) -> Vec<f64> {
    if e_max <= e_min {
        return vec![e_min];
    }
    let ratio = e_max / e_min;
    let n = cells.max((ratio.ln() / ROW_REACH.ln()).ceil() as usize);
    let mut e: Vec<f64> = (0..=n)
        .map(|i| e_min * ratio.powf(i as f64 / n as f64))
        .collect();
    (e[0], e[n]) = (e_min, e_max);
    e
}

/// The energies (keV) strictly between e_min and e_max at which the coating's
/// materials' scattering-factor tables have nodes, ascending.
fn optical_nodes(coating: &Coating, e_min: f64, e_max: f64) -> Vec<f64> {
    let stack = &coating.stack;
    let mut nodes: Vec<f64> = stack
        .layers
        .iter()
        .map(|l| l.material.as_ref())
        .chain([&stack.substrate])
        .flat_map(|m| {
            m.composition
                .moles_per_gram
                .iter()
                .flat_map(|&(z, _)| scattering_table(m.constants, z).energy_kev.iter().copied())
        })
        .filter(|&e| e > e_min && e < e_max)
        .collect();
    nodes.sort_by(f64::total_cmp);
    nodes.dedup();
    nodes
}

/// The smallest x_c = E √(2δ) (keV) of the coating's densest material at
/// either end of the energy range: where R falls off its plateau.
fn critical_x(coating: &Coating, e_min: f64, e_max: f64) -> Result<f64, EnergyOutOfRange> {
    let stack = &coating.stack;
    let mut x_c = f64::INFINITY;
    for e in [e_min, e_max] {
        let mut delta_max: f64 = 0.0;
        for m in stack
            .layers
            .iter()
            .map(|l| l.material.as_ref())
            .chain([&stack.substrate])
        {
            delta_max = delta_max.max(m.delta_beta(e)?.0);
        }
        x_c = x_c.min(e * (2.0 * delta_max).sqrt());
    }
    Ok(x_c)
}
