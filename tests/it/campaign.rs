//! A campaign from one trace: the planner against REST's rule and the closed
//! form of a uniform field, each (setting, mass) tally against a direct trace
//! at that setting, exact sums across parts of a run, and bad campaigns
//! refused by key.

use crate::common::{device, repo, write};
use traxer::scene::Scene;
use traxer::trace::{run, RunConfig};

/// BabyIAXO's scene with `campaign` appended as its magnet's campaign.
pub fn babyiaxo_with(dir: &std::path::Path, campaign: &str) -> std::path::PathBuf {
    let text = without_campaign();
    write(
        dir,
        "c.toml",
        &format!("{text}\n[magnet.campaign]\n{campaign}\n"),
    )
}

/// BabyIAXO's scene without its own campaign table.
fn without_campaign() -> String {
    let text = std::fs::read_to_string(repo().join("scenes/babyiaxo_axion_image.toml")).unwrap();
    let cut = text
        .find("\n[magnet.campaign]")
        .expect("the scene has a campaign");
    text[..cut].to_string()
}

pub const SMALL: &str = "temperature_k = 1.8\npressures_mbar = [1.0, 3.0]\nvacuum_masses = 3\nmasses_per_step = 2\nvacuum_hours = 100.0\ngas_hours = 200.0\nenergy_kev = [1.0, 10.0, 6]\nrings_mm = [20.0, 8]\nsees = 0.05\n";

fn load(path: &std::path::Path, defines: &[&str]) -> Result<Scene, String> {
    let d: Vec<String> = defines.iter().map(|s| s.to_string()).collect();
    Scene::load(&device(), path, &d).map_err(|e| e.to_string())
}

#[test]
fn each_settings_tally_is_a_direct_trace_at_that_setting() {
    let dir = tempfile::tempdir().unwrap();
    let path = babyiaxo_with(dir.path(), SMALL);
    let defines = ["magnet=true", "emission=primakoff", "pixels=100"];
    let scene = load(&path, &defines).unwrap();
    let c = traxer::output::campaign::campaign_of(&scene)
        .unwrap()
        .clone();
    assert_eq!(c.settings.len(), 3);
    let cfg = RunConfig::new(6000, 7);
    let result = run(&scene, &cfg).unwrap();
    let tally = result.campaign[0].values();
    let bins = c.bins();
    // Every pair of the 3.0 mbar setting, and the vacuum's lightest mass.
    let mut checked = 0;
    for (k, &(s, m)) in c.pairs.iter().enumerate() {
        let setting = &c.settings[s as usize];
        if !(setting.pressure_mbar() == 3.0 || (s == 0 && m == 0)) {
            continue;
        }
        let mass = c.masses[m as usize];
        let direct_defines = [
            "magnet=true".to_string(),
            "emission=primakoff".into(),
            "pixels=100".into(),
            format!("helium_mbar={}", setting.pressure_mbar()),
            "helium_k=1.8".into(),
            format!("axion_mass_ev={mass:e}"),
        ];
        let text =
            std::fs::read_to_string(repo().join("scenes/babyiaxo_axion_image.toml")).unwrap();
        let plain = write(dir.path(), "d.toml", &text);
        let d = Scene::load(&device(), &plain, &direct_defines).unwrap();
        let mut dcfg = cfg.clone();
        dcfg.photon_list = 1_000_000;
        let direct = run(&d, &dcfg).unwrap();
        let mut binned = vec![0.0; bins];
        for p in &direct.photons {
            if let Some(b) = c.bin([p.local.x, p.local.y], p.record.energy) {
                binned[b] += p.record.weight;
            }
        }
        let ours = &tally[k * bins..(k + 1) * bins];
        let largest = binned.iter().copied().fold(0.0, f64::max);
        assert!(largest > 0.0, "pair {k}: no photons");
        for (a, b) in ours.iter().zip(&binned) {
            assert!(
                (a - b).abs() <= 1e-9 * largest,
                "pair {k} ({}, {mass} eV): {a:e} vs {b:e}",
                setting.label()
            );
        }
        checked += 1;
    }
    assert!(checked >= 3, "{checked} pairs checked");
}

#[test]
fn parts_of_a_campaign_add_up_to_its_bits() {
    let dir = tempfile::tempdir().unwrap();
    let path = babyiaxo_with(dir.path(), SMALL);
    let scene = load(&path, &["magnet=true", "emission=primakoff", "pixels=100"]).unwrap();
    let whole = run(&scene, &RunConfig::new(8192, 3)).unwrap();
    let mut parts = Vec::new();
    for (first, n) in [(0, 4096), (4096, 4096)] {
        let mut cfg = RunConfig::new(n, 3);
        cfg.first_photon = first;
        cfg.threads = 1;
        parts.push(run(&scene, &cfg).unwrap());
    }
    let mut sum = parts[1].campaign[0].clone();
    sum.add(&parts[0].campaign[0]);
    assert_eq!(sum, whole.campaign[0]);
    assert!(sum.values().iter().any(|v| *v > 0.0));
}

