//! Runs cut into shards and merged, and runs stopped (by a signal, or killed at
//! any moment) and resumed, through the `traxer` binary: the results must be the
//! bit-identical files of one uninterrupted run.

use crate::common::{repo, run_fails, run_ok, traxer, write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The Wolter-I scene with gold mirrors (weights below 1, so that floating-point
/// sums in another grouping would differ), energy bands, a detector grid, class
/// images; written into `dir` with absolute mesh paths.
fn wolter_scene(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(repo().join("scenes/wolter1_parallel.toml")).unwrap();
    let meshes = repo().join("meshes");
    let text = text
        .replace("\"../meshes/", &format!("\"{}/", meshes.display()))
        .replace(
            "pixels = [512, 512]",
            "pixels = [300, 300]\nenergy_bins = [1.0, 2.0, 4]\npixel_grid = { pixels = [64, 64], pitch = 0.055, rotation = 10.0, center = [0.0, 0.0] }\nhistory_images = true",
        );
    write(dir, "wolter.toml", &text)
}

/// A point source right in front of a large, finely pixelled sensor: fast to
/// trace, with big checkpoints (tens of MB, so that a kill can land inside a
/// write) and weights that differ from photon to photon.
fn big_sensor_scene(dir: &Path) -> PathBuf {
    write(
        dir,
        "big.toml",
        r#"
[materials.detector]
type = "sensor"
size = [40.0, 40.0]
pixels = [1500, 1500]

[[sources]]
type = "point"
position = [0.0, 0.0, 60.0]
target = { center = [0.0, 0.0, 1.0], radius = 20.0 }
energy = { line = 3.0 }

[[objects]]
name = "sensor"
material = "detector"
shape = { type = "rectangle", size = [40.0, 40.0] }
"#,
    )
}

fn trace(scene: &Path, out: &Path, args: &[&str]) -> std::process::Command {
    let mut c = traxer();
    c.arg("trace")
        .arg(scene)
        .arg("-o")
        .arg(out)
        .arg("-q")
        .args(args);
    c
}

/// A JSON document without what differs between runs of the same numbers:
/// provenance (command line, time, shards) and timing.
fn without_run_details(path: &Path) -> serde_json::Value {
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let o = v.as_object_mut().unwrap();
    o.remove("provenance");
    if let Some(s) = o.get_mut("statistics").and_then(|s| s.as_object_mut()) {
        for k in [
            "seconds",
            "threads",
            "photons_per_second",
            "sensor_photons_per_second",
        ] {
            s.remove(k);
        }
    }
    v
}

/// The encoded tally of a run-state file (what follows its two header lines).
fn tally_bytes(path: &Path) -> Vec<u8> {
    let bytes = std::fs::read(path).unwrap();
    let mut lines = bytes.splitn(3, |&b| b == b'\n');
    lines.nth(2).unwrap().to_vec()
}

/// Every file of `a` is in `b` with the same bytes, JSON apart from provenance
/// and timing, the run state apart from its header.
fn assert_same_results(a: &Path, b: &Path) {
    let mut names: Vec<String> = std::fs::read_dir(a)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    names.sort();
    assert!(names.len() >= 9, "{names:?}");
    for n in &names {
        let (fa, fb) = (a.join(n), b.join(n));
        assert!(fb.is_file(), "{} lacks {n}", b.display());
        if n.ends_with(".json") {
            assert_eq!(without_run_details(&fa), without_run_details(&fb), "{n}");
        } else if n == "run_state.bin" {
            assert!(tally_bytes(&fa) == tally_bytes(&fb), "{n}");
        } else {
            assert!(
                std::fs::read(&fa).unwrap() == std::fs::read(&fb).unwrap(),
                "{n}"
            );
        }
    }
}

#[test]
fn four_shards_merged_in_any_order_give_the_files_of_one_run_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let scene = wolter_scene(dir.path());
    let common = [
        "-n",
        "200000",
        "-s",
        "7",
        "-D",
        "coating=gold",
        "-D",
        "off_axis=0.01",
        "--photon-list",
        "3000",
    ];
    let one = dir.path().join("one");
    run_ok(trace(&scene, &one, &common).arg("-j").arg("2"));
    let shard = |k: u64| {
        let out = dir.path().join(format!("shard{k}"));
        // Shards on different thread counts, as on a cluster's mixed nodes.
        run_ok(trace(&scene, &out, &common).args([
            "--shard",
            &format!("{k}/4"),
            "-j",
            &(1 + k % 2).to_string(),
        ]));
        out
    };
    let shards: Vec<PathBuf> = (1..=4).map(shard).collect();
    for (name, order) in [("merged_a", [2, 0, 3, 1]), ("merged_b", [3, 2, 1, 0])] {
        let out = dir.path().join(name);
        let mut c = traxer();
        c.args(["merge", "-q", "-o"]).arg(&out);
        for i in order {
            c.arg(&shards[i]);
        }
        run_ok(&mut c);
        assert_same_results(&one, &out);
    }
    // The files hold what they should: the grid, the class images and the list.
    for f in ["sensor_grid.npy", "sensor_front_rear.npy", "photons.npy"] {
        assert!(one.join(f).is_file(), "{f}");
    }
    // The provenance says what was merged.
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("merged_a/summary.json")).unwrap(),
    )
    .unwrap();
    let shards_json = &summary["provenance"]["shards"];
    assert_eq!(shards_json["cut_into"], 4);
    assert_eq!(shards_json["parts"], serde_json::json!([1, 2, 3, 4]));
    assert_eq!(shards_json["partial"], false);
    assert_eq!(summary["provenance"]["photons"], 200000);
    // A shard is a part: its image differs from the whole run's.
    assert!(
        std::fs::read(one.join("sensor.npy")).unwrap()
            != std::fs::read(shards[0].join("sensor.npy")).unwrap()
    );
}

