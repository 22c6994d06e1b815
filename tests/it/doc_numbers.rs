//! The numbers the README and the docs quote come out of the commands written
//! beside them (issue 39: quoted numbers had drifted from what the commands
//! give). Each test runs the documented command (same seed, same photons) and
//! checks that the docs quote what it prints, to the digits they show. The cheap
//! ones run with the suite; the expensive ones (10 million photons) are ignored
//! here and run by `scripts/doc_numbers.sh`, which re-derives every checked
//! number.

use crate::common::{repo, run_ok, traxer};
use std::path::Path;

/// A doc's text with every run of whitespace one space (quotes span lines).
fn doc(file: &str) -> String {
    let text = std::fs::read_to_string(repo().join(file)).unwrap();
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Checks that `file` quotes `text` (whitespace-insensitive).
fn assert_quoted(file: &str, text: &str) {
    let text = text.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        doc(file).contains(&text),
        "{file} does not quote what its command gives now: \"{text}\" (update the doc, or find what changed the result)"
    );
}

fn csv_rows(path: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect()
}

/// The stdout of `traxer ARGS` run in the repository, written to `out`.
fn stdout(args: &[&str], out: &Path) -> String {
    let o = run_ok(traxer().current_dir(repo()).args(args).arg("-o").arg(out));
    String::from_utf8(o.stdout).unwrap()
}

#[test]
fn the_effective_area_numbers_of_the_docs_come_out_of_their_command() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("area");
    stdout(
        &[
            "effective-area",
            "scenes/llnl_effective_area.toml",
            "--energies",
            "1:10:0.1",
            "--angles",
            "0:10:2.5",
            "-q",
        ],
        &out,
    );
    // effective_area.csv: angle, energy, area, error, ...
    let rows = csv_rows(&out.join("effective_area.csv"));
    let at = |angle: f64, energy: f64| {
        rows.iter()
            .find(|r| r[0] == angle && (r[1] - energy).abs() < 1e-9)
            .unwrap()
            .clone()
    };
    // off_axis.csv: angle, cx, cy, hpd, d80, d90, hpd″, d80″, d90″, photons, geometric
    let off = csv_rows(&out.join("off_axis.csv"));
    let (on, far) = (&off[0], &off[4]);
    let peak = at(0.0, 1.4);
    assert_quoted(
        "README.md",
        &format!(
            "collect {:.2} cm² geometrically and {:.2} ± {:.2} cm² at 1.4 keV",
            on[10], peak[2], peak[3]
        ),
    );
    let telescope = "docs/telescope.md";
    assert_quoted(
        telescope,
        &format!(
            "collect {:.2} cm² geometrically; with the coatings the area is {:.2} ± {:.2} cm² at 1.4 keV",
            on[10], peak[2], peak[3]
        ),
    );
    assert_quoted(
        telescope,
        &format!("at 1.4 keV {:.2} cm² at 2.5′", at(2.5, 1.4)[2]),
    );
    assert_quoted(telescope, &format!("({:.2} cm² at 10′)", at(10.0, 1.4)[2]));
    assert_quoted(
        telescope,
        &format!("the image moves {:.2} mm per 2.5′", (far[1] - on[1]) / 4.0),
    );
    assert_quoted(
        telescope,
        &format!(
            "HPD shrinks from {:.1}″ to {:.1}″ while the 90 % diameter grows from {:.0}″ to {:.0}″",
            on[6], far[6], on[8], far[8]
        ),
    );
    let core = dir.path().join("core");
    stdout(
        &[
            "effective-area",
            "scenes/llnl_effective_area.toml",
            "--energies",
            "1.5",
            "--angles",
            "0",
            "--radius",
            "1",
            "-q",
        ],
        &core,
    );
    let r = csv_rows(&core.join("effective_area.csv"));
    assert_quoted(
        telescope,
        &format!(
            "({:.2} cm² at 1.5 keV within 1 mm of the image centre",
            r[0][2]
        ),
    );
}

