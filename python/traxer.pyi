"""traxer: an X-ray raytracer for the grazing-incidence telescopes of axion
helioscopes, on Intel Embree.

Load a scene with ``traxer.Scene(path, defines={...})`` and trace it with
``scene.trace(photons, seed=1)``: the result holds each sensor's image as numpy
arrays, bit for bit what ``traxer trace`` writes for the same scene and seed, and
``result.save(folder)`` writes the same files. Also ``traxer.reflectivity``,
``traxer.eef``, ``Scene.effective_area`` and ``traxer.SolarEmission``.
"""

import os
from typing import Any, Literal, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str
embree_version: str
"""The version of the Embree library traxer was built against and loaded."""
git_hash: str
"""The commit traxer was built from (with "-dirty" for local changes)."""

_Path = Union[str, os.PathLike[str]]
_Value = Union[bool, int, float, str, Sequence["_Value"]]

class InputError(ValueError):
    """Bad input: a setting, a data file, an output folder. The message says which
    and what is expected."""

class SceneError(InputError):
    """A scene file that cannot be loaded."""

    file: str
    """The scene (or included) file."""
    line: Optional[int]
    """1-based line of the problem, when it has a place in the file."""
    key: Optional[str]
    """The dotted key of the value or table at fault, e.g.
    "materials.detector.pixels[1]" or "objects[3].shape"; None for problems of
    the whole file or of a ``defines`` entry."""
    message: str
    """What is wrong and what is expected."""

class Scene:
    """A scene file (TOML, see docs/scene-format.md), loaded and built for tracing.

    ``defines`` sets variables declared in the file's ``[vars]``, like the CLI's
    ``-D name=value``: a dict ``{"name": value}`` (bool, number, string or list)
    or a list of ``"name=value"`` strings. Raises ``FileNotFoundError`` if there is
    no such file, ``SceneError`` for a scene that cannot be loaded.
    """

    def __init__(
        self,
        path: _Path,
        defines: Optional[Union[Mapping[str, _Value], Sequence[str]]] = None,
    ) -> None: ...
    @property
    def path(self) -> str: ...
    @property
    def sha256(self) -> str:
        """SHA-256 of the scene file's bytes."""
    @property
    def sensors(self) -> list[str]:
        """The sensors' names, in the scene's order."""
    @property
    def objects(self) -> list[str]:
        """The objects' names, in the scene's order (photon lists index them)."""
    @property
    def variables(self) -> dict[str, Any]:
        """The scene's variables after ``defines``."""
    @property
    def warnings(self) -> list[str]: ...
    @property
    def triangle_count(self) -> int: ...
    def trace(
        self,
        photons: int | float,
        seed: int = 1,
        threads: int = 0,
        photon_list: int = 0,
        progress: bool = False,
        out: Optional[_Path] = None,
        checkpoint_every: Optional[float] = None,
    ) -> TraceResult:
        """Traces ``photons`` photons, as ``traxer trace SCENE --photons N --seed S``.

        Photon i uses the random stream (seed, i): the images are the same for any
        ``threads`` (0: one per core) and equal the CLI's bit for bit.
        ``photon_list``: also keep the first N photons recorded on a sensor.
        ``progress``: draw a progress bar on stderr. The GIL is released while
        tracing; Ctrl-C stops the run after the current batch (about a million
        photons) with KeyboardInterrupt.

        ``out``: also write the results folder of ``traxer trace --out`` (the same
        files, bit for bit), all at once when the run ends. ``checkpoint_every``
        (seconds, needs ``out``): keep a checkpoint there; a run stopped by Ctrl-C
        or killed is continued by ``traxer.resume(out)``.
        """
    def effective_area(
        self,
        energies_keV: Sequence[float] | npt.ArrayLike,
        angles_arcmin: Sequence[float] | npt.ArrayLike = ...,
        photons: Optional[int | float] = None,
        seed: int = 1,
        threads: int = 0,
        sensor: Optional[str] = None,
        radius_mm: Optional[float] = None,
        progress: bool = False,
    ) -> EffectiveArea:
        """The effective area A_eff(E, θ), as ``traxer effective-area``.

        The scene's only source must be a parallel beam covering the telescope's
        entrance; it is tilted to each of ``angles_arcmin`` (default: on axis).
        Each angle traces ``photons`` photons once and evaluates every photon's
        weight at every energy.
        """

