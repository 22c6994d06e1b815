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
_Value = Union[bool, int, float, str, Sequence["_Value"], Mapping[str, "_Value"]]
# An astropy Quantity (astropy is optional): wherever a physical value is taken,
# a Quantity is converted to the documented unit, and one of the wrong kind is
# refused with InputError; plain numbers are in the unit the name says.
_Quantity = Any
_Number = Union[float, _Quantity]
_Numbers = Union[float, Sequence[float], npt.ArrayLike, _Quantity]

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
    ``-D name=value``: a dict ``{"name": value}`` (bool, number, string, list, or
    a dict for an inline table such as a roughness PSD) or a list of
    ``"name=value"`` strings. Raises ``FileNotFoundError`` if there is
    no such file, ``SceneError`` for a scene that cannot be loaded.
    """

    def __init__(
        self,
        path: _Path,
        defines: Optional[Union[Mapping[str, _Value], Sequence[str]]] = None,
    ) -> None: ...
    @property
    def path(self) -> str:
        """The scene file's path."""
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
        """The scene's variables after ``defines``: {name: value}."""
    @property
    def warnings(self) -> list[str]:
        """The warnings the scene gave when it was loaded."""
    @property
    def triangle_count(self) -> int:
        """Number of triangles of the meshed objects."""
    def trace(
        self,
        photons: int | float,
        seed: int = 1,
        threads: int = 0,
        photon_list: int = 0,
        progress: bool = False,
        out: Optional[_Path] = None,
        checkpoint_every: Optional[_Number] = None,
        replace: bool = False,
    ) -> TraceResult:
        """Traces ``photons`` photons, as ``traxer trace SCENE --photons N --seed S``.

        Photon i uses the random stream (seed, i), so the images are the same for
        any ``threads`` (0: one per core) and equal the CLI's bit for bit.
        ``photon_list``: also keep the first N photons recorded on a sensor.
        ``progress``: draw a progress bar on stderr. The GIL is released while
        tracing; Ctrl-C stops the run after the current batch (about a million
        photons) with KeyboardInterrupt.

        ``out``: also write the results folder of ``traxer trace --out`` (the same
        files, bit for bit), all at once when the run ends. ``checkpoint_every``
        (seconds, needs ``out``): keep a checkpoint there; a run stopped by Ctrl-C
        or killed is continued by ``traxer.resume(out)``. A folder holding the
        results of a run with other inputs (scene, variables, seed, photons) is
        refused unless ``replace=True``.
        """
    def effective_area(
        self,
        energies_keV: _Numbers,
        angles_arcmin: Optional[_Numbers] = None,
        photons: Optional[int | float] = None,
        seed: int = 1,
        threads: int = 0,
        sensor: Optional[str] = None,
        radius_mm: Optional[_Number] = None,
        progress: bool = False,
        out: Optional[_Path] = None,
        resume: bool = False,
    ) -> EffectiveArea:
        """The telescope's effective area A_eff(E, θ), as ``traxer effective-area``.

        The scene's only source must be a parallel beam covering the telescope's
        entrance; it is tilted to each of ``angles_arcmin`` (None: on axis only).
        Each angle traces ``photons`` photons (default 200 000) once and
        evaluates every photon's weight at every energy. Energies, angles and
        ``radius_mm`` may be astropy Quantities. With ``out`` the sweep writes
        the files of ``traxer effective-area --out`` there and records each
        angle: Ctrl-C stops it after the current angle, and ``resume=True``
        takes up the recorded angles.
        """
    def psf_library(
        self,
        energies_keV: _Numbers,
        angles_arcmin: Optional[_Numbers] = None,
        azimuths_deg: Optional[_Numbers] = None,
        photons: Optional[int | float] = None,
        seed: int = 1,
        threads: int = 0,
        sensor: Optional[str] = None,
        window: int = 101,
        progress: bool = False,
        out: Optional[_Path] = None,
        resume: bool = False,
    ) -> PsfLibrary:
        """The PSF library, as ``traxer psf``: the scene's parallel beam (its
        only source) tilted to each of ``angles_arcmin`` towards each of
        ``azimuths_deg`` (None: 0 only) at each of ``energies_keV``, ``photons``
        photons per point (default 200 000) with the trace's random streams, so
        that a point equals a trace of the scene set to that angle and energy;
        a window of ``window`` pixels around each image's centroid, normalised
        to 1. Energies and angles may be astropy Quantities. With ``out`` the
        library writes the files of ``traxer psf --out`` there and records each
        point: Ctrl-C stops it after the current point, and ``resume=True``
        takes up the recorded points.
        """
    def fit_figure_error(
        self,
        target_hpd: float,
        target_c80: float,
        target_c90: float,
        bounds: Optional[dict[str, tuple[float, float] | float]] = None,
        global_evals: int = 150,
        local_evals: int = 60,
        local_algorithm: str = "sbplx",
        check_seeds: int = 3,
        target_error: float = 2.0,
        predict: Optional[list[_Path]] = None,
        predict_seeds: int = 4,
        name: str = "fitted",
        photons: Optional[int | float] = None,
        seed: int = 1,
        threads: int = 0,
        sensor: Optional[str] = None,
        progress: bool = False,
        out: Optional[_Path] = None,
        resume: bool = False,
    ) -> FigureErrorFit:
        """The figure-error fit, as ``traxer fit-figure-error``: the
        figure-error parameters of every mirror fitted to the measured
        ``target_hpd``, ``target_c80`` and ``target_c90`` (arcsec), each
        evaluation traced with the same ``photons`` (default 1 000 000) and
        ``seed``; DIRECT-L over ``bounds`` ({name: (low, high)} or {name:
        value} to hold it; defaults in_plane_narrow 0–120, in_plane_wide
        0–900, wide_fraction 0–0.6, out_of_plane 0) for ``global_evals``, then
        ``local_algorithm`` ("sbplx", "bobyqa" or "nelder_mead") for
        ``local_evals``; then the spread over ``check_seeds`` more seeds, the
        parameters' errors for a ``target_error`` (per cent) and each scene of
        ``predict`` with ``predict_seeds`` seeds. With ``out`` (a folder) the
        fit writes the files of ``traxer fit-figure-error --out`` there and
        records each evaluation: Ctrl-C stops it, and ``resume=True`` takes up
        the recorded evaluations."""
    def focus(
        self,
        start: float,
        stop: float,
        var: str = "sensor_z",
        steps: int = 13,
        photons: Optional[int | float] = None,
        seed: int = 1,
        threads: int = 0,
        sensor: Optional[str] = None,
        progress: bool = False,
        out: Optional[_Path] = None,
        resume: bool = False,
    ) -> FocusScan:
        """The focus scan, as ``traxer focus``: the scene traced at ``steps``
        values of the variable ``var`` (declared in its [vars], e.g.
        "sensor_z"), evenly spaced from ``start`` to ``stop``, ``photons``
        photons each (default 1 000 000), the diameters measured and a defocus
        curve fitted to each. With ``out`` (a folder) the scan writes the files
        of ``traxer focus --out`` there and records each position: Ctrl-C stops
        it after the current position, and ``resume=True`` takes up the
        recorded ones."""
    def compare(
        self,
        resolutions: Optional[list[str]] = None,
        also: Optional[list[_Path]] = None,
        photons: Optional[int | float] = None,
        seed: int = 1,
        threads: int = 0,
        sensor: Optional[str] = None,
        progress: bool = False,
        out: Optional[_Path] = None,
        resume: bool = False,
    ) -> Comparison:
        """The analytic scene against meshes of it, as ``traxer compare``: the
        scene traced with its analytic objects exact, then tessellated at each
        of ``resolutions`` ("SEGMENTSxRINGS" strings, e.g. "120x4"; default
        those of the command), then each scene file of ``also`` as written
        (with this scene's variables), all with the same photons (default
        2 000 000 per run). With ``out`` (a folder) the comparison writes the
        files of ``traxer compare --out`` there and records each row: Ctrl-C
        stops it after the current row, and ``resume=True`` takes up the
        recorded ones."""
    def systematics(
        self,
        photons: Optional[int | float] = None,
        seed: int = 1,
        threads: int = 0,
        sensor: Optional[str] = None,
        sources: Optional[list[str]] = None,
        figure_draws: int = 20,
        figure_preset: Optional[str] = None,
        figure_hold: Optional[list[str]] = None,
        pointing_arcmin: float = 1.0,
        tilt_arcmin: float = 1.0,
        solar_model: str = "b16_gs98",
        gas_pressure_mbar: Optional[tuple[float, float]] = None,
        gas_temperature_k: Optional[tuple[float, float]] = None,
        vary: Optional[dict[str, tuple[float, float]]] = None,
        central_mm: float = 5.0,
        central_radius_mm: Optional[float] = None,
        progress: bool = False,
        out: Optional[_Path] = None,
        resume: bool = False,
    ) -> Systematics:
        """The image's systematic uncertainty, as ``traxer systematics``: the
        scene traced under each source of uncertainty with the same photons
        (``photons`` per variation, default 1 000 000). Sources (default: every
        one the scene's variables support): "figure" (``figure_draws``
        parameter sets from the preset's covariance; ``figure_hold`` the
        parameters held, default those the fit found unconstrained),
        "optical_constants" (the coatings' f1, f2 from Chantler's table
        instead of Henke's), "solar_model", "pointing_x"/"pointing_y" (± ``pointing_arcmin``),
        "tilt_x"/"tilt_y" (± ``tilt_arcmin``), "gas_pressure"/"gas_temperature"
        (ranges (low, high), default the scene's ± 50 mbar, ± 10 K); ``vary``: a
        dict of other scene variables and their (low, high). The table's
        "central" flux is in the ``central_mm`` square about the sensor's
        centre, or with ``central_radius_mm`` in that circle (a signal region).
        With ``out`` the study writes the files of ``traxer systematics --out``
        there and records each variation: Ctrl-C stops it after the current
        variation, and ``resume=True`` takes up the recorded ones.
        """

