//! `-q` means the same for every command: no progress bar and no notes on
//! stderr, and on stdout only the result (nothing for commands whose result is
//! files: trace, tessellate, merge, render). Each command is run on valid input
//! with `-q` and an empty reflectivity cache (so the table notes would appear).

use crate::common::{repo, run_ok, traxer};

#[test]
fn quiet_commands_say_nothing_on_stderr() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let wolter = repo().join("scenes/wolter1_parallel.toml");
    let area = repo().join("scenes/llnl_effective_area.toml");
    let p = |s: &str| t.join(s).to_str().unwrap().to_string();
    let w = wolter.to_str().unwrap().to_string();
    let commands: Vec<(Vec<String>, bool)> = vec![
        (
            vec![
                "trace".into(),
                w.clone(),
                "-n".into(),
                "3000".into(),
                "--out".into(),
                p("tr"),
            ],
            true,
        ),
        (
            vec![
                "trace".into(),
                w.clone(),
                "-n".into(),
                "3000".into(),
                "--shard".into(),
                "1/2".into(),
                "--out".into(),
                p("s1"),
            ],
            true,
        ),
        (
            vec![
                "trace".into(),
                w.clone(),
                "-n".into(),
                "3000".into(),
                "--shard".into(),
                "2/2".into(),
                "--out".into(),
                p("s2"),
            ],
            true,
        ),
        (
            vec!["merge".into(), p("s1"), p("s2"), "--out".into(), p("mg")],
            true,
        ),
        (
            vec!["tessellate".into(), w.clone(), "--out".into(), p("tess")],
            true,
        ),
        (vec!["inspect".into(), p("tess/sensor.obj")], false),
        (vec!["info".into()], false),
        (
            vec![
                "reflectivity".into(),
                "--coating".into(),
                "gold".into(),
                "--energy".into(),
                "1,2".into(),
                "--angle".into(),
                "0:2:0.1".into(),
                "--plot".into(),
                p("r.png"),
            ],
            false,
        ),
        (
            vec![
                "eef".into(),
                p("tr/sensor.npy"),
                "--plot".into(),
                p("sensor_eef.png"),
            ],
            false,
        ),
        (vec!["solar-flux".into(), "--out".into(), p("sf")], false),
        (
            vec![
                "render".into(),
                w.clone(),
                "--width".into(),
                "24".into(),
                "--height".into(),
                "16".into(),
                "--look-from".into(),
                "0,300,3200".into(),
                "--look-at".into(),
                "0,0,3000".into(),
                "--out".into(),
                p("r2.png"),
            ],
            true,
        ),
        (
            vec![
                "focus".into(),
                w.clone(),
                "--var".into(),
                "focus_shift".into(),
                "--from".into(),
                "-2".into(),
                "--to".into(),
                "2".into(),
                "--steps".into(),
                "4".into(),
                "-n".into(),
                "3000".into(),
                "--out".into(),
                p("fo"),
            ],
            false,
        ),
        (
            vec![
                "effective-area".into(),
                area.to_str().unwrap().into(),
                "--energies".into(),
                "1,2".into(),
                "-n".into(),
                "3000".into(),
                "--out".into(),
                p("ea"),
            ],
            false,
        ),
        (
            vec!["bench".into(), w.clone(), "-n".into(), "3000".into()],
            false,
        ),
    ];
    for (args, files_only) in commands {
        let out = run_ok(
            traxer()
                .env("TRAXER_CACHE", t.join("cache"))
                .args(&args)
                .arg("-q"),
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.is_empty(),
            "traxer {} -q said on stderr: {err}",
            args[0]
        );
        if files_only {
            assert!(
                out.stdout.is_empty(),
                "traxer {} -q printed: {}",
                args[0],
                String::from_utf8_lossy(&out.stdout)
            );
        }
    }
}
