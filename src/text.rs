//! Numbers in messages, as a physicist reads them: a value a user gave
//! (1e-200, 0.5, 3e14) printed plainly where that is short and in exponent form
//! otherwise — never Rust's full decimal expansion of a tiny or huge double,
//! which runs to hundreds of digits. A leaf: used by every layer, uses none.

/// `x` for a message: plain for 1e-4 ≤ |x| < 1e6 (and 0), else as 1.5e-200;
/// the shortest digits that read back as `x` either way.
pub fn number(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || !x.is_finite() || (1e-4..1e6).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::number;

    #[test]
    fn numbers_stay_short_and_exact() {
        assert_eq!(number(-0.5), "-0.5");
        assert_eq!(number(0.0), "0");
        assert_eq!(number(1e-200), "1e-200");
        assert_eq!(number(3e14), "3e14");
        assert_eq!(number(123456.0), "123456");
        assert_eq!(number(f64::NAN), "NaN");
        assert_eq!(number(1e-200).parse::<f64>().unwrap(), 1e-200);
    }
}
