//! Adding the tallies of shards into the tally of their run, after checking that
//! they are finished, disjoint parts of one and the same run. The headers are
//! checked first; the tallies are then read one at a time and added into one
//! exact sum, so a merge holds two tallies at most, whatever the number of
//! shards.

use super::StateHeader;
use crate::trace::Tally;
use std::path::{Path, PathBuf};

/// Why shards cannot be merged (exit code 2), naming the folder at fault.
#[derive(Debug, thiserror::Error)]
#[error("{}: {message}", folder.display())]
pub struct MergeError {
    pub folder: PathBuf,
    pub message: String,
}

/// The merged run.
pub struct Merged {
    pub header: StateHeader,
    pub tally: Tally,
}

/// Shards of one run, as "2, 5 and 7 of 8".
fn list(parts: &[u64], of: u64) -> String {
    let shown: Vec<String> = parts.iter().take(20).map(u64::to_string).collect();
    let more = if parts.len() > 20 {
        format!(" and {} more", parts.len() - 20)
    } else {
        String::new()
    };
    format!("{}{more} of {of}", shown.join(", "))
}

/// Merges `shards` (folder, header); with `partial`, missing shards are allowed
/// and recorded in the header. `tally_of` reads a shard's tally (given its
/// folder and the header read before, which the tally's file must still hold).
/// The result is the same for any order of the shards.
pub fn merge<E: From<MergeError>>(
    shards: Vec<(PathBuf, StateHeader)>,
    partial: bool,
    mut tally_of: impl FnMut(&Path, &StateHeader) -> Result<Tally, E>,
) -> Result<Merged, E> {
    let (header, shards) = checked_header(shards, partial)?;
    let photon_list = header.identity.photon_list;
    let mut sum: Option<Tally> = None;
    for (dir, h) in &shards {
        let t = tally_of(dir, h)?;
        match &mut sum {
            None => sum = Some(t),
            Some(s) => s.add(&t, photon_list),
        }
    }
    Ok(Merged {
        header,
        tally: sum.expect("checked: at least one shard"),
    })
}

/// The merged run's header, after checking the shards' headers.
#[allow(clippy::type_complexity)]
fn checked_header(
    shards: Vec<(PathBuf, StateHeader)>,
    partial: bool,
) -> Result<(StateHeader, Vec<(PathBuf, StateHeader)>), MergeError> {
    let fail = |folder: &Path, message: String| MergeError {
        folder: folder.to_path_buf(),
        message,
    };
    let Some((first_dir, first)) = shards.first() else {
        return Err(fail(
            Path::new("traxer merge"),
            "no shard folders to merge".into(),
        ));
    };
    let n = first.identity.shards;
    if n == 0 || n > super::shard::MAX_SHARDS {
        return Err(fail(
            first_dir,
            format!("names a run cut into {n} shards, which cannot be"),
        ));
    }
    let mut holder: Vec<Option<&Path>> = vec![None; n as usize + 1];
    for (dir, h) in &shards {
        if let Some(diff) = h.identity.difference(&first.identity) {
            return Err(fail(
                dir,
                format!(
                    "is a shard of another run than {}: {diff}",
                    first_dir.display()
                ),
            ));
        }
        if !h.complete() {
            return Err(fail(
                dir,
                format!(
                    "holds an unfinished run ({} of {} photons traced): finish it with `traxer trace --resume {}` first",
                    h.traced,
                    h.photons,
                    dir.display()
                ),
            ));
        }
        for &k in &h.parts {
            if k == 0 || k > n {
                return Err(fail(
                    dir,
                    format!("names shard {k} of {n}, which cannot be"),
                ));
            }
            if let Some(other) = holder[k as usize] {
                return Err(fail(
                    dir,
                    format!(
                        "holds shard {k}/{n}, which {} holds too: each shard is merged once",
                        other.display()
                    ),
                ));
            }
            holder[k as usize] = Some(dir);
        }
    }
    let missing: Vec<u64> = (1..=n).filter(|&k| holder[k as usize].is_none()).collect();
    if !missing.is_empty() && !partial {
        return Err(fail(
            first_dir,
            format!(
                "shards {} are missing: add their folders, or merge without them with --partial (recorded in the provenance)",
                list(&missing, n)
            ),
        ));
    }
    let parts: Vec<u64> = (1..=n).filter(|&k| holder[k as usize].is_some()).collect();
    let mut shards = shards;
    shards.sort_by_key(|(_, h)| h.parts.first().copied());
    let mut header = shards[0].1.clone();
    header.parts = parts;
    header.missing = missing;
    for (_, h) in shards.iter().skip(1) {
        header.photons += h.photons;
        header.traced += h.traced;
        header.seconds += h.seconds;
    }
    Ok((header, shards))
}