/// The lines of a trace's printout that do not depend on the machine (all but
/// the first, which has the time).
fn printout(out: &str) -> Vec<String> {
    out.lines()
        .skip(1)
        .filter(|l| !l.starts_with("wrote"))
        .map(|l| match l.find(", escaped") {
            // The README shortens the fates line after the figure-error count.
            Some(k) if l.contains("reached a sensor") => format!("{}, ...", &l[..k]),
            _ => l.to_string(),
        })
        .collect()
}

#[test]
fn the_readme_printouts_and_the_strongback_numbers_come_out_of_their_commands() {
    let dir = tempfile::tempdir().unwrap();
    let panter = stdout(
        &["trace", "scenes/panter_al_ka.toml", "-n", "4e6"],
        &dir.path().join("panter"),
    );
    for line in printout(&panter) {
        assert_quoted("README.md", &line);
    }
    let cast = stdout(
        &[
            "trace",
            "scenes/cast_axion_image.toml",
            "-n",
            "1e6",
            "--fits",
        ],
        &dir.path().join("cast"),
    );
    for line in printout(&cast) {
        assert_quoted("README.md", &line);
    }
    // The sky WCS's measured plate scale and turn.
    let sky: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("cast/chip.json")).unwrap())
            .unwrap();
    let sky = &sky["sensor"]["sky_wcs"];
    let f = |k: &str| sky[k].as_f64().unwrap();
    assert_quoted(
        "README.md",
        &format!(
            "{:.4} ± {:.4} mm per arcmin ({:.0} % of f·θ), the image turned by {:.1}°",
            f("plate_scale_mm_per_arcmin"),
            f("plate_scale_error_mm_per_arcmin"),
            100.0 * f("plate_scale_mm_per_arcmin") / (1500.0 * std::f64::consts::PI / 180.0 / 60.0),
            f("rotation_deg")
        )
        .replace('-', "−"),
    );
    // The strongback as built: what the README and docs/cast.md say it changes.
    stdout(
        &[
            "trace",
            "scenes/cast_axion_image.toml",
            "-n",
            "1e6",
            "-D",
            "strongback_nm=200000",
        ],
        &dir.path().join("strongback"),
    );
    let json = |name: &str| -> serde_json::Value {
        serde_json::from_str(
            &std::fs::read_to_string(dir.path().join(name).join("chip.json")).unwrap(),
        )
        .unwrap()
    };
    let (off, on) = (json("cast"), json("strongback"));
    let flux = |v: &serde_json::Value| v["sensor"]["total_flux"].as_f64().unwrap();
    let hpd = |v: &serde_json::Value| v["sensor"]["image_quality"]["hpd_arcsec"].as_f64().unwrap();
    let less = 100.0 * (1.0 - flux(&on) / flux(&off));
    let smaller = 100.0 * (1.0 - hpd(&on) / hpd(&off));
    assert_quoted(
        "README.md",
        &format!(
            "{less:.1} % less flux on the chip ({:.4e} instead of {:.4e} X-rays/s) and an HPD of {:.1}″ instead of {:.1}″ (−{smaller:.1} %",
            flux(&on),
            flux(&off),
            hpd(&on),
            hpd(&off)
        ),
    );
    assert_quoted(
        "docs/cast.md",
        &format!(
            "loses {less:.1} % of its flux on the chip, {:.4e} → {:.4e} s⁻¹, and its HPD shrinks {smaller:.1} %, {:.1}″ → {:.1}″",
            flux(&off),
            flux(&on),
            hpd(&off),
            hpd(&on)
        ),
    );
}