class SensorImage:
    """One sensor's image of a trace, in the units of the CLI's files."""

    name: str
    flux: npt.NDArray[np.float64]
    """[iy, ix], or [band, iy, ix] with energy bins; ix along the sensor's local
    x. The sum of photon weights per pixel, or axions per second with a Sun
    source (see ``unit``). Equal to NAME.npy."""
    counts: npt.NDArray[np.uint64]
    """Photons per pixel, the shape of ``flux``. Equal to NAME_counts.npy."""
    unit: Literal["ph", "s-1"]
    size_mm: tuple[float, float]
    pixels: tuple[int, int]
    """(nx, ny)."""
    pixel_pitch_mm: tuple[float, float]
    focal_length_mm: Optional[float]
    energy_band_edges_keV: Optional[list[float]]
    x_mm: npt.NDArray[np.float64]
    """Pixel-centre positions along local x (mm); pixel (0, 0) has its corner at
    (-size_x/2, -size_y/2)."""
    y_mm: npt.NDArray[np.float64]
    quality: Optional[dict[str, Any]]
    """centroid_mm, total_flux, hpd_mm, d80_mm, d90_mm and, with a focal length,
    hpd_arcsec, d80_arcsec, d90_arcsec, of the image summed over bands; None
    without flux."""
    eef_radius_mm: npt.NDArray[np.float64]
    eef_fraction: npt.NDArray[np.float64]
    total_flux: float
    total_counts: int
    conversion: Optional[dict[str, Any]]
    """For a gas detector, where its X-rays converted (None otherwise):
    entered_flux, converted_flux (in ``unit``), converted_fraction,
    mean_depth_mm, median_depth_mm, quantiles_mm [(q, depth)], as in NAME.json;
    depth_edges_mm and depth_flux (the histogram below the gas entrance, as
    NAME_conversion_depth.csv); spectrum [depth slice, energy bin] with
    spectrum_depth_edges_mm and spectrum_energy_edges_keV."""

class TraceResult:
    """A finished trace."""

    sensors: dict[str, SensorImage]
    """Each sensor's image, in the scene's order."""
    statistics: dict[str, Any]
    """Photon fates and counters, as summary.json's "statistics"."""
    sources: list[dict[str, Any]]
    """The sources, as summary.json's "sources"."""
    photons: Optional[np.ndarray]
    """The photon list (``photon_list=N``): a structured array like photons.npy
    (index, sensor, x_mm, y_mm, dir_x, dir_y, dir_z, energy_kev, weight,
    reflections, first_mirror, last_mirror, class); None without one."""
    @property
    def provenance(self) -> dict[str, Any]: ...
    @property
    def seconds(self) -> float: ...
    @property
    def threads(self) -> int: ...
    @property
    def photons_traced(self) -> int: ...
    def __getitem__(self, sensor: str) -> SensorImage: ...
    def save(self, folder: _Path, fits: bool = False) -> int:
        """Writes the files of ``traxer trace`` into ``folder`` (NAME.npy,
        NAME_counts.npy, PNGs, NAME.json, summary.json, run_state.bin, the photon
        list, and NAME.fits with ``fits=True``), all at once; returns the number
        of files."""

class EffectiveArea:
    """The effective area over energies and off-axis angles."""

    sensor: str
    energies_keV: npt.NDArray[np.float64]
    angles_arcmin: npt.NDArray[np.float64]
    area_cm2: npt.NDArray[np.float64]
    """[angle, energy]."""
    error_cm2: npt.NDArray[np.float64]
    """Monte Carlo standard error of ``area_cm2``."""
    by_class_cm2: npt.NDArray[np.float64]
    """[angle, energy, class], classes as in ``classes``."""
    classes: list[str]
    geometric_area_cm2: npt.NDArray[np.float64]
    """Per angle: the area with every reflectivity and transmission 1."""
    quality: list[Optional[dict[str, Any]]]
    on_sensor: list[int]
    counted: list[int]
    aperture_cm2: float
    radius_mm: Optional[float]
    seconds: float
    threads: int
    @property
    def provenance(self) -> dict[str, Any]: ...
    def save(self, folder: _Path) -> None:
        """Writes the files of ``traxer effective-area`` into ``folder``."""

