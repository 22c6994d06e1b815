//! A published sensitivity curve read from a file, to draw beside the
//! combined curve of a campaign (`traxer reach --reference FILE`): two
//! numbers per line, m_a (eV) and the limit on the coupling (GeV⁻¹),
//! whitespace- or comma-separated, `#` comments and blank lines skipped.
//!
//! Data flow: `cli::campaign_reach` reads it with [`read_reference_curve`];
//! `output::campaign_reach` draws it in `reach.png` and names it in
//! `reach.json`.

use std::path::Path;

/// A reference curve: its name (the file's stem) and its points, ascending
/// in mass.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceCurve {
    pub label: String,
    pub file: String,
    pub points: Vec<(f64, f64)>,
}

message_error!(
    /// A reference-curve file that cannot be read, naming the file and line.
    ReferenceCurveError
);

/// Reads the reference curve in `path`: refuses a line that is not two
/// positive finite numbers, masses that do not ascend, or a file without
/// points, naming the line.
pub fn read_reference_curve(path: &Path) -> Result<ReferenceCurve, ReferenceCurveError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| ReferenceCurveError(format!("{name}: cannot read it: {e}")))?;
    let mut points: Vec<(f64, f64)> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        let numbers: Option<Vec<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
        let at = |what: &str| ReferenceCurveError(format!("{name}:{}: {what}", i + 1));
        let (m, g) = match numbers.as_deref() {
            Some([m, g]) if m.is_finite() && g.is_finite() && *m > 0.0 && *g > 0.0 => (*m, *g),
            _ => {
                return Err(at(&format!(
                    "`{line}`: two positive numbers expected, m_a (eV) and the limit (GeV⁻¹)"
                )))
            }
        };
        if let Some(&(last, _)) = points.last() {
            if m <= last {
                return Err(at(&format!(
                    "m_a = {m} eV after {last} eV: the masses must ascend"
                )));
            }
        }
        points.push((m, g));
    }
    if points.is_empty() {
        return Err(ReferenceCurveError(format!(
            "{name}: no points (two numbers per line: m_a (eV) and the limit (GeV⁻¹))"
        )));
    }
    let label = path
        .file_stem()
        .map_or(name.clone(), |s| s.to_string_lossy().into_owned());
    Ok(ReferenceCurve {
        label,
        file: name,
        points,
    })
}