#[test]
fn merge_refuses_shards_that_are_not_one_run_and_names_the_folder() {
    let dir = tempfile::tempdir().unwrap();
    let scene = wolter_scene(dir.path());
    let d = |n: &str| dir.path().join(n);
    let shard = |name: &str, args: &[&str]| {
        let n = if name == "more" { "50000" } else { "40000" };
        run_ok(&mut trace(&scene, &d(name), &[&["-n", n], args].concat()));
        d(name)
    };
    let s1 = shard("s1", &["--shard", "1/4"]);
    let s2 = shard("s2", &["--shard", "2/4"]);
    let s3 = shard("s3", &["--shard", "3/4"]);
    let seed = shard("seed", &["--shard", "4/4", "-s", "2"]);
    let energy = shard("energy", &["--shard", "4/4", "-D", "energy=1.5"]);
    let more = shard("more", &["--shard", "4/4"]);
    let five = shard("five", &["--shard", "4/5"]);
    let whole = shard("whole", &[]);
    let merge = |dirs: &[&PathBuf], extra: &[&str]| {
        let mut c = traxer();
        c.args(["merge", "-q", "-o"]).arg(d("merged")).args(extra);
        for x in dirs {
            c.arg(x);
        }
        c
    };
    let cases: Vec<(Vec<&PathBuf>, Vec<&str>)> = vec![
        (
            vec![&s1, &s2, &s3, &s1],
            vec!["s1", "holds shard 1/4, which", "s1 holds too"],
        ),
        (
            vec![&s1, &s3],
            vec!["s1", "shards 2, 4 of 4 are missing", "--partial"],
        ),
        (vec![&s1, &s2, &s3, &seed], vec!["seed", "seed 2, not 1"]),
        (
            vec![&s1, &s2, &s3, &energy],
            vec!["energy", "variable energy = 1.5, not 1.49"],
        ),
        (
            vec![&s1, &s2, &s3, &more],
            vec!["more", "50000 photons, not 40000"],
        ),
        (vec![&s1, &s2, &s3, &five], vec!["five", "5 shards, not 4"]),
        (vec![&s1, &whole], vec!["whole", "1 shards, not 4"]),
    ];
    for (dirs, needles) in cases {
        let err = run_fails(&mut merge(&dirs, &[]), 2);
        for n in &needles {
            assert!(err.contains(n), "stderr lacks {n:?}:\n{err}");
        }
        assert!(
            !d("merged").exists(),
            "a refused merge wrote {}",
            d("merged").display()
        );
    }
    // Nothing to merge, a folder without a run state, the output in a shard.
    run_fails(traxer().args(["merge", "-o"]).arg(d("merged")), 2);
    let err = run_fails(&mut merge(&[&dir.path().to_path_buf()], &[]), 2);
    assert!(err.contains("holds no run_state.bin"), "{err}");
    // A run_state.bin that is a folder is not "none".
    let odd = dir.path().join("odd");
    std::fs::create_dir_all(odd.join("run_state.bin")).unwrap();
    let err = run_fails(&mut merge(&[&odd], &[]), 2);
    assert!(err.contains("run_state.bin: is not a file"), "{err}");
    let err = run_fails(traxer().args(["merge", "-o"]).arg(&s1).arg(&s1).arg(&s2), 2);
    assert!(err.contains("is the shard folder"), "{err}");
    assert!(!d("merged").exists());
    // A partial merge, asked for, says what it lacks.
    run_ok(&mut merge(&[&s3, &s1], &["--partial"]));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d("merged/summary.json")).unwrap()).unwrap();
    let p = &summary["provenance"]["shards"];
    assert_eq!(p["missing"], serde_json::json!([2, 4]));
    assert_eq!(p["partial"], true);
    assert_eq!(summary["statistics"]["photons_emitted"], 20000);
}

