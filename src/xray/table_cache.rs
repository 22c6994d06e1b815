//! A disk cache of reflectivity tables, so that building the same scene again
//! (a scan over a scene variable, a second Python session, the next shard) skips
//! the Parratt evaluations that dominate a CAST scene's build.
//!
//! Data flow: `scene::build` asks [`ReflectivityTable::cached`] for each
//! coating's table → the file named by the key is read if it exists and checks
//! out, else the table is built and written for next time.
//!
//! The key is the SHA-256 of everything the table depends on: the coating as
//! built (its layers, roughnesses, its materials' compositions and densities
//! and which table of optical constants they take, through `Debug`, which
//! prints each f64 exactly), the energy range and angle limit (their bits),
//! traxer's version, the source text of the modules that compute tables and the
//! text of the scattering-factor tables themselves. A change to any of them is a different file, never a stale
//! table. Each file ends with the SHA-256 of its contents; a damaged file is
//! rebuilt. Files are written atomically (a temporary file renamed), so runs
//! sharing the cache concurrently see a whole table or none, and two writers of
//! one key write the same bytes. Values are stored as their bits: a table read
//! back is the table built, and images are the same with or without the cache.
//!
//! The folder (`crate::environment`, where the library reads the environment):
//! `TRAXER_CACHE` if set (`off` disables the cache), else
//! `$XDG_CACHE_HOME/traxer`, else `~/.cache/traxer`; tables go in its
//! `reflectivity/`. A cache that cannot be written is skipped silently: it only
//! saves time. Reading a table marks it used (its modification time), so that
//! [`cached_tables`] can say when each was last used; `traxer cache` lists the
//! tables and clears them ([`clear_tables`]). The folder is bounded: after a
//! table is written, the least recently used others are removed until the
//! tables take at most `TRAXER_CACHE_MAX_MB` (default 4000 MB; the table just
//! written is kept even alone above it).

use super::coating::Coating;
use super::optical::EnergyOutOfRange;
use super::table::{ReflectivityTable, TableParts};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// The first bytes of a table file; bump the number when the layout changes.
const MAGIC: &[u8] = b"traxer reflectivity table 2\n";

/// The source of the modules whose code decides a table's values.
const TABLE_SOURCES: [&str; 7] = [
    include_str!("table.rs"),
    include_str!("table_grid.rs"),
    include_str!("parratt.rs"),
    include_str!("coating.rs"),
    include_str!("optical.rs"),
    include_str!("compound.rs"),
    include_str!("elements.rs"),
];

pub use crate::environment::reflectivity_cache_dir as cache_dir;

/// The digest of the table-making sources and the scattering-factor tables
/// (4 MB of text: hashed once per process, not once per table).
fn sources_digest() -> &'static [u8] {
    static DIGEST: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
    DIGEST.get_or_init(|| {
        let mut h = Sha256::new();
        for source in TABLE_SOURCES
            .into_iter()
            .chain(super::elements::table_files())
        {
            h.update(Sha256::digest(source.as_bytes()));
        }
        h.finalize().to_vec()
    })
}

/// The file of the table for these inputs.
fn key(coating: &Coating, e_min: f64, e_max: f64, theta_max: f64) -> String {
    let mut h = Sha256::new();
    h.update(MAGIC);
    h.update(env!("CARGO_PKG_VERSION").as_bytes());
    h.update(sources_digest());
    h.update(format!("{coating:?}").as_bytes());
    for x in [e_min, e_max, theta_max] {
        h.update(x.to_bits().to_le_bytes());
    }
    format!("{:x}", h.finalize())
}

impl ReflectivityTable {
    /// The table of [`ReflectivityTable::new`], read from the disk cache when
    /// it holds it; otherwise built, with a notice saying so (it takes
    /// seconds for a broad band), and stored for next time.
    pub fn cached(
        coating: &Coating,
        e_min: f64,
        e_max: f64,
        theta_max: f64,
    ) -> Result<ReflectivityTable, EnergyOutOfRange> {
        let path =
            cache_dir().map(|d| d.join(format!("{}.bin", key(coating, e_min, e_max, theta_max))));
        if let Some(table) = path.as_deref().and_then(|p| read(p, coating)) {
            // Marked used (the listing's "last used"; an error only loses that).
            let _ = path.as_deref().map(|p| {
                std::fs::File::options()
                    .append(true)
                    .open(p)
                    .and_then(|f| f.set_modified(std::time::SystemTime::now()))
            });
            return Ok(table);
        }
        // Energies as a person writes them (10, not 10.000000000000007).
        let kev = |e: f64| format!("{}", (e * 1e6).round() / 1e6);
        let energies = if e_min == e_max {
            format!("at {} keV", kev(e_min))
        } else {
            format!("for {}–{} keV", kev(e_min), kev(e_max))
        };
        crate::progress::notice(&format!(
            "building the reflectivity table of coating `{}` {energies}{}",
            coating.name,
            match &path {
                Some(p) => format!(
                    " (once: kept in {} for the next build)",
                    p.parent().unwrap_or(p).display()
                ),
                None => String::new(),
            }
        ));
        let table = ReflectivityTable::new(coating, e_min, e_max, theta_max)?;
        if let Some(p) = &path {
            // Only time is lost if the cache cannot be written.
            let dir = p.parent().expect("a file in a folder");
            let _ = std::fs::create_dir_all(dir)
                .and_then(|()| crate::files::atomic_write(p, &encode(&table)))
                .and_then(|()| evict(dir, p, size_limit_bytes()));
        }
        Ok(table)
    }
}

