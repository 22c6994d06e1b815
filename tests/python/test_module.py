"""The Python module `traxer` (python/, installed by scripts/test-python.sh with
`pip install ./python`) against the `traxer` binary built from the same sources:

- the same scene and seed give the CLI's images, counts, photon list, statistics
  and image quality bit for bit, and `save` writes byte-identical arrays, PNGs and
  CSVs; the images do not depend on `threads`;
- reflectivity, effective area and solar emission equal the CLI's numbers;
- `eef` gives the closed-form diameters of a uniform disk;
- bad input raises SceneError (with file, line and message) or InputError,
  never a crash; the GIL is released while tracing and Ctrl-C stops a run.

TRAXER names the binary (default: target/release/traxer).
"""

import csv
import io
import json
import math
import os
import pathlib
import shutil
import subprocess
import threading
import time
import _thread

import numpy as np
import pytest

import traxer

REPO = pathlib.Path(__file__).resolve().parents[2]
BIN = os.environ.get("TRAXER", str(REPO / "target" / "release" / "traxer"))
WOLTER = REPO / "scenes" / "wolter1_parallel.toml"
CAST = REPO / "scenes" / "cast_axion_image.toml"
BABYIAXO = REPO / "scenes" / "babyiaxo_axion_image.toml"
PANTER = REPO / "scenes" / "panter_al_ka.toml"
LLNL_AREA = REPO / "scenes" / "llnl_effective_area.toml"
SOLAR_MODEL = REPO.parent / "shared" / "solar" / "SolarModel_B16-AGSS09met.dat"