#[test]
fn bad_shards_are_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let scene = wolter_scene(dir.path());
    let out = dir.path().join("out");
    for (args, needle) in [
        (vec!["--shard", "0/4"], "must be 1 to 4"),
        (vec!["--shard", "5/4"], "must be 1 to 4"),
        (vec!["--shard", "3"], "expected K/N"),
        (vec!["-n", "3", "--shard", "1/4"], "at most 3 shards"),
        (vec!["--checkpoint-every=-1"], "--checkpoint-every -1"),
    ] {
        let err = run_fails(&mut trace(&scene, &out, &args), 2);
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!out.exists());
    }
}

/// Waits until `found` (or the process ends); whether it was found.
fn wait_for(child: &mut std::process::Child, found: impl Fn() -> bool, limit: Duration) -> bool {
    let start = Instant::now();
    while start.elapsed() < limit {
        if found() {
            return true;
        }
        if child.try_wait().unwrap().is_some() {
            return found();
        }
        std::thread::sleep(Duration::from_micros(500));
    }
    false
}

/// A temporary file of a checkpoint being written in `dir`.
fn checkpoint_being_written(dir: &Path) -> bool {
    std::fs::read_dir(dir).is_ok_and(|entries| {
        entries.flatten().any(|e| {
            let n = e.file_name().to_string_lossy().into_owned();
            n.starts_with(".checkpoint.bin.") && n.ends_with(".tmp")
        })
    })
}

/// Waits until the run writing into `out` traces (its staging folder beside
/// `out` exists: made just before the photon loop, after the scene is loaded,
/// however slow a loaded machine makes that), and a little longer.
fn tracing_started(child: &mut std::process::Child, out: &Path) {
    let parent = out.parent().unwrap();
    let prefix = format!(".{}.traxer-", out.file_name().unwrap().to_string_lossy());
    let staging = || {
        std::fs::read_dir(parent).is_ok_and(|entries| {
            entries
                .flatten()
                .any(|e| e.file_name().to_string_lossy().starts_with(&prefix))
        })
    };
    assert!(wait_for(child, staging, Duration::from_secs(60)));
    std::thread::sleep(Duration::from_millis(300));
}

fn signal(child: &std::process::Child, sig: &str) {
    run_ok(std::process::Command::new("kill").args([sig, &child.id().to_string()]));
}

