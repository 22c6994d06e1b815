#!/usr/bin/env python3
"""Writes the independent reference numbers that tests/it/xray.rs compares with.

* Optical constants δ, β: from the Python package `periodictable` (its own formula
  parser, masses and interpolation of the same Henke tables).
* Reflectivity of the shipped coatings: the Parratt recursion of the Python package
  `xraydb` (multilayer_reflectivity), fed with periodictable's δ, β so that the
  comparison tests traxer's Fresnel/Parratt code and layer construction, not the
  difference between the Henke and Chantler tables. s polarisation only: xraydb 4.5's
  p branch uses k_z/n instead of k_z/n² at the vacuum interface.

Run once (CI does not need Python):
    python3 -m venv /tmp/ref && /tmp/ref/bin/pip install periodictable==2.1.0 xraydb==4.5.8
    /tmp/ref/bin/python scripts/reference_reflectivity.py
"""
import sys as _sys

if __name__ == "__main__" and any(a in ("-h", "--help") for a in _sys.argv[1:]):
    print(__doc__)
    _sys.exit(0)
import csv
import math
import os

import numpy as np
import periodictable
import periodictable.xsf as xsf
import xraydb
import xraydb.xray

OUT = os.path.join(os.path.dirname(__file__), "..", "tests", "data")

MATERIALS = {  # name: (formula, density) as in data/coatings.toml
    "C": ("C", 2.26),
    "Pt": ("Pt", 21.41),
    "SiO2": ("SiO2", 2.65),
    "Au": ("Au", 19.32),
}


def delta_beta(formula, density, energy_kev):
    n = xsf.index_of_refraction(formula, density=density, energy=energy_kev)
    return 1.0 - n.real, -n.imag


def patched_delta_beta(material, density, energy_ev):
    e = np.atleast_1d(np.asarray(energy_ev, dtype=float)) / 1000.0
    d, b = zip(*(delta_beta(material, density, x) for x in e))
    d, b = np.array(d), np.array(b)
    if np.ndim(energy_ev) == 0:
        return d[0], b[0], 0.0
    return d, b, np.zeros_like(d)


xraydb.xray.xray_delta_beta = patched_delta_beta


def depth_graded(d_min, d_max, c, n):
    k = (d_min / d_max) ** (1.0 / c)
    b = (1.0 - n * k) / (k - 1.0)
    a = d_min * (b + n) ** c
    return [a / (b + i) ** c for i in range(1, n + 1)]


RECIPES = {  # name: (d_min, d_max, gamma, N)
    "llnl_recipe_1": (11.5, 22.5, 0.45, 2),
    "llnl_recipe_2": (7.0, 19.0, 0.45, 3),
    "llnl_recipe_3": (5.5, 16.0, 0.40, 4),
    "llnl_recipe_4": (5.0, 14.0, 0.40, 5),
}


def stack(name):
    if name in RECIPES:
        d_min, d_max, gamma, n = RECIPES[name]
        layers, thick = [], []
        for d in depth_graded(d_min, d_max, 1.0, n):
            layers += ["C", "Pt"]
            thick += [10.0 * gamma * d, 10.0 * (1.0 - gamma) * d]  # Å
        return layers, thick, "SiO2"
    if name == "gold":
        return ["Au"], [500.0], "SiO2"
    raise KeyError(name)


def main():
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "reference_optical_constants.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["material", "energy_keV", "delta", "beta"])
        for name, (formula, rho) in MATERIALS.items():
            for e in [0.1, 0.5, 1.0, 1.49, 2.0, 4.51, 6.41, 8.0, 10.0, 20.0]:
                d, b = delta_beta(formula, rho, e)
                w.writerow([name, e, repr(float(d)), repr(float(b))])
    with open(os.path.join(OUT, "reference_reflectivity.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["coating", "energy_keV", "theta_deg", "R_s"])
        thetas = np.linspace(0.05, 3.0, 60)
        for name in list(RECIPES) + ["gold"]:
            layers, thick, sub = stack(name)
            dens = [MATERIALS[m][1] for m in layers]
            for e in [1.49, 4.51, 6.41, 8.0]:
                r = xraydb.multilayer_reflectivity(
                    [MATERIALS[m][0] for m in layers], thick, MATERIALS[sub][0],
                    np.radians(thetas), e * 1000.0, density=dens,
                    substrate_density=MATERIALS[sub][1], polarization="s")
                for t, rv in zip(thetas, r):
                    w.writerow([name, e, repr(float(t)), repr(float(rv))])
    print("periodictable", periodictable.__version__, "xraydb", xraydb.__version__)


if __name__ == "__main__":
    main()