def cli(*args):
    out = subprocess.run([BIN, *map(str, args)], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return out


def binned_scene(tmp):
    """The Wolter-I scene with a 120 × 90 sensor (x and y cannot swap unnoticed)
    with 3 energy bands (a [band, iy, ix] cube) and a focal length (arcsec)."""
    text = WOLTER.read_text().replace('"../meshes/', '"%s/' % (REPO / "meshes"))
    assert "pixels = [512, 512]" in text
    text = text.replace(
        "pixels = [512, 512]",
        "pixels = [120, 90]\nenergy_bins = [1.0, 2.0, 3]\nfocal_length = 1500.0",
    )
    path = tmp / "binned.toml"
    path.write_text(text)
    return path


# Each case: scene, CLI -D definitions and the same as Python defines, photons,
# seed, photon list. CAST has a Sun (images in axions/s), a pixel grid, foils.
CASES = {
    "wolter": (WOLTER, ["off_axis=0.02", "coating=gold"], {"off_axis": 0.02, "coating": "gold"},
               150_000, 7, 50),
    "cast": (CAST, ["window_nm=150"], {"window_nm": 150.0}, 100_000, 3, 0),
    # A dict is an inline table: the mirrors' roughness PSD.
    "panter_rough": (
        PANTER,
        ['roughness={ psd = { type = "power_law", k = 0.02, n = 1.5 }, band_per_um = [0.001, 1.0] }'],
        {"roughness": {"psd": {"type": "power_law", "k": 0.02, "n": 1.5}, "band_per_um": [1e-3, 1.0]}},
        100_000, 5, 0,
    ),
}


@pytest.fixture(scope="module", params=sorted(CASES))
def pair(request, tmp_path_factory):
    """(CLI results folder, Python result, Python saved folder, case)."""
    scene, defs, defines, n, seed, listed = CASES[request.param]
    tmp = tmp_path_factory.mktemp(request.param)
    args = ["trace", scene, "-n", n, "--seed", seed, "--out", tmp / "cli", "-q", "--fits"]
    for d in defs:
        args += ["-D", d]
    if listed:
        args += ["--photon-list", listed]
    cli(*args)
    result = traxer.Scene(scene, defines=defines).trace(n, seed=seed, photon_list=listed)
    result.save(tmp / "py", fits=True)
    return tmp / "cli", result, tmp / "py", request.param


def test_images_equal_the_cli_bit_for_bit(pair):
    out, result, _, _ = pair
    assert list(result.sensors) == [s["name"] for s in json.loads((out / "summary.json").read_text())["sensors"]]
    for name, img in result.sensors.items():
        flux = np.load(out / f"{name}.npy")
        counts = np.load(out / f"{name}_counts.npy")
        assert img.flux.dtype == np.float64 and img.counts.dtype == np.uint64
        assert img.flux.shape == flux.shape and img.flux.tobytes() == flux.tobytes()
        assert img.counts.shape == counts.shape and np.array_equal(img.counts, counts)
        assert img.total_counts > 1000, "too few photons for the comparison to mean anything"


def test_statistics_quality_and_units_equal_the_cli(pair):
    out, result, _, case = pair
    summary = json.loads((out / "summary.json").read_text())
    timing = {"seconds", "threads", "photons_per_second", "sensor_photons_per_second"}
    cli_stats = {k: v for k, v in summary["statistics"].items() if k not in timing}
    py_stats = {k: v for k, v in result.statistics.items() if k not in timing}
    assert py_stats == cli_stats
    for name, img in result.sensors.items():
        sensor = json.loads((out / f"{name}.json").read_text())["sensor"]
        assert img.quality == sensor["image_quality"]
        assert img.quality["hpd_mm"] > 0
        assert list(img.pixel_pitch_mm) == sensor["pixel_pitch_mm"]
        assert img.total_flux == sensor["total_flux"]
    # A Sun makes images in axions per second, the others weighted photons.
    assert {img.unit for img in result.sensors.values()} == {"s-1" if case == "cast" else "ph"}
    for name, img in result.sensors.items():
        conv = json.loads((out / f"{name}.json").read_text())["sensor"]["conversion"]
        if conv is None:
            assert img.conversion is None
            continue
        # The CAST detector's gas: the same numbers as the CLI's, the histogram
        # as its CSV, and the spectrum adding up to the converted flux.
        c = img.conversion
        assert c["median_depth_mm"] == conv["median_depth_mm"]
        assert c["converted_fraction"] == conv["converted_fraction"]
        rows = np.loadtxt(out / f"{name}_conversion_depth.csv", delimiter=",", skiprows=1)
        assert np.allclose(c["depth_flux"], rows[:, 2], rtol=1e-12)
        assert np.isclose(c["depth_flux"].sum(), c["converted_flux"], rtol=1e-9)
        assert np.isclose(c["spectrum"].sum(), c["converted_flux"], rtol=1e-3)
    assert result.provenance["seed"] == summary["provenance"]["seed"]
    assert result.provenance["scene_sha256"] == summary["provenance"]["scene_sha256"]
    assert result.provenance["variables"] == summary["provenance"]["variables"]


def test_photon_list_equals_the_cli(pair):
    out, result, _, case = pair
    if case != "wolter":
        assert result.photons is None
        return
    listed = np.load(out / "photons.npy")
    assert result.photons.dtype == listed.dtype
    assert len(result.photons) == 50 and result.photons.tobytes() == listed.tobytes()


def test_grid_image_in_memory_equals_the_cli_grid_files(pair):
    out, result, _, case = pair
    for name, img in result.sensors.items():
        grid = json.loads((out / f"{name}.json").read_text())["sensor"]["pixel_grid"]
        if grid is None:
            assert img.grid is None
            continue
        g = img.grid
        on_disk = np.load(out / f"{name}_grid.npy")
        assert g.flux.tobytes() == on_disk.tobytes() and g.flux.shape == on_disk.shape
        assert list(g.pixels) == grid["pixels"] and g.pitch_mm == grid["pitch_mm"]
        assert g.flux_on_grid == grid["flux_on_grid"]
        assert g.flux_outside_grid == grid["flux_outside_grid"] >= 0
        # The flux is conserved: on the grid plus beside it is the image's.
        assert math.isclose(g.flux_on_grid + g.flux_outside_grid, img.total_flux, rel_tol=1e-9)
        # Pixel centres: the CSV's, [iy, ix], one pitch apart.
        rows = np.loadtxt(out / f"{name}_grid.csv", delimiter=",", skiprows=1)
        ny, nx = g.flux.shape
        assert np.allclose(g.x_mm.ravel(), rows[:, 2], atol=1e-6)
        assert np.allclose(g.y_mm.ravel(), rows[:, 3], atol=1e-6)
        step = math.hypot(g.x_mm[0, 1] - g.x_mm[0, 0], g.y_mm[0, 1] - g.y_mm[0, 0])
        assert math.isclose(step, g.pitch_mm, rel_tol=1e-9)
        assert not g.flux.flags.writeable
    assert case != "cast" or any(i.grid is not None for i in result.sensors.values())


def test_result_names_its_path_classes_and_lists_energy_kev(pair):
    _, result, _, case = pair
    assert result.classes == ["direct", "front_rear", "front_only", "rear_only", "other"]
    if case == "wolter":
        assert "energy_keV" in result.photons.dtype.names
        assert not result.photons.flags.writeable
        assert set(np.unique(result.photons["class"])) <= set(range(len(result.classes)))


def test_class_images_in_memory_equal_the_cli_class_files(tmp_path):
    text = WOLTER.read_text().replace('"../meshes/', '"%s/' % (REPO / "meshes"))
    assert "pixels = [512, 512]" in text
    text = text.replace("pixels = [512, 512]", "pixels = [64, 64]\nhistory_images = true")
    scene = tmp_path / "classes.toml"
    scene.write_text(text)
    cli("trace", scene, "-n", 20_000, "--seed", 4, "--out", tmp_path / "cli", "-q")
    result = traxer.Scene(scene).trace(20_000, seed=4)
    img = next(iter(result.sensors.values()))
    assert list(img.by_class) == result.classes
    for cls, flux in img.by_class.items():
        on_disk = np.load(tmp_path / "cli" / f"{img.name}_{cls}.npy")
        assert flux.tobytes() == on_disk.tobytes(), cls
    # The classes split the image: they add up to it.
    assert np.allclose(sum(img.by_class.values()), img.flux, rtol=1e-12, atol=0)
    assert img.by_class["front_rear"].sum() > 0.5 * img.total_flux
    # A sensor without history images has none.
    assert traxer.Scene(WOLTER).trace(1000).sensors["sensor"].by_class is None


def test_images_by_process_build_the_image_for_other_couplings(tmp_path):
    """The docs' recipe: one trace of Primakoff + ABC gives the image for any
    couplings. Converted in the magnet (the scene's default) the X-rays scale as
    (g_aγ/g_aγ₀)² × [(g_aγ/g_aγ₀)² × primakoff + (g_ae/g_ae₀)² × abc] (P ∝ g_aγ²);
    either equals a trace with those couplings to 1e-12 of the largest pixel,
    and the images equal the CLI's NAME_PROCESS.npy bit for bit."""
    scene = REPO / "scenes" / "cast_axion_electron_image.toml"
    run = traxer.Scene(scene).trace(30_000, seed=2)  # g_aγ = 1e-12, g_ae = 1e-13
    chip = run["chip"]
    assert list(chip.by_process) == ["primakoff", "abc", "atomic", "electron_ion",
                                     "electron_electron", "compton"]
    assert np.allclose(chip.by_process["primakoff"] + chip.by_process["abc"], chip.flux,
                       rtol=1e-13, atol=0)
    four = sum(chip.by_process[p] for p in ["atomic", "electron_ion", "electron_electron", "compton"])
    assert np.allclose(four, chip.by_process["abc"], rtol=1e-13, atol=0)
    g_agamma, g_ae = 4e-12, 0.5e-13
    axions = (g_agamma / 1e-12) ** 2 * chip.by_process["primakoff"] \
        + (g_ae / 1e-13) ** 2 * chip.by_process["abc"]
    image = (g_agamma / 1e-12) ** 2 * axions
    direct = traxer.Scene(scene, {"g_agamma": g_agamma, "g_ae": g_ae}).trace(30_000, seed=2)
    assert np.abs(image - direct["chip"].flux).max() <= 1e-12 * direct["chip"].flux.max()
    # The test can fail: without P's g_aγ², or without the squares, the image is another.
    for wrong in [axions, 4 * chip.by_process["primakoff"] + 0.5 * chip.by_process["abc"]]:
        assert np.abs(wrong - direct["chip"].flux).max() > 1e-3 * direct["chip"].flux.max()
    # Before the conversion (-D magnet=false), the axions scale without P.
    off = {"magnet": False}
    bare = traxer.Scene(scene, off).trace(30_000, seed=2)["chip"].by_process
    bare_axions = (g_agamma / 1e-12) ** 2 * bare["primakoff"] + (g_ae / 1e-13) ** 2 * bare["abc"]
    direct = traxer.Scene(scene, {**off, "g_agamma": g_agamma, "g_ae": g_ae}).trace(30_000, seed=2)
    assert np.abs(bare_axions - direct["chip"].flux).max() <= 1e-12 * direct["chip"].flux.max()
    cli("trace", scene, "-n", 30_000, "--seed", 2, "--out", tmp_path / "cli", "-q")
    for name, flux in chip.by_process.items():
        assert flux.tobytes() == np.load(tmp_path / "cli" / f"chip_{name}.npy").tobytes()
    # A Sun of one process has no split.
    assert traxer.Scene(CAST).trace(1000)["chip"].by_process is None


def test_a_mass_scan_equals_the_cli_and_direct_traces(tmp_path):
    """With the magnet and a mass scan, `by_mass` holds one image per mass
    from the same photons: bit for bit the CLI's NAME_by_mass.npy, and the
    image of a direct trace at that mass to 1e-12 of its largest pixel."""
    masses = [0.0, 0.02]
    vars_ = {"magnet": True, "axion_masses_ev": masses}
    run = traxer.Scene(CAST, vars_).trace(20_000, seed=3)["chip"]
    assert list(run.by_mass) == masses
    cli("trace", CAST, "-n", 20_000, "--seed", 3, "-D", "magnet=true", "--masses", "0,0.02",
        "--out", tmp_path / "cli", "-q")
    stack = np.load(tmp_path / "cli" / "chip_by_mass.npy")
    for k, m in enumerate(masses):
        assert run.by_mass[m].tobytes() == stack[k].tobytes()
        direct = traxer.Scene(CAST, {"magnet": True, "axion_mass_ev": m}).trace(20_000, seed=3)
        flux = direct["chip"].flux
        assert np.abs(run.by_mass[m] - flux).max() <= 1e-12 * flux.max()
    # Coherence is lost at 0.02 eV in CAST's 9.26 m: fewer X-rays.
    assert run.by_mass[0.02].sum() < 0.9 * run.by_mass[0.0].sum()
    assert traxer.Scene(CAST, {"magnet": True}).trace(1000)["chip"].by_mass is None


def test_signal_and_reach_equal_the_cli(tmp_path):
    """traxer.signal and traxer.reach give the numbers of `traxer signal` and
    `traxer reach` on the same run; without background the limit is the
    classical 3.0 counts (ln 20)."""
    run = tmp_path / "run"
    cli("trace", CAST, "-n", 10_000, "-D", "magnet=true", "-D", "pixels=200",
        "-D", "energy_bins=[1,10,9]", "--masses", "0,0.02", "--out", run, "-q")
    s = traxer.signal(run, fraction=0.8)
    cli("signal", run, "--fraction", "0.8", "--out", tmp_path / "s", "-q")
    rows = list(csv.DictReader(open(tmp_path / "s" / "signal.csv")))
    assert [float(r["x_rays_per_s"]) for r in rows] == pytest.approx(list(s["x_rays_per_s"]), rel=1e-12)
    assert s["spectrum_x_rays_per_s"].shape == (2, 9)
    r = traxer.reach([run], background=0.0, tracking_hours=1000.0, radius_mm=3.0, window=(2.0, 7.0))
    cli("reach", run, "--radius-mm", "3", "--window", "2,7", "--background", "0",
        "--tracking-hours", "1000", "--out", tmp_path / "r", "-q")
    rows = list(csv.DictReader(open(tmp_path / "r" / "reach.csv")))
    curve = r["curves"][0]
    assert r["coupling"] == "g_agamma" and curve["setting"] == "vacuum"
    assert [float(x["g_agamma_limit_per_gev"]) for x in rows] == pytest.approx(list(curve["limit"]), rel=1e-12)
    assert curve["counts_limit"] == pytest.approx([math.log(20)] * 2, rel=1e-9)
    with pytest.raises(traxer.InputError, match="radius_mm or fraction"):
        traxer.signal(run)
    with pytest.raises(traxer.InputError, match="band"):
        traxer.reach([run], 1e-7, 100.0, radius_mm=3.0, window=(1.5, 7.0))
    # One run as a str and the window as a list, as the rest of the module
    # takes them (issue 59: raw type errors before), give the same limits.
    one = traxer.reach(str(run), background=0.0, tracking_hours=1000.0, radius_mm=3.0, window=[2, 7])
    assert list(one["curves"][0]["limit"]) == list(curve["limit"])
    # Hours meant as years get a warning; a background of 1e300 is refused
    # (it once summed Poisson terms for ever).
    with pytest.warns(UserWarning, match="tracking-hours"):
        traxer.reach(run, background=0.0, tracking_hours=1.5, radius_mm=3.0)
    with pytest.raises(traxer.InputError, match="counts per keV"):
        traxer.reach(run, background=1e300, tracking_hours=1000.0, radius_mm=3.0)
    # The region lies on the brightest mass (0 here), or on the one named, as
    # the CLI's --region-mass; it says which.
    assert s["placed_on_mass_eV"] == 0.0
    named = traxer.signal(run, fraction=0.8, region_mass=0.02)
    cli("signal", run, "--fraction", "0.8", "--region-mass", "0.02", "--out", tmp_path / "n", "-q")
    rows = list(csv.DictReader(open(tmp_path / "n" / "signal.csv")))
    assert [float(r["x_rays_per_s"]) for r in rows] == pytest.approx(list(named["x_rays_per_s"]), rel=1e-12)
    assert named["placed_on_mass_eV"] == 0.02 and named["radius_mm"] != s["radius_mm"]
    with pytest.raises(traxer.InputError, match="not one of the run's masses"):
        traxer.signal(run, fraction=0.8, region_mass=0.05)


def test_a_campaign_and_its_reach_equal_the_cli(tmp_path):
    """With [magnet.campaign], `TraceResult.campaign` holds campaign.json's
    settings, masses and pairs and each sensor's tallies, bit for bit the
    CLI's NAME_campaign.npy for the same photons; traxer.reach on the
    campaign run gives the CLI's combined curve (reach.csv), one-channel and
    binned, with the hours written with the run."""
    vars_ = {"magnet": True, "campaign": True, "emission": "primakoff", "pixels": 100}
    result = traxer.Scene(BABYIAXO, vars_).trace(3000, seed=5)
    run = tmp_path / "run"
    cli("trace", BABYIAXO, "-n", 3000, "--seed", 5, "-D", "magnet=true", "-D", "campaign=true",
        "-D", "emission=primakoff", "-D", "pixels=100", "--out", run, "-q")
    doc = json.loads((run / "campaign.json").read_text())
    c = result.campaign
    for key in ("settings", "masses_ev", "pairs", "energy_edges_kev", "ring_edges_mm", "centre_mm"):
        assert c[key] == doc[key], key
    tally = np.load(run / "detector_campaign.npy")
    assert c["tallies"]["detector"].shape == tally.shape == (len(doc["pairs"]), len(doc["energy_edges_kev"]) - 1, len(doc["ring_edges_mm"]) - 1)
    assert c["tallies"]["detector"].tobytes() == tally.tobytes()
    assert tally.sum() > 0
    assert traxer.Scene(BABYIAXO, {"magnet": True, "pixels": 100}).trace(500).campaign is None
    for binned, flag in ((False, []), (True, ["--binned"])):
        r = traxer.reach(run, background=1e-7, radius_mm=5.0, window=(1.0, 10.0), binned=binned)
        out = tmp_path / ("r_binned" if binned else "r")
        cli("reach", run, "--radius-mm", "5", "--background", "1e-7", "--window", "1,10", *flag,
            "--out", out, "-q")
        rows = list(csv.DictReader(open(out / "reach.csv")))
        # The CSV writes "inf" where no setting sees the mass; Python NaN.
        cli_limits = [float(x["g_agamma_limit_per_gev"]) for x in rows]
        cli_limits = [math.nan if math.isinf(v) else v for v in cli_limits]
        assert list(r["masses_eV"]) == pytest.approx([float(x["axion_mass_ev"]) for x in rows], rel=1e-12)
        assert np.isfinite(r["limit"]).any()
        assert list(r["limit"]) == pytest.approx(cli_limits, rel=1e-12, nan_ok=True)
        assert r["coupling"] == "g_agamma"
        assert [s["tracking_hours"] for s in r["settings"]] == pytest.approx([s["tracking_hours"] for s in doc["settings"]], rel=1e-12)
    with pytest.raises(traxer.InputError, match="campaign run"):
        traxer.reach([tmp_path / "nothing"], 1e-7, 100.0, radius_mm=3.0, binned=True)
    with pytest.raises(traxer.InputError, match="centre_mm"):
        traxer.reach(run, 1e-7, radius_mm=3.0, center=(1.0, 0.0))


def test_signal_reach_and_conversion_take_astropy_quantities(tmp_path):
    """As the rest of the module does (issue 59 §4: raw type errors before):
    masses in eV or as masses (m c²), fields in T, temperatures in °C,
    lengths, hours and background rates, each equal to the plain numbers; a
    Quantity of the wrong kind is refused by name."""
    u = pytest.importorskip("astropy.units")
    plain = traxer.conversion_probability([1.0, 4.0], [0.0, 0.333], field_t=9.0, length_m=9.26,
                                          gas="He", pressure_mbar=10.0, temperature_k=1.8)
    with_units = traxer.conversion_probability(
        [1.0, 4.0] * u.keV, [0.0, 333.0] * u.meV, field_t=9 * u.T, length_m=926 * u.cm,
        gas="He", pressure_mbar=1000 * u.Pa, temperature_k=1.8 * u.K)
    assert with_units == pytest.approx(plain, rel=1e-12)
    # 1 eV/c² as a mass is 1.78266192e-36 kg: the same P.
    kg = traxer.conversion_probability(4.0, [0.02 * 1.78266192e-36] * u.kg, field_t=9.0, length_m=9.26)
    ev = traxer.conversion_probability(4.0, [0.02], field_t=9.0, length_m=9.26)
    assert kg == pytest.approx(ev, rel=1e-6)
    celsius = traxer.conversion_probability(4.0, [0.333], field_t=9.0, length_m=9.26, gas="He",
                                            pressure_mbar=10.0, temperature_k=(1.8 - 273.15) * u.deg_C,)
    assert celsius == pytest.approx(plain[1:, 1:], rel=1e-9)
    with pytest.raises(traxer.InputError, match="field_t: a Quantity in m is not a magnetic field"):
        traxer.conversion_probability(4.0, field_t=9 * u.m, length_m=9.26)
    run = tmp_path / "run"
    cli("trace", CAST, "-n", 5_000, "-D", "magnet=true", "-D", "pixels=100",
        "-D", "energy_bins=[1,10,9]", "--masses", "0,0.02", "--out", run, "-q")
    s = traxer.signal(run, radius_mm=0.3 * u.cm, center=[0.1, -0.2] * u.mm, region_mass=20 * u.meV)
    t = traxer.signal(run, radius_mm=3.0, center=(0.1, -0.2), region_mass=0.02)
    assert list(s["x_rays_per_s"]) == list(t["x_rays_per_s"])
    a = traxer.reach(run, background=1e-7 / (u.keV * u.cm**2 * u.s), tracking_hours=[1 * u.year],
                     radius_mm=3.0, window=(2, 7) * u.keV)
    b = traxer.reach(run, background=1e-7, tracking_hours=8766.0, radius_mm=3.0, window=(2, 7))
    assert list(a["curves"][0]["limit"]) == pytest.approx(list(b["curves"][0]["limit"]), rel=1e-12)
    with pytest.raises(traxer.InputError, match="region_mass: a Quantity in s is not an axion mass"):
        traxer.signal(run, radius_mm=3.0, region_mass=1 * u.s)


def test_save_writes_the_cli_files(pair):
    out, _, saved, _ = pair
    cli_files = sorted(p.name for p in out.iterdir())
    assert sorted(p.name for p in saved.iterdir()) == cli_files
    same_bytes = [n for n in cli_files if n.endswith((".npy", ".png", ".csv"))]
    assert any(n.endswith("_counts.npy") for n in same_bytes)
    for n in same_bytes:
        assert (saved / n).read_bytes() == (out / n).read_bytes(), n
    # FITS headers carry a date: compare the data.
    from astropy.io import fits
    for n in cli_files:
        if n.endswith(".fits"):
            with fits.open(out / n) as a, fits.open(saved / n) as b:
                assert np.array_equal(a[0].data, b[0].data)
    # A saved run merges like a CLI run (run_state.bin holds the exact sums).
    cli("merge", saved, "--out", saved.parent / "merged", "-q")
    for n in cli_files:
        if n.endswith(".npy"):
            assert (saved.parent / "merged" / n).read_bytes() == (out / n).read_bytes(), n


def test_energy_cube_and_threads(tmp_path):
    scene = binned_scene(tmp_path)
    cli("trace", scene, "-n", 80_000, "--seed", 11, "--out", tmp_path / "cli", "-q")
    s = traxer.Scene(scene)
    one = s.trace(80_000, seed=11, threads=1)
    two = s.trace(80_000, seed=11, threads=2)
    img = one["sensor"]
    assert img.flux.shape == (3, 90, 120)
    assert img.flux.tobytes() == np.load(tmp_path / "cli" / "sensor.npy").tobytes()
    assert img.flux.tobytes() == two["sensor"].flux.tobytes()
    assert img.energy_band_edges_keV == pytest.approx([1.0, 4 / 3, 5 / 3, 2.0], abs=1e-12)
    # Pixel centres: 120 pixels across the sensor's width, symmetric about 0.
    assert img.x_mm.shape == (120,) and img.y_mm.shape == (90,)
    assert img.x_mm[0] == pytest.approx(-img.x_mm[-1]) and img.x_mm[0] < 0
    assert img.x_mm[1] - img.x_mm[0] == pytest.approx(img.pixel_pitch_mm[0])
    # The arcsec diameters are the mm ones at the focal length.
    q = img.quality
    assert q["hpd_arcsec"] == pytest.approx(2 * math.degrees(math.atan(q["hpd_mm"] / 2 / 1500)) * 3600, rel=1e-9)


def test_reflectivity_equals_the_cli(tmp_path):
    energies = [1.49, 4.51, 8.05]
    angles = np.arange(0.1, 1.2, 0.1)
    cli("reflectivity", "--coating", "llnl_recipe_3", "--energy", ",".join(map(str, energies)),
        "--angle", ",".join(repr(float(a)) for a in angles), "--plot", tmp_path / "r.png",
        "--csv", tmp_path / "r.csv")
    rows = list(csv.DictReader(open(tmp_path / "r.csv")))
    grid = traxer.reflectivity("llnl_recipe_3", np.array(energies)[:, None], angles[None, :])
    assert grid.shape == (3, len(angles))
    s = traxer.reflectivity("llnl_recipe_3", np.array(energies)[:, None], angles[None, :], "s")
    p = traxer.reflectivity("llnl_recipe_3", np.array(energies)[:, None], angles[None, :], polarisation="p")
    assert np.allclose(grid, 0.5 * (s + p), rtol=0, atol=1e-15)
    assert len(rows) == grid.size
    for row in rows:
        i = energies.index(float(row["energy_keV"]))
        j = int(np.argmin(abs(angles - float(row["angle_deg"]))))
        assert grid[i, j] == float(row["R"])
    # Pairs broadcast element by element; a scalar with an array too.
    pairs = traxer.reflectivity("gold", [1.49, 8.05], [0.3, 0.3])
    assert pairs.shape == (2,)
    assert traxer.reflectivity("gold", 8.05, [0.3])[0] == pairs[1]
    # Total external reflection: far below the critical angle R is near 1.
    assert 0.9 < traxer.reflectivity("gold", 1.49, 0.05)
    # Chantler's table: the same curve within a few per cent, not the same
    # numbers (two compilations), and the CLI's option gives what Python gives.
    henke = traxer.reflectivity("gold", [1.0, 8.0], 0.5)
    chantler = traxer.reflectivity("gold", [1.0, 8.0], 0.5, optical_constants="chantler")
    assert np.all(abs(chantler / henke - 1) < 0.05) and np.all(chantler != henke)
    out = cli("reflectivity", "--coating", "gold", "--energy", "1.0,8.0", "--angle", "0.5",
              "--optical-constants", "chantler", "--plot", tmp_path / "c.png")
    printed = [float(line.split(",")[2]) for line in out.stdout.splitlines()[1:]]
    assert np.allclose(printed, chantler, rtol=1e-12, atol=0)


def test_eef_of_a_uniform_disk():
    """A uniform disk of radius R: the fraction within r is (r/R)², so the
    diameters holding 50/80/90 % are 2R√0.5, 2R√0.8, 2R√0.9. Pixelation on a
    0.01 mm grid at R = 1 mm moves them by well under 1 %."""
    n, pitch, radius = 400, 0.01, 1.0
    c = (np.arange(n) + 0.5) * pitch - n * pitch / 2
    x, y = np.meshgrid(c + 0.1, c - 0.05)
    disk = (x**2 + y**2 <= radius**2).astype(np.int32)
    q = traxer.eef(disk, pixel_pitch_mm=pitch, focal_length_mm=10_000.0)
    assert q["centroid_mm"] == pytest.approx([-0.1, 0.05], abs=2e-4)
    for key, f in (("hpd_mm", 0.5), ("d80_mm", 0.8), ("d90_mm", 0.9)):
        assert q[key] == pytest.approx(2 * radius * math.sqrt(f), rel=0.01), key
    assert q["hpd_arcsec"] == pytest.approx(2 * math.degrees(math.atan(q["hpd_mm"] / 2e4)) * 3600)
    assert q["fraction"][-1] == pytest.approx(1.0) and np.all(np.diff(q["radius_mm"]) >= 0)
    # Summed over bands for a cube; (x, y) pitches.
    cube = np.stack([disk, disk]).astype(float)
    assert traxer.eef(cube, (pitch, pitch))["hpd_mm"] == q["hpd_mm"]


def test_eef_equals_the_cli(tmp_path):
    rng = np.random.default_rng(5)
    image = rng.exponential(size=(40, 60))
    np.save(tmp_path / "img.npy", image)
    out = cli("eef", tmp_path / "img.npy", "--pixel-pitch", "0.05,0.07", "--focal-length", 1500,
              "--json", "--plot", tmp_path / "e.png")
    q = traxer.eef(image, (0.05, 0.07), 1500.0)
    assert {k: v for k, v in q.items() if k not in ("radius_mm", "fraction")} == json.loads(out.stdout)


def test_effective_area_equals_the_cli(tmp_path):
    args = dict(energies=[1.5, 4.5, 8.0], angles=[0.0, 6.0], photons=20_000, seed=2)
    cli("effective-area", LLNL_AREA, "--energies", "1.5,4.5,8.0", "--angles", "0,6",
        "-n", args["photons"], "--seed", args["seed"], "--out", tmp_path / "cli", "-q")
    a = traxer.Scene(LLNL_AREA).effective_area(args["energies"], args["angles"],
                                                photons=args["photons"], seed=args["seed"])
    assert a.area_cm2.shape == (2, 3) and a.by_class_cm2.shape == (2, 3, 5)
    rows = list(csv.DictReader(open(tmp_path / "cli" / "effective_area.csv")))
    assert len(rows) == 6
    area_key = next(k for k in rows[0] if k.startswith("area"))
    for row in rows:
        i = [0.0, 6.0].index(float(next(v for k, v in row.items() if "arcmin" in k)))
        j = args["energies"].index(float(next(v for k, v in row.items() if k.startswith("energy"))))
        assert a.area_cm2[i, j] == float(row[area_key])
    # The classes add up to the whole; on axis the telescope is not vignetted.
    assert np.allclose(a.by_class_cm2.sum(axis=2), a.area_cm2, rtol=1e-12)
    assert a.area_cm2[0, 0] > a.area_cm2[1, 0] > 0
    a.save(tmp_path / "py")
    assert (tmp_path / "py" / "effective_area.csv").read_bytes() == (tmp_path / "cli" / "effective_area.csv").read_bytes()


def test_solar_emission_equals_the_cli(tmp_path):
    cli("solar-flux", "--out", tmp_path / "cli")
    doc = json.loads((tmp_path / "cli" / "solar_flux.json").read_text())
    sun = traxer.SolarEmission.builtin()
    assert sun.flux(1.0) == pytest.approx(doc["flux_per_cm2_s"], rel=1e-12)
    # Within 20 % of the CAST 2007 parameterisation (another solar model).
    assert 0.8 < sun.flux() / doc["cast2007_flux_per_cm2_s_0_to_20keV"] < 1.2
    spectrum = list(csv.reader(open(tmp_path / "cli" / "spectrum.csv")))
    assert sun.rates.shape == (len(sun.radii), len(sun.energies_keV))
    assert len(sun.spectrum()) == len(sun.energies_keV)
    # dΦ/dE falls as 1/d²; its integral is the flux.
    assert sun.spectrum(2.0) == pytest.approx(sun.spectrum(1.0) / 4, rel=1e-12)
    assert sun.flux(0.989) == pytest.approx(sun.flux(1.0) / 0.989**2, rel=1e-12)
    assert sun.luminosity(0, 5) + sun.luminosity(5, 100) == pytest.approx(sun.luminosity(), rel=1e-12)
    del spectrum
    sun.save_csv(tmp_path / "table.csv")
    again = traxer.SolarEmission.from_csv(tmp_path / "table.csv")
    assert np.array_equal(again.rates, sun.rates) and np.array_equal(again.radii, sun.radii)


@pytest.mark.skipif(not SOLAR_MODEL.exists(), reason="../shared/solar is not here")
def test_solar_model_equals_the_cli(tmp_path):
    radii, energies = "0.05,0.1,0.2,0.3", "1.0,3.0,6.0"
    cli("solar-flux", "--model", SOLAR_MODEL, "--radii", radii, "--energies", energies,
        "--out", tmp_path / "cli")
    table = traxer.SolarEmission.from_csv(tmp_path / "cli" / "emission.csv")
    model = traxer.SolarEmission.from_model(SOLAR_MODEL, [1.0, 3.0, 6.0], radii=[0.05, 0.1, 0.2, 0.3])
    # The CSV holds 7 significant digits: a relative rounding of at most 5e-7.
    assert np.allclose(model.rates, table.rates, rtol=6e-7, atol=0)
    assert model.rates.min() > 0


def test_abc_emission_per_process_equals_the_cli_and_scales_as_g_squared(tmp_path):
    cli("solar-flux", "--emission", "primakoff+abc", "--g-agamma", "1e-12", "--g-ae", "2e-13",
        "--out", tmp_path / "cli")
    doc = json.loads((tmp_path / "cli" / "solar_flux.json").read_text())
    both = traxer.SolarEmission.builtin("primakoff+abc", g_agamma=1e-12, g_ae=2e-13)
    assert both.flux() == pytest.approx(doc["flux_per_cm2_s"], rel=1e-12)
    parts = both.process_spectra()
    assert set(parts) == {"primakoff", "atomic", "electron_ion", "electron_electron", "compton", "abc"}
    # The four processes add up to ABC, ABC and Primakoff to the total.
    four = sum(parts[k] for k in ("atomic", "electron_ion", "electron_electron", "compton"))
    assert np.allclose(four, parts["abc"], rtol=2e-6)
    assert np.allclose(parts["abc"] + parts["primakoff"], both.spectrum(), rtol=1e-9)
    # Fluxes scale as the couplings squared (the reference couplings: 1e-10, 1e-13).
    abc = traxer.SolarEmission.builtin("abc")
    assert np.allclose(4 * abc.spectrum(), parts["abc"], rtol=1e-12)
    with pytest.raises(traxer.InputError, match="g_ae"):
        traxer.SolarEmission.builtin("abc", g_ae=-1.0)
    with pytest.raises(traxer.InputError, match="emission"):
        traxer.SolarEmission.builtin("axion")


@pytest.mark.skipif(not SOLAR_MODEL.exists(), reason="../shared/solar is not here")
def test_abc_from_the_model_equals_the_cli(tmp_path):
    op = SOLAR_MODEL.parent / "op"
    radii, energies = "0.05,0.1,0.2,0.3", "0.9,1.0,3.0,6.0"
    cli("solar-flux", "--emission", "abc", "--model", SOLAR_MODEL, "--opacities", op,
        "--radii", radii, "--energies", energies, "--out", tmp_path / "cli")
    table = traxer.SolarEmission.from_csv(tmp_path / "cli" / "emission.csv")
    model = traxer.SolarEmission.from_model(SOLAR_MODEL, [0.9, 1.0, 3.0, 6.0], radii=[0.05, 0.1, 0.2, 0.3],
                                            emission="abc", opacities=op)
    assert np.allclose(model.rates, table.rates, rtol=6e-7, atol=0)
    with pytest.raises(traxer.InputError, match="opacities"):
        traxer.SolarEmission.from_model(SOLAR_MODEL, [1.0], radii=[0.1, 0.2], emission="abc")


def test_scene_errors_name_file_line_and_key(tmp_path):
    bad = tmp_path / "bad.toml"
    text = WOLTER.read_text().replace('"../meshes/', '"%s/' % (REPO / "meshes"))
    lines = text.splitlines()
    at = next(i for i, l in enumerate(lines) if l.startswith("pixels = "))
    lines[at] = "pixels = [512, -3]"
    bad.write_text("\n".join(lines) + "\n")
    with pytest.raises(traxer.SceneError) as e:
        traxer.Scene(bad)
    assert e.value.file == str(bad) and e.value.line == at + 1
    assert e.value.key == "materials.detector.pixels[1]"
    assert "pixels" in str(e.value) and "expected u32" in e.value.message
    with pytest.raises(traxer.SceneError) as e:
        traxer.Scene(WOLTER, defines={"no_such_variable": 1})
    assert "no_such_variable" in str(e.value) and e.value.line is None and e.value.key is None
    with pytest.raises(FileNotFoundError):  # as open() says it (issue 32)
        traxer.Scene(tmp_path / "missing.toml")
    # Scene errors are input errors are ValueErrors.
    assert issubclass(traxer.SceneError, traxer.InputError) and issubclass(traxer.InputError, ValueError)


def test_bad_input_raises_never_crashes(tmp_path):
    s = traxer.Scene(WOLTER)
    bad_calls = [
        lambda: s.trace(0),
        lambda: s.trace(10, threads=100_000),
        lambda: s.trace(10, photon_list=10**9),
        lambda: traxer.Scene(WOLTER, defines="coating=gold"),
        lambda: traxer.Scene(WOLTER, defines=["coating"]),
        lambda: traxer.Scene(WOLTER, defines={"coating": object()}),
        lambda: traxer.reflectivity("unobtainium", 1.0, 0.5),
        lambda: traxer.reflectivity("gold", 100.0, 0.5),
        lambda: traxer.reflectivity("gold", 1.0, 0.5, polarisation="q"),
        lambda: traxer.reflectivity("gold", 1.0, 0.5, optical_constants="cromer"),
        lambda: traxer.eef(np.ones(5), 0.1),
        lambda: traxer.eef(-np.ones((3, 3)), 0.1),
        lambda: traxer.eef(np.zeros((3, 3)), 0.1),
        lambda: traxer.eef(np.ones((3, 3)), -1.0),
        lambda: traxer.eef(np.ones((3, 3)), 0.1, focal_length_mm=0.0),
        lambda: s.effective_area([1.0], sensor="nope", photons=100),
        lambda: s.effective_area([100.0], photons=100),
        lambda: traxer.SolarEmission.from_csv(tmp_path / "missing.csv"),
        lambda: traxer.SolarEmission.builtin().flux(-1.0),
    ]
    for i, call in enumerate(bad_calls):
        with pytest.raises(traxer.InputError):
            call()
    # A folder of other files is not overwritten.
    (tmp_path / "mine.txt").write_text("keep")
    with pytest.raises(traxer.InputError):
        s.trace(1000).save(tmp_path)
    assert (tmp_path / "mine.txt").read_text() == "keep"
    with pytest.raises(KeyError):
        s.trace(1000)["no_such_sensor"]


def test_gil_is_released_while_tracing():
    """While another thread traces, this one keeps running Python: with the GIL
    held it could not run at all until the trace returned."""
    s = traxer.Scene(WOLTER)
    started = threading.Event()
    result = {}

    def work():
        started.set()
        result["r"] = s.trace(3_000_000, threads=1)

    t = threading.Thread(target=work)
    t.start()
    started.wait()
    time.sleep(0.05)  # into the trace
    spins = 0
    while t.is_alive():
        spins += 1
    t.join()
    assert result["r"].photons_traced == 3_000_000
    assert spins > 100_000


def test_ctrl_c_stops_a_trace():
    """KeyboardInterrupt arrives between batches (about a million photons), long
    before the 200 million photons are done."""
    s = traxer.Scene(WOLTER)
    timer = threading.Timer(0.5, _thread.interrupt_main)
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        s.trace(200_000_000)
    assert time.monotonic() - start < 30


def test_trace_into_a_folder_writes_the_cli_files(tmp_path):
    """Scene.trace(out=...) writes the folder `traxer trace --out` writes, bit
    for bit, and returns the same result."""
    n, seed = 200_000, 5
    cli("trace", WOLTER, "-n", n, "--seed", seed, "--out", tmp_path / "cli", "-q")
    r = traxer.Scene(WOLTER).trace(n, seed=seed, out=tmp_path / "py")
    names = sorted(p.name for p in (tmp_path / "cli").iterdir())
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == names
    for name in names:
        if name.endswith((".npy", ".png", ".csv")) or name == "run_state.bin":
            a = (tmp_path / "cli" / name).read_bytes()
            b = (tmp_path / "py" / name).read_bytes()
            if name == "run_state.bin":  # the header holds paths and times
                a, b = a.split(b"\n", 2)[2], b.split(b"\n", 2)[2]
            assert a == b, name
    cli_flux = np.load(tmp_path / "cli" / "sensor.npy")
    assert np.array_equal(r.sensors["sensor"].flux, cli_flux)
    with pytest.raises(traxer.InputError, match="checkpoint_every needs out"):
        traxer.Scene(WOLTER).trace(1000, checkpoint_every=1.0)


def test_a_python_run_stopped_by_ctrl_c_resumes_to_the_uninterrupted_result(tmp_path):
    """With checkpoint_every, Ctrl-C leaves a checkpoint; traxer.resume (or the
    CLI's --resume) finishes the run with the files of one uninterrupted run."""
    n, seed = 30_000_000, 11
    s = traxer.Scene(WOLTER)
    out = tmp_path / "stopped"
    timer = threading.Timer(0.3, _thread.interrupt_main)
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        s.trace(n, seed=seed, out=out, checkpoint_every=0)
    timer.cancel()
    assert (out / "checkpoint.bin").is_file()
    r = traxer.resume(out)
    assert not (out / "checkpoint.bin").exists()
    assert r.photons_traced == n
    cli("trace", WOLTER, "-n", n, "--seed", seed, "--out", tmp_path / "whole", "-q")
    for name in ("sensor.npy", "sensor_counts.npy", "sensor_projections.csv"):
        assert (out / name).read_bytes() == (tmp_path / "whole" / name).read_bytes(), name
    # A finished folder returns its result at once.
    again = traxer.resume(out)
    assert np.array_equal(again.sensors["sensor"].flux, r.sensors["sensor"].flux)
    with pytest.raises(traxer.InputError, match="not the results folder of a stopped run"):
        traxer.resume(tmp_path)


def test_resuming_a_finished_run_checks_its_scene(tmp_path):
    """traxer.resume of a finished folder returns its result only with the
    run's own scene: a scene file edited since (or a different one given as
    scene=) is refused, not read as if it had made the images."""
    (tmp_path / "scenes").mkdir()
    shutil.copytree(REPO / "meshes", tmp_path / "meshes")
    scene = tmp_path / "scenes" / "scene.toml"
    shutil.copy(WOLTER, scene)
    out = tmp_path / "run"
    r = traxer.Scene(scene).trace(20_000, seed=3, out=out)
    again = traxer.resume(out)
    assert np.array_equal(again.sensors["sensor"].flux, r.sensors["sensor"].flux)
    scene.write_text(scene.read_text() + "\n# edited\n")
    with pytest.raises(traxer.InputError, match="changed since the run"):
        traxer.resume(out)


def test_the_example_runs(tmp_path):
    """python/examples/axion_image.py, with fewer photons: it ends well and
    writes the files of `traxer trace`."""
    import sys
    env = dict(os.environ, PHOTONS="100000", OUT=str(tmp_path / "out"), MPLBACKEND="Agg")
    out = subprocess.run([sys.executable, str(REPO / "python" / "examples" / "axion_image.py")],
                         capture_output=True, text=True, env=env)
    assert out.returncode == 0, out.stderr
    assert "window transmission" in out.stdout
    assert (tmp_path / "out" / "chip.npy").exists() and (tmp_path / "out" / "summary.json").exists()


@pytest.mark.skipif(not SOLAR_MODEL.exists(), reason="../shared/solar is not here")
def test_a_degenerate_solar_model_raises_input_error_not_a_panic(tmp_path):
    """A model whose mass fractions are all zero (or whose numbers are absurd)
    raises traxer.InputError naming the file, never a PanicException."""
    lines = []
    for line in SOLAR_MODEL.read_text().splitlines():
        fields = line.split()
        if line.startswith("#") or len(fields) < 7:
            lines.append(line)
        else:
            lines.append(" ".join(fields[:6] + ["0.0"] * (len(fields) - 6)))
    bad = tmp_path / "empty.dat"
    bad.write_text("\n".join(lines))
    with pytest.raises(traxer.InputError, match="empty.dat:.*mass fractions add up to 0"):
        traxer.SolarEmission.from_model(bad, [1.0, 2.0, 3.0])
    with pytest.raises(traxer.InputError, match="distance"):
        traxer.SolarEmission.builtin().flux(1e300)


def test_python_arguments_are_read_as_python_reads_them(tmp_path):
    """A negative photon count names the argument (not an OverflowError), a whole
    float such as 1e4 is a count, a fraction is refused, a missing scene file is
    a FileNotFoundError."""
    s = traxer.Scene(WOLTER)
    with pytest.raises(traxer.InputError, match=r"photons=-5: photons must be ≥ 1"):
        s.trace(-5)
    with pytest.raises(traxer.InputError, match="photons=2.5"):
        s.trace(2.5)
    assert s.trace(1e4, seed=3).photons_traced == 10_000
    assert np.array_equal(s.trace(1e4, seed=3).sensors["sensor"].flux,
                          s.trace(10_000, seed=3).sensors["sensor"].flux)
    with pytest.raises(FileNotFoundError):
        traxer.Scene(tmp_path / "no_such_scene.toml")


def test_python_messages_name_no_cli_options(tmp_path):
    """Errors seen from Python speak of its arguments, not of `--energies`,
    `--sensor` or `--out`."""
    s = traxer.Scene(WOLTER)
    calls = [
        lambda: s.effective_area([100.0], photons=100),
        lambda: s.effective_area([1.0], angles_arcmin=[1e4], photons=100),
        lambda: s.effective_area([1.0], sensor="nope", photons=100),
        lambda: s.effective_area([1.0], photons=1),
        lambda: s.effective_area([1.0], radius_mm=-1.0, photons=100),
    ]
    (tmp_path / "mine.txt").write_text("keep")
    calls.append(lambda: s.trace(1000).save(tmp_path))
    for call in calls:
        with pytest.raises(traxer.InputError) as e:
            call()
        assert " --" not in str(e.value) and not str(e.value).startswith("--"), str(e.value)


def test_arrays_handed_out_are_read_only_and_angles_are_grazing():
    """`flux *= 2` cannot make a result disagree with its own quality and save();
    a copy is the user's to change. Grazing angles lie in 0–90°."""
    r = traxer.Scene(WOLTER).trace(20_000, seed=2)
    image = r.sensors["sensor"]
    before = image.flux.copy()
    with pytest.raises(ValueError):
        image.flux *= 2
    with pytest.raises(ValueError):
        image.counts[0, 0] = 7
    assert np.array_equal(image.flux, before)
    mine = image.flux.copy()
    mine *= 2
    assert np.array_equal(mine, 2 * before)
    with pytest.raises(traxer.InputError, match="angles_deg=120"):
        traxer.reflectivity("gold", 1.0, 120.0)
    assert traxer.reflectivity("gold", 1.0, 90.0) < 1.0


def test_reprs_count_in_english():
    r = repr(traxer.Scene(CAST))
    assert "1 sensor," in r and "1 source)" in r, r


def test_scene_variable_errors_name_no_cli_option():
    with pytest.raises(traxer.SceneError) as e:
        traxer.Scene(WOLTER, defines={"no_such_variable": 1})
    assert "-D" not in str(e.value) and "no_such_variable" in str(e.value)
    with pytest.raises(traxer.SceneError) as e:
        traxer.Scene(PANTER, defines={"figure_error": "nosuch"})
    assert "-D" not in str(e.value) and 'variable override figure_error="nosuch"' in str(e.value)


def test_astropy_quantities_are_converted_never_misread():
    """A Quantity converts to the documented unit (independently: 30′ = 0.5°,
    3000 eV = 3 keV, hc/λ = 12.398 keV·Å / λ); one of the wrong kind raises
    InputError naming the argument; plain numbers keep their units."""
    u = pytest.importorskip("astropy.units")
    gold = lambda e, a: float(traxer.reflectivity("gold", e, a))
    assert gold(3 * u.keV, 30 * u.arcmin) == gold(3.0, 0.5)
    assert gold(3000 * u.eV, 0.5 * u.deg) == gold(3.0, 0.5)
    assert gold(3 * u.keV, (0.5 * u.deg).to(u.rad)) == pytest.approx(gold(3.0, 0.5), rel=1e-12)
    hc_kev_angstrom = 12.398419843320026  # CODATA 2018
    assert gold((hc_kev_angstrom / 3.0) * u.AA, 0.5) == pytest.approx(gold(3.0, 0.5), rel=1e-9)
    grid = traxer.reflectivity("gold", np.array([1.5, 3.0])[:, None] * u.keV, np.array([30, 60]) * u.arcmin)
    assert np.array_equal(grid, traxer.reflectivity("gold", np.array([1.5, 3.0])[:, None], [0.5, 1.0]))
    for call, name in [
        (lambda: traxer.reflectivity("gold", 3 * u.keV, 2 * u.keV), "angles_deg"),
        (lambda: traxer.reflectivity("gold", 3 * u.s, 0.5), "energies_keV"),
        (lambda: traxer.eef(np.ones((8, 8)), 1 * u.s), "pixel_pitch_mm"),
        (lambda: traxer.SolarEmission.builtin(g_agamma=1e-10 * u.m), "g_agamma"),
        (lambda: traxer.SolarEmission.builtin().flux(distance_au=1 * u.s), "distance_au"),
    ]:
        with pytest.raises(traxer.InputError, match=name):
            call()
    # Lengths, distances and couplings.
    img = np.zeros((40, 40))
    img[15:25, 15:25] = 1
    assert traxer.eef(img, 55 * u.um)["hpd_mm"] == traxer.eef(img, 0.055)["hpd_mm"]
    assert traxer.eef(img, (0.055 * u.mm, 55 * u.um), 1.5 * u.m)["hpd_arcsec"] == traxer.eef(img, 0.055, 1500.0)["hpd_arcsec"]
    sun = traxer.SolarEmission.builtin()
    assert sun.flux(distance_au=149_597_870.7 * u.km) == pytest.approx(sun.flux(), rel=1e-12)
    assert sun.flux(e_min_keV=2000 * u.eV, e_max_keV=7 * u.keV) == sun.flux(e_min_keV=2, e_max_keV=7)
    assert np.array_equal(sun.spectrum(2 * u.AU), sun.spectrum(2.0))
    # A scene variable's unit is the scene's business: a Quantity is refused.
    with pytest.raises(traxer.InputError, match="sensor_z.*Quantity"):
        traxer.Scene(WOLTER, defines={"sensor_z": -1500 * u.mm})
    # g_aγ = 1e-13 MeV⁻¹ is 1e-10 GeV⁻¹.
    assert traxer.SolarEmission.builtin(g_agamma=1e-13 / u.MeV).flux() == pytest.approx(sun.flux(), rel=1e-12)


def test_effective_area_takes_quantity_arrays():
    u = pytest.importorskip("astropy.units")
    scene = traxer.Scene(LLNL_AREA)
    plain = scene.effective_area([1.5, 3.0], [0.0, 5.0], photons=4000, seed=3)
    q = scene.effective_area(np.array([1500.0, 3000.0]) * u.eV, [0, 300] * u.arcsec, photons=4000, seed=3)
    assert np.array_equal(plain.area_cm2, q.area_cm2)
    assert np.array_equal(q.energies_keV, [1.5, 3.0]) and np.array_equal(q.angles_arcmin, [0.0, 5.0])
    with pytest.raises(traxer.InputError, match="angles_arcmin"):
        scene.effective_area([1.5], [1.0] * u.keV, photons=100)
    with pytest.raises(traxer.InputError, match="radius_mm"):
        scene.effective_area([1.5], photons=100, radius_mm=2 * u.keV)


def test_reflectivity_tables_are_cached_between_builds(tmp_path, monkeypatch, capsys):
    """A scan rebuilds the scene per value: the second build reads the tables the
    first one kept (in TRAXER_CACHE), says nothing, and traces the same photons."""
    monkeypatch.setenv("TRAXER_CACHE", str(tmp_path / "cache"))
    first = traxer.Scene(WOLTER, defines={"coating": "gold"}).trace(5000, seed=2)
    said = capsys.readouterr().err
    assert "traxer: building the reflectivity table of coating `gold`" in said, said
    assert list((tmp_path / "cache" / "reflectivity").iterdir())
    second = traxer.Scene(WOLTER, defines={"coating": "gold"}).trace(5000, seed=2)
    assert "building" not in capsys.readouterr().err
    assert first["sensor"].flux.tobytes() == second["sensor"].flux.tobytes()


def test_couplings_an_emission_lacks_or_that_underflow_are_refused_by_name():
    """Before: builtin("primakoff", g_ae=...) ignored g_ae, and g_ae=1e-200 gave
    an emission of exactly zero without a word (issue 39)."""
    with pytest.raises(traxer.InputError, match="g_ae is the coupling of the ABC emission"):
        traxer.SolarEmission.builtin("primakoff", g_ae=1e-12)
    with pytest.raises(traxer.InputError, match="g_agamma is the coupling of the Primakoff"):
        traxer.SolarEmission.builtin("abc", g_agamma=1e-11)
    with pytest.raises(traxer.InputError, match=r"g_ae = 1e-200: .*underflow"):
        traxer.SolarEmission.builtin("abc", g_ae=1e-200)
    with pytest.raises(traxer.InputError, match='lower case: "abc"'):
        traxer.SolarEmission.builtin("ABC")


def test_save_refuses_a_folder_of_another_run_unless_asked_to_replace(tmp_path):
    """A results folder never silently takes the results of a run with other
    inputs: save() refuses it, naming the difference, unless replace=True."""
    scene = traxer.Scene(REPO / "scenes" / "wolter1_parallel.toml")
    first = scene.trace(1000, seed=1)
    first.save(tmp_path / "run")
    flux = np.load(tmp_path / "run" / "sensor.npy").sum()
    other = scene.trace(1000, seed=2)
    with pytest.raises(traxer.InputError, match="seed 2, not 1"):
        other.save(tmp_path / "run")
    assert np.load(tmp_path / "run" / "sensor.npy").sum() == flux
    first.save(tmp_path / "run")  # the same run again: nothing lost
    other.save(tmp_path / "run", replace=True)
    assert np.load(tmp_path / "run" / "sensor.npy").sum() != flux


def test_effective_area_save_writes_the_arfs_too(tmp_path):
    """Python's EffectiveArea.save writes the CLI's OGIP ARFs, one per angle."""
    from astropy.io import fits as _fits
    scene = traxer.Scene(str(REPO / "scenes" / "llnl_effective_area.toml"))
    ea = scene.effective_area(np.array([1.0, 1.5, 2.0]), [0.0, 5.0], photons=20000)
    ea.save(tmp_path / "ea")
    for angle in ("0", "5"):
        with _fits.open(tmp_path / "ea" / f"effective_area_{angle}arcmin.arf") as h:
            np.testing.assert_allclose(h["SPECRESP"].data["SPECRESP"],
                                       ea.area_cm2[0 if angle == "0" else 1], rtol=1e-6)


def test_psf_library_in_python_equals_the_cli(tmp_path):
    """`Scene.psf_library` gives the images of `traxer psf` bit for bit, and
    `save` writes the same psf.npy."""
    scene = REPO / "scenes" / "xmm_effective_area.toml"
    lib = traxer.Scene(scene).psf_library([1.5, 6.4], angles_arcmin=[0, 5], photons=10_000,
                                          window=41, seed=3)
    assert lib.images.shape == (2, 1, 2, 41, 41)
    assert np.allclose(lib.images.sum(axis=(-1, -2)), 1.0, rtol=1e-12)
    cli("psf", scene, "--energies", "1.5,6.4", "--angles", "0,5", "-n", 10_000,
        "--window", 41, "--seed", 3, "--out", tmp_path / "cli", "-q")
    assert lib.images.tobytes() == np.load(tmp_path / "cli" / "psf.npy").tobytes()
    lib.save(tmp_path / "py")
    assert np.load(tmp_path / "py" / "psf.npy").tobytes() == lib.images.tobytes()
    assert 0.9 < lib.fraction_in_window.min() <= 1.0


def test_builtin_emission_of_the_gs98_model_is_brighter():
    """solar_model="b16_gs98" takes the B16-GS98 tables: its Primakoff flux at
    1 AU (3.738e11 cm⁻² s⁻¹) is 5.3 % above AGSS09met's, ABC's 5.7 %; a name
    that is not a model is refused."""
    for emission, ratio in [("primakoff", 1.053), ("abc", 1.057)]:
        gs98 = traxer.SolarEmission.builtin(emission, solar_model="b16_gs98").flux()
        agss = traxer.SolarEmission.builtin(emission).flux()
        assert abs(gs98 / agss - ratio) < 0.002, (emission, gs98 / agss)
    with pytest.raises(traxer.InputError, match="b16_gs98"):
        traxer.SolarEmission.builtin(solar_model="gs98")


def test_systematics_in_python_equals_the_cli(tmp_path):
    """`Scene.systematics` traces the variations of `traxer systematics` with
    the same photons: the same table and maps bit for bit; `save` writes the
    CLI's files; the total σ is the sources' in quadrature; and a source the
    scene cannot vary is refused by name."""
    scene = REPO / "scenes" / "panter_al_ka.toml"
    s = traxer.Scene(scene).systematics(photons=20_000, sources=["figure"], figure_draws=3,
                                        vary={"sensor_z": (-1539.0, -1499.0)}, seed=2)
    assert [r["source"] for r in s.table] == ["nominal"] + ["figure"] * 3 + ["vary:sensor_z"] * 2
    assert s.variations.shape[0] == 6 and s.nominal.shape == s.variations.shape[1:]
    assert set(s.sigma_by_source) == {"figure", "vary:sensor_z"}
    np.testing.assert_allclose(
        s.sigma ** 2, s.sigma_by_source["figure"] ** 2 + s.sigma_by_source["vary:sensor_z"] ** 2,
        rtol=1e-12, atol=0)
    cli("systematics", scene, "-n", 20_000, "--sources", "figure", "--figure-draws", 3,
        "--vary", "sensor_z=-1539:-1499", "--seed", 2, "--out", tmp_path / "cli", "-q")
    assert s.variations.tobytes() == np.load(tmp_path / "cli" / "map_variations.npy").tobytes()
    s.save(tmp_path / "py")
    for f in ("systematics.csv", "map_sigma.npy", "map_mean.npy"):
        assert (tmp_path / "py" / f).read_bytes() == (tmp_path / "cli" / f).read_bytes(), f
    # With out=, the study writes the CLI's folder itself (record included).
    traxer.Scene(scene).systematics(photons=20_000, sources=["figure"], figure_draws=3,
                                    vary={"sensor_z": (-1539.0, -1499.0)}, seed=2,
                                    out=tmp_path / "py_out")
    names = sorted(p.name for p in (tmp_path / "cli").iterdir())
    assert sorted(p.name for p in (tmp_path / "py_out").iterdir()) == names
    for f in ("systematics.csv", "map_sigma.npy", "map_variations.npy"):
        assert (tmp_path / "py_out" / f).read_bytes() == (tmp_path / "cli" / f).read_bytes(), f
    summary = json.loads((tmp_path / "cli" / "systematics.json").read_text())
    assert s.summary["sources"] == summary["sources"]
    with pytest.raises(traxer.InputError, match="cannot vary pointing_x"):
        traxer.Scene(scene).systematics(photons=1000, sources=["pointing_x"])


def test_the_cli_and_python_share_one_reflectivity_cache(tmp_path, monkeypatch, capsys):
    """A table the CLI built and cached is the one Python reads: no table is
    built again, no file added (the cache's key is the coating, the energies
    and the table code, the same in both builds)."""
    monkeypatch.setenv("TRAXER_CACHE", str(tmp_path / "cache"))
    scene = REPO / "scenes" / "panter_al_ka.toml"
    cli("trace", scene, "-n", 2000, "--out", tmp_path / "cli", "-q")
    tables = sorted((tmp_path / "cache" / "reflectivity").iterdir())
    assert tables, "the CLI cached its tables"
    capsys.readouterr()
    traxer.Scene(scene).trace(2000)
    assert "building the reflectivity table" not in capsys.readouterr().err
    assert sorted((tmp_path / "cache" / "reflectivity").iterdir()) == tables


DIRECT_SCENE = """
[materials.chip]
type = "sensor"
size = [14.0, 14.0]
pixels = [70, 70]

[[sources]]
type = "parallel"
direction = [0, 0, -1]
aperture = { center = [5, 0, 10], radius = 3.0 }
energy = { line = 3.0 }

[[objects]]
name = "chip"
material = "chip"
shape = { type = "rectangle", size = [14.0, 14.0] }

[[objects]]
name = "flat"
material = "mirror"
shape = { type = "rectangle", size = [10.0, 10.0] }
transform = [ { translate = [50, 0, 0] } ]
"""


def test_a_trace_warns_of_a_sensor_that_sees_the_source_directly(tmp_path):
    """As the CLI does: a scene with mirrors whose sensor records no reflected
    photon, and circles beyond the sensor's edge, each give a UserWarning."""
    scene = tmp_path / "direct.toml"
    scene.write_text(DIRECT_SCENE)
    with pytest.warns(UserWarning) as caught:
        traxer.Scene(scene).trace(20_000, seed=1)
    said = " ".join(str(w.message) for w in caught)
    assert "was reflected by a mirror" in said and "beyond the sensor" in said


def test_conversion_probability_equals_the_cli():
    """P(a→γ) from Python is the CLI's, number for number; CAST's vacuum
    number is (g B L / 2)² = 1.70e-17 with the units of the issue
    (1 T = 195.35 eV², 1 m = 5.0677e6 eV⁻¹)."""
    cast = traxer.conversion_probability([1.0, 4.0], field_t=9.0, length_m=9.26)
    assert cast.shape == (2, 1)
    assert cast[0, 0] == pytest.approx((1e-19 * 9 * 195.35 * 9.26 * 5.0677e6 / 2) ** 2, rel=1e-3)
    masses = [0.0, 0.01, 0.02]
    p = traxer.conversion_probability([1.0, 4.0], masses, field_map="bykovskiy_201906", bore_average=True)
    out = cli("conversion", "--field-map", "bykovskiy_201906", "--energies", "1,4",
              "--masses", "0,0.01,0.02", "--bore-average", "-q")
    printed = [float(line.split(",")[2]) for line in out.stdout.splitlines()[1:]]
    assert p.shape == (2, 3)
    assert list(p.ravel()) == printed
    # Helium's phase and attenuation: the physics is checked against the closed
    # form at 1, 4 and 8 keV in tests/it/magnet.rs; here Python must be the CLI.
    he = traxer.conversion_probability([1.0, 4.0, 8.0], [0.0, 0.333], field_t=9.0, length_m=9.26,
                                       gas="He", pressure_mbar=10.0, temperature_k=1.8)
    out = cli("conversion", "--field-t", "9", "--length-m", "9.26", "--energies", "1,4,8",
              "--masses", "0,0.333", "--gas", "He", "--pressure-mbar", "10",
              "--temperature-k", "1.8", "-q")
    assert list(he.ravel()) == [float(line.split(",")[2]) for line in out.stdout.splitlines()[1:]]
    assert he[0, 1] < 0.1 * cast[0, 0]  # 1 keV: absorbed on the way (ΓL ≈ 15)
    with pytest.raises(traxer.InputError, match="field_t"):
        traxer.conversion_probability(4.0)
    with pytest.raises(traxer.InputError, match="pressure_mbar"):
        traxer.conversion_probability(4.0, field_t=9.0, length_m=9.26, gas="He")
    # Issue 59: NaN and P > 1 once came back as numbers; now refused by name.
    with pytest.raises(traxer.InputError, match="g_agamma"):
        traxer.conversion_probability(4.0, field_t=9.0, length_m=9.26, g_agamma=0.1)
    with pytest.raises(traxer.InputError, match="masses_eV"):
        traxer.conversion_probability(4.0, [1e153], field_t=9.0, length_m=9.26)
    with pytest.raises(traxer.InputError, match="bore_average"):
        traxer.conversion_probability(4.0, field_map="bykovskiy_201906", at=(100.0, 0.0), bore_average=True)


def test_a_python_sweep_into_a_folder_stops_on_ctrl_c_and_resumes(tmp_path):
    """Scene.effective_area(out=...) keeps the record `traxer effective-area`
    keeps: Ctrl-C stops it after the current angle (a KeyboardInterrupt whose
    note says how to continue), and resume=True takes up the recorded angles and
    writes the files of one uninterrupted CLI run, bit for bit."""
    angles = [0.1 * k for k in range(60)]
    energies = [1.5, 4.5]
    s = traxer.Scene(LLNL_AREA)
    out = tmp_path / "py"
    timer = threading.Timer(1.0, _thread.interrupt_main)
    timer.start()
    with pytest.raises(KeyboardInterrupt) as stopped:
        s.effective_area(energies, angles, photons=100_000, seed=4, out=out)
    timer.cancel()
    assert "--resume" in " ".join(getattr(stopped.value, "__notes__", []))
    record = (out / "effective_area_checkpoint.jsonl").read_text()
    done = record.count('"off_axis_arcmin"')
    assert 0 < done < len(angles), done
    assert not (out / "effective_area.csv").exists()  # nothing but the record yet
    with pytest.raises(traxer.InputError, match="resume"):
        s.effective_area(energies, angles, photons=100_000, seed=4, out=out)
    a = s.effective_area(energies, angles, photons=100_000, seed=4, out=out, resume=True)
    assert a.area_cm2.shape == (len(angles), len(energies))
    # Re-traced angles would give the same numbers: the sweep says it took the
    # recorded ones from the record.
    assert json.loads((out / "effective_area.json").read_text())["provenance"]["points_from_record"] == done
    cli("effective-area", LLNL_AREA, "--energies", "1.5,4.5",
        "--angles", ",".join(map(repr, angles)), "-n", 100_000, "--seed", 4,
        "--out", tmp_path / "cli", "-q")
    names = sorted(p.name for p in (tmp_path / "cli").iterdir())
    assert sorted(p.name for p in out.iterdir()) == names
    for name in names:
        if name.endswith(".csv"):
            assert (out / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    with pytest.raises(traxer.InputError, match="needs out"):
        s.effective_area(energies, [0.0], photons=1000, resume=True)


def test_a_python_psf_library_into_a_folder_writes_the_cli_files(tmp_path):
    """Scene.psf_library(out=...) writes the folder `traxer psf --out` writes
    (psf.npy bit for bit, the same file names)."""
    scene = REPO / "scenes" / "xmm_effective_area.toml"
    args = dict(angles_arcmin=[0, 5], photons=5_000, window=31, seed=2)
    lib = traxer.Scene(scene).psf_library([1.5], out=tmp_path / "py", **args)
    cli("psf", scene, "--energies", "1.5", "--angles", "0,5", "-n", 5_000,
        "--window", 31, "--seed", 2, "--out", tmp_path / "cli", "-q")
    names = sorted(p.name for p in (tmp_path / "cli").iterdir())
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == names
    assert (tmp_path / "py" / "psf.npy").read_bytes() == (tmp_path / "cli" / "psf.npy").read_bytes()
    assert np.load(tmp_path / "py" / "psf.npy").tobytes() == lib.images.tobytes()


def test_compare_in_python_measures_what_the_cli_does_and_stops_and_resumes(tmp_path):
    """`Scene.compare` traces the rows of `traxer compare` with the same
    photons: the same measured columns of compare.csv (the speed columns aside);
    into a folder it stops on Ctrl-C after a row and resume=True ends with the
    uninterrupted rows."""
    scene = REPO / "scenes" / "panter_al_ka.toml"
    s = traxer.Scene(scene)
    c = s.compare(["4x1", "30x1"], photons=100_000, seed=2)
    rows = c.rows
    assert [r["representation"] for r in rows] == ["analytic", "mesh 4x1", "mesh 30x1"]
    assert rows[0]["diameter_diff_pct"]["hpd"] == 0.0
    assert rows[1]["triangles"] < rows[2]["triangles"]
    # 4 segments per shell are far from the cones: the HPD moves by far more
    # than the 100 000 photons' noise (common photons: differences are not noise).
    assert abs(rows[1]["diameter_diff_pct"]["hpd"]) > abs(rows[2]["diameter_diff_pct"]["hpd"])
    assert "| analytic |" in c.markdown
    cli("compare", scene, "--resolutions", "4x1,30x1", "-n", 100_000, "--seed", 2,
        "--out", tmp_path / "cli", "-q")
    c.save(tmp_path / "py")

    def measured(folder):
        lines = (folder / "compare.csv").read_text().splitlines()
        return [line.rsplit(",", 2)[0] for line in lines]

    assert measured(tmp_path / "py") == measured(tmp_path / "cli")
    with pytest.raises(traxer.InputError, match="SEGMENTSxRINGS"):
        s.compare(["30"], photons=1000)
    # Into a folder: stopped after a row, resumed to the same measurement.
    out = tmp_path / "stopped"
    many = [f"{k}x1" for k in range(4, 40)]
    timer = threading.Timer(1.0, _thread.interrupt_main)
    timer.start()
    with pytest.raises(KeyboardInterrupt) as stopped:
        s.compare(many, photons=100_000, seed=2, out=out)
    timer.cancel()
    assert "--resume" in " ".join(getattr(stopped.value, "__notes__", []))
    done = (out / "compare_checkpoint.jsonl").read_text().count('"label"')
    assert 0 < done < len(many) + 1, done
    resumed = s.compare(many, photons=100_000, seed=2, out=out, resume=True)
    assert json.loads((out / "compare.json").read_text())["provenance"]["points_from_record"] == done
    whole = s.compare(many, photons=100_000, seed=2)
    assert [r["image_quality"] for r in resumed.rows] == [r["image_quality"] for r in whole.rows]
    assert measured(out)[1:] == [line.rsplit(",", 2)[0] for line in
                                 _compare_csv_lines(whole, tmp_path / "whole")][1:]


def _compare_csv_lines(comparison, folder):
    comparison.save(folder)
    return (folder / "compare.csv").read_text().splitlines()


def test_focus_in_python_equals_the_cli(tmp_path):
    """`Scene.focus` traces the positions of `traxer focus` with the same
    photons: the same diameters bit for bit, and `save` writes the same
    focus.csv; the HPD's fitted best focus lies inside the sweep, which
    brackets the shipped scene's sensor."""
    scene = REPO / "scenes" / "panter_al_ka.toml"
    f = traxer.Scene(scene).focus(-1534, -1504, steps=5, photons=50_000, seed=2)
    assert f.values.tolist() == [-1534.0, -1526.5, -1519.0, -1511.5, -1504.0]
    assert f.hpd_mm.shape == (5,) and (f.hpd_mm > 0).all()
    assert (f.d80_mm > f.hpd_mm).all() and (f.d90_mm > f.d80_mm).all()
    z0 = f.fits["hpd"]["z0"]
    assert -1534 < z0 < -1504, z0
    cli("focus", scene, "--from", -1534, "--to", -1504, "--steps", 5, "-n", 50_000,
        "--seed", 2, "--out", tmp_path / "cli", "-q")
    f.save(tmp_path / "py")
    assert (tmp_path / "py" / "focus.csv").read_bytes() == (tmp_path / "cli" / "focus.csv").read_bytes()
    with pytest.raises(traxer.InputError, match="steps"):
        traxer.Scene(scene).focus(-1534, -1504, steps=2, photons=1000)


def test_figure_error_fit_in_python_equals_the_cli(tmp_path):
    """`Scene.fit_figure_error` runs the evaluations of `traxer
    fit-figure-error` with the same photons: history.csv bit for bit, the
    same best parameters; its preset names itself; bad bounds are refused."""
    scene = REPO / "scenes" / "panter_al_ka.toml"
    args = dict(global_evals=6, local_evals=3, check_seeds=1, photons=20_000, seed=2)
    fit = traxer.Scene(scene).fit_figure_error(206, 397, 549, name="py_fit", **args)
    assert len(fit.history) == 9
    assert fit.best == fit.summary["best"]["parameters"]
    assert "[figure_errors.py_fit]" in fit.preset
    cli("fit-figure-error", scene, "--target-hpd", 206, "--target-c80", 397, "--target-c90", 549,
        "--global-evals", 6, "--local-evals", 3, "--check-seeds", 1, "-n", 20_000, "--seed", 2,
        "--out", tmp_path / "cli", "-q")
    fit.save(tmp_path / "py")
    assert (tmp_path / "py" / "history.csv").read_bytes() == (tmp_path / "cli" / "history.csv").read_bytes()
    with pytest.raises(traxer.InputError, match="not a parameter"):
        traxer.Scene(scene).fit_figure_error(206, 397, 549, bounds={"narrow": (0, 10)}, **args)