#[test]
fn a_run_killed_at_any_moment_and_resumed_gives_the_uninterrupted_result() {
    let dir = tempfile::tempdir().unwrap();
    let scene = big_sensor_scene(dir.path());
    let args = ["-n", "12000000", "-s", "3"];
    let reference = dir.path().join("reference");
    run_ok(&mut trace(&scene, &reference, &args));
    let out = dir.path().join("run");
    let start = |dir: &Path| {
        let mut c = if dir.join("checkpoint.bin").is_file() {
            let mut c = traxer();
            c.args(["trace", "-q", "--resume"]).arg(dir);
            c
        } else {
            trace(&scene, dir, &args)
        };
        c.args(["--checkpoint-every", "0"]);
        c.stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap()
    };
    // Kill moments: early (scene load), inside checkpoint writes, between them.
    let mut killed_in_write = 0;
    let moments = [
        "early",
        "write",
        "after 0.7 s",
        "write",
        "write",
        "after 1.3 s",
    ];
    for moment in moments {
        let mut child = start(&out);
        match moment {
            "early" => std::thread::sleep(Duration::from_millis(30)),
            "write" => {
                wait_for(
                    &mut child,
                    || checkpoint_being_written(&out),
                    Duration::from_secs(60),
                );
            }
            m => {
                let s: f64 = m
                    .trim_start_matches("after ")
                    .trim_end_matches(" s")
                    .parse()
                    .unwrap();
                std::thread::sleep(Duration::from_secs_f64(s));
            }
        }
        signal(&child, "-KILL");
        child.wait().unwrap();
        // SIGKILL leaves the temporary file of a write it interrupted.
        if moment == "write" && checkpoint_being_written(&out) {
            killed_in_write += 1;
        }
    }
    assert!(
        killed_in_write >= 1,
        "no kill landed inside a checkpoint write"
    );
    // Resumed to the end (a kill may have come after the end: then nothing is left).
    let mut child = start(&out);
    assert!(child.wait().unwrap().success());
    assert!(!out.join("checkpoint.bin").exists());
    assert!(
        !checkpoint_being_written(&out),
        "a stale temporary file stayed"
    );
    assert_same_results(&reference, &out);
}

#[test]
fn sigterm_and_sigint_write_a_checkpoint_and_the_resumed_run_is_bit_identical() {
    let dir = tempfile::tempdir().unwrap();
    let scene = big_sensor_scene(dir.path());
    let args = ["-n", "30000000", "-s", "5"];
    let reference = dir.path().join("reference");
    run_ok(&mut trace(&scene, &reference, &args));
    let out = dir.path().join("run");
    let checkpoint = out.join("checkpoint.bin");
    // A long interval: only the signals write checkpoints.
    let mut child = trace(
        &scene,
        &out,
        &[&args[..], &["--checkpoint-every", "3600"]].concat(),
    )
    .stderr(std::process::Stdio::piped())
    .spawn()
    .unwrap();
    tracing_started(&mut child, &out);
    signal(&child, "-TERM");
    let stopped = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&stopped.stderr);
    assert_eq!(stopped.status.code(), Some(130), "{err}");
    assert!(err.contains("traxer trace --resume"), "{err}");
    assert!(checkpoint.is_file(), "{err}");
    // A new run into the folder would throw the stopped one away: refused.
    let refused = run_fails(&mut trace(&scene, &out, &args), 2);
    assert!(refused.contains("--resume"), "{refused}");
    // Resumed, stopped again with SIGINT, resumed to the end.
    let mut child = traxer()
        .args(["trace", "-q", "--checkpoint-every", "3600", "--resume"])
        .arg(&out)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    tracing_started(&mut child, &out);
    signal(&child, "-INT");
    let stopped = child.wait_with_output().unwrap();
    if stopped.status.code() == Some(130) {
        assert!(checkpoint.is_file());
        run_ok(traxer().args(["trace", "-q", "--resume"]).arg(&out));
    } else {
        // The rest was traced before the signal came: finished normally.
        assert!(stopped.status.success());
    }
    assert_same_results(&reference, &out);
    // Resuming a finished run does nothing, and says so.
    let again = run_ok(traxer().args(["trace", "--resume"]).arg(&out));
    assert!(String::from_utf8_lossy(&again.stdout).contains("nothing to resume"));
}

