//! Chemical compositions: a formula ("Pt", "SiO2", "Ca(OH)2", "La1.9Sr0.1CuO4") or a
//! mixture of formulas by mass fraction (glasses such as Schott D 263), reduced to
//! moles of each element per gram — all the refractive index needs.

use super::elements::element;
use std::collections::BTreeMap;

/// Moles of each element (by Z) per gram of material.
#[derive(Clone, Debug, PartialEq)]
pub struct Composition {
    pub moles_per_gram: Vec<(u32, f64)>,
}

message_error!(
    /// A chemical formula or mixture that cannot be used.
    FormulaError
);

/// Atoms per formula unit, by element symbol.
pub fn parse_formula(formula: &str) -> Result<BTreeMap<String, f64>, FormulaError> {
    let chars: Vec<char> = formula.chars().filter(|c| !c.is_whitespace()).collect();
    let mut pos = 0;
    let counts = parse_group(&chars, &mut pos, formula)?;
    if pos != chars.len() {
        return Err(FormulaError::from(format!(
            "formula `{formula}`: unexpected `{}`",
            chars[pos]
        )));
    }
    if counts.is_empty() {
        return Err(FormulaError::from(format!(
            "formula `{formula}` names no element"
        )));
    }
    Ok(counts)
}

fn parse_number(chars: &[char], pos: &mut usize) -> Option<f64> {
    let start = *pos;
    while *pos < chars.len() && (chars[*pos].is_ascii_digit() || chars[*pos] == '.') {
        *pos += 1;
    }
    (*pos > start)
        .then(|| chars[start..*pos].iter().collect::<String>().parse().ok())
        .flatten()
}

fn parse_group(
    chars: &[char],
    pos: &mut usize,
    formula: &str,
) -> Result<BTreeMap<String, f64>, FormulaError> {
    let mut counts = BTreeMap::new();
    while *pos < chars.len() {
        let c = chars[*pos];
        if c == ')' {
            break;
        }
        let part = if c == '(' {
            *pos += 1;
            let inner = parse_group(chars, pos, formula)?;
            if *pos >= chars.len() || chars[*pos] != ')' {
                return Err(FormulaError::from(format!(
                    "formula `{formula}`: unclosed `(`"
                )));
            }
            *pos += 1;
            inner
        } else if c.is_ascii_uppercase() {
            let mut sym = c.to_string();
            *pos += 1;
            while *pos < chars.len() && chars[*pos].is_ascii_lowercase() {
                sym.push(chars[*pos]);
                *pos += 1;
            }
            if element(&sym).is_none() {
                return Err(FormulaError::from(format!(
                    "formula `{formula}`: unknown element `{sym}` (H … U)"
                )));
            }
            BTreeMap::from([(sym, 1.0)])
        } else {
            return Err(FormulaError::from(format!(
                "formula `{formula}`: unexpected `{c}` (elements start with a capital letter)"
            )));
        };
        let n = if *pos < chars.len() && (chars[*pos].is_ascii_digit() || chars[*pos] == '.') {
            parse_number(chars, pos).ok_or_else(|| format!("formula `{formula}`: bad number"))?
        } else {
            1.0
        };
        if !(n > 0.0 && n.is_finite()) {
            return Err(FormulaError::from(format!(
                "formula `{formula}`: counts must be positive"
            )));
        }
        for (k, v) in part {
            *counts.entry(k).or_insert(0.0) += v * n;
        }
    }
    Ok(counts)
}

impl Composition {
    /// A pure compound.
    pub fn formula(formula: &str) -> Result<Composition, FormulaError> {
        Composition::mixture(&[(formula.to_string(), 1.0)])
    }

    /// A mixture of compounds by mass fraction; fractions are normalised to sum 1
    /// (they must already sum to 1 within 2 %, to catch typos).
    pub fn mixture(parts: &[(String, f64)]) -> Result<Composition, FormulaError> {
        let total: f64 = parts.iter().map(|p| p.1).sum();
        if parts.is_empty()
            || parts.iter().any(|p| p.1.is_nan() || p.1 <= 0.0)
            || (total - 1.0).abs() > 0.02
        {
            return Err(FormulaError::from(format!(
                "mass fractions must be positive and sum to 1 (they sum to {total})"
            )));
        }
        let mut moles: BTreeMap<u32, f64> = BTreeMap::new();
        for (formula, w) in parts {
            let atoms = parse_formula(formula)?;
            let molar_mass: f64 = atoms
                .iter()
                .map(|(s, n)| n * element(s).expect("checked").mass)
                .sum();
            for (s, n) in atoms {
                let z = element(&s).expect("checked").z;
                *moles.entry(z).or_insert(0.0) += (w / total) * n / molar_mass;
            }
        }
        Ok(Composition {
            moles_per_gram: moles.into_iter().collect(),
        })
    }
}
