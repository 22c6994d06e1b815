//! `traxer cache`: the reflectivity tables kept on disk, listed or cleared.

use serde_json::json;
use traxer::xray::table_cache::{cache_dir, cached_tables, clear_tables, size_limit_bytes};

/// List the reflectivity tables traxer keeps on disk, or clear them.
///
/// Scene builds keep each coating's reflectivity table (its R(E, θ) grid) in
/// the cache folder so that the next build of the same coating and energy
/// range reads it instead of computing it: TRAXER_CACHE if set (off: no
/// cache), else $XDG_CACHE_HOME/traxer, else ~/.cache/traxer, in its
/// reflectivity/. Lists each table file with its size and when it was last
/// used, most recent first, and the total; --clear removes them (a table is
/// rebuilt when a scene needs it again). Other files in the folder are left
/// alone. The folder is bounded by TRAXER_CACHE_MAX_MB (default 4000): a build
/// that writes a table removes the least recently used others beyond it.
#[derive(clap::Args)]
pub struct CacheArgs {
    /// Remove every table file.
    #[arg(long)]
    pub clear: bool,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub quiet: super::args::QuietArg,
}

pub fn run(a: CacheArgs) -> anyhow::Result<()> {
    let Some(dir) = cache_dir() else {
        say!("the cache is off (TRAXER_CACHE=off, or no home folder): nothing is kept");
        return Ok(());
    };
    let mb = |b: u64| b as f64 / 1e6;
    if a.clear {
        let (n, bytes) = clear_tables(&dir)?;
        say!(
            "removed {n} table file{} ({:.0} MB) from {}",
            if n == 1 { "" } else { "s" },
            mb(bytes),
            dir.display()
        );
        return Ok(());
    }
    let tables = cached_tables(&dir)?;
    let total: u64 = tables.iter().map(|t| t.bytes).sum();
    let age = |t: &std::time::SystemTime| t.elapsed().map_or(0.0, |d| d.as_secs_f64() / 3600.0);
    if a.json {
        let files: Vec<_> = tables
            .iter()
            .map(|t| json!({"file": t.path, "mb": mb(t.bytes), "hours_since_used": age(&t.last_used)}))
            .collect();
        say!(
            "{}",
            serde_json::to_string_pretty(
                &json!({"folder": dir, "tables": files, "total_mb": mb(total), "bound_mb": mb(size_limit_bytes())})
            )?
        );
        return Ok(());
    }
    say!(
        "{}: {} reflectivity table{}, {:.0} MB (bound: {:.0} MB, TRAXER_CACHE_MAX_MB)",
        dir.display(),
        tables.len(),
        if tables.len() == 1 { "" } else { "s" },
        mb(total),
        mb(size_limit_bytes())
    );
    for t in &tables {
        let name = t.path.file_name().unwrap_or_default().to_string_lossy();
        say!(
            "  {name}  {:>8.1} MB  last used {:.1} h ago",
            mb(t.bytes),
            age(&t.last_used)
        );
    }
    Ok(())
}
