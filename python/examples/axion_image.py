"""The solar axion image at CAST from Python: trace the Sun through the magnet
bore, the LLNL telescope and the detector window, look at the image with numpy,
compare two window thicknesses, and save the same files as `traxer trace`.

    pip install ./python                       # once, from the repository
    python python/examples/axion_image.py      # about 10 s on two cores

Optional: PHOTONS=200000 (photons per run), OUT=folder (default out/python_axion_image);
with matplotlib installed it also draws the image to OUT/axion_image.png.
"""

import os
import pathlib

import numpy as np

import traxer

REPO = pathlib.Path(__file__).resolve().parents[2]
PHOTONS = int(os.environ.get("PHOTONS", "1000000"))
OUT = pathlib.Path(os.environ.get("OUT", "out/python_axion_image"))

scene = traxer.Scene(REPO / "scenes" / "cast_axion_image.toml")
print(scene, "traxer", traxer.__version__, "Embree", traxer.embree_version)

# The image in X-rays per second per pixel converting in the detector gas over
# that pixel, the axions converted in CAST's 9 T magnet, for g_aγ = 1e-10 GeV⁻¹
# (defines={"magnet": False}: the axions before the conversion).
result = scene.trace(PHOTONS, seed=1)
chip = result["chip"]
print(f"{chip.total_flux:.4e} X-rays/s (unit {chip.unit}) on the {chip.size_mm[0]} mm chip, "
      f"{result.statistics['reached_sensor']} of {PHOTONS} photons")
q = chip.quality
print(f"centroid ({q['centroid_mm'][0]:.3f}, {q['centroid_mm'][1]:.3f}) mm, "
      f"HPD {q['hpd_mm']:.3f} mm ({q['hpd_arcsec']:.1f}″), 90 % {q['d90_mm']:.3f} mm")

# Where the flux is: the brightest pixel, and the flux within 1 mm of the centroid.
iy, ix = np.unravel_index(np.argmax(chip.flux), chip.flux.shape)
print(f"brightest pixel at x = {chip.x_mm[ix]:.3f} mm, y = {chip.y_mm[iy]:.3f} mm")
x, y = np.meshgrid(chip.x_mm - q["centroid_mm"][0], chip.y_mm - q["centroid_mm"][1])
inner = chip.flux[x**2 + y**2 < 1.0].sum() / chip.total_flux
print(f"{100 * inner:.1f} % of the flux within 1 mm of the centroid")

# The same Sun without the 300 nm Si3N4 window: its transmission, energy-averaged.
bare = traxer.Scene(REPO / "scenes" / "cast_axion_image.toml",
                     defines={"window_nm": 0})
open_flux = bare.trace(PHOTONS, seed=1)["chip"].total_flux
print(f"window transmission (flux with / without): {chip.total_flux / open_flux:.3f}")

# Reflectivity of the telescope's coatings at the solar spectrum's peak, 3 keV.
angles = np.linspace(0.1, 1.0, 10)
for recipe in ("llnl_recipe_1", "llnl_recipe_4"):
    r = traxer.reflectivity(recipe, 3.0, angles)
    print(recipe, "R at 3 keV, 0.1–1.0°:", np.array2string(r, precision=3))

# The spectrum of the axions at Earth (built-in Primakoff table).
sun = traxer.SolarEmission.builtin()
peak = sun.energies_keV[np.argmax(sun.spectrum(0.989))]
print(f"solar axion flux at 0.989 AU: {sun.flux(0.989):.3e} cm⁻² s⁻¹, peak at {peak:.1f} keV")

n = result.save(OUT)
print(f"wrote {n} files to {OUT}")
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    pass
else:
    half = [chip.x_mm[0], chip.x_mm[-1], chip.y_mm[0], chip.y_mm[-1]]
    plt.imshow(chip.flux, origin="lower", extent=half, cmap="viridis")
    plt.colorbar(label="axions / s / pixel")
    plt.xlabel("x [mm]")
    plt.ylabel("y [mm]")
    plt.title(f"CAST solar axion image, HPD {q['hpd_arcsec']:.0f}″")
    plt.savefig(OUT / "axion_image.png", dpi=120)
    print("drew", OUT / "axion_image.png")
