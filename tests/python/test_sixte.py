"""The PSF library and the vignetting file read the way SIXTE reads them.

SIXTE is not installed here (it needs HEASoft), so its two readers are followed
step by step in Python, from the simulator's own code (libsixt/psf.c: newPSF and
get_psf_pos; libsixt/vignetting.c: newVignetting and get_Vignetting_Factor):
which HDUs and keywords they read, the units they convert, how they pick an
image or a value, and where a pixel lands in the focal plane. astropy only
decodes the FITS bytes. A file these readers cannot take, or take wrongly,
fails here, as it would in SIXTE.

Run by scripts/test-python.sh (part of scripts/test.sh); TRAXER names the binary.
"""

import csv
import json
import math
import re

import numpy as np
import pytest
from astropy.io import fits

from test_fits import REPO, traxer


# --- libsixt/vignetting.c ----------------------------------------------------

class SixteVignetting:
    """newVignetting: the first table HDU (fits_open_table on a file name), the
    columns ENERG_LO, ENERG_HI, THETA, PHI and VIGNET found case-insensitively,
    the array's shape from TDIMn of VIGNET as "(nE,nTheta,nPhi)", each column
    read from row 1 element 1 onwards (across rows) as float, THETA and PHI
    turned from degrees into radians, VIGNET[e][t][p] = buffer[e + t·nE +
    p·nE·nTheta]."""

    def __init__(self, path):
        with fits.open(path) as h:
            table = next(x for x in h if isinstance(x, (fits.BinTableHDU, fits.TableHDU)))
            by_upper = {n.upper(): n for n in table.columns.names}
            column = {c: by_upper[c] for c in ("ENERG_LO", "ENERG_HI", "THETA", "PHI", "VIGNET")}
            k = table.columns.names.index(column["VIGNET"]) + 1
            self.ne, self.nt, self.nphi = map(
                int, re.match(r"\((\d+),(\d+),(\d+)\)", table.header[f"TDIM{k}"]).groups())

            def read(name, n):
                flat = np.concatenate([np.asarray(r, dtype=np.float64).ravel()
                                       for r in table.data[column[name]]])
                return flat[:n].astype(np.float32)

            self.lo = read("ENERG_LO", self.ne)
            self.hi = read("ENERG_HI", self.ne)
            self.theta = read("THETA", self.nt) * np.float32(math.pi / 180.0)
            self.phi = read("PHI", self.nphi) * np.float32(math.pi / 180.0)
            buffer = read("VIGNET", self.ne * self.nt * self.nphi)
        self.emin, self.emax = float(self.lo.min()), float(self.hi.max())
        self.vignet = [[[buffer[e + t * self.ne + p * self.ne * self.nt]
                         for p in range(self.nphi)] for t in range(self.nt)]
                       for e in range(self.ne)]

    def factor(self, energy, theta, phi=0.0):
        """get_Vignetting_Factor: −1 outside [Emin, Emax]; else the bin with
        lo < E ≤ hi, the nearest θ (the first of equals), φ ignored (index 0)."""
        if energy < self.emin or energy > self.emax:
            return -1.0
        for e in range(self.ne):
            if self.lo[e] < energy <= self.hi[e]:
                best, factor = -1.0, 0.0
                for t in range(self.nt):
                    if abs(theta - self.theta[t]) < best or best < 0.0:
                        best, factor = abs(theta - self.theta[t]), self.vignet[e][t][0]
                return float(factor)
        raise AssertionError("SIXTE asserts an energy bin exists")