class SensorImage:
    """One sensor's image of a trace.

    In the units of the CLI's files; ``grid`` is the image on the detector's
    pixels, ``by_class`` the image split by photon path, ``by_process`` by
    emission process."""

    name: str
    """The sensor's name in the scene."""
    flux: npt.NDArray[np.float64]
    """[iy, ix], or [band, iy, ix] with energy bins; ix along the sensor's local
    x. The sum of photon weights per pixel, or axions per second with a Sun
    source — X-rays per second with a magnet (see ``unit``). Equal to NAME.npy."""
    counts: npt.NDArray[np.uint64]
    """Photons per pixel, the shape of ``flux``. Equal to NAME_counts.npy."""
    unit: Literal["ph", "s-1"]
    """"ph" (weighted photons per pixel) or "s-1" (axions per second per pixel;
    with a magnet, X-rays per second)."""
    size_mm: tuple[float, float]
    """(x, y) extent of the sensor, mm."""
    pixels: tuple[int, int]
    """(nx, ny)."""
    pixel_pitch_mm: tuple[float, float]
    """(x, y) pixel pitch, mm."""
    focal_length_mm: Optional[float]
    """The sensor's focal length (mm) for angular diameters, or None."""
    energy_band_edges_keV: Optional[list[float]]
    """The energy bands' edges (keV) of a [band, iy, ix] image, or None."""
    x_mm: npt.NDArray[np.float64]
    """Pixel-centre positions along local x (mm); pixel (0, 0) has its corner at
    (-size_x/2, -size_y/2)."""
    y_mm: npt.NDArray[np.float64]
    """Pixel-centre positions along local y (mm)."""
    quality: Optional[dict[str, Any]]
    """centroid_mm, total_flux, hpd_mm, d80_mm, d90_mm and, with a focal length,
    hpd_arcsec, d80_arcsec, d90_arcsec, of the image summed over bands; None
    without flux. The d* are diameters around the centroid."""
    eef_radius_mm: npt.NDArray[np.float64]
    """The encircled-energy curve: radius (mm) around the centroid …"""
    eef_fraction: npt.NDArray[np.float64]
    """… and the fraction of the flux within it."""
    total_flux: float
    """The sum of ``flux``, in ``unit``."""
    total_counts: int
    """The sum of ``counts``."""
    conversion: Optional[dict[str, Any]]
    """For a gas detector, where its X-rays converted (None otherwise): a dict
    with the numbers of NAME.json → conversion (mean_depth_mm, quantiles_mm
    [(q, depth)], converted_fraction, entered_flux, converted_flux, in the
    image's unit), depth_edges_mm and depth_flux (the histogram below the gas
    entrance), and spectrum [slice, energy bin] with spectrum_depth_edges_mm
    and spectrum_energy_edges_keV."""
    grid: Optional[GridImage]
    """The image on the sensor's detector pixel grid (``pixel_grid`` in the
    scene; the GridPix's 256 × 256 pixels of 55 µm) as a ``traxer.GridImage``,
    equal to NAME_grid.npy; None for a sensor without one."""
    by_class: Optional[dict[str, npt.NDArray[np.float64]]]
    """With ``history_images = true`` on the sensor: {class: flux [iy, ix]} for
    each photon-path class of ``TraceResult.classes`` (direct, front_rear,
    front_only, rear_only, other), equal to NAME_CLASS.npy; None otherwise."""
    by_process: Optional[dict[str, npt.NDArray[np.float64]]]
    """With a Sun emitting Primakoff and ABC: {process: flux [iy, ix]} for
    "primakoff" and "abc", from the same photons as ``flux`` (they add up to
    its sum over bands), and ABC's four processes ("atomic", "electron_ion",
    "electron_electron", "compton", adding up to "abc"), equal to
    NAME_PROCESS.npy; ABC alone has the four; None for a source of one
    process. Each scales as its coupling squared (g_aγ², g_ae²; with a magnet g_aγ⁴ and g_ae² g_aγ²): the image for
    other couplings is their sum so scaled, equal to a trace with them."""
    by_mass: Optional[dict[float, npt.NDArray[np.float64]]]
    """With a magnet's mass scan (`masses_ev`, `--masses`): {axion mass (eV):
    flux} in the shape and units of `flux`, from the same photons (each
    weight times its path's P(m) / P at the scene's mass), equal to the
    slices of NAME_by_mass.npy; None without a scan."""