#[test]
fn checkpoints_of_another_scene_or_build_and_damaged_ones_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = big_sensor_scene(dir.path());
    let out = dir.path().join("run");
    let checkpoint = out.join("checkpoint.bin");
    let mut child = trace(&scene, &out, &["-n", "50000000", "--checkpoint-every", "0"])
        .spawn()
        .unwrap();
    wait_for(&mut child, || checkpoint.is_file(), Duration::from_secs(60));
    signal(&child, "-KILL");
    child.wait().unwrap();
    let good = std::fs::read(&checkpoint).unwrap();
    let resume = || {
        let mut c = traxer();
        c.args(["trace", "-q", "--resume"]).arg(&out);
        c
    };
    // The header edited: with its checksum left as it was, and made to fit.
    let edit_header = |from: &str, to: &str, fix_checksum: bool| {
        let mut lines = good.splitn(3, |&b| b == b'\n');
        let (first, head, body) = (
            lines.next().unwrap(),
            lines.next().unwrap(),
            lines.next().unwrap(),
        );
        let head = String::from_utf8(head.to_vec()).unwrap();
        assert!(head.contains(from), "{head}");
        let head = head.replacen(from, to, 1);
        let first = if fix_checksum {
            format!(
                "traxer run state 5 {}",
                traxer::files::sha256_hex(head.as_bytes())
            )
            .into_bytes()
        } else {
            first.to_vec()
        };
        [&first[..], b"\n", head.as_bytes(), b"\n", body].concat()
    };
    for (bytes, needle) in [
        (
            edit_header("\"traxer_version\":\"", "\"traxer_version\":\"9.", true),
            "was written by traxer 9.",
        ),
        (
            edit_header("\"seconds\":", "\"seconds\":1", false),
            "its header (line 2) is damaged or was edited",
        ),
        (good[..good.len() - 10].to_vec(), "its tally is damaged"),
        (b"hello\n".to_vec(), "is not a traxer run-state file"),
    ] {
        std::fs::write(&checkpoint, &bytes).unwrap();
        let err = run_fails(&mut resume(), 2);
        assert!(err.contains(needle), "{needle}: {err}");
        assert!(err.contains("checkpoint.bin"), "{err}");
    }
    // The scene file changed since the run stopped.
    std::fs::write(&checkpoint, &good).unwrap();
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(&scene, text.replace("line = 3.0", "line = 3.5")).unwrap();
    let err = run_fails(&mut resume(), 2);
    assert!(
        err.contains("changed since the run stopped") && err.contains("scene file with SHA-256"),
        "{err}"
    );
    std::fs::write(&scene, text).unwrap();
    // A folder that is not a stopped run's.
    let err = run_fails(traxer().args(["trace", "--resume"]).arg(dir.path()), 2);
    assert!(
        err.contains("is not the results folder of a stopped run"),
        "{err}"
    );
    // With the checkpoint and scene as they were, the run finishes.
    run_ok(&mut resume());
    assert!(!checkpoint.exists());
}

