//! Reading and writing run-state files: a run's [`StateHeader`] and its exact
//! [`Tally`], the layout described in `run/mod.rs` (a magic first line with the
//! header's SHA-256, the header as JSON, the tally in postcard). `run` writes
//! them at the end of a run and at checkpoints; `merge` and `resume` read them.

use super::StateHeader;
use crate::files::{atomic_write, sha256_hex};
use crate::trace::Tally;
use std::path::{Path, PathBuf};

/// The first line of every run-state file starts so; the number is the layout's
/// version, and the SHA-256 of the header line follows it (the header holds the
/// tally's SHA-256: the whole file is covered).
const MAGIC: &str = "traxer run state 5";

/// A file that is not a run-state file this traxer can read (exit code 2).
#[derive(Debug, thiserror::Error)]
#[error("{}: {message}", path.display())]
pub struct RunStateError {
    pub path: PathBuf,
    pub message: String,
}

/// The bytes of a run-state file holding `tally` under `header` (whose hash and
/// length of the tally are set here).
pub fn state_bytes(mut header: StateHeader, tally: &Tally) -> Vec<u8> {
    let body = postcard::to_allocvec(tally).expect("a tally of plain numbers encodes");
    header.tally_sha256 = sha256_hex(&body);
    header.tally_bytes = body.len() as u64;
    let head = serde_json::to_string(&header).expect("a header of plain values encodes");
    let first = format!("{MAGIC} {}", sha256_hex(head.as_bytes()));
    let mut bytes = Vec::with_capacity(first.len() + head.len() + body.len() + 2);
    bytes.extend_from_slice(first.as_bytes());
    bytes.push(b'\n');
    bytes.extend_from_slice(head.as_bytes());
    bytes.push(b'\n');
    bytes.extend_from_slice(&body);
    bytes
}

/// Writes a run-state file atomically: a reader (or a run killed at any moment)
/// finds the previous file whole or the new one whole.
pub fn write_state(path: &Path, header: StateHeader, tally: &Tally) -> std::io::Result<()> {
    atomic_write(path, &state_bytes(header, tally))
}

/// Reads a run-state file: its header and its tally (checked against the hash
/// in the header).
pub fn read_state(path: &Path) -> Result<(StateHeader, Tally), RunStateError> {
    let bytes = read_bytes(path)?;
    let (header, body) = split(path, &bytes)?;
    if body.len() as u64 != header.tally_bytes || sha256_hex(body) != header.tally_sha256 {
        return Err(failure(
            path,
            format!(
                "its tally is damaged: {} bytes where the header says {}, or a different SHA-256",
                body.len(),
                header.tally_bytes
            ),
        ));
    }
    let tally: Tally = postcard::from_bytes(body)
        .map_err(|e| failure(path, format!("its tally cannot be decoded: {e}")))?;
    Ok((header, tally))
}

/// Reads only the header of a run-state file (its first two lines; the tally
/// is not read).
pub fn read_header(path: &Path) -> Result<StateHeader, RunStateError> {
    use std::io::{BufRead, Read};
    let file =
        std::fs::File::open(path).map_err(|e| failure(path, format!("cannot read it: {e}")))?;
    // A header is a few kB; a line this long is not one.
    let mut reader = std::io::BufReader::new(file).take(MAX_HEADER_BYTES);
    let mut head = Vec::new();
    for _ in 0..2 {
        reader
            .read_until(b'\n', &mut head)
            .map_err(|e| failure(path, format!("cannot read it: {e}")))?;
    }
    split(path, &head).map(|(h, _)| h)
}

/// The longest first two lines `read_header` reads.
const MAX_HEADER_BYTES: u64 = 1 << 24;

fn failure(path: &Path, message: String) -> RunStateError {
    RunStateError {
        path: path.to_path_buf(),
        message,
    }
}

fn read_bytes(path: &Path) -> Result<Vec<u8>, RunStateError> {
    std::fs::read(path).map_err(|e| failure(path, format!("cannot read it: {e}")))
}

/// The header and the encoded tally.
fn split<'a>(path: &Path, bytes: &'a [u8]) -> Result<(StateHeader, &'a [u8]), RunStateError> {
    let mut lines = bytes.splitn(3, |&b| b == b'\n');
    let first = lines.next().unwrap_or_default();
    let Some(hash) = first
        .strip_prefix(MAGIC.as_bytes())
        .and_then(|h| h.strip_prefix(b" "))
    else {
        let older = first.starts_with(b"traxer run state ");
        return Err(failure(
            path,
            if older {
                format!("was written by another traxer version (its first line is not `{MAGIC} SHA-256`): finish or merge it with that version")
            } else {
                format!("is not a traxer run-state file (its first line is not `{MAGIC} SHA-256`)")
            },
        ));
    };
    let head = lines.next().unwrap_or_default();
    if sha256_hex(head).as_bytes() != hash {
        return Err(failure(
            path,
            "its header (line 2) is damaged or was edited: its SHA-256 is not the one on line 1"
                .into(),
        ));
    }
    let header: StateHeader = serde_json::from_slice(head)
        .map_err(|e| failure(path, format!("its header (line 2) cannot be read: {e}")))?;
    Ok((header, lines.next().unwrap_or_default()))
}
