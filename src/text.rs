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

/// `x` with four decimals where that is short (|x| < 1e6), else in exponent
/// form with four: a radius of 1e300 mm is not printed in 305 characters.
pub fn four_decimals(x: f64) -> String {
    if x.abs() < 1e6 || !x.is_finite() {
        format!("{x:.4}")
    } else {
        format!("{x:.4e}")
    }
}

/// `s` cut to about `max` characters for a message: the start, how many
/// characters were left out, and the end (a 100 000-character value is not
/// echoed whole).
pub fn shorten(s: &str, max: usize) -> String {
    let n = s.chars().count();
    if n <= max {
        return s.to_string();
    }
    let head: String = s.chars().take(max * 2 / 3).collect();
    let tail: String = s.chars().skip(n - max / 6).collect();
    format!("{head}…({} characters)…{tail}", n - max * 2 / 3 - max / 6)
}

/// `s` with every word (a run without spaces) longer than `max` characters
/// shortened ([`shorten`]): for messages that quote what a user gave.
pub fn shorten_words(s: &str, max: usize) -> String {
    if s.len() <= max {
        return s.to_string();
    }
    s.split(' ')
        .map(|w| shorten(w, max))
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::{number, shorten, shorten_words};

    #[test]
    fn long_words_are_cut_in_the_middle() {
        assert_eq!(shorten("abc", 10), "abc");
        let long = "1".repeat(1000);
        let s = shorten_words(&format!("value \"{long}\" refused"), 120);
        assert!(
            s.starts_with("value \"111") && s.ends_with("11\" refused"),
            "{s}"
        );
        assert!(s.contains("characters)") && s.len() < 200, "{s}");
    }

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
