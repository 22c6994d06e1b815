#!/usr/bin/env python3
"""Writes data/chantler/*.nff: Chantler's (NIST FFAST) atomic form factors f1, f2
for H ... U between 10 eV and 30 keV, in the Henke .nff layout traxer reads
(energy in eV, f1, f2), as the second table of optical constants
(`optical_constants = "chantler"` in a scene; the `optical_constants` source of
`traxer systematics`).

The numbers are Chantler's as the database of the Python package xraydb 4.5.8
holds them (its table `Chantler`: the FFAST energies, f1 − Z, f2 and the
element's relativistic and nuclear-Thomson corrections). The total real form
factor is f1 = Z + (f1 − Z) + f_rel(H82, 3/5 CL) + f_NT, the sum Chantler's
tables recommend (C. T. Chantler, J. Phys. Chem. Ref. Data 24, 71 (1995) and
29, 597 (2000)). Rows are Chantler's own nodes (no resampling), from the last
node at or below 10 eV to the first at or above 30 keV; an energy FFAST
repeats at an absorption edge is written 1e-6 relative higher the second time.

Also writes data/chantler/scattering.csv: each element's X-ray scattering
cross-section (coherent + incoherent, FFAST's [sigma/rho]coh+inc, which FFAST
takes from Hubbell's tables) in barn per atom, on 61 energies from 30 eV to
30 keV equally spaced in log E (20 a decade; the cross-sections are smooth,
log-log interpolation between them is good to < 0.3 %). With Henke's
photoabsorption it gives the total attenuation of the magnet's buffer gas.

Usage (installs xraydb into a throw-away venv):
    python3 -m venv /tmp/xr && /tmp/xr/bin/pip install xraydb==4.5.8
    /tmp/xr/bin/python scripts/make_chantler_tables.py
"""
import sys as _sys

if __name__ == "__main__" and any(a in ("-h", "--help") for a in _sys.argv[1:]):
    print(__doc__)
    _sys.exit(0)
import json
import hashlib
import pathlib

import xraydb

OUT = pathlib.Path(__file__).resolve().parent.parent / "data" / "chantler"
E_LOW, E_HIGH = 10.0, 30000.0


def main():
    assert xraydb.__version__ == "4.5.8", xraydb.__version__
    db = xraydb.get_xraydb()
    OUT.mkdir(exist_ok=True)
    sums = []
    for z in range(1, 93):
        symbol = db.symbol(z)
        row = db.get_cache("Chantler", column="element", value=symbol)[0]
        energy = json.loads(row.energy)
        f1 = json.loads(row.f1)
        f2 = json.loads(row.f2)
        lo = max(i for i, e in enumerate(energy) if e <= E_LOW)
        hi = min(i for i, e in enumerate(energy) if e >= E_HIGH)
        shift = z + row.corr_cl35 + row.corr_nucl
        lines = [
            f"# Chantler (NIST FFAST) {symbol}, Z = {z}: f1 = Z + (f1 - Z) + f_rel(3/5CL) "
            f"{row.corr_cl35} + f_NT {row.corr_nucl}; from xraydb 4.5.8 by "
            "scripts/make_chantler_tables.py",
            "E(eV)\tf1\tf2",
        ]
        previous = 0.0
        for i in range(lo, hi + 1):
            # At an absorption edge FFAST gives the edge energy twice (below,
            # then above): the second is written 1e-6 relative higher, so that
            # the edge stays a step for a reader that needs ascending energies.
            e = energy[i] if energy[i] > previous else previous * (1 + 1e-6)
            previous = e
            lines.append(f"{e:.10g}\t{f1[i] + shift:.6g}\t{f2[i]:.6g}")
        text = "\n".join(lines) + "\n"
        name = f"{symbol.lower()}.nff"
        (OUT / name).write_text(text)
        sums.append(f"{hashlib.sha256(text.encode()).hexdigest()}  {name}")
    rows = ["# X-ray scattering cross-sections (coherent + incoherent) per atom, NIST FFAST "
            "(Chantler 1995, 2000; [sigma/rho]coh+inc) from xraydb 4.5.8 by "
            "scripts/make_chantler_tables.py",
            "Z,symbol,energy_keV,sigma_scatter_barn"]
    energies = [0.03 * 10 ** (k / 20) for k in range(61)]
    for z in range(1, 93):
        symbol = db.symbol(z)
        mass = xraydb.atomic_mass(symbol)
        for e in energies:
            per_gram = float(xraydb.mu_chantler(symbol, e * 1000.0, incoh=True))
            barn = per_gram * mass / 6.02214076e23 / 1e-24
            rows.append(f"{z},{symbol},{e:.6g},{barn:.6g}")
    text = "\n".join(rows) + "\n"
    (OUT / "scattering.csv").write_text(text)
    sums.append(f"{hashlib.sha256(text.encode()).hexdigest()}  scattering.csv")
    (OUT / "SHA256SUMS").write_text("\n".join(sums) + "\n")


if __name__ == "__main__":
    main()
