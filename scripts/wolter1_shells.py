#!/usr/bin/env python3
"""Prints the [[objects]] of a true Wolter-I telescope (paraboloid + hyperboloid per
shell) for a traxer scene file, in traxer's conventions:

* optical axis = z, photons arrive travelling towards -z;
* intersection plane (where paraboloid and hyperboloid meet) at z = 0;
* focus at z = -F;
* paraboloid on z in [0, L], hyperboloid on z in [-L, 0];
* equal grazing angles on both mirrors at the intersection plane:
  theta = atan(r0 / F) / 4 (Van Speybroeck & Chase 1972).

traxer's paraboloid is r^2 = 4 q (z_l + q) with its focus at the local origin, and
its hyperboloid z_l^2/a^2 - r^2/b^2 = 1 centred at the local origin, so each
surface is placed with a translation.

Usage: scripts/wolter1_shells.py F L r0 [r0 ...]
"""
import sys as _sys

if __name__ == "__main__" and any(a in ("-h", "--help") for a in _sys.argv[1:]):
    print(__doc__)
    _sys.exit(0)
import math
import sys


def shell(F, L, r0):
    theta = math.atan(r0 / F) / 4.0
    # The paraboloid sends axial rays towards its focus at an angle 2θ to the axis.
    D = r0 / math.tan(2.0 * theta)  # axial distance from the plane to that focus
    zp = -D                          # world z of the paraboloid focus
    q = (-D + math.sqrt(D * D + r0 * r0)) / 2.0
    # Hyperboloid: foci at the paraboloid focus (zp) and the telescope focus (-F).
    zc = (zp - F) / 2.0              # centre
    c = abs(-F - zp) / 2.0
    d_far = math.hypot(r0, 0.0 - zp)
    d_near = math.hypot(r0, 0.0 + F)
    a = (d_far - d_near) / 2.0
    b = math.sqrt(c * c - a * a)
    return theta, zp, q, zc, a, b


def main():
    F, L = float(sys.argv[1]), float(sys.argv[2])
    for i, r0 in enumerate(map(float, sys.argv[3:]), start=1):
        theta, zp, q, zc, a, b = shell(F, L, r0)
        print(f"# shell {i}: r0 = {r0} mm at the intersection plane, grazing angle {math.degrees(theta):.4f} deg")
        print("[[objects]]")
        print(f'name = "paraboloid_{i}"')
        print('material = "shell"')
        print(f'shape = {{ type = "paraboloid", focal_length = {q!r}, z_start = {-zp!r}, z_end = {L - zp!r} }}')
        print(f"transform = [ {{ translate = [0.0, 0.0, {zp!r}] }} ]")
        print()
        print("[[objects]]")
        print(f'name = "hyperboloid_{i}"')
        print('material = "shell"')
        print(f'shape = {{ type = "hyperboloid", semi_axis_a = {a!r}, semi_axis_b = {b!r}, z_start = {-L - zc!r}, z_end = {-zc!r} }}')
        print(f"transform = [ {{ translate = [0.0, 0.0, {zc!r}] }} ]")
        print()


if __name__ == "__main__":
    main()