class GridImage:
    """A sensor's image on its detector pixel grid (the scene's ``pixel_grid``),
    summed over energy bands, flux conserved by overlap area."""

    flux: npt.NDArray[np.float64]
    """Flux per grid pixel [iy, ix], in the sensor image's unit."""
    pixels: tuple[int, int]
    """(nx, ny) grid pixels."""
    pitch_mm: float
    """The grid's pixel pitch, mm (square pixels)."""
    rotation_deg: float
    """Degrees, counter-clockwise from the sensor's x axis to the grid's."""
    center_mm: tuple[float, float]
    """The grid's centre on the sensor (local x, y), mm."""
    x_mm: npt.NDArray[np.float64]
    """Sensor x (mm) of each grid pixel's centre, [iy, ix] (a turned grid's
    centres are not a product of two axes)."""
    y_mm: npt.NDArray[np.float64]
    """Sensor y (mm) of each grid pixel's centre, [iy, ix]."""
    flux_on_grid: float
    """The flux landing on the grid."""
    flux_outside_grid: float
    """The flux of the sensor image outside the grid (never negative)."""

class TraceResult:
    """A finished trace: each sensor's image, the statistics, the sources, the
    provenance and the photon list; ``save(folder)`` writes the CLI's files."""

    sensors: dict[str, SensorImage]
    """Each sensor's image, {name: SensorImage}, in the scene's order."""
    statistics: dict[str, Any]
    """Photon fates and counters, as summary.json's "statistics"."""
    sources: list[dict[str, Any]]
    """The sources, as summary.json's "sources"."""
    photons: Optional[np.ndarray]
    """The photon list (``photon_list=N``): a read-only structured array like
    photons.npy (index, sensor, x_mm, y_mm, dir_x, dir_y, dir_z, energy_keV,
    weight, reflections, first_mirror, last_mirror, class); None without one."""
    classes: list[str]
    """The photon-path classes by index, as ``photons["class"]`` and the class
    images number them: direct (no reflection), front_rear (a front then a
    rear mirror: the focus), front_only, rear_only, other."""
    campaign: Optional[dict[str, Any]]
    """With a magnet's campaign ([magnet.campaign]): campaign.json's content
    (settings with their tracking hours, masses_ev, pairs [setting, mass],
    energy_edges_kev, ring_edges_mm, centre_mm, the planner and the
    allocation) and ``tallies`` {sensor: X-rays per second [pair, energy,
    ring]}, equal to NAME_campaign.npy; None without a campaign."""
    @property
    def provenance(self) -> dict[str, Any]:
        """The provenance record of the run (as in every JSON the CLI writes)."""
    @property
    def seconds(self) -> float:
        """Seconds spent tracing."""
    @property
    def threads(self) -> int:
        """Worker threads used (the result does not depend on it)."""
    @property
    def photons_traced(self) -> int:
        """Photons traced."""
    def __getitem__(self, sensor: str) -> SensorImage: ...
    def save(self, folder: _Path, fits: bool = False, replace: bool = False) -> int:
        """Writes the files of ``traxer trace`` into ``folder`` (created if
        needed): per sensor NAME.npy, NAME_counts.npy, PNGs, NAME.json, ...,
        summary.json, run_state.bin (for ``traxer merge``), the photon list if
        one was kept, and with ``fits=True`` each sensor's image as NAME.fits.
        All files appear at once; returns the number of files written. A
        folder holding the results of a run with other inputs is refused unless
        ``replace=True``."""