def test_effective_area_writes_the_vignetting_sixte_reads(tmp_path):
    """vignetting_sixte.fits, read as SIXTE reads it, gives at every energy and
    off-axis angle of the sweep (and at angles nearer one than another) the
    area over the on-axis area, so that the on-axis ARF times it is the
    off-axis ARF; energies beyond the bins give SIXTE's −1. The table traxer
    also writes (vignetting.fits) is not SIXTE's layout, as its reader says."""
    out = tmp_path / "ea"
    said = traxer("effective-area", REPO / "scenes" / "llnl_effective_area.toml",
                  "--energies", "1:3:0.5", "--angles", "0,2.5,5", "-n", 30000, "--out", out)
    assert "vignetting_sixte.fits" in said.stdout
    with open(out / "effective_area.csv") as f:
        rows = list(csv.DictReader(f))
    area = {(float(r["off_axis_arcmin"]), float(r["energy_keV"])): float(r["area_cm2"])
            for r in rows}
    v = SixteVignetting(out / "vignetting_sixte.fits")
    assert (v.ne, v.nt, v.nphi) == (5, 3, 1)
    radians = lambda arcmin: arcmin / 60.0 * math.pi / 180.0
    for (angle, energy), a in area.items():
        expected = a / area[(0.0, energy)]
        for near in (angle, angle + 0.9):
            assert v.factor(energy, radians(near)) == pytest.approx(expected, rel=2e-7)
    assert v.factor(0.5, 0.0) == -1.0 and v.factor(10.0, 0.0) == -1.0
    with fits.open(out / "effective_area_0arcmin.arf") as h0, \
            fits.open(out / "effective_area_5arcmin.arf") as h5:
        on, off = h0["SPECRESP"].data, h5["SPECRESP"].data
        for k, energy in enumerate(0.5 * (on["ENERG_LO"] + on["ENERG_HI"])):
            assert on["SPECRESP"][k] * v.factor(float(energy), radians(5.0)) == \
                pytest.approx(off["SPECRESP"][k], rel=1e-6)
    with pytest.raises(KeyError):
        SixteVignetting(out / "vignetting.fits")
    # Without the axis among the angles there is no on-axis ARF to scale: no
    # file, and the command says why.
    out2 = tmp_path / "off"
    said = traxer("effective-area", REPO / "scenes" / "llnl_effective_area.toml",
                  "--energies", "1,2", "--angles", "2.5,5", "-n", 2000, "--out", out2)
    assert not (out2 / "vignetting_sixte.fits").exists()
    assert "no vignetting_sixte.fits" in said.stdout and "on-axis" in said.stdout


# --- libsixt/psf.c -----------------------------------------------------------

class SixtePsf:
    """newPSF: every HDU that is an image (the primary included) must carry
    ENERGY [eV], THETA [arcmin] and PHI [deg], turned into keV and radians; the
    values are collected (equal within 1e-6 relative) and sorted; each image's
    CDELT, CRPIX, CRVAL and CUNIT ("m", or "arcsec" scaled by
    tan(1″)·focal length) are read, and its pixels normalised to a sum of 1."""

    def __init__(self, path, focal_length_m):
        self.items = {}
        grids = ([], [], [])
        with fits.open(path) as h:
            for hdu in h:
                if not isinstance(hdu, (fits.PrimaryHDU, fits.ImageHDU)):
                    continue
                head = hdu.header
                key = (head["ENERGY"] * 1e-3, head["THETA"] * math.pi / 180.0 / 60.0,
                       head["PHI"] * math.pi / 180.0)
                for values, value in zip(grids, key):
                    if not any(abs(v - value) <= abs(value * 1e-6) for v in values):
                        values.append(value)
                cunit = (head["CUNIT1"], head["CUNIT2"])
                scale = 1.0
                if cunit == ("arcsec", "arcsec"):
                    scale = math.tan(1.0 / 3600.0 * math.pi / 180.0) * focal_length_m
                elif cunit != ("m", "m"):
                    raise ValueError("PSF pixel width must be given either in [m] or in [arcsec]")
                data = np.asarray(hdu.data, dtype=np.float64)
                self.items[key] = dict(
                    data=data / data.sum(),
                    cdelt=(head["CDELT1"] * scale, head["CDELT2"] * scale),
                    crpix=(head["CRPIX1"], head["CRPIX2"]),
                    crval=(head["CRVAL1"] * scale, head["CRVAL2"] * scale))
        self.energies, self.thetas, self.phis = (sorted(v) for v in grids)
        self.focal_length = focal_length_m

    def mean_position(self, energy, theta, phi):
        """get_psf_pos at a grid point (SIXTE's random choice of a neighbouring
        image then never leaves it): the probability-weighted focal-plane
        position (m) of the pixels, each at its centre (the random offset's
        mean, 0.5): x = f·tan θ + (x1 − CRPIX1 + 1)·CDELT1 + CRVAL1,
        y = (y1 − CRPIX2 + 1)·CDELT2 + CRVAL2, turned by φ."""
        item = self.items[(energy, theta, phi)]
        ny, nx = item["data"].shape
        x1, y1 = np.meshgrid(np.arange(nx), np.arange(ny))
        x2 = (self.focal_length * math.tan(theta)
              + (x1 - item["crpix"][0] + 1.0) * item["cdelt"][0] + item["crval"][0])
        y2 = (y1 - item["crpix"][1] + 1.0) * item["cdelt"][1] + item["crval"][1]
        x = math.cos(phi) * x2 - math.sin(phi) * y2
        y = math.sin(phi) * x2 + math.cos(phi) * y2
        p = item["data"]
        return float((p * x).sum()), float((p * y).sum())


