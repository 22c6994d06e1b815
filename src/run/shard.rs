//! One of N equal parts of a run: which photon indices it traces.

/// More shards than this is a typo, not a cluster (Slurm's default array limit
/// is 1001 tasks).
pub const MAX_SHARDS: u64 = 1_000_000;

/// Shard `index` (1-based) of `count` of a run of `total` photons.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: u64,
    pub count: u64,
    pub total: u64,
}

impl Shard {
    /// The whole run as its only shard.
    pub fn whole(total: u64) -> Shard {
        Shard {
            index: 1,
            count: 1,
            total,
        }
    }

    /// Parses `K/N` for a run of `total` photons: 1 ≤ K ≤ N ≤ total (each shard
    /// has at least one photon).
    pub fn parse(text: &str, total: u64) -> Result<Shard, String> {
        let expected =
            || format!("--shard {text}: expected K/N, shard K of N (1 ≤ K ≤ N), e.g. 3/8");
        let (k, n) = text.split_once('/').ok_or_else(expected)?;
        let k: u64 = k.trim().parse().map_err(|_| expected())?;
        let n: u64 = n.trim().parse().map_err(|_| expected())?;
        if n == 0 {
            return Err(format!(
                "--shard {text}: a run is cut into at least 1 shard"
            ));
        }
        if n > MAX_SHARDS {
            return Err(format!("--shard {text}: at most {MAX_SHARDS} shards"));
        }
        if k == 0 || k > n {
            return Err(format!(
                "--shard {text}: the shard number must be 1 to {n} (shards are counted from 1)"
            ));
        }
        if n > total {
            return Err(format!(
                "--shard {text}: {n} shards of a run of {total} photons would leave shards without photons; use at most {total} shards or more --photons"
            ));
        }
        Ok(Shard {
            index: k,
            count: n,
            total,
        })
    }

    /// Its photon indices: [⌊total·(K−1)/N⌋, ⌊total·K/N⌋).
    pub fn range(&self) -> std::ops::Range<u64> {
        let at = |k: u64| (self.total as u128 * k as u128 / self.count as u128) as u64;
        at(self.index - 1)..at(self.index)
    }

    /// Its number of photons.
    pub fn photons(&self) -> u64 {
        let r = self.range();
        r.end - r.start
    }

    /// The range of shard `index` of the same cut.
    pub fn sibling(&self, index: u64) -> Shard {
        Shard { index, ..*self }
    }
}

#[cfg(test)]
mod tests {
    use super::Shard;

    #[test]
    fn shards_tile_the_run_without_gaps_or_overlaps() {
        for (total, n) in [(10, 3), (1_000_003, 7), (5, 5), (u64::MAX, 4)] {
            let s = Shard::parse(&format!("1/{n}"), total).unwrap();
            let mut next = 0;
            for k in 1..=n {
                let r = s.sibling(k).range();
                assert_eq!(r.start, next);
                assert!(r.end > r.start);
                // Equal parts: sizes differ by at most one photon.
                assert!(r.end - r.start >= total / n && r.end - r.start <= total / n + 1);
                next = r.end;
            }
            assert_eq!(next, total);
        }
    }

    #[test]
    fn bad_shards_are_refused_with_what_is_expected() {
        for (text, total, says) in [
            ("0/4", 100, "1 to 4"),
            ("5/4", 100, "1 to 4"),
            ("1/0", 100, "at least 1 shard"),
            ("4", 100, "expected K/N"),
            ("a/b", 100, "expected K/N"),
            ("1/8", 5, "at most 5 shards"),
            ("1/2000000", u64::MAX, "at most 1000000 shards"),
        ] {
            let e = Shard::parse(text, total).unwrap_err();
            assert!(e.contains(says), "{text}: {e}");
        }
    }
}
