//! CSV tables (the `csv` crate: fields with commas, quotes or newlines, such as
//! file paths, are quoted), written atomically.

use crate::files::atomic_write;
use std::path::Path;

/// The table as CSV text: `header`, then one line per row.
pub fn csv_text<R, F>(header: &[&str], rows: R) -> String
where
    R: IntoIterator<Item = Vec<F>>,
    F: AsRef<[u8]>,
{
    let mut w = csv::WriterBuilder::new()
        .flexible(false)
        .from_writer(Vec::new());
    let written = w.write_record(header).and_then(|_| {
        rows.into_iter()
            .try_for_each(|r| w.write_record(r.iter().map(|f| f.as_ref())))
    });
    // Writing into memory cannot fail; rows of the wrong length are a bug.
    written.expect("CSV rows as long as the header");
    let bytes = w.into_inner().expect("CSV into memory");
    String::from_utf8(bytes).expect("CSV of UTF-8 fields")
}

/// Writes the table to `path` atomically.
pub fn write_csv<R, F>(path: &Path, header: &[&str], rows: R) -> std::io::Result<()>
where
    R: IntoIterator<Item = Vec<F>>,
    F: AsRef<[u8]>,
{
    atomic_write(path, csv_text(header, rows).as_bytes())
}