def test_psf_library_puts_each_image_where_traxer_traced_it_at_any_azimuth(tmp_path):
    """Read as SIXTE reads it, every image of the library lands in the focal
    plane where traxer traced it: the SIXTE-weighted mean position of its
    pixels is the centroid of the traced window (psf.npy on the sensor's
    pixels), at φ = 0 to rounding and at φ = 90° and 30° (where SIXTE turns the
    image by φ, and traxer stores it turned back, resampled) within a tenth of
    a pixel. Before, an image at φ ≠ 0 landed several mm away."""
    scene = REPO / "scenes" / "xmm_effective_area.toml"
    out = tmp_path / "psf"
    traxer("psf", scene, "--energies", "1.5,6", "--angles", "0,10", "--azimuths", "0,30,90",
           "--window", 61, "-n", 20000, "--out", out, "-q")
    desc = json.loads((out / "psf.json").read_text())
    stack = np.load(out / "psf.npy")
    f_m = desc["focal_length_mm"] * 1e-3
    psf = SixtePsf(out / "psf.fits", f_m)
    assert len(psf.energies) == 2 and len(psf.thetas) == 2 and len(psf.phis) == 3
    pitch, size = desc["pixel_pitch_mm"], desc["sensor_size_mm"]
    for p in desc["points"]:
        a = desc["angles_arcmin"].index(p["angle_arcmin"])
        z = desc["azimuths_deg"].index(p["azimuth_deg"])
        e = desc["energies_keV"].index(p["energy_keV"])
        window = stack[a, z, e]
        ny, nx = window.shape
        x0, y0 = p["window_corner_pixel"]
        xs = ((x0 + np.arange(nx) + 0.5) * pitch[0] - 0.5 * size[0]) * 1e-3
        ys = ((y0 + np.arange(ny) + 0.5) * pitch[1] - 0.5 * size[1]) * 1e-3
        traced = ((window.sum(axis=0) * xs).sum(), (window.sum(axis=1) * ys).sum())
        key = (p["energy_keV"], p["angle_arcmin"] * math.pi / 180.0 / 60.0,
               p["azimuth_deg"] * math.pi / 180.0)
        key = (min(psf.energies, key=lambda v: abs(v - key[0])),
               min(psf.thetas, key=lambda v: abs(v - key[1])),
               min(psf.phis, key=lambda v: abs(v - key[2])))
        sixte = psf.mean_position(*key)
        tolerance = 1e-12 if p["azimuth_deg"] == 0.0 else 0.1 * pitch[0] * 1e-3
        for k in (0, 1):
            assert abs(sixte[k] - traced[k]) <= tolerance, (p, sixte, traced)


def test_the_sixte_vignetting_is_in_rising_theta_whatever_order_the_angles_came(tmp_path):
    """SIXTE interpolates in THETA, which must rise: a sweep given as 5,0
    writes the table of a sweep given as 0,5 (issue 59: it was written in
    the given order)."""
    tables = []
    for angles in ("5,0", "0,5"):
        out = tmp_path / angles.replace(",", "_")
        traxer("effective-area", REPO / "scenes" / "llnl_effective_area.toml",
               "--energies", "2,4", "--angles", angles, "-n", 20000, "-q", "--out", out)
        with fits.open(out / "vignetting_sixte.fits") as f:
            d = f[1].data
            tables.append((np.array(d["THETA"]).ravel(), np.array(d["VIGNET"]).ravel()))
    (theta, vig), (theta_sorted, vig_sorted) = tables
    assert list(theta) == sorted(theta) and list(theta) == list(theta_sorted)
    assert list(vig) == list(vig_sorted)