#[test]
fn the_planner_starts_where_a_uniform_fields_vacuum_p_halves() {
    // A uniform field over L: P ∝ sinc²(qL/2), half at qL/2 = 1.391557
    // (sin x / x = 1/√2), q = m²/2E: the first setting's photon mass is
    // √(4 · 1.391557 E / L), here from the bore's 10 m and 4.2 keV.
    let dir = tempfile::tempdir().unwrap();
    let text = without_campaign().replace("field_map = \"bykovskiy_201906\"", "field_t = 2.0");
    let path = write(
        dir.path(),
        "u.toml",
        &format!("{text}\n[magnet.campaign]\ntemperature_k = 1.8\nplan = {{ up_to_ev = 0.05 }}\nvacuum_hours = 1.0\ngas_hours = 1.0\n"),
    );
    let scene = load(&path, &["magnet=true"]).unwrap();
    let c = traxer::output::campaign::campaign_of(&scene).unwrap();
    let length: f64 = 10.0 / 1.973_269_804e-7; // eV⁻¹
    let first: f64 = (4.0 * 1.391_557 * 4200.0 / length).sqrt();
    assert!(
        (c.settings[1].photon_mass_ev / first - 1.0).abs() < 1e-5,
        "{} vs {first}",
        c.settings[1].photon_mass_ev
    );
    // Each step is FWHM / (e^(−m·20) + 1): the half width of setting k's
    // resonance lies at half the step times that factor above it, where
    // the uniform field's closed form (with helium's attenuation) is half
    // its peak.
    let magnet = scene.magnet.as_deref().unwrap();
    for k in 1..c.settings.len() - 1 {
        let (m, next) = (
            c.settings[k].photon_mass_ev,
            c.settings[k + 1].photon_mass_ev,
        );
        let f = (-m * 20.0).exp() + 1.0;
        let half = m + 0.5 * (next - m) * f;
        let gas = c.settings[k].gas.as_ref().unwrap();
        let gamma = gas.attenuation_ev(4.2).unwrap();
        let p = |ma: f64| {
            let q = (ma * ma - gas.photon_mass2_ev2).abs() / 8400.0;
            traxer::magnet::conversion::uniform_probability(
                magnet.g_agamma_gev * 1e-9,
                2.0 * 195.3537,
                length,
                q,
                gamma,
            )
        };
        assert!(
            (p(half) / p(m) - 0.5).abs() < 1e-4,
            "setting {k}: {}",
            p(half) / p(m)
        );
    }
}

#[test]
fn bad_campaigns_are_refused_by_key() {
    let dir = tempfile::tempdir().unwrap();
    for (campaign, says) in [
        ("temperature_k = 1.8\npressures_mbar = [2.0, 1.0]\nvacuum_hours = 1.0\ngas_hours = 1.0", "is not above entry 1"),
        ("temperature_k = 1.8\npressures_mbar = []\nvacuum_hours = 1.0\ngas_hours = 1.0", "no gas settings"),
        ("temperature_k = 1.8\npressures_mbar = [500.0]\nvacuum_hours = 1.0\ngas_hours = 1.0", "would be liquid"),
        ("temperature_k = 1.8\nplan = { up_to_ev = 0.001 }\nvacuum_hours = 1.0\ngas_hours = 1.0", "ask for a heavier mass"),
        ("temperature_k = 1.8\npressures_mbar = [1.0, 2.0]\nfractions = [0.5, 0.6]\nvacuum_hours = 1.0\ngas_hours = 1.0", "together 1"),
        ("temperature_k = 1.8\nplan = { up_to_ev = 0.25 }\nmasses_per_step = 200\nrings_mm = [20.0, 100]\nvacuum_hours = 1.0\ngas_hours = 1.0", "tallied sums, more than"),
        ("temperature_k = 1.8\nvacuum_hours = 1.0\ngas_hours = 1.0", "plan = { up_to_ev"),
        ("temperature_k = -1.0\npressures_mbar = [1.0]\nvacuum_hours = 1.0\ngas_hours = 1.0", "temperature_k"),
        ("temperature_k = 1.8\npressures_mbar = [1.0]\ncentre_mm = [nan, 0.0]\nvacuum_hours = 1.0\ngas_hours = 1.0", "centre_mm"),
        ("temperature_k = 1.8\npressures_mbar = [1e300]\nvacuum_hours = 1.0\ngas_hours = 1.0", "campaign"),
        ("temperature_k = 1.8\npressures_mbar = [1.0]\nvacuum_hours = nan\ngas_hours = 1.0", "vacuum_hours"),
    ] {
        let path = babyiaxo_with(dir.path(), campaign);
        let e = load(&path, &["magnet=true"]).err().unwrap_or_else(|| panic!("accepted: {}", campaign.replace('\n', "; ")));
        assert!(e.contains("campaign") && e.contains(says), "{campaign}:\n{e}");
    }
}