class EffectiveArea:
    """The effective area of a telescope over energies and off-axis angles."""

    sensor: str
    """The sensor counted on."""
    energies_keV: npt.NDArray[np.float64]
    """The energies, keV."""
    angles_arcmin: npt.NDArray[np.float64]
    """The off-axis angles, arcmin."""
    area_cm2: npt.NDArray[np.float64]
    """The effective area, cm², [angle, energy]."""
    error_cm2: npt.NDArray[np.float64]
    """The Monte Carlo standard error of ``area_cm2``, cm²."""
    by_class_cm2: npt.NDArray[np.float64]
    """The area split by photon path, cm², [angle, energy, class], classes as
    in ``classes``."""
    classes: list[str]
    """The photon-path classes: direct, front_rear, front_only, rear_only, other."""
    geometric_area_cm2: npt.NDArray[np.float64]
    """Per angle: the area with every reflectivity and transmission 1, cm²."""
    quality: list[Optional[dict[str, Any]]]
    """Per angle: the image's centroid and 50/80/90 % diameters (a dict), or None."""
    on_sensor: list[int]
    """Per angle: photons that reached the sensor."""
    counted: list[int]
    """Per angle: photons counted (within ``radius_mm`` if given)."""
    counts: str
    """What the area counts: X-rays reaching the sensor, or on a gas detector
    X-rays converting in its gas (the trace's rate)."""
    aperture_cm2: float
    """The beam's cross-section on axis, cm²."""
    radius_mm: Optional[float]
    """The counting radius around the image centroid (mm), or None."""
    seconds: float
    """Seconds spent tracing."""
    threads: int
    """Worker threads used (the result does not depend on them)."""
    @property
    def provenance(self) -> dict[str, Any]:
        """The provenance record of the sweep."""
    def save(self, folder: _Path) -> None:
        """Writes the files of ``traxer effective-area`` into ``folder``:
        effective_area.csv, off_axis.csv, effective_area.json, the plots and
        (with two energies or more) one OGIP ARF per angle,
        ``effective_area_<angle>arcmin.arf``, all at once."""