#[test]
#[ignore = "expensive (two traces of 10 million photons): scripts/doc_numbers.sh runs it"]
fn the_readme_axion_table_comes_out_of_its_commands() {
    let dir = tempfile::tempdir().unwrap();
    let mut cells: Vec<[String; 3]> = Vec::new();
    for scene in ["cast_axion_image", "cast_axion_electron_image"] {
        let out = dir.path().join(scene);
        stdout(
            &[
                "trace",
                &format!("scenes/{scene}.toml"),
                "-n",
                "1e7",
                "-q",
                "-D",
                "magnet=false",
            ],
            &out,
        );
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("chip.json")).unwrap()).unwrap();
        let s = &v["sensor"];
        let q = |k: &str| s["image_quality"][k].as_f64().unwrap();
        cells.push([
            format!("{:.2e} s⁻¹", s["total_flux"].as_f64().unwrap()),
            format!(
                "{:.1}″ / {:.1}″ / {:.1}″",
                q("hpd_arcsec"),
                q("d80_arcsec"),
                q("d90_arcsec")
            ),
            format!(
                "{:.2} mm",
                s["conversion"]["median_depth_mm"].as_f64().unwrap()
            ),
        ]);
    }
    for (k, row) in [
        "| on the chip (converting in the gas) |",
        "| HPD / 80 % / 90 % |",
        "| conversion depth behind the window: median |",
    ]
    .iter()
    .enumerate()
    {
        assert_quoted(
            "README.md",
            &format!("{row} {} | {} |", cells[0][k], cells[1][k]),
        );
    }
}

/// `x` written with as many digits after the point, in exponent form, as
/// `quoted` (e.g. "1.128e9" → three).
fn like(x: f64, quoted: &str) -> String {
    let mantissa = quoted.split('e').next().unwrap();
    let digits = mantissa.split('.').nth(1).map_or(0, str::len);
    format!("{x:.digits$e}")
}

#[test]
fn the_abc_flux_table_of_docs_cast_comes_out_of_its_command() {
    let dir = tempfile::tempdir().unwrap();
    let out = run_ok(
        traxer()
            .current_dir(repo())
            .args(["solar-flux", "--emission", "abc", "-o"])
            .arg(dir.path().join("abc")),
    );
    let printed = String::from_utf8(out.stdout).unwrap();
    let flux = |process: &str| -> f64 {
        printed
            .lines()
            .find(|l| l.split_whitespace().next() == Some(process))
            .and_then(|l| l.split_whitespace().nth(1))
            .unwrap_or_else(|| panic!("{process} in {printed}"))
            .parse()
            .unwrap()
    };
    let cast = doc("docs/cast.md");
    for (row, process) in [
        (
            "| atomic (free–bound, bound–bound, metals' free–free) |",
            "atomic",
        ),
        ("| electron–ion bremsstrahlung |", "electron_ion"),
        ("| electron–electron bremsstrahlung |", "electron_electron"),
        ("| Compton |", "compton"),
        ("| total, 0.1–15 keV |", "abc"),
    ] {
        let at = cast
            .find(row)
            .unwrap_or_else(|| panic!("docs/cast.md has no row {row}"));
        let quoted = cast[at + row.len()..].split('|').next().unwrap().trim();
        assert_eq!(
            like(flux(process), quoted),
            quoted,
            "docs/cast.md {row} quotes {quoted}, the command gives {}",
            flux(process)
        );
    }
}

/// The probabilities `traxer conversion ARGS` prints.
fn conversion(args: &str) -> Vec<f64> {
    let o = run_ok(
        traxer()
            .current_dir(repo())
            .arg("conversion")
            .args(args.split(' '))
            .arg("-q"),
    );
    String::from_utf8(o.stdout)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(2).unwrap().parse().unwrap())
        .collect()
}

