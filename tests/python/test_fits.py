"""FITS images written by `traxer trace --fits`, read by astropy (an independent
FITS and WCS implementation): the data equal the .npy bit for bit, the WCS puts the
pixel centres where traxer's own outputs say they are, in mm and in arcsec, the
energy cube's third axis is at the band centres, and shards merged with --fits give
the data of one run.

Run by scripts/test-python.sh (part of scripts/test.sh); TRAXER names the binary.
"""

import csv
import json
import os
import pathlib
import subprocess
import warnings

import numpy as np
import pytest
from astropy.io import fits
from astropy.table import Table
from astropy.wcs import WCS

REPO = pathlib.Path(__file__).resolve().parents[2]
TRAXER = os.environ.get("TRAXER", str(REPO / "target" / "release" / "traxer"))


def traxer(*args):
    out = subprocess.run([TRAXER, *map(str, args)], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return out


def wolter_scene(tmp, binned):
    """The shipped Wolter-I scene with absolute mesh paths; 200 × 150 pixels (not
    square, so that x and y cannot be swapped unnoticed); with 4 energy bands and no
    focal length, or one band and f = 1500 mm."""
    text = (REPO / "scenes" / "wolter1_parallel.toml").read_text()
    text = text.replace('"../meshes/', '"%s/' % (REPO / "meshes"))
    extra = "\nenergy_bins = [1.0, 2.0, 4]" if binned else "\nfocal_length = 1500.0"
    assert "pixels = [512, 512]" in text
    text = text.replace("pixels = [512, 512]", "pixels = [200, 150]" + extra)
    path = tmp / ("binned.toml" if binned else "plain.toml")
    path.write_text(text)
    return path


def run(tmp, scene, name, *extra):
    out = tmp / name
    traxer("trace", scene, "-n", 60000, "-D", "off_axis=0.05", "-D", "focus_shift=20",
           "--out", out, "-q", "--fits", *extra)
    return out


@pytest.fixture(scope="module")
def plain(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("plain")
    return run(tmp, wolter_scene(tmp, False), "out")


def test_data_equal_the_npy(plain):
    with fits.open(plain / "sensor.fits") as f:
        data = f[0].data
        assert f[0].header["BITPIX"] == -64
        npy = np.load(plain / "sensor.npy")
        assert data.shape == npy.shape == (150, 200)
        assert np.array_equal(data, npy)
        assert data.sum() > 0


def test_wcs_puts_pixel_centres_where_traxer_reports_them(plain):
    header = fits.getheader(plain / "sensor.fits")
    with open(plain / "sensor_projections.csv") as f:
        rows = list(csv.DictReader(f))
    x_mm = np.array([float(r["x_mm"]) for r in rows if r["x_mm"]])
    y_mm = np.array([float(r["y_mm"]) for r in rows if r["y_mm"]])
    assert len(x_mm) == 200 and len(y_mm) == 150
    w = WCS(header)
    # 0-based pixel indices, numpy's (ix along axis 1, iy along axis 0).
    wx, _ = w.pixel_to_world_values(np.arange(200), np.zeros(200))
    _, wy = w.pixel_to_world_values(np.zeros(150), np.arange(150))
    # CFITSIO writes 15 significant digits: 1e-12 mm on a 14 mm sensor.
    assert np.allclose(wx, x_mm, rtol=0, atol=1e-12)
    assert np.allclose(wy, y_mm, rtol=0, atol=1e-12)
    assert w.wcs.cunit[0] == "mm"


def test_arcsec_wcs_has_the_plate_scale_of_the_reported_diameters(plain):
    header = fits.getheader(plain / "sensor.fits")
    summary = json.loads((plain / "sensor.json").read_text())["sensor"]
    q = summary["image_quality"]
    f_mm = q["focal_length_mm"]
    wa = WCS(header, key="A")
    assert str(wa.wcs.cunit[0]) == "arcsec"
    ix = np.arange(200)
    ax, _ = wa.pixel_to_world_values(ix, np.zeros(200))
    x_mm, _ = WCS(header).pixel_to_world_values(ix, np.zeros(200))
    # Small-angle plate scale: 206264.806″ per radian over the focal length.
    assert np.allclose(ax, x_mm / f_mm * 206264.80624709636, rtol=1e-12, atol=1e-9)
    # traxer's diameters in arcsec are 2 atan(r/f): the same scale to (r/f)²/3.
    for d in ("hpd", "d80", "d90"):
        scale = q[d + "_arcsec"] / q[d + "_mm"]
        assert scale == pytest.approx(header["CDELT1A"] / header["CDELT1"], rel=1e-5)


def test_header_carries_unit_band_and_provenance(plain):
    header = fits.getheader(plain / "sensor.fits")
    prov = json.loads((plain / "sensor.json").read_text())["provenance"]
    assert header["BUNIT"] == "ph"
    assert header["E_MIN"] == header["E_MAX"] == 1.49
    assert header["SEED"] == prov["seed"] == 1
    assert header["PHOTONS"] == prov["photons"] == 60000
    assert header["SCENESHA"] == prov["scene_sha256"]
    assert header["SCENE"] == "plain.toml"
    assert prov["git_hash"] in header["CREATOR"]
    assert header["PROVFILE"] == "sensor.json"
    files = json.loads((plain / "sensor.json").read_text())["sensor"]["files"]
    assert files["fits"] == "sensor.fits"


def test_energy_bins_make_a_cube_with_an_energy_axis(tmp_path):
    out = run(tmp_path, wolter_scene(tmp_path, True), "binned")
    with fits.open(out / "sensor.fits") as f:
        data, header = f[0].data, f[0].header
    npy = np.load(out / "sensor.npy")
    assert data.shape == npy.shape == (4, 150, 200)
    assert np.array_equal(data, npy)
    edges = json.loads((out / "sensor.json").read_text())["sensor"]["energy_band_edges_keV"]
    centres = 0.5 * (np.array(edges[:-1]) + np.array(edges[1:]))
    w = WCS(header)
    assert w.naxis == 3 and str(w.wcs.cunit[2]) == "keV"
    _, _, e = w.pixel_to_world_values(np.zeros(4), np.zeros(4), np.arange(4))
    assert np.allclose(e, centres, rtol=1e-12)
    # No focal length in this scene: no angular WCS.
    assert "CTYPE1A" not in header
    assert (header["E_MIN"], header["E_MAX"]) == (1.0, 2.0)


def test_merged_shards_give_the_fits_data_of_one_run(tmp_path, plain):
    scene = wolter_scene(tmp_path, False)
    parts = [run(tmp_path, scene, "shard%d" % k, "--shard", "%d/2" % k) for k in (1, 2)]
    merged = tmp_path / "merged"
    traxer("merge", *parts, "--out", merged, "-q", "--fits")
    one = fits.getdata(plain / "sensor.fits")
    assert np.array_equal(fits.getdata(merged / "sensor.fits"), one)
    assert fits.getheader(merged / "sensor.fits")["PHOTONS"] == 60000


def test_without_fits_no_fits_file(tmp_path):
    out = tmp_path / "nofits"
    traxer("trace", wolter_scene(tmp_path, False), "-n", 1000, "--out", out, "-q")
    assert not (out / "sensor.fits").exists()
    assert (out / "sensor.npy").exists()


def test_primary_header_has_no_extension_name(plain):
    with fits.open(plain / "sensor.fits") as f:
        assert "EXTNAME" not in f[0].header


def windowed_centre(image, pitch, radius):
    """The centroid within `radius` of itself (mm from the image's centre), as
    traxer's sky measurement takes image centres (analysis::centre)."""
    ny, nx = image.shape
    x = (np.arange(nx) + 0.5) * pitch - 0.5 * nx * pitch
    y = (np.arange(ny) + 0.5) * pitch - 0.5 * ny * pitch
    X, Y = np.meshgrid(x, y)
    c = np.array([(image * X).sum(), (image * Y).sum()]) / image.sum()
    for _ in range(100):
        inside = (X - c[0]) ** 2 + (Y - c[1]) ** 2 <= radius**2
        w = image * inside
        c = np.array([(w * X).sum(), (w * Y).sum()]) / w.sum()
    return c


def test_the_sky_wcs_puts_an_off_axis_sun_where_it_was(tmp_path):
    """The `S` WCS of a Sun scene is helioprojective (HPLN/HPLT from the Sun's
    centre, astropy reads it), measured by tracing. A Sun pointed 3′ and −2′
    off (along the scene's offset axes) images where that WCS, made for the
    Sun on axis, says a point 180″, −120″ from the on-axis Sun's centre lands:
    within 5 % of the offset plus 3″ (the LLNL segment's image centre moves
    slightly non-linearly with pointing: +3′ lands at 187″, −3′ at −177″ in
    this frame; the WCS is linear, measured at ±2′; 3″ covers the Monte Carlo
    noise of the measurement and of these 10⁶-photon images). The on-axis
    image's centre is the Sun's centre within a pixel of the GridPix grid (55 µm,
    7.6″ here)."""
    cast = REPO / "scenes" / "cast_axion_image.toml"
    on, off = tmp_path / "on", tmp_path / "off"
    traxer("trace", cast, "-n", "1e6", "--out", on, "-q", "--fits")
    traxer("trace", cast, "-n", "1e6", "-D", "offset_x=3", "-D", "offset_y=-2", "--out", off, "-q")
    header = fits.getheader(on / "chip.fits")
    assert header["CTYPE1S"] == "HPLN-TAN" and header["CTYPE2S"] == "HPLT-TAN"
    assert header["WCSNAMES"] == "HELIOPROJECTIVE"
    wcs = WCS(header, key="S")
    sky = json.loads((on / "chip.json").read_text())["sensor"]["sky_wcs"]
    radius = sky["calibration"]["window_radius_mm"]
    pitch = 14.0 / 1000

    def world(image):
        c = windowed_centre(image, pitch, radius)
        px, py = (c + 7.0) / pitch - 0.5
        lon, lat = wcs.pixel_to_world_values(px, py)
        # degrees, wrapped to ±180°, in arcsec
        return [((v + 180.0) % 360.0 - 180.0) * 3600.0 for v in (float(lon), float(lat))]

    centre = world(np.load(on / "chip.npy"))
    assert np.hypot(*centre) < 0.055 / header["SKYSCALE"] * 60.0, centre
    got = world(np.load(off / "chip.npy"))
    for g, want in zip(got, [180.0, -120.0]):
        assert abs(g - want) < 0.05 * np.hypot(180.0, 120.0) + 3.0, (got, centre)
    # The plate scale the header states is not f·θ (0.436 mm/arcmin at 1.5 m):
    # the bore, the 30° segments and the gas make it 10–20 % smaller.
    assert 0.80 * 0.4363 < header["SKYSCALE"] < 0.92 * 0.4363, header["SKYSCALE"]
    assert header["SKYSCERR"] < 0.005 * header["SKYSCALE"]
    # The grid FITS carries the same frame: the Sun's centre (its reference
    # pixel) is the same point of the sensor, through the grid's turn and centre.
    gh = fits.getheader(on / "chip_grid.fits")
    gx, gy = WCS(gh).pixel_to_world_values(gh["CRPIX1S"] - 1, gh["CRPIX2S"] - 1)
    turn = np.radians(gh["GRIDROT"])
    local = [
        gh["GRIDCX"] + np.cos(turn) * gx - np.sin(turn) * gy,
        gh["GRIDCY"] + np.sin(turn) * gx + np.cos(turn) * gy,
    ]
    assert np.allclose(local, sky["calibration"]["centre_mm"], atol=1e-9), local


def test_process_images_are_extensions_with_the_primary_wcs(tmp_path):
    """A Sun with Primakoff and ABC: chip.fits holds the total as its primary
    image and one image extension per process (PRIMAKOFF, ABC and ABC's four
    processes), equal to chip_PROCESS.npy, PRIMAKOFF and ABC adding up to the
    total, with the same WCS (mm, focal plane, sky) as the primary."""
    out = tmp_path / "electron"
    traxer("trace", REPO / "scenes" / "cast_axion_electron_image.toml", "-n", 30000,
           "--out", out, "-q", "--fits")
    with fits.open(out / "chip.fits") as f:
        assert [h.name for h in f] == ["PRIMARY", "PRIMAKOFF", "ABC", "ATOMIC", "ELECTRON_ION",
                                       "ELECTRON_ELECTRON", "COMPTON"]
        total = f[0].data
        for h in f[1:]:
            assert h.header["PROCESS"] == h.name.lower()
            assert np.array_equal(h.data, np.load(out / f"chip_{h.name.lower()}.npy"))
            for key in [" ", "A", "S"]:
                a, b = WCS(f[0].header, key=key), WCS(h.header, key=key)
                assert np.allclose(a.pixel_to_world_values(3.0, 7.0),
                                   b.pixel_to_world_values(3.0, 7.0), rtol=0, atol=1e-15)
            assert h.header["BUNIT"] == f[0].header["BUNIT"]
        assert np.allclose(f[1].data + f[2].data, total, rtol=1e-13, atol=0)
        assert f[1].data.sum() > 0 and f[2].data.sum() > 50 * f[1].data.sum()


def test_no_sky_wcs_without_a_sun(tmp_path):
    """A lab beam is not the sky: its FITS has the mm and focal-plane WCS only."""
    scene = wolter_scene(tmp_path, False)
    out = tmp_path / "lab"
    traxer("trace", scene, "-n", 20000, "--out", out, "-q", "--fits")
    header = fits.getheader(out / "sensor.fits")
    assert "CTYPE1A" in header and "CTYPE1S" not in header and "WCSNAMES" not in header


def test_grid_image_fits_equals_the_grid_npy_and_eef_reads_fits(tmp_path):
    out = tmp_path / "cast"
    traxer("trace", REPO / "scenes" / "cast_axion_image.toml", "-n", 30000, "--out", out, "-q", "--fits")
    with fits.open(out / "chip_grid.fits") as f:
        data, header = f[0].data, f[0].header
    assert np.array_equal(data, np.load(out / "chip_grid.npy"))
    sensor = json.loads((out / "chip.json").read_text())["sensor"]
    assert header["CDELT1"] == sensor["pixel_grid"]["pitch_mm"]
    assert sensor["pixel_grid"]["files"]["grid_fits"] == "chip_grid.fits"
    # `traxer eef` on the FITS and on the .npy (pitch from the sensor's JSON)
    # give the image quality the JSON reports.
    for name in ["chip.fits", "chip.npy"]:
        q = json.loads(traxer("eef", out / name, "--json", "--plot", tmp_path / (name + ".png")).stdout)
        assert q["hpd_mm"] == pytest.approx(sensor["image_quality"]["hpd_mm"], rel=1e-12)
        assert q["hpd_arcsec"] == pytest.approx(sensor["image_quality"]["hpd_arcsec"], rel=1e-12)
    grid = json.loads(traxer("eef", out / "chip_grid.npy", "--json", "--plot", tmp_path / "g.png").stdout)
    from_fits = json.loads(traxer("eef", out / "chip_grid.fits", "--json", "--plot", tmp_path / "h.png").stdout)
    assert grid == from_fits
    # The grid's 55 µm pixels resample the image: its HPD within 2 %.
    assert grid["hpd_mm"] == pytest.approx(sensor["image_quality"]["hpd_mm"], rel=0.02)


def test_effective_area_writes_ogip_arfs_equal_to_its_csv(tmp_path):
    """`effective-area` writes one OGIP ARF per off-axis angle (CAL/GEN/92-002 §4,
    type I): a null primary array, one SPECRESP BINTABLE with ENERG_LO, ENERG_HI
    (keV, contiguous bins centred on the sweep's energies) and SPECRESP (cm²),
    the memo's keywords; the areas are the CSV's (to float32)."""
    out = tmp_path / "ea"
    traxer("effective-area", REPO / "scenes" / "llnl_effective_area.toml",
           "--energies", "1:3:0.5", "--angles", "0,2.5", "-n", 50000, "--out", out, "-q")
    with open(out / "effective_area.csv") as f:
        rows = list(csv.DictReader(f))
    for angle in ("0", "2.5"):
        with fits.open(out / f"effective_area_{angle}arcmin.arf") as h:
            assert len(h) == 2 and h[0].data is None
            ext = h["SPECRESP"]
            hdr = ext.header
            assert hdr["XTENSION"] == "BINTABLE"
            for key, value in [("HDUCLASS", "OGIP"), ("HDUCLAS1", "RESPONSE"),
                               ("HDUCLAS2", "SPECRESP"), ("HDUVERS", "1.1.0"),
                               ("TUNIT1", "keV"), ("TUNIT2", "keV"),
                               ("TUNIT3", "cm**2")]:
                assert hdr[key] == value, key
            for key in ("TELESCOP", "INSTRUME", "FILTER"):
                assert hdr[key].strip(), key
            assert hdr["OFFAXIS"] == float(angle)
            assert list(ext.columns.names) == ["ENERG_LO", "ENERG_HI", "SPECRESP"]
            lo, hi, area = (ext.data[c] for c in ("ENERG_LO", "ENERG_HI", "SPECRESP"))
        mine = [r for r in rows if float(r["off_axis_arcmin"]) == float(angle)]
        energies = np.array([float(r["energy_keV"]) for r in mine])
        np.testing.assert_allclose(0.5 * (lo + hi), energies, rtol=1e-6)
        np.testing.assert_array_equal(lo[1:], hi[:-1])
        assert np.all(hi > lo) and lo[0] > 0
        csv_area = np.array([float(r["area_cm2"]) for r in mine])
        np.testing.assert_allclose(area, csv_area, rtol=1e-6)
        assert np.all(csv_area > 1.0)
    # One energy has no bin width: no ARF, and the CLI says so.
    out1 = tmp_path / "one"
    said = traxer("effective-area", REPO / "scenes" / "llnl_effective_area.toml",
                  "--energies", "1.5", "--angles", "0", "-n", 2000, "--out", out1)
    assert not list(out1.glob("*.arf")) and "no ARF" in said.stdout


def test_effective_area_writes_the_vignetting_as_a_fits_table(tmp_path):
    """vignetting.fits: one row per angle and energy, the CSV's areas and errors,
    VIGNET = the area over the on-axis area at the same energy."""
    out = tmp_path / "ea"
    traxer("effective-area", REPO / "scenes" / "llnl_effective_area.toml",
           "--energies", "1,1.5,3", "--angles", "0,5", "-n", 40000, "--out", out, "-q")
    with open(out / "effective_area.csv") as f:
        rows = list(csv.DictReader(f))
    with fits.open(out / "vignetting.fits") as h:
        t = h["VIGNETTING"]
        assert t.header["VIGREF"] == 0.0 and t.header["TUNIT3"] == "cm**2"
        d = t.data
        assert len(d) == len(rows) == 6
        for row, r in zip(d, rows):
            assert row["OFFAXIS"] == float(r["off_axis_arcmin"])
            assert row["ENERGY"] == float(r["energy_keV"])
            assert row["AREA"] == float(r["area_cm2"])
            assert row["AREA_ERR"] == float(r["error_cm2"])
        for row in d:
            on = d[(d["OFFAXIS"] == 0.0) & (d["ENERGY"] == row["ENERGY"])]["AREA"][0]
            assert row["VIGNET"] == pytest.approx(row["AREA"] / on, rel=1e-12)
        five = d[d["OFFAXIS"] == 5.0]["VIGNET"]
        assert np.all(five < 1.0) and np.all(five > 0.5)


def test_psf_library_is_the_layout_sixte_reads_and_equals_plain_traces(tmp_path):
    """`traxer psf` writes one image per HDU (the primary included) with the
    keywords SIXTE's PSF reader takes (ENERGY in eV, THETA in arcmin, PHI in
    degrees, CUNIT m, CDELT/CRPIX/CRVAL) and the OGIP CAL/GEN/92-027 classes;
    each image is normalised to 1, equals psf.npy, and equals the window of a
    plain `traxer trace` of the scene set to that angle and energy (the same
    photons: to rounding); nominal position f·tan θ + CRVAL + pixel offset is
    where the WCS A (the sensor's mm) puts the pixel."""
    scene = REPO / "scenes" / "xmm_effective_area.toml"
    out = tmp_path / "psf"
    traxer("psf", scene, "--energies", "1.5,8", "--angles", "0,10", "--window", 51,
           "-n", 20000, "--out", out, "-q")
    stack = np.load(out / "psf.npy")
    assert stack.shape == (2, 1, 2, 51, 51)
    desc = json.loads((out / "psf.json").read_text())
    with fits.open(out / "psf.fits") as f:
        assert len(f) == 4
        grid = f[0].header
        assert (grid["NPSFIMG"], grid["NPSFE"], grid["NPSFT"], grid["NPSFP"]) == (4, 2, 2, 1)
        assert [grid["PSFE1"], grid["PSFE2"], grid["PSFT2"], grid["PSFP1"]] == [1.5, 8.0, 10.0, 0.0]
        for k, h in enumerate(f):
            p = desc["points"][k]
            a, e = desc["angles_arcmin"].index(p["angle_arcmin"]), desc["energies_keV"].index(p["energy_keV"])
            assert np.array_equal(h.data, stack[a, 0, e])
            assert abs(h.data.sum() - 1.0) < 1e-12
            head = h.header
            assert head["ENERGY"] == p["energy_keV"] * 1000 and head["THETA"] == p["angle_arcmin"]
            assert head["PHI"] == 0.0 and head["CUNIT1"] == "m" and head["CUNIT2"] == "m"
            for key, value in [("HDUCLASS", "OGIP"), ("HDUCLAS1", "IMAGE"), ("HDUCLAS2", "PSF"),
                               ("CTYPE1", "DETX"), ("CTYPE2", "DETY")]:
                assert head[key] == value, key
            assert head["CDELT1"] == 50e-6 and head["CRPIX1"] == 26.0
            theta = np.radians(head["THETA"] / 60.0)
            for px in [(0.0, 0.0), (50.0, 20.0)]:
                mm = WCS(head, key="A").pixel_to_world_values(*px)
                m = WCS(head, key=" ").pixel_to_world_values(*px)
                nominal = [head["FOCALLEN"] * np.tan(theta), 0.0]
                assert np.allclose([(m[i] + nominal[i]) * 1e3 for i in (0, 1)], mm, atol=1e-9)
            # A plain trace of the scene at this angle and energy.
            plain = tmp_path / f"trace{k}"
            traxer("trace", scene, "-n", 20000, "-D", f"energy={p['energy_keV']}",
                   "-D", f"off_axis={p['angle_arcmin'] / 60.0!r}", "--out", plain, "-q")
            image = np.load(plain / "sensor.npy")
            x0, y0 = p["window_corner_pixel"]
            window = image[y0:y0 + 51, x0:x0 + 51]
            assert np.allclose(h.data, window / window.sum(), rtol=1e-12, atol=1e-15)
            assert abs(p["fraction_in_window"] - window.sum() / image.sum()) < 1e-12
    # The 8 keV image differs from the 1.5 keV one (the energy is applied).
    assert not np.allclose(stack[1, 0, 0], stack[1, 0, 1])


def test_psf_library_refuses_what_it_cannot_place(tmp_path):
    """A window larger than the sensor, and a sensor without a focal length
    (the nominal position f·tan θ is undefined), are refused with exit code 2
    and no files."""
    out = tmp_path / "psf"
    bad = subprocess.run([TRAXER, "psf", str(REPO / "scenes" / "xmm_effective_area.toml"),
                          "--window", "3000", "-n", "100", "--out", str(out)],
                         capture_output=True, text=True)
    assert bad.returncode == 2 and "does not fit" in bad.stderr, bad.stderr
    assert not (out / "psf.fits").exists()
    plain = wolter_scene(tmp_path, True)  # energy bins, no focal length
    bad = subprocess.run([TRAXER, "psf", str(plain), "-n", "100", "--out", str(out)],
                         capture_output=True, text=True)
    assert bad.returncode == 2 and "focal_length" in bad.stderr, bad.stderr
    assert not (out / "psf.fits").exists()


def test_signal_spectrum_fits_holds_the_csv_per_mass(tmp_path):
    """`traxer signal` writes one SPECTRUM table per axion mass: ENERG_LO,
    ENERG_HI (keV) and RATE (X-rays/s) equal to signal_spectrum.csv, with the
    mass and the region in the header."""
    run_dir = tmp_path / "run"
    traxer("trace", REPO / "scenes" / "cast_axion_image.toml", "-n", 5000, "-q",
           "-D", "magnet=true", "-D", "pixels=100", "-D", "energy_bins=[1,10,9]",
           "--masses", "0,0.02", "-o", run_dir)
    traxer("signal", run_dir, "--radius-mm", "3", "-q", "-o", tmp_path / "s")
    rows = list(csv.DictReader(open(tmp_path / "s" / "signal_spectrum.csv")))
    with fits.open(tmp_path / "s" / "signal_spectrum.fits") as f:
        tables = [h for h in f if h.name == "SPECTRUM"]
        assert len(tables) == 2
        for k, (h, mass) in enumerate(zip(tables, [0.0, 0.02])):
            assert h.header["MASS_EV"] == mass and h.header["REG_R"] == 3.0
            assert h.header["HDUCLASS"] == "OGIP" and h.columns["ENERG_LO"].unit == "keV"
            mine = [r for r in rows if float(r["axion_mass_ev"]) == mass]
            assert list(h.data["ENERG_LO"]) == [float(r["energy_lo_kev"]) for r in mine]
            assert list(h.data["RATE"]) == [float(r["x_rays_per_s"]) for r in mine]
            # The FITS spelling of counts per second, which astropy parses
            # without a UnitsWarning (`counts/s` drew one: issue 59).
            assert h.columns["RATE"].unit == "ct / s"
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                assert str(Table.read(h).columns["RATE"].unit) in ("ct / s", "ct s-1")