class PsfLibrary:
    """A PSF library: the telescope's image of a source at infinity over
    energies, off-axis angles and azimuths (``Scene.psf_library``)."""

    sensor: str
    """The sensor imaged on."""
    energies_keV: npt.NDArray[np.float64]
    """The energies, keV."""
    angles_arcmin: npt.NDArray[np.float64]
    """The off-axis angles, arcmin."""
    azimuths_deg: npt.NDArray[np.float64]
    """The azimuths of the tilt, degrees."""
    images: npt.NDArray[np.float64]
    """The normalised images, [angle, azimuth, energy, iy, ix] (equal to psf.npy)."""
    corner: npt.NDArray[np.float64]
    """Each window's first sensor pixel (ix, iy), [angle, azimuth, energy, 2]."""
    fraction_in_window: npt.NDArray[np.float64]
    """Each window's share of the flux on the sensor, [angle, azimuth, energy]."""
    centroid_mm: npt.NDArray[np.float64]
    """Each image's centroid on the sensor (local mm), [angle, azimuth, energy, 2]."""
    pixel_pitch_mm: tuple[float, float]
    """The sensor's pixel pitch (x, y), mm."""
    focal_length_mm: float
    """The sensor's focal length, mm."""
    window: int
    """Pixels per side of each window."""
    seconds: float
    """Seconds spent tracing."""
    @property
    def provenance(self) -> dict[str, Any]:
        """The provenance record of the library."""
    def save(self, folder: _Path) -> None:
        """Writes the files of ``traxer psf`` into ``folder``: psf.fits (one image
        per HDU, the layout SIXTE reads), psf.npy and psf.json, all at once."""

class Systematics:
    """The image's systematic uncertainty: the scene traced under each source of
    uncertainty with the same photons (``Scene.systematics``)."""

    nominal: npt.NDArray[np.float64]
    """The nominal scene's map, [iy, ix], on the sensor's detector grid (or its
    image binned to at most 256 pixels a side)."""
    mean: npt.NDArray[np.float64]
    """The nominal map plus each source's mean shift."""
    sigma: npt.NDArray[np.float64]
    """The total systematic σ per map pixel (the sources in quadrature)."""
    sigma_by_source: dict[str, npt.NDArray[np.float64]]
    """Each source's σ map, by source name."""
    sigma_relative: npt.NDArray[np.float64]
    """The total σ over the mean map, per pixel (NaN where the mean is not
    positive)."""
    sigma_noise: npt.NDArray[np.float64]
    """The Monte Carlo noise of ``sigma``, per pixel, from the two halves of the
    photons."""
    variations: npt.NDArray[np.float64]
    """Every traced variation's map, [variation, iy, ix], in the order of ``table``."""
    seconds: float
    """Seconds spent tracing."""
    @property
    def summary(self) -> dict[str, Any]:
        """Each source's effect, the nominal values and the total (systematics.json)."""
    @property
    def table(self) -> list[dict[str, Any]]:
        """One dict per traced variation: source, variation, its settings and quantities."""
    @property
    def provenance(self) -> dict[str, Any]:
        """The provenance record of the study."""
    def save(self, folder: _Path) -> None:
        """Writes the files of ``traxer systematics`` into ``folder``:
        systematics.csv, systematics.json, systematics.fits, the map_*.npy and
        the PNGs, all at once."""