#[test]
fn the_magnet_numbers_of_docs_magnet_come_out_of_their_commands() {
    let table = [
        (
            "--field-t 9 --length-m 9.26 --g-agamma 1e-10 --energies 4",
            "| CAST, 9 T over 9.26 m |",
        ),
        (
            "--field-map bykovskiy_201906 --g-agamma 1e-10 --energies 4",
            "| BabyIAXO's map, on the bore's axis |",
        ),
        (
            "--field-map bykovskiy_201906 --g-agamma 1e-10 --energies 4 --bore-average",
            "| BabyIAXO's map, averaged over the 700 mm bore |",
        ),
        (
            "--field-t 2 --length-m 10 --g-agamma 1e-10 --energies 4",
            "| a uniform 2 T over 10 m |",
        ),
    ];
    let mut p = Vec::new();
    for (args, row) in table {
        assert_quoted("docs/magnet.md", &format!("traxer conversion {args}"));
        let v = conversion(args)[0];
        assert_quoted("docs/magnet.md", &format!("{row} {v:.4e} |"));
        p.push(v);
    }
    // The equivalent fields and the map's share of a uniform 2 T.
    let b = |x: f64| 2.0 * (x / p[3]).sqrt();
    assert_quoted(
        "docs/magnet.md",
        &format!("| {:.4e} | {:.2} T over 10 m |", p[1], b(p[1])),
    );
    assert_quoted(
        "docs/magnet.md",
        &format!("| {:.4e} | {:.2} T over 10 m |", p[2], b(p[2])),
    );
    assert_quoted(
        "docs/magnet.md",
        &format!(
            "converts {:.0} % of what a uniform 2 T",
            100.0 * p[2] / p[3]
        ),
    );
    assert_quoted(
        "docs/magnet.md",
        &format!("({:.0} % on the axis)", 100.0 * p[1] / p[3]),
    );
    // The helium table.
    let args = "--field-map bykovskiy_201906 --energies 2,4,8 --masses 0.3,0.333 --gas He --pressure-mbar 10 --temperature-k 1.8 --bore-average";
    assert_quoted("docs/magnet.md", &format!("traxer conversion {args}"));
    let he = conversion(args);
    for (k, e) in [2, 4, 8].iter().enumerate() {
        assert_quoted(
            "docs/magnet.md",
            &format!("| {e} keV | {:.1e} | {:.2e} |", he[2 * k], he[2 * k + 1]),
        );
    }
}

#[test]
#[ignore = "expensive (two BabyIAXO traces of 1e6 photons through the field map): scripts/doc_numbers.sh runs it"]
fn the_traced_x_ray_rates_of_docs_magnet_come_out_of_their_commands() {
    let dir = tempfile::tempdir().unwrap();
    for (k, defines) in [
        &["-D", "magnet=true"][..],
        &[
            "-D",
            "magnet=true",
            "-D",
            "emission=primakoff",
            "-D",
            "g_agamma=1e-10",
        ][..],
    ]
    .iter()
    .enumerate()
    {
        let mut args = vec!["trace", "scenes/babyiaxo_axion_image.toml"];
        args.extend_from_slice(defines);
        args.extend_from_slice(&["-n", "1e6"]);
        let out = stdout(&args, &dir.path().join(format!("t{k}")));
        let line = out.lines().find(|l| l.contains("X-rays/s")).unwrap();
        let quoted = line.split("photons, ").nth(1).unwrap().trim();
        assert_quoted("docs/magnet.md", quoted);
        if k == 1 {
            assert_quoted("README.md", quoted);
        }
    }
}

/// The rows `traxer reach` prints, as docs/magnet.md's table writes them:
/// (setting's first two words or "vacuum", mass, the four numbers).
fn reach_rows(out: &str) -> Vec<String> {
    out.lines()
        .skip(1)
        .map(|l| {
            let (setting, numbers) = match l.strip_prefix("He ") {
                Some(rest) => {
                    let p = rest.split_whitespace().next().unwrap();
                    (format!("He {p} mbar"), l.rsplit(')').next().unwrap())
                }
                None => ("vacuum".to_string(), l.trim_start_matches("vacuum")),
            };
            let v: Vec<&str> = numbers.split_whitespace().collect();
            format!("| {setting} | {} |", v.join(" | "))
        })
        .collect()
}