#[test]
fn the_cluster_scripts_run_shards_resume_a_stopped_one_and_merge_bit_identically() {
    // As HTCondor runs them (shards counted from 0, no Slurm): run-shard.sh for
    // each shard, one of them stopped by SIGTERM (passed on to traxer, which
    // checkpoints) and run again, then merge-shards.sh.
    let dir = tempfile::tempdir().unwrap();
    let scene = big_sensor_scene(dir.path());
    let root = dir.path().join("runs");
    let options = ["-s", "9"];
    let reference = dir.path().join("reference");
    run_ok(&mut trace(
        &scene,
        &reference,
        &[&["-n", "16000000"], &options[..]].concat(),
    ));
    let script = |name: &str| {
        let mut c = std::process::Command::new("bash");
        c.arg(repo().join("cluster").join(name))
            .env("TRAXER", env!("CARGO_BIN_EXE_traxer"))
            .env("TRAXER_SHARD_BASE", "0")
            .env("TRAXER_CHECKPOINT_EVERY", "0")
            .env_remove("SLURM_JOB_ID");
        c
    };
    let shard = |process: u32| {
        let mut c = script("run-shard.sh");
        c.arg(process.to_string())
            .args(["4"])
            .arg(&scene)
            .arg("16000000")
            .arg(&root)
            .args(options);
        c
    };
    for p in [0, 2, 3] {
        run_ok(&mut shard(p));
    }
    let mut child = shard(1)
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let checkpoint = root.join("shard-2-of-4/checkpoint.bin");
    assert!(wait_for(
        &mut child,
        || checkpoint.is_file(),
        Duration::from_secs(60)
    ));
    signal(&child, "-TERM");
    let out = child.wait_with_output().unwrap();
    assert_eq!(
        out.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert!(checkpoint.is_file());
    // Run again: it resumes; once more: it is finished and does nothing.
    let again = run_ok(&mut shard(1));
    assert!(String::from_utf8_lossy(&again.stdout).contains("--resume"));
    let once_more = run_ok(&mut shard(1));
    assert!(String::from_utf8_lossy(&once_more.stdout).contains("is finished"));
    let mut merge = script("merge-shards.sh");
    run_ok(merge.arg(&root).arg("4"));
    assert_same_results(&reference, &root.join("merged"));
}

/// A Sun whose emission is the table `table.csv` beside the scene (rates
/// `rates` at radii 0.1 and 0.2, energies 1 and 2 keV), shining on a sensor.
fn sun_table_scene(dir: &Path, rates: [f64; 4]) -> PathBuf {
    let rows: String = [(0.1, 1.0), (0.1, 2.0), (0.2, 1.0), (0.2, 2.0)]
        .iter()
        .zip(rates)
        .map(|((r, e), x)| format!("{r},{e},{x:e}\n"))
        .collect();
    write(
        dir,
        "table.csv",
        &format!("Radius,Energy [keV],emRates\n{rows}"),
    );
    write(
        dir,
        "sun.toml",
        r#"
[materials.detector]
type = "sensor"
size = [40.0, 40.0]
pixels = [100, 100]

[[sources]]
type = "sun"
emission = "table.csv"
target = { center = [0.0, 0.0, 0.0], radius = 10.0 }

[[objects]]
name = "sensor"
material = "detector"
shape = { type = "rectangle", size = [40.0, 40.0] }
transform = [ { translate = [0.0, 0.0, -10.0] } ]
"#,
    )
}

#[test]
fn shards_traced_with_two_emission_tables_or_an_edited_run_state_are_not_merged() {
    let dir = tempfile::tempdir().unwrap();
    let d = |n: &str| dir.path().join(n);
    let first = [1e-30, 2e-30, 1e-30, 2e-30];
    let scene = sun_table_scene(dir.path(), first);
    run_ok(&mut trace(
        &scene,
        &d("s1"),
        &["-n", "20000", "--shard", "1/2"],
    ));
    sun_table_scene(dir.path(), [1e-30, 2e-30, 1e-30, 3e-30]);
    run_ok(&mut trace(
        &scene,
        &d("s2"),
        &["-n", "20000", "--shard", "2/2"],
    ));
    let merge = |dirs: &[&str]| {
        let mut c = traxer();
        c.args(["merge", "-q", "-o"]).arg(d("merged"));
        for x in dirs {
            c.arg(d(x));
        }
        c
    };
    // The table now differs from the first shard's: named.
    let err = run_fails(&mut merge(&["s1", "s2"]), 2);
    assert!(err.contains("input file table.csv with SHA-256"), "{err}");
    assert!(!d("merged").exists());
    // With the first table back, the second shard differs from the first.
    sun_table_scene(dir.path(), first);
    let err = run_fails(&mut merge(&["s1", "s2"]), 2);
    assert!(
        err.contains("s2")
            && err.contains("is a shard of another run")
            && err.contains("table.csv"),
        "{err}"
    );
    assert!(!d("merged").exists());
    // The scene moved: --scene names its new place.
    let moved = d("moved.toml");
    std::fs::rename(&scene, &moved).unwrap();
    let err = run_fails(&mut merge(&["s1", "s2"]), 2);
    assert!(
        err.contains("is no longer there") && err.contains("--scene"),
        "{err}"
    );
    std::fs::rename(&moved, &scene).unwrap();
    // A run state whose shard list was edited (shard 1 posing as shard 2).
    // (s2 holds the shard of the other table: replaced, as asked.)
    run_ok(&mut trace(
        &scene,
        &d("s2"),
        &["-n", "20000", "--shard", "2/2", "--replace"],
    ));
    run_ok(&mut merge(&["s1", "s2"]));
    std::fs::create_dir(d("fake")).unwrap();
    let state = std::fs::read(d("s1/run_state.bin")).unwrap();
    let at = state
        .windows(11)
        .position(|w| w == b"\"parts\":[1]")
        .expect("the header lists its shards");
    let mut edited = state.clone();
    edited[at + 9] = b'2';
    std::fs::write(d("fake/run_state.bin"), edited).unwrap();
    std::fs::remove_dir_all(d("merged")).unwrap();
    let err = run_fails(&mut merge(&["s1", "fake"]), 2);
    assert!(
        err.contains("fake") && err.contains("damaged or was edited"),
        "{err}"
    );
    assert!(!d("merged").exists());
}

#[test]
fn a_run_whose_mesh_was_replaced_is_not_resumed() {
    let dir = tempfile::tempdir().unwrap();
    let square = |half: f64| {
        format!("v -{half} -{half} 0\nv {half} -{half} 0\nv {half} {half} 0\nv -{half} {half} 0\nf 1 2 3\nf 1 3 4\n")
    };
    write(dir.path(), "sensor.obj", &square(20.0));
    let scene = std::fs::read_to_string(big_sensor_scene(dir.path()))
        .unwrap()
        .replace(
            "shape = { type = \"rectangle\", size = [40.0, 40.0] }",
            "shape = { type = \"mesh\", file = \"sensor.obj\" }",
        );
    let scene = write(dir.path(), "mesh.toml", &scene);
    let out = dir.path().join("run");
    let checkpoint = out.join("checkpoint.bin");
    let mut child = trace(&scene, &out, &["-n", "50000000", "--checkpoint-every", "0"])
        .spawn()
        .unwrap();
    wait_for(&mut child, || checkpoint.is_file(), Duration::from_secs(60));
    signal(&child, "-KILL");
    child.wait().unwrap();
    assert!(checkpoint.is_file());
    write(dir.path(), "sensor.obj", &square(19.0));
    let err = run_fails(traxer().args(["trace", "-q", "--resume"]).arg(&out), 2);
    assert!(
        err.contains("input file sensor.obj with SHA-256") && err.contains("checkpoint.bin"),
        "{err}"
    );
    assert!(
        checkpoint.is_file(),
        "the refused resume removed the checkpoint"
    );
    // The mesh as it was, but the scene moved: the message says how to go on,
    // and the run continues from the scene's new place.
    write(dir.path(), "sensor.obj", &square(20.0));
    let moved = dir.path().join("moved.toml");
    std::fs::rename(&scene, &moved).unwrap();
    let err = run_fails(traxer().args(["trace", "-q", "--resume"]).arg(&out), 2);
    assert!(
        err.contains("is no longer there") && err.contains("traxer trace NEW_PATH --resume"),
        "{err}"
    );
    run_ok(
        traxer()
            .args(["trace", "-q"])
            .arg(&moved)
            .arg("--resume")
            .arg(&out),
    );
    assert!(!checkpoint.exists() && out.join("run_state.bin").is_file());
}

/// Peak memory (kB) of `traxer merge -o OUT DIRS...`, measured by a Python
/// wrapper so that no other test's processes count.
fn merge_peak_kb(out: &Path, dirs: &[PathBuf]) -> u64 {
    let script = "import resource, subprocess, sys\n\
                  r = subprocess.run(sys.argv[1:])\n\
                  assert r.returncode == 0, r.returncode\n\
                  print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)";
    let exe = env!("CARGO_BIN_EXE_traxer");
    let mut c = std::process::Command::new("python3");
    c.args(["-c", script, exe, "merge", "-q", "-o"]).arg(out);
    c.args(dirs);
    let o = run_ok(&mut c);
    String::from_utf8_lossy(&o.stdout).trim().parse().unwrap()
}

#[test]
fn merge_memory_does_not_grow_with_the_number_of_shards() {
    let dir = tempfile::tempdir().unwrap();
    let scene = big_sensor_scene(dir.path());
    // All shards of a cut of the run into `n`, in folders `{prefix}K`.
    let cut = |n: u64, prefix: &str| -> Vec<PathBuf> {
        (1..=n)
            .map(|k| {
                let d = dir.path().join(format!("{prefix}{k}"));
                let shard = format!("{k}/{n}");
                run_ok(&mut trace(&scene, &d, &["-n", "8000", "--shard", &shard]));
                d
            })
            .collect()
    };
    let shards = cut(8, "s");
    // Two shards of another cut of the same scene, for the baseline.
    let pair = cut(2, "p");
    let two = merge_peak_kb(&dir.path().join("m2"), &pair);
    let eight = merge_peak_kb(&dir.path().join("m8"), &shards);
    // Each tally of the 1500 × 1500 sensor is tens of MB: holding all eight at
    // once would take about four times the memory of two.
    assert!(
        (eight as f64) < 1.5 * two as f64,
        "peak memory of a merge: {eight} kB for 8 shards, {two} kB for 2"
    );
    assert_eq!(
        tally_bytes(&dir.path().join("m2/run_state.bin")),
        tally_bytes(&dir.path().join("m8/run_state.bin"))
    );
}