class FigureErrorFit:
    """A figure-error fit (``Scene.fit_figure_error``)."""

    @property
    def summary(self) -> dict[str, Any]:
        """fit.json as a dict."""
    @property
    def best(self) -> dict[str, float]:
        """The best parameters: in_plane_narrow, in_plane_wide, out_of_plane
        (arcsec) and wide_fraction."""
    @property
    def history(self) -> list[dict[str, Any]]:
        """Every evaluation in order: its index, stage, parameters, diameters
        and error (history.csv as dicts)."""
    @property
    def preset(self) -> str:
        """figure_error.toml's text."""
    @property
    def provenance(self) -> dict[str, Any]:
        """The provenance record of the fit."""
    def save(self, folder: _Path) -> None:
        """Writes the files of ``traxer fit-figure-error`` into ``folder``:
        history.csv, figure_error.toml and fit.json, all at once."""

class FocusScan:
    """A focus scan: the image's diameters at each value of the scene variable
    that places the sensor (``Scene.focus``)."""

    variable: str
    """The scene variable swept."""
    sensor: str
    """The sensor measured."""
    values: npt.NDArray[np.float64]
    """The variable's values."""
    hpd_mm: npt.NDArray[np.float64]
    """Half-power diameter (mm) at each value (NaN without an image)."""
    d80_mm: npt.NDArray[np.float64]
    """80 % diameter (mm) at each value."""
    d90_mm: npt.NDArray[np.float64]
    """90 % diameter (mm) at each value."""
    photons_on_sensor: npt.NDArray[np.uint64]
    """Photons recorded on the sensor at each value."""
    clipped: list[float]
    """The values where the image is probably larger than the sensor."""
    @property
    def fits(self) -> dict[str, dict[str, Any]]:
        """The defocus fit of each diameter ("hpd", "d80", "d90"): z0 (the
        best focus), z0_std_error, d0, slope, ... (as focus.json's fit_*), or
        {"error": why} where the fit failed."""
    @property
    def provenance(self) -> dict[str, Any]:
        """The provenance record of the scan."""
    def save(self, folder: _Path) -> None:
        """Writes the files of ``traxer focus`` into ``folder``: focus.csv,
        focus.json and focus.png, all at once."""

class Comparison:
    """The analytic scene against meshes of it (``Scene.compare``)."""

    @property
    def rows(self) -> list[dict[str, Any]]:
        """One dict per traced variant, the analytic scene first: its
        representation, scene, triangles, image_quality (centroid and 50/80/90 %
        diameters), the differences to the analytic row in per cent, photons on
        the sensor, photons per second and seconds (the rows of compare.json)."""
    @property
    def markdown(self) -> str:
        """The table ``traxer compare`` prints."""
    @property
    def provenance(self) -> dict[str, Any]:
        """The provenance record of the comparison."""
    def save(self, folder: _Path) -> None:
        """Writes the files of ``traxer compare`` into ``folder``: compare.csv
        and compare.json, both at once."""

