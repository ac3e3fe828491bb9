"""Illuminance maps in lux: the library of ``spectrace lux``.

:func:`render_lux` renders a loaded scene's sensor with the ``illuminance`` integrator
(the scene's own integrator is not used) in passes and returns a :class:`LuxMap`: the
illuminance E_v in lux per pixel on the first surface each pixel sees, or on a virtual
work plane (a point and a normal, e.g. 0.85 m above the floor) where the camera rays cross
it, occluders still casting shadows. The lux come from the integrator's AOV channels
``lux`` and ``measured`` (see ``spectrace help illuminance``), never through the colour
film, so the number is exact in every variant. A pixel has data when at least
:data:`MIN_MEASURED` of its samples measured a point (the others: a ray that hits nothing,
or on the work plane a ray parallel to it, crossing it behind the camera or stopped by a
surface before it); its value is then the mean over those samples. Pixels without data
hold 0 and are left out of the statistics: minimum, mean and maximum lux and the
uniformity U0 = E_min / E_mean of EN 12464-1.

:func:`write_lux_exr` writes the map as one float32 channel ``Y`` in lux; :func:`plot_lux`
a false-colour PNG with a labelled colour bar and iso-lux contour lines (matplotlib,
imported here only, with the Agg backend). :func:`lux_scene_tree` prepares a scene's XML
for the command: ``illuminance`` instead of its integrator, and a box-filtered ``hdrfilm``
of the same size (each pixel the mean over its footprint) instead of its film.

Calculation grids, sensor points, luminance, glare and reports live in
:mod:`spectrace.lighting` (one module each).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from spectrace.errors import ParameterError

__all__ = ["LuxMap", "MIN_MEASURED", "PLANE_FORMAT", "lux_scene_tree", "lux_statistics",
           "parse_plane", "parse_range", "plot_lux", "render_lux", "write_lux_exr"]

#: Fraction of a pixel's samples that must measure a point for the pixel to have data.
MIN_MEASURED = 0.5
#: How a work plane is written on the command line.
PLANE_FORMAT = "'x,y,z nx,ny,nz' (a point and a normal, e.g. '0,0.85,0 0,1,0')"
#: Camera rays per side of the grid on which :func:`check_plane_visible` looks for the plane.
PLANE_CHECK_GRID = 33
#: Colour map of the false-colour PNG, and the colour of pixels without data.
COLOUR_MAP = "viridis"
NO_DATA_COLOUR = "0.55"
#: Iso-lux lines: about this many levels; the map is smoothed with a Gaussian of
#: CONTOUR_SIGMA (a fraction of the smaller image side, at least one pixel) for them only.
CONTOUR_LEVELS = 8
CONTOUR_SIGMA = 1.0 / 96.0
#: --log without --range: the lower end of the scale is the maximum over this.
LOG_DECADES = 1e3

Plane = tuple[tuple[float, float, float], tuple[float, float, float]]


@dataclass
class LuxMap:
    """An illuminance map and its statistics (over the pixels with data)."""

    lux: np.ndarray  # (H, W) float32, lux; 0 where there is no data
    valid: np.ndarray  # (H, W) bool: the pixel has data
    minimum: float  # lux
    mean: float
    maximum: float
    uniformity: float  # U0 = E_min / E_mean (NaN when E_mean is 0)
    spp: int
    seconds: float
    interrupted: bool = False
    nonfinite: int = 0
    plane: Plane | None = None
    max_depth: int = 1

    @property
    def no_data(self) -> int:
        """Number of pixels without data."""
        return int(self.valid.size - self.valid.sum())

    def summary(self) -> str:
        """One line: E_min, E_mean, E_max in lux and U0."""
        u0 = "n/a" if math.isnan(self.uniformity) else f"{self.uniformity:.3f}"
        return (f"E_min {self.minimum:.4g} lx, E_mean {self.mean:.4g} lx, "
                f"E_max {self.maximum:.4g} lx, U0 = E_min/E_mean {u0}")


# -- parsing ---------------------------------------------------------------------------------

#: The largest magnitude a number of the command line may have: the renderer computes in
#: float32, so larger values would become infinite there.
FLOAT32_MAX = float(np.finfo(np.float32).max)


def _floats(text: str, count: int) -> list[float] | None:
    parts = text.split(",")
    if len(parts) != count:
        return None
    try:
        values = [float(p) for p in parts]
    except ValueError:
        return None
    return values if all(math.isfinite(v) for v in values) else None


def parse_plane(text: str, name: str = "plane") -> Plane:
    """``"x,y,z nx,ny,nz"`` -> ((x, y, z), unit normal). ParameterError when malformed, the
    message calling the value ``name`` (the command line gives its flag)."""
    parts = str(text).split()
    point = _floats(parts[0], 3) if len(parts) == 2 else None
    normal = _floats(parts[1], 3) if len(parts) == 2 else None
    if point is None or normal is None:
        raise ParameterError(f"{name} {text!r}: expected {PLANE_FORMAT}")
    if max(abs(c) for c in point) > FLOAT32_MAX:
        raise ParameterError(f"{name} {text!r}: the point's coordinates must be at most "
                             f"{FLOAT32_MAX:.3g} in magnitude (the renderer computes in "
                             "float32)")
    # scaled by its largest component first: no overflow or underflow in the length
    big = max(abs(c) for c in normal)
    scaled = [c / big for c in normal] if big > 0.0 else normal
    length = math.sqrt(sum(c * c for c in scaled))
    if not length > 0.0:
        raise ParameterError(f"{name} {text!r}: the normal must not be zero")
    return tuple(point), tuple(c / length for c in scaled)


def parse_range(text: str, log: bool = False,
                names: tuple[str, str] = ("value_range", "log")) -> tuple[float, float]:
    """``"MIN,MAX"`` (lux) -> (MIN, MAX) with 0 <= MIN < MAX (0 < MIN with ``log``).
    ParameterError otherwise; ``names`` are what the message calls ``text`` and ``log``
    (the command line gives its flags)."""
    name, log_name = names
    values = _floats(str(text), 2)
    if values is None:
        raise ParameterError(f"{name} {text!r}: expected MIN,MAX in lux (e.g. 0,500)")
    low, high = values
    if not 0.0 <= low < high:
        raise ParameterError(f"{name} {text!r}: expected 0 <= MIN < MAX")
    if log and not low > 0.0:
        raise ParameterError(f"{name} {text!r}: {log_name} needs MIN > 0")
    return low, high


def plane_string(plane: Plane) -> str:
    """The plane written as on the command line."""
    return " ".join(",".join(f"{c:g}" for c in v) for v in plane)


# -- the scene -------------------------------------------------------------------------------

#: The ``<default>`` by which a scene may scale its lights for display (absolute photometry
#: renders nearly black): a lux map sets it to 1 unless the user gives it.
DISPLAY_EXPOSURE = "exposure"


def true_units(root: ET.Element, params: dict[str, str]) -> dict[str, str]:
    """``params`` with the scene's display ``exposure`` set to 1 when the scene declares
    that ``<default>``, uses it (``$exposure``) and the user did not set it, so the lights
    are in their true units."""
    from spectrace.scene import uses_parameter

    declared = any(d.get("name") == DISPLAY_EXPOSURE for d in root.iter("default"))
    if declared and uses_parameter(root, DISPLAY_EXPOSURE) and DISPLAY_EXPOSURE not in params:
        return {**params, DISPLAY_EXPOSURE: "1"}
    return params


def lux_scene_tree(root: ET.Element) -> ET.Element:
    """Modify the scene tree ``root`` in place for a lux map: its integrators become one
    ``illuminance``, each sensor's film a box-filtered ``hdrfilm`` (pixel format
    ``luminance``) keeping the film's id and geometry (width, height, crop, values such as
    ``$res`` copied verbatim). Returns ``root``. ParameterError when it has no sensor."""
    from spectrace.scene import new_film

    sensors = list(root.iter("sensor"))
    if not sensors:
        raise ParameterError("no <sensor> to measure from")
    for old in [child for child in root if child.tag == "integrator"]:
        root.remove(old)
    root.insert(0, ET.Element("integrator", {"type": "illuminance"}))
    for sensor in sensors:
        film = new_film(sensor, "hdrfilm")
        ET.SubElement(film, "string", {"name": "pixel_format", "value": "luminance"})
        ET.SubElement(film, "string", {"name": "component_format", "value": "float32"})
        ET.SubElement(film, "rfilter", {"type": "box"})
    return root


def illuminance_integrator(plane: Plane | None = None, max_depth: int | None = None,
                           shadows: bool = True):
    """An ``illuminance`` integrator, registered for the active variant if it is not yet."""
    import mitsuba as mi

    from spectrace import registry

    registry.require({"illuminance"})
    spec = {"type": "illuminance", "shadows": bool(shadows)}
    if max_depth is not None:
        spec["max_depth"] = int(max_depth)
    if plane is not None:
        point, normal = plane
        spec["plane_point"] = mi.ScalarPoint3f(*point)
        spec["plane_normal"] = mi.ScalarVector3f(*normal)
    try:
        return mi.load_dict(spec)
    except (RuntimeError, ValueError) as e:
        from spectrace.scene import load_error

        raise load_error(e) from None


def check_plane_visible(scene, plane: Plane, sensor=0, name: str = "plane") -> None:
    """ParameterError unless some camera ray of a PLANE_CHECK_GRID^2 grid over the film of
    ``sensor`` (an index into the scene's sensors, or a sensor) crosses the plane in front
    of the camera (not parallel to it, not behind); the message calls the plane ``name``."""
    import drjit as dr
    import mitsuba as mi

    n = PLANE_CHECK_GRID
    u = (np.arange(n) + 0.5) / n
    uu, vv = np.meshgrid(u, u)
    position = mi.Point2f(uu.ravel().astype(np.float32), vv.ravel().astype(np.float32))
    camera = scene.sensors()[sensor] if isinstance(sensor, int) else sensor
    ray, _ = camera.sample_ray(0.0, 0.5, position, mi.Point2f(0.5))
    (px, py, pz), (nx, ny, nz) = plane
    normal = mi.Vector3f(nx, ny, nz)
    cos = dr.dot(ray.d, normal)
    t = dr.dot(mi.Point3f(px, py, pz) - ray.o, normal) / cos
    crosses = (dr.abs(cos) > 1e-6) & (t > 0.0) & dr.isfinite(t) & (t < ray.maxt)
    if not bool(dr.any(crosses)):
        parallel = bool(dr.all(dr.abs(cos) <= 1e-6))
        why = "it is parallel to the view" if parallel else \
            "it is behind the camera or parallel to the view"
        raise ParameterError(f"{name} {plane_string(plane)!r}: the camera sees no point of "
                             f"the plane ({why})")


# -- rendering and statistics ----------------------------------------------------------------

def lux_statistics(lux: np.ndarray, valid: np.ndarray) -> tuple[float, float, float, float]:
    """(E_min, E_mean, E_max, U0 = E_min / E_mean) over the pixels with data (U0 NaN when
    E_mean is 0). ParameterError when no pixel has data."""
    values = np.asarray(lux, dtype=np.float64)[np.asarray(valid, dtype=bool)]
    if values.size == 0:
        raise ParameterError("no pixel measured a point (nothing in view, or the work plane "
                        "hidden behind surfaces)")
    low, mean, high = float(values.min()), float(values.mean()), float(values.max())
    return low, mean, high, (low / mean if mean > 0.0 else float("nan"))


def render_lux(scene, spp: int, seed: int = 0, plane: Plane | None = None,
               max_depth: int | None = None, *, spp_per_pass: int | None = None,
               shadows: bool = True, sensor=0,
               on_pass: Callable[[int, int], None] | None = None) -> LuxMap:
    """The illuminance map of ``scene``'s sensor (see the module docstring).

    ``plane`` = (point, normal) measures on that work plane; ``max_depth`` (default 1:
    direct light) > 1 adds interreflections. ``sensor``: an index into the scene's sensors
    or a sensor object. The scene's integrator is not used; the film must have AOV channels
    (``hdrfilm``: box-filter it for pixel means over footprints).
    ParameterError when the plane is not in view or no pixel has data.
    """
    from spectrace.passes import render_passes

    if plane is not None:
        check_plane_visible(scene, plane, sensor)
    integrator = illuminance_integrator(plane, max_depth, shadows)
    result = render_passes(scene, spp, seed=seed, spp_per_pass=spp_per_pass, sensor=sensor,
                           integrator=integrator, on_pass=on_pass)
    image = result.image
    if image.ndim != 3 or image.shape[-1] < 3:
        raise ParameterError("the film has no AOV channels: use an hdrfilm")
    total, measured = image[..., -2].astype(np.float64), image[..., -1].astype(np.float64)
    valid = measured >= MIN_MEASURED
    lux = np.where(valid, total / np.where(valid, measured, 1.0), 0.0).astype(np.float32)
    if result.spp == 0 or not valid.any():
        if plane is not None:
            raise ParameterError(f"plane {plane_string(plane)!r}: no pixel sees the plane "
                                 "(surfaces hide it from the camera)")
    low, mean, high, u0 = lux_statistics(lux, valid)
    return LuxMap(lux, valid, low, mean, high, u0, result.spp, result.seconds,
                  result.interrupted, result.nonfinite, plane,
                  1 if max_depth is None else int(max_depth))


# -- files -----------------------------------------------------------------------------------

def write_lux_exr(path, luxmap: LuxMap, header: dict | None = None) -> None:
    """Write the map as one float32 channel ``Y`` in lux (0 where there is no data), with
    the statistics and ``header`` (int, float or str values) as attributes; atomic
    (:func:`spectrace.images.write_exr_channels`)."""
    from spectrace.images import write_exr_channels

    attributes = {"units": "lux", "spp": int(luxmap.spp), "max_depth": int(luxmap.max_depth),
                  "E_min": float(luxmap.minimum), "E_mean": float(luxmap.mean),
                  "E_max": float(luxmap.maximum), "no_data_pixels": int(luxmap.no_data)}
    if not math.isnan(luxmap.uniformity):
        attributes["U0"] = float(luxmap.uniformity)
    if luxmap.plane is not None:
        attributes["plane"] = plane_string(luxmap.plane)
    attributes.update(header or {})
    write_exr_channels(path, {"Y": luxmap.lux}, attributes)


def read_lux_exr(path) -> tuple[np.ndarray, dict]:
    """The ``Y`` channel (lux) of a lux EXR as (H, W) float32, and its header."""
    from spectrace.images import read_channel_exr

    return read_channel_exr(path, "Y")


def _smooth(values: np.ndarray, valid: np.ndarray, sigma: float) -> np.ndarray:
    """Gaussian smoothing of the pixels with data (normalised convolution, separable)."""
    radius = max(1, int(math.ceil(3.0 * sigma)))
    x = np.arange(-radius, radius + 1, dtype=np.float64)
    kernel = np.exp(-0.5 * (x / sigma) ** 2)

    def blur(a):
        a = np.apply_along_axis(lambda r: np.convolve(r, kernel, mode="same"), 0, a)
        return np.apply_along_axis(lambda r: np.convolve(r, kernel, mode="same"), 1, a)

    weight = blur(valid.astype(np.float64))
    total = blur(np.where(valid, values, 0.0))
    return np.where(weight > 1e-12, total / np.maximum(weight, 1e-12), 0.0)


def contour_levels(low: float, high: float, log: bool = False) -> np.ndarray:
    """Iso-lux levels strictly inside (low, high): round numbers, about CONTOUR_LEVELS."""
    from matplotlib import ticker

    if log:
        locator = ticker.LogLocator(base=10.0, subs=(1.0, 2.0, 5.0))
    else:
        locator = ticker.MaxNLocator(CONTOUR_LEVELS)
    levels = np.asarray(locator.tick_values(low, high), dtype=np.float64)
    return levels[(levels > low) & (levels < high)]


def display_range(luxmap: LuxMap, value_range=None, log: bool = False) -> tuple[float, float]:
    """The colour scale's (min, max) in lux: ``value_range``, or 0 (log: max / LOG_DECADES,
    or the smallest positive value if larger) to the maximum."""
    if value_range is not None:
        return float(value_range[0]), float(value_range[1])
    high = luxmap.maximum if luxmap.maximum > 0.0 else 1.0
    if not log:
        return 0.0, high
    positive = luxmap.lux[luxmap.valid & (luxmap.lux > 0.0)]
    low = max(float(positive.min()) if positive.size else 0.0, high / LOG_DECADES)
    return (low, high) if low < high else (high / LOG_DECADES, high)


def plot_lux(path, luxmap: LuxMap, value_range=None, log: bool = False,
             title: str | None = None, label: str = "illuminance E_v (lx)") -> np.ndarray:
    """Write the false-colour PNG of ``luxmap``: colour bar in lux (``label``), iso-lux
    contour lines (labelled), pixels without data in grey; atomic. Returns the contour
    levels drawn."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import colors
    from matplotlib.figure import Figure

    from spectrace.images import atomic_path

    low, high = display_range(luxmap, value_range, log)
    norm = colors.LogNorm(low, high, clip=True) if log else colors.Normalize(low, high, clip=True)
    cmap = matplotlib.colormaps[COLOUR_MAP].with_extremes(bad=NO_DATA_COLOUR)
    lux = np.ma.masked_array(luxmap.lux.astype(np.float64), mask=~luxmap.valid)
    if log:
        lux = np.ma.masked_less_equal(lux, 0.0)
    h, w = luxmap.lux.shape
    width = 7.0
    fig = Figure(figsize=(width, max(2.5, width * 0.8 * h / w)), dpi=120)
    ax = fig.add_subplot()
    image = ax.imshow(lux, cmap=cmap, norm=norm, interpolation="nearest")
    levels = contour_levels(low, high, log)
    if levels.size and luxmap.valid.sum() > 4 and min(h, w) > 2:
        sigma = max(1.0, CONTOUR_SIGMA * min(h, w))
        smooth = np.ma.masked_array(_smooth(luxmap.lux.astype(np.float64), luxmap.valid, sigma),
                                    mask=~luxmap.valid)
        lines = ax.contour(smooth, levels=levels, colors="white", linewidths=0.8)
        ax.clabel(lines, fmt=lambda v: f"{v:g}", fontsize=7)
    else:
        lines = None
    bar = fig.colorbar(image, ax=ax)
    bar.set_label(label)
    if lines is not None and len(lines.levels):
        bar.add_lines(lines)
    ax.set_axis_off()
    ax.set_title(title if title is not None else luxmap.summary(), fontsize=8)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    return levels