#[test]
#[ignore = "expensive (four traces of 1e6 photons, BabyIAXO's through its field map): scripts/doc_numbers.sh runs it"]
fn the_reach_numbers_of_docs_magnet_come_out_of_their_commands() {
    let dir = tempfile::tempdir().unwrap();
    let d = |n: &str| dir.path().join(n).to_str().unwrap().to_string();
    let common = [
        "-n",
        "1e6",
        "-q",
        "-D",
        "magnet=true",
        "-D",
        "emission=primakoff",
        "-D",
        "g_agamma=1e-10",
        "-D",
        "pixels=300",
        "-D",
        "energy_bins=[1,10,9]",
    ];
    let trace = |scene: &str, extra: &[&str], out: &str| {
        let mut args = vec!["trace", scene];
        args.extend_from_slice(&common);
        args.extend_from_slice(extra);
        stdout(&args, Path::new(&d(out)));
    };
    let bx = "scenes/babyiaxo_axion_image.toml";
    trace(
        bx,
        &[
            "--masses",
            "0,0.001,0.002,0.005,0.01,0.015,0.02,0.03,0.04,0.05,0.07,0.1",
        ],
        "vac",
    );
    // The script's helium settings: masses m_γ (1 + s k / 4), k = −4..4.
    for (p, span) in [("1", 0.04), ("10", 0.008)] {
        let m = 0.3331 * (p.parse::<f64>().unwrap() / 10.0).sqrt();
        let masses: Vec<String> = (-4..=4)
            .map(|k| format!("{:.6}", m * (1.0 + span * k as f64 / 4.0)))
            .collect();
        // The scene's mass is the setting's m_γ (the middle one): the region
        // lies on the resonant image.
        let (he, first) = (
            format!("helium_mbar={p}"),
            format!("axion_mass_ev={}", masses[4]),
        );
        let list = masses.join(",");
        trace(
            bx,
            &[
                "-D",
                &he,
                "-D",
                "helium_k=1.8",
                "-D",
                &first,
                "--masses",
                &list,
            ],
            p,
        );
    }
    let reach = |runs: &[String], extra: &[&str], out: &str| {
        let mut args: Vec<&str> = vec!["reach"];
        args.extend(runs.iter().map(String::as_str));
        args.extend_from_slice(&["--fraction", "0.8", "--window", "1,7"]);
        args.extend_from_slice(extra);
        reach_rows(&stdout(&args, Path::new(&d(out))))
    };
    let rows = reach(
        &[d("vac"), d("1"), d("10")],
        &[
            "--background",
            "1e-7",
            "--bores",
            "2",
            "--tracking-hours",
            "6574.5,100,100",
        ],
        "r",
    );
    for mass in [
        "| 0 |",
        "| 0.01 |",
        "| 0.02 |",
        "| 0.05 |",
        "| 0.105335 |",
        "| 0.3331 |",
    ] {
        let row = rows.iter().find(|r| r.contains(mass)).unwrap();
        assert_quoted("docs/magnet.md", row);
    }
    let plateau: f64 = rows[0]
        .split(" | ")
        .nth(5)
        .unwrap()
        .trim_end_matches(" |")
        .parse()
        .unwrap();
    assert_quoted(
        "README.md",
        &format!("{plateau:.2e} GeV⁻¹ on\nBabyIAXO's vacuum plateau"),
    );
    trace(
        "scenes/cast_axion_image.toml",
        &[
            "--masses",
            "0,0.002,0.005,0.01,0.015,0.02,0.03,0.04,0.05,0.07,0.1",
        ],
        "cast",
    );
    let cast = reach(
        &[d("cast")],
        &["--background", "1e-6", "--tracking-hours", "300"],
        "rc",
    );
    let plateau = cast[0].split(" | ").nth(5).unwrap().trim_end_matches(" |");
    assert_quoted("docs/magnet.md", &format!("g_aγ < {plateau} GeV⁻¹"));
}