class SolarEmission:
    """A solar axion emission table w(r, E) on a radius × energy grid."""

    @property
    def description(self) -> str:
        """Where the table comes from."""
    @property
    def coupling(self) -> str:
        """The couplings it is for."""
    @staticmethod
    def builtin(
        emission: Literal["primakoff", "abc", "primakoff+abc"] = "primakoff",
        g_agamma: _Number = 1e-10,
        g_ae: _Number = 1e-13,
        solar_model: Literal["b16_agss09met", "b16_gs98"] = "b16_agss09met",
    ) -> SolarEmission:
        """The built-in emission of the B16-AGSS09met standard solar model (or
        ``solar_model="b16_gs98"``): "primakoff" (g_aγ in GeV⁻¹), "abc" (the
        axion–electron processes, g_ae) or "primakoff+abc"; fluxes scale as the
        couplings squared."""
    @staticmethod
    def from_model(
        path: _Path,
        energies_keV: _Numbers,
        radii: Optional[_Numbers] = None,
        emission: Literal["primakoff", "abc", "primakoff+abc"] = "primakoff",
        opacities: Optional[_Path] = None,
        g_agamma: _Number = 1e-10,
        g_ae: _Number = 1e-13,
    ) -> SolarEmission:
        """The emission of a standard solar model file in the B16 format, on
        ``energies_keV`` (cell centres) and ``radii`` (fractions of R_sun; None:
        every shell of the model file). ABC needs ``opacities``, the folder of
        the Opacity Project tables."""
    def process_spectra(self, distance_au: _Number = 1.0) -> dict[str, npt.NDArray[np.float64]]:
        """dΦ/dE per process at the grid's energies (axions cm⁻² s⁻¹ keV⁻¹ at
        ``distance_au``): a dict with "primakoff", "atomic", "electron_ion",
        "electron_electron", "compton" and "abc" as the emission has them."""
    @staticmethod
    def from_csv(path: _Path) -> SolarEmission:
        """An emission table CSV (columns Radius, Energy [keV], emRates)."""
    @property
    def radii(self) -> npt.NDArray[np.float64]:
        """Radii of the grid, fractions of R_sun."""
    @property
    def energies_keV(self) -> npt.NDArray[np.float64]:
        """Energies of the grid, keV."""
    @property
    def rates(self) -> npt.NDArray[np.float64]:
        """w(r, E) in keV, [radius, energy]."""
    def spectrum(self, distance_au: _Number = 1.0) -> npt.NDArray[np.float64]:
        """dΦ/dE at the grid's energies, axions cm⁻² s⁻¹ keV⁻¹, at ``distance_au``."""
    def luminosity(self, e_min_keV: _Number = 0.0, e_max_keV: Optional[_Number] = None) -> float:
        """Axions per second emitted by the Sun with energies in [e_min_keV,
        e_max_keV] (None: no upper limit)."""
    def flux(
        self,
        distance_au: _Number = 1.0,
        e_min_keV: _Number = 0.0,
        e_max_keV: Optional[_Number] = None,
    ) -> float:
        """Axion flux, cm⁻² s⁻¹, at ``distance_au`` with energies in [e_min_keV,
        e_max_keV] (None: no upper limit)."""
    def save_csv(self, path: _Path) -> None:
        """Writes the table as an emission CSV (atomically), for a Sun source's
        ``emission = "FILE.csv"``."""

def resume(
    folder: _Path,
    threads: int = 0,
    checkpoint_every: _Number = 60.0,
    progress: bool = False,
    scene: Optional[_Path] = None,
) -> TraceResult:
    """Continues the stopped run in ``folder`` (a ``Scene.trace(..., out=folder,
    checkpoint_every=S)`` or ``traxer trace --checkpoint-every S`` that was
    stopped) to its end, writing the same files as an uninterrupted run, and
    returns its result. A finished run's folder returns its result at once,
    once its scene is checked to be the run's (the same file, input files and
    variables). ``scene``: where the scene file is now, if it moved (its
    SHA-256 is checked). Ctrl-C stops it again after the current batch, with
    the checkpoint written."""

def reflectivity(
    coating: str,
    energies_keV: _Numbers,
    angles_deg: _Numbers,
    polarisation: Literal["unpolarised", "unpolarized", "s", "p"] = "unpolarised",
    optical_constants: Literal["henke", "chantler"] = "henke",
) -> npt.NDArray[np.float64]:
    """Reflectivity R(E, θ) of a mirror coating.

    ``coating``: a shipped one such as "llnl_recipe_3" or "gold", or "FILE" /
    "FILE:NAME"; energies (keV) and grazing angles (degrees, 0–90) broadcast
    like numpy arguments (``E[:, None], theta[None, :]`` gives the grid); either
    may be an astropy Quantity. ``optical_constants``: the layers' table of
    scattering factors, "henke" or "chantler" (a second opinion)."""