/// One table file of the cache.
#[derive(Clone, Debug)]
pub struct CachedTable {
    pub path: PathBuf,
    pub bytes: u64,
    /// When it was written or last read.
    pub last_used: std::time::SystemTime,
}

/// Whether `name` is a table file's name: 64 hexadecimal digits and `.bin`.
fn is_table_name(name: &str) -> bool {
    name.strip_suffix(".bin")
        .is_some_and(|k| k.len() == 64 && k.bytes().all(|b| b.is_ascii_hexdigit()))
}

/// The table files in the cache folder `dir`, most recently used first (none
/// if the folder does not exist); other files are not the cache's.
pub fn cached_tables(dir: &Path) -> std::io::Result<Vec<CachedTable>> {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(e),
    };
    let mut tables = Vec::new();
    for entry in entries {
        let entry = entry?;
        if !is_table_name(&entry.file_name().to_string_lossy()) {
            continue;
        }
        let meta = entry.metadata()?;
        tables.push(CachedTable {
            path: entry.path(),
            bytes: meta.len(),
            last_used: meta.modified()?,
        });
    }
    tables.sort_by_key(|t| std::cmp::Reverse(t.last_used));
    Ok(tables)
}

pub use crate::environment::{
    reflectivity_cache_bytes as size_limit_bytes, DEFAULT_CACHE_MAX_MB as DEFAULT_MAX_MB,
};

/// Removes the least recently used tables of `dir` other than `keep` until
/// they take at most `limit` bytes.
fn evict(dir: &Path, keep: &Path, limit: u64) -> std::io::Result<()> {
    let tables = cached_tables(dir)?; // most recently used first
    let mut total: u64 = tables.iter().map(|t| t.bytes).sum();
    for t in tables.iter().rev() {
        if total <= limit {
            break;
        }
        if t.path != keep && std::fs::remove_file(&t.path).is_ok() {
            total -= t.bytes;
        }
    }
    Ok(())
}

/// Removes every table file from the cache folder `dir` (nothing else);
/// returns how many and their bytes.
pub fn clear_tables(dir: &Path) -> std::io::Result<(usize, u64)> {
    let tables = cached_tables(dir)?;
    for t in &tables {
        std::fs::remove_file(&t.path)?;
    }
    Ok((tables.len(), tables.iter().map(|t| t.bytes).sum()))
}

/// The table's file contents.
fn encode(t: &ReflectivityTable) -> Vec<u8> {
    let p = t.parts();
    let mut b = MAGIC.to_vec();
    b.extend((p.energies.len() as u64).to_le_bytes());
    p.energies
        .iter()
        .for_each(|e| b.extend(e.to_bits().to_le_bytes()));
    b.extend(p.theta_max.to_bits().to_le_bytes());
    for (&step, &n) in p.x_steps.iter().zip(&p.row_lengths) {
        b.extend(step.to_bits().to_le_bytes());
        b.extend((n as u64).to_le_bytes());
    }
    b.extend((p.values.len() as u64).to_le_bytes());
    p.values
        .iter()
        .for_each(|v| b.extend(v.to_bits().to_le_bytes()));
    let sum = Sha256::digest(&b);
    b.extend(sum);
    b
}

/// The table in `path`, if the file exists and is whole.
fn read(path: &Path, coating: &Coating) -> Option<ReflectivityTable> {
    let bytes = std::fs::read(path).ok()?;
    let (body, sum) = bytes.split_at(bytes.len().checked_sub(32)?);
    if Sha256::digest(body).as_slice() != sum {
        return None;
    }
    let mut r = Reader(body.strip_prefix(MAGIC)?);
    let n_energies = r.u64()? as usize;
    if r.0.len() < 24 * n_energies {
        return None;
    }
    let energies = (0..n_energies)
        .map(|_| r.f64())
        .collect::<Option<Vec<f64>>>()?;
    let theta_max = r.f64()?;
    let (mut x_steps, mut row_lengths) = (Vec::new(), Vec::new());
    for _ in 0..n_energies {
        x_steps.push(r.f64()?);
        row_lengths.push(r.u64()? as usize);
    }
    let n = r.u64()? as usize;
    if r.0.len() != 4usize.checked_mul(n)? {
        return None;
    }
    let values = (0..n).map(|_| r.f32()).collect::<Option<Vec<f32>>>()?;
    ReflectivityTable::from_parts(
        coating,
        TableParts {
            energies,
            x_steps,
            theta_max,
            row_lengths,
            values,
        },
    )
}

/// Little-endian numbers off the front of a byte slice.
struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> Option<[u8; N]> {
        let (head, rest) = self.0.split_first_chunk::<N>()?;
        self.0 = rest;
        Some(*head)
    }
    fn u64(&mut self) -> Option<u64> {
        self.take().map(u64::from_le_bytes)
    }
    fn f64(&mut self) -> Option<f64> {
        self.u64().map(f64::from_bits)
    }
    fn f32(&mut self) -> Option<f32> {
        self.take().map(|b| f32::from_bits(u32::from_le_bytes(b)))
    }
}
