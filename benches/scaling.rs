//! `cargo bench --bench scaling`: the bookkeeping around the photons must grow
//! linearly with what it keeps, or a large scene or study spends its time there
//! instead of tracing. Each line times one piece at two sizes, n and 4n (or
//! 10n), in one run, and prints the ratio: near the size ratio for linear
//! work, its square for quadratic. Three regressions it would show (issue 49):
//! - a study's record (`run::record::Record`) rewritten whole after every
//!   point: 4001 angles took 56 s at 2 photons per point;
//! - the figures' count of what stopped reflected photons
//!   (`output::stopped_by_part`), which searched the parts by name for each
//!   object: a 100 000-object scene's figures took a minute;
//! - the effective-area sweep's check for repeated angles, a search among the
//!   earlier ones for each angle: 60 s before a too-large sweep was refused.

use std::time::Instant;
use traxer::run::record::Record;
use traxer::studies::effective_area::{check, AreaSweep};

/// Seconds `f` takes (the best of three: the machine is shared).
fn seconds(mut f: impl FnMut()) -> f64 {
    (0..3)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn line(what: &str, sizes: [usize; 2], t: [f64; 2]) {
    println!(
        "{what:<58} n = {:>8}: {:>9.4} s   n = {:>8}: {:>9.4} s   ratio {:>6.1} (size ratio {})",
        sizes[0],
        t[0],
        sizes[1],
        t[1],
        t[1] / t[0],
        sizes[1] / sizes[0]
    );
}

/// A study record of n points like an effective-area sweep's.
fn record(n: usize) -> f64 {
    let dir = tempfile::tempdir().expect("temporary folder");
    seconds(|| {
        let path = dir.path();
        let _ = std::fs::remove_file(path.join(Record::<Vec<f64>>::file_name("bench")));
        let identity = serde_json::json!({ "photons": 2, "angles": (0..n).collect::<Vec<_>>() });
        let mut r = Record::<Vec<f64>>::open(path, "bench", identity, false).expect("record");
        for k in 0..n {
            let point = vec![k as f64, 0.25 * k as f64, 1.0 / (k + 1) as f64];
            assert!(r.add(k, &point).is_none(), "write failed");
        }
    })
}

/// The part sums of n objects in n / 4 parts (a telescope's shells).
fn stopped(n: usize) -> f64 {
    let names: Vec<(String, String)> = (0..n)
        .map(|k| {
            (
                format!("part_{}", k / 4),
                format!("part_{}_{}", k / 4, k % 4),
            )
        })
        .collect();
    let counts: Vec<u64> = (0..n as u64).map(|k| k % 7).collect();
    seconds(|| {
        let objects = names.iter().map(|(p, o)| (p.as_str(), o.as_str()));
        let sums = traxer::output::stopped_by_part(objects, &counts);
        assert!(!sums.is_empty());
    })
}

/// The sweep check on n distinct angles at one energy.
fn sweep_check(n: usize) -> f64 {
    let s = AreaSweep {
        energies: vec![1.5],
        angles_arcmin: (0..n).map(|k| k as f64 * 1e-3).collect(),
        sampling: traxer::studies::Sampling {
            photons: 100,
            seed: 1,
            threads: 1,
            sensor: None,
        },
        radius_mm: None,
    };
    seconds(|| {
        let _ = check(&s);
    })
}

fn main() {
    let both = |f: fn(usize) -> f64, n: usize, k: usize| ([n, k * n], [f(n), f(k * n)]);
    let (s, t) = both(record, 1000, 4);
    line("study record, points appended", s, t);
    let (s, t) = both(stopped, 10_000, 10);
    line("stopped after reflection, by part (objects)", s, t);
    let (s, t) = both(sweep_check, 100_000, 10);
    line("effective-area sweep check (angles; 1e6 is the cap)", s, t);
    let (s, t) = both(sweep_check, 1_000_000, 4);
    line("effective-area sweep check, refused by the size cap", s, t);
}