def conversion_probability(
    energies_keV: _Numbers,
    masses_eV: Optional[_Numbers] = None,
    field_t: Optional[_Number] = None,
    length_m: Optional[_Number] = None,
    field_map: Optional[str] = None,
    gas: Optional[str] = None,
    pressure_mbar: Optional[_Number] = None,
    temperature_k: Optional[_Number] = None,
    g_agamma: _Number = 1e-10,
    at: Union[tuple[_Number, _Number], _Quantity] = (0.0, 0.0),
    bore_average: bool = False,
    step_mm: Optional[_Number] = None,
) -> npt.NDArray[np.float64]:
    """The axion–photon conversion probability P(a→γ) of a magnet, as
    ``traxer conversion``: a uniform field (``field_t`` in T over ``length_m``)
    or a field map (``field_map``: a shipped one such as "bykovskiy_201906",
    BabyIAXO's, or a file of rows x y z Bx By Bz in mm and T), with an optional
    buffer gas (``gas`` a formula, "He" for helium-3 or -4, with
    ``pressure_mbar`` and ``temperature_k``), at ``g_agamma`` (GeV⁻¹), along the
    axial line through ``at`` (mm) or averaged over the bore
    (``bore_average``). ``masses_eV``: a list (default [0]). Every number may
    be an astropy Quantity (masses in eV or as masses, fields in T, °C for the
    temperature). Returns a float64 array [energy, mass]."""

def signal(
    run: Union[str, os.PathLike[str]],
    radius_mm: Optional[_Number] = None,
    fraction: Optional[float] = None,
    center: Optional[Union[tuple[_Number, _Number], _Quantity]] = None,
    sensor: Optional[str] = None,
    region_mass: Optional[_Number] = None,
) -> dict[str, Any]:
    """The expected X-rays in a signal region per axion mass, as ``traxer
    signal``, from the results folder ``run`` of a trace with the magnet on: a
    circle of ``radius_mm``, or the one holding ``fraction`` of the flux of the
    image that places it — that of ``region_mass`` (eV, one of the run's
    masses), by default the run's brightest — about ``center`` (mm, the
    sensor's frame) or that image's centroid. Lengths and the mass may be
    astropy Quantities. Returns a dict: sensor, center_mm, radius_mm, area_cm2,
    placed_on_mass_eV, fraction, energy_band_edges_keV, masses_eV,
    x_rays_per_s [mass], x_rays_per_hour [mass], spectrum_x_rays_per_s
    [mass, band]."""

def reach(
    runs: Union[str, os.PathLike[str], list[Union[str, os.PathLike[str]]]],
    background: _Number,
    tracking_hours: Optional[_Numbers] = None,
    radius_mm: Optional[_Number] = None,
    fraction: Optional[float] = None,
    center: Optional[Union[tuple[_Number, _Number], _Quantity]] = None,
    window: Optional[_Numbers] = None,
    bores: float = 1.0,
    efficiency: float = 1.0,
    sensor: Optional[str] = None,
    region_mass: Optional[_Number] = None,
    binned: bool = False,
) -> dict[str, Any]:
    """The median expected 95 % CL upper limit on g_aγ (Primakoff runs) or
    g_ae·g_aγ (ABC runs) per axion mass, as ``traxer reach``: CLs, exact
    Poisson, one bin (the region and the energy ``window`` (lo, hi) keV, on the
    run's band edges; default all), ``background`` in counts per keV per cm² per
    second, ``tracking_hours`` for every run or a list with one per run, ``bores`` identical lines,
    ``efficiency`` beyond the run's; each run's region placed on the image of
    ``region_mass`` (eV) or of its brightest mass. The background, hours,
    lengths and the mass may be astropy Quantities. Returns a dict: coupling,
    window_keV and curves, one per run: setting, run, region (with
    placed_on_mass_ev), tracking_hours, masses_eV, signal, background,
    counts_limit and limit (NaN without signal).

    A campaign run (one folder holding campaign.json) gives one combined
    curve, as ``traxer reach`` on it: the settings that recorded each mass
    combined, their tracking hours from the run unless ``tracking_hours``
    lists one per setting, ``binned=True`` for channels of energy bins ×
    rings. Returns reach.json's content (what, channels, coupling, exposure,
    energy_window_keV, region, settings, masses [{axion_mass_ev,
    limit_per_gev, method, parts}]) with ``masses_eV`` and ``limit`` as arrays
    (NaN where no setting sees the mass)."""

def eef(
    image: npt.ArrayLike,
    pixel_pitch_mm: Union[_Number, tuple[_Number, _Number]],
    focal_length_mm: Optional[_Number] = None,
) -> dict[str, Any]:
    """Encircled energy of an image, as ``traxer eef``.

    ``image`` [iy, ix] (or [band, iy, ix], summed): centroid_mm, total_flux,
    hpd_mm, d80_mm, d90_mm (diameters around the centroid), their *_arcsec with
    a focal length, and the curve as radius_mm and fraction."""