#[test]
fn on_rests_planning_field_the_planner_gives_rests_73_helium_settings() {
    // REST-for-Physics' BabyIAXO sensitivity example plans "73 density
    // settings that extend the axion search up to 0.25 eV" (axionlib's
    // sensitivity examples README) on a uniform 1.73 T over 10 m; traxer's
    // planner on the same field (plan_field_t) must give as many, and on the
    // scene's field map fewer, wider steps over the same range.
    let scene = repo().join("scenes/babyiaxo_axion_image.toml");
    let base = [
        "magnet=true",
        "campaign=true",
        "emission=primakoff",
        "campaign_sees=0.05",
    ];
    let count = |extra: &[&str]| {
        let d: Vec<&str> = base.iter().chain(extra).copied().collect();
        let s = load(&scene, &d).unwrap();
        let c = traxer::output::campaign::campaign_of(&s).unwrap();
        let gas: Vec<f64> = c
            .settings
            .iter()
            .filter(|s| s.gas.is_some())
            .map(|s| s.photon_mass_ev)
            .collect();
        (gas.len(), gas[gas.len() - 1])
    };
    let (rest, last) = count(&[]);
    assert_eq!(rest, 73, "REST's plan: 73 helium settings");
    assert!((0.25..0.26).contains(&last), "last setting {last} eV");
    let (map, last) = count(&["plan_field_t=0"]);
    assert!((60..73).contains(&map), "the map's plan: {map} settings");
    assert!((0.25..0.26).contains(&last), "last setting {last} eV");
    for bad in ["plan_field_t=-1", "plan_field_t=nan"] {
        let d: Vec<&str> = base.iter().chain(&[bad]).copied().collect();
        let e = load(&scene, &d).err().expect(bad);
        assert!(e.contains("field_t"), "{bad}: {e}");
    }
}

#[test]
fn the_ksvz_allocation_is_rests_rule() {
    // REST's BabyIAXO gas phase (axionlib examples/03.IAXO,
    // GenerateSignalComponents("BabyIAXO.rml", "GasSignal", 1.5, 5, 0.5)):
    // the first 5 settings share 0.5 of the 1.5 years equally, every later
    // one a share of the rest ∝ 1 / (m⁴ S). Checked on arbitrary rates S: the
    // defaults, then 2 first settings with 0.4 of the time.
    let dir = tempfile::tempdir().unwrap();
    let pressures = "pressures_mbar = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0]";
    for (extra, first, share) in [
        ("", 5, 1.0 / 3.0),
        ("ksvz_first_settings = 2\nksvz_first_share = 0.4\n", 2, 0.4),
    ] {
        let campaign = format!("temperature_k = 1.8\n{pressures}\nvacuum_hours = 100.0\ngas_hours = 300.0\nallocation = \"ksvz\"\n{extra}");
        let scene = load(&babyiaxo_with(dir.path(), &campaign), &["magnet=true"]).unwrap();
        let c = traxer::output::campaign::campaign_of(&scene).unwrap();
        assert_eq!(c.settings.len(), 9);
        let signal: Vec<f64> = (0..9).map(|s| 1.0 + ((s * 7919) % 13) as f64).collect();
        let hours = c.hours(&signal);
        assert_eq!(hours[0], 100.0, "the vacuum's hours");
        let gas = &hours[1..];
        for h in &gas[..first] {
            assert!((h - 300.0 * share / first as f64).abs() < 1e-9, "{gas:?}");
        }
        let ksvz = |s: usize| hours[s] * c.settings[s].photon_mass_ev.powi(4) * signal[s];
        for s in first + 2..9 {
            assert!(
                (ksvz(s) / ksvz(first + 1) - 1.0).abs() < 1e-12,
                "{s}: {gas:?}"
            );
        }
        let later: f64 = gas[first..].iter().sum();
        assert!((later - 300.0 * (1.0 - share)).abs() < 1e-9, "{later}");
    }
    let campaign = format!("temperature_k = 1.8\n{pressures}\nvacuum_hours = 1.0\ngas_hours = 1.0\nallocation = \"ksvz\"\nksvz_first_share = 1.0");
    let e = load(&babyiaxo_with(dir.path(), &campaign), &["magnet=true"])
        .err()
        .unwrap();
    assert!(e.contains("ksvz_first_share"), "{e}");
}
