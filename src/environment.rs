//! What the library takes from the process's environment, in one place: the
//! folder of the reflectivity-table cache and its bound (read by
//! `xray::table_cache`, shown by `traxer cache`). Nothing else in the library
//! reads environment variables; the physics modules ask here. Uses none.

use std::path::PathBuf;

/// The reflectivity cache's folder: `TRAXER_CACHE` if set (`off` or empty:
/// no cache, `None`), else `$XDG_CACHE_HOME/traxer`, else `~/.cache/traxer`;
/// the tables go in its `reflectivity/`. `None` also when no home is known.
pub fn reflectivity_cache_dir() -> Option<PathBuf> {
    let root = match std::env::var_os("TRAXER_CACHE") {
        Some(v) if v == "off" || v.is_empty() => return None,
        Some(v) => PathBuf::from(v),
        None => match std::env::var_os("XDG_CACHE_HOME").filter(|v| !v.is_empty()) {
            Some(x) => PathBuf::from(x).join("traxer"),
            None => PathBuf::from(std::env::var_os("HOME")?)
                .join(".cache")
                .join("traxer"),
        },
    };
    Some(root.join("reflectivity"))
}

/// The default bound of the cache folder (MB).
pub const DEFAULT_CACHE_MAX_MB: f64 = 4000.0;

/// The cache's bound in bytes: `TRAXER_CACHE_MAX_MB` if it is a number ≥ 0,
/// else [`DEFAULT_CACHE_MAX_MB`].
pub fn reflectivity_cache_bytes() -> u64 {
    let mb = std::env::var("TRAXER_CACHE_MAX_MB")
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|v| v.is_finite() && *v >= 0.0)
        .unwrap_or(DEFAULT_CACHE_MAX_MB);
    (mb * 1e6) as u64
}

/// Why the environment's settings cannot be taken as given: a
/// `TRAXER_CACHE_MAX_MB` that is not a number of MB ≥ 0, or a `TRAXER_CACHE`
/// that names something other than a folder. The front ends refuse to start
/// on it, where the library would otherwise fall back to its defaults
/// without a word.
pub fn check() -> Result<(), String> {
    if let Ok(v) = std::env::var("TRAXER_CACHE_MAX_MB") {
        if !v
            .trim()
            .parse::<f64>()
            .is_ok_and(|x| x.is_finite() && x >= 0.0)
        {
            return Err(format!(
                "TRAXER_CACHE_MAX_MB={v}: the reflectivity cache's bound is a number of MB ≥ 0 (unset: {DEFAULT_CACHE_MAX_MB} MB)"
            ));
        }
    }
    if let Some(v) = std::env::var_os("TRAXER_CACHE").filter(|v| v != "off" && !v.is_empty()) {
        let p = PathBuf::from(&v);
        if p.exists() && !p.is_dir() {
            return Err(format!(
                "TRAXER_CACHE={}: not a folder (the reflectivity cache is a folder; `off` turns it off)",
                p.display()
            ));
        }
    }
    Ok(())
}
