#!/usr/bin/env python3
"""Measures what every shipped scene gives, for tests/data/scene_expectations.toml.

Each scene with sources is traced with 8 seeds (101..108) of 200 000 photons; the
mean and the standard deviation of one run are printed as TOML for: the fraction
of photons reaching the sensor, the flux per emitted photon, and the HPD, 80 % and
90 % diameters (arcsec when the sensor has a focal length, else mm).

Run it only when a change is *meant* to alter results, check the differences, and
say why in the commit:
    cargo build --release && scripts/scene_expectations.py > tests/data/scene_expectations.toml
(spheres.toml, a render-only scene, is measured by the test itself; its entry is
kept by hand.) With scene names as arguments (e.g. `cast_axion_image`), only those
are measured: paste their entries over the old ones. `--seeds N` takes seeds
101..100+N instead of 8 (the entry then says `seeds = N`): a spread estimated from
8 runs can come out well below the true one (a χ² of 7 degrees of freedom), and
a test at 5 of them then fails at honest seeds.
"""
import sys as _sys

if __name__ == "__main__" and any(a in ("-h", "--help") for a in _sys.argv[1:]):
    print(__doc__)
    _sys.exit(0)
import glob
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "target", "release", "traxer")
_args = _sys.argv[1:]
_n_seeds = 8
if "--seeds" in _args:
    _k = _args.index("--seeds")
    _n_seeds = int(_args[_k + 1])
    del _args[_k:_k + 2]
PHOTONS, SEEDS = 200_000, range(101, 101 + _n_seeds)

print("# Written by scripts/scene_expectations.py: mean and standard deviation of one")
print(f"# {PHOTONS}-photon run over seeds {SEEDS.start}..{SEEDS.stop - 1}, per shipped scene.")
print(f"photons = {PHOTONS}")
with tempfile.TemporaryDirectory() as tmp:
    for scene in sorted(glob.glob(os.path.join(ROOT, "scenes", "*.toml"))):
        name = os.path.basename(scene)[:-5]
        if _args and name not in _args:
            continue
        if "[[sources]]" not in open(scene).read():
            continue
        runs = []
        for seed in SEEDS:
            out = os.path.join(tmp, f"{name}_{seed}")
            subprocess.run([BIN, "trace", scene, "-n", str(PHOTONS), "-s", str(seed), "-q", "-o", out], check=True)
            s = json.load(open(os.path.join(out, "summary.json")))
            st, sensor = s["statistics"], s["sensors"][0]
            q = sensor["image_quality"]
            unit = "arcsec" if q.get("hpd_arcsec") is not None else "mm"
            d = lambda k: q[f"{k}_{unit}"]
            runs.append((st["reached_sensor"] / st["photons_emitted"],
                         sensor["total_flux"] / st["photons_emitted"], d("hpd"), d("d80"), d("d90")))
        cols = list(zip(*runs))
        print(f"\n[scenes.{name}]")
        print(f'diameter_unit = "{unit}"')
        if _n_seeds != 8:
            print(f"seeds = {_n_seeds}")
        for key, col in zip(["reached_fraction", "flux_per_photon", "hpd", "d80", "d90"], cols):
            print(f"{key} = [{statistics.mean(col):.6g}, {statistics.stdev(col):.3g}]")
        sys.stdout.flush()