class SolarEmission:
    """A solar axion emission table w(r, E) on a radius × energy grid."""

    description: str
    coupling: str
    @staticmethod
    def builtin(
        emission: Literal["primakoff", "abc", "primakoff+abc"] = "primakoff",
        g_agamma: float = 1e-10,
        g_ae: float = 1e-13,
    ) -> SolarEmission:
        """The built-in emission of the B16-AGSS09met solar model: Primakoff
        (g_aγ in GeV⁻¹), ABC (axion–electron: atomic, electron–ion and
        electron–electron bremsstrahlung, Compton; g_ae) or both; fluxes ∝ g²."""
    @staticmethod
    def from_model(
        path: _Path,
        energies_keV: Sequence[float] | npt.ArrayLike,
        radii: Optional[Sequence[float] | npt.ArrayLike] = None,
        emission: Literal["primakoff", "abc", "primakoff+abc"] = "primakoff",
        opacities: Optional[_Path] = None,
        g_agamma: float = 1e-10,
        g_ae: float = 1e-13,
    ) -> SolarEmission:
        """The emission of a standard solar model file (B16 format) on the grid;
        ``radii`` in fractions of R_sun (None: the model's shells); ABC needs
        ``opacities``, the Opacity Project tables' folder."""
    def process_spectra(self, distance_au: float = 1.0) -> dict[str, npt.NDArray[np.float64]]:
        """dΦ/dE per process (primakoff, atomic, electron_ion, electron_electron,
        compton, abc), axions cm⁻² s⁻¹ keV⁻¹, at the grid's energies."""
    @staticmethod
    def from_csv(path: _Path) -> SolarEmission:
        """An emission table CSV (Radius, Energy [keV], emRates)."""
    @property
    def radii(self) -> npt.NDArray[np.float64]: ...
    @property
    def energies_keV(self) -> npt.NDArray[np.float64]: ...
    @property
    def rates(self) -> npt.NDArray[np.float64]:
        """w(r, E) in keV, [radius, energy]."""
    def spectrum(self, distance_au: float = 1.0) -> npt.NDArray[np.float64]:
        """dΦ/dE at the grid's energies, axions cm⁻² s⁻¹ keV⁻¹."""
    def luminosity(self, e_min_keV: float = 0.0, e_max_keV: float = ...) -> float:
        """Axions per second emitted with energies in [e_min_keV, e_max_keV]."""
    def flux(
        self, distance_au: float = 1.0, e_min_keV: float = 0.0, e_max_keV: float = ...
    ) -> float:
        """Axion flux in cm⁻² s⁻¹ at ``distance_au``."""
    def save_csv(self, path: _Path) -> None:
        """Writes the table as an emission CSV for a Sun source (atomically)."""

def resume(
    folder: _Path,
    threads: int = 0,
    checkpoint_every: float = 60.0,
    progress: bool = False,
    scene: Optional[_Path] = None,
) -> TraceResult:
    """Continues the stopped run in ``folder`` (``Scene.trace(..., out=folder,
    checkpoint_every=S)`` or ``traxer trace --checkpoint-every S``) to its end,
    writing the files of an uninterrupted run, and returns its result; a finished
    run's folder returns its result at once. ``scene``: where the scene file is
    now, if it moved (its SHA-256 is checked). The resumed run keeps a checkpoint
    every ``checkpoint_every`` seconds; Ctrl-C stops it again after a batch."""

def reflectivity(
    coating: str,
    energies_keV: npt.ArrayLike,
    angles_deg: npt.ArrayLike,
    polarisation: Literal["unpolarised", "unpolarized", "s", "p"] = "unpolarised",
) -> npt.NDArray[np.float64]:
    """R(E, θ) of a coating (a shipped one such as "llnl_recipe_3" or "gold", or
    "FILE" / "FILE:NAME"); energies and grazing angles broadcast like numpy
    arguments (``E[:, None], theta[None, :]`` gives the grid)."""

def eef(
    image: npt.ArrayLike,
    pixel_pitch_mm: Union[float, tuple[float, float]],
    focal_length_mm: Optional[float] = None,
) -> dict[str, Any]:
    """Encircled energy of an image [iy, ix] (or [band, iy, ix], summed), as
    ``traxer eef``: centroid_mm, total_flux, hpd_mm, d80_mm, d90_mm, their
    *_arcsec with a focal length, and the curve as radius_mm and fraction."""
