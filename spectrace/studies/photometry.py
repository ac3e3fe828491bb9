"""Photometry: the study of ``notebooks/photometry.ipynb``.

The room of ``scenes/luminaires.xml`` (5 m x 4 m, 2.7 m high, four ``ieslight``
luminaires of a 3000 K LED spectrum) measured as a lighting designer would:

* :func:`room_luminaires` reads the luminaires from the scene file itself (photometric
  file, position, aim, luminous flux) and :func:`polar_curve` gives their polar diagrams;
* :func:`hand_calculation` is the designer's point-by-point method, written from the
  photometric definitions independently of the renderer: E = sum over luminaires of
  I(gamma, C) cos(theta) / d^2 (for a luminaire aimed straight down at a horizontal
  plane, cos(theta) = cos(gamma) and d = h / cos(gamma): E = I cos^3(gamma) / h^2), no
  shadows, no interreflections;
* :func:`work_plane` renders the illuminance on the work plane (0.85 m) seen straight
  from above by an orthographic camera inside the room (``illuminance`` integrator,
  :func:`spectrace.lux.render_lux`), with the floor position of every pixel, so that the
  map can be read along a line and integrated: :func:`utilisation_factor` = lumens on the
  work plane / lumens emitted, direct and with interreflections; :func:`task_area` masks
  the plane without the 0.5 m border zone of EN 12464-1 for the uniformity U0;
* :func:`room_image` renders the room itself, in spectral or RGB variants at the same
  exposure (one photometric scale in every variant: a colour stands for the spectra of
  the same film Y, see ``spectrace help luminous``).

Sources: CIE 121-1996 (photometry of luminaires); EN 12464-1:2021 (work plane, task area,
border zone, uniformity U0); IES LM-63-2019 (Type C angles); Tregenza and Loe (2014),
*The Design of Lighting*, ch. 7 (point-by-point calculation, utilisation factor).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from spectrace.studies import budget, display, load_scene, save_figure, scene_path, text_table

__all__ = ["BORDER", "ROOM", "ROOM_X", "ROOM_Z", "WORK_PLANE_HEIGHT", "Luminaire", "WorkPlane",
           "budget", "display", "hand_calculation", "load_scene",
           "luminaire_frame", "polar_curve", "room_image", "room_luminaires", "save_figure",
           "task_area", "text_table", "uniformity", "utilisation_factor", "work_plane"]

#: The scene of the study, its floor extent (m) and the work plane of EN 12464-1.
ROOM = "luminaires"
ROOM_X = (-2.5, 2.5)
ROOM_Z = (-2.0, 2.0)
WORK_PLANE_HEIGHT = 0.85
#: Border zone (m) of EN 12464-1 left out of the task area.
BORDER = 0.5
#: Height of the orthographic camera that looks down on the work plane: below the
#: luminaires, just above the ball on the left table (0.75 to 0.99 m), which the plane
#: cuts: the plane inside the ball is hidden from the camera (no data, no flux).
CAMERA_HEIGHT = 1.0


@dataclass
class Luminaire:
    """An ``ieslight`` of the room: its photometry and placement (scene file values)."""

    filename: str  # as written in the scene (relative to its folder)
    photometry: object  # spectrace.photometry.Photometry
    origin: np.ndarray  # (3,) position (m)
    frame: np.ndarray  # (3, 3): rows local X, Y, Z in world coordinates (Z: gamma = 0)
    flux_factor: float  # luminous_flux / file flux, or 1

    @property
    def flux(self) -> float:
        """Luminous flux emitted (lm) at exposure 1."""
        return float(self.photometry.flux) * self.flux_factor

    def intensity(self, gamma, c) -> np.ndarray:
        """Luminous intensity (cd) at Type C angles in degrees, rescaled as in the scene."""
        return self.photometry.intensity(gamma, c) * self.flux_factor


def luminaire_frame(origin, target, up) -> np.ndarray:
    """The frame of Mitsuba's ``lookat``: local Z along target - origin, local X = up x Z
    (normalised), local Y = Z x X; rows X, Y, Z."""
    z = np.asarray(target, np.float64) - np.asarray(origin, np.float64)
    z /= np.linalg.norm(z)
    x = np.cross(np.asarray(up, np.float64), z)
    x /= np.linalg.norm(x)
    return np.stack([x, np.cross(z, x), z])


def _vector(text: str) -> np.ndarray:
    return np.array([float(v) for v in text.split(",")], np.float64)


def room_luminaires(scene: str = ROOM) -> list[Luminaire]:
    """The ``ieslight`` emitters of the scene file, in file order, at exposure 1 (the
    scene's ``scale`` is its camera exposure). Each needs a ``lookat`` placement."""
    from spectrace.photometry import read_photometry

    path = scene_path(scene)
    luminaires = []
    for emitter in ET.parse(path).getroot().iter("emitter"):
        if emitter.get("type") != "ieslight":
            continue
        filename = emitter.find("string[@name='filename']").get("value")
        lookat = emitter.find("transform[@name='to_world']/lookat")
        origin = _vector(lookat.get("origin"))
        frame = luminaire_frame(origin, _vector(lookat.get("target")),
                                _vector(lookat.get("up")))
        photometry = read_photometry(Path(path).parent / filename)
        flux = emitter.find("float[@name='luminous_flux']")
        factor = 1.0 if flux is None else float(flux.get("value")) / float(photometry.flux)
        luminaires.append(Luminaire(filename, photometry, origin, frame, factor))
    return luminaires


def polar_curve(luminaire: Luminaire, c_plane: float = 0.0, n: int = 361):
    """(theta in radians from -pi to pi, cd) of the C plane ``c_plane`` and its opposite
    C + 180: theta = gamma on the C side, -gamma on the other, as polar diagrams draw."""
    gamma = np.linspace(0.0, 180.0, n)
    right = luminaire.intensity(gamma, c_plane)
    left = luminaire.intensity(gamma, c_plane + 180.0)
    theta = np.radians(np.concatenate([-gamma[::-1], gamma[1:]]))
    return theta, np.concatenate([left[::-1], right[1:]])


def hand_calculation(luminaires, points, normal=(0.0, 1.0, 0.0)) -> np.ndarray:
    """Direct illuminance (lux) at ``points`` (..., 3) on a surface of ``normal``: the sum
    of I(gamma, C) cos(theta) / d^2, gamma and C the Type C angles of the direction from
    each luminaire to the point (gamma from local +Z, C from local +X counterclockwise
    seen from above the luminaire, so C = 90 along local -Y). No shadows."""
    points = np.asarray(points, np.float64)
    n = np.asarray(normal, np.float64) / np.linalg.norm(normal)
    E = np.zeros(points.shape[:-1])
    for lum in luminaires:
        v = points - lum.origin
        d = np.linalg.norm(v, axis=-1)
        u = v / d[..., None]
        local = u @ lum.frame.T  # components along local X, Y, Z
        gamma = np.degrees(np.arccos(np.clip(local[..., 2], -1.0, 1.0)))
        c = np.mod(np.degrees(np.arctan2(-local[..., 1], local[..., 0])), 360.0)
        cos_theta = np.maximum(-(u @ n), 0.0)
        E += lum.intensity(gamma, c) * cos_theta / d**2
    return E


# -- rendering --------------------------------------------------------------------------------

def room_image(variant: str, res: int, spp: int, exposure: float | None = None,
               seed: int = 0) -> np.ndarray:
    """The room (its own camera and integrator) as linear sRGB (H, W, 3) in ``variant``, at
    the display ``exposure`` (None: the scene's own), the same in every variant."""
    import spectrace

    spectrace.set_variant(variant)
    extra = {} if exposure is None else {"exposure": exposure}
    scene = load_scene(ROOM, res=res, spp=spp, **extra)
    return spectrace.render(scene, spp=spp, seed=seed).image[..., :3]


@dataclass
class WorkPlane:
    """The illuminance on the work plane seen from above, and where each pixel is."""

    luxmap: object  # spectrace.lux.LuxMap
    x: np.ndarray  # (W,) x of the pixel centres (m)
    z: np.ndarray  # (H,) z of the pixel centres (m)
    pixel_area: float  # m^2 of plane per pixel

    @property
    def points(self) -> np.ndarray:
        """(H, W, 3) plane points at the pixel centres."""
        xx, zz = np.meshgrid(self.x, self.z)
        return np.stack([xx, np.full_like(xx, WORK_PLANE_HEIGHT), zz], axis=-1)

    def row(self, z: float) -> int:
        """The pixel row nearest to z."""
        return int(np.argmin(np.abs(self.z - z)))

    @property
    def flux(self) -> float:
        """Luminous flux on the plane (lm): the pixel means times the pixel area."""
        return float(self.luxmap.lux.sum()) * self.pixel_area


def work_plane(variant: str, res: int, spp: int, max_depth: int = 1,
               seed: int = 0) -> WorkPlane:
    """Illuminance on the work plane y = WORK_PLANE_HEIGHT over the whole room, seen by an
    orthographic camera looking straight down from CAMERA_HEIGHT (``res`` pixels along x,
    4/5 of it along z). ``spp`` 1: one sample at each pixel centre (the value there); more:
    independent samples, box filter (the mean over the pixel). Scene at exposure 1, its
    luminaires points (``opening`` point: the law of the hand calculation)."""
    import mitsuba as mi

    import spectrace
    from spectrace.lux import render_lux

    spectrace.set_variant(variant)
    # its own sensor is not used; point openings: the hand calculation is the point law
    scene = load_scene(ROOM, res=8, spp=4, exposure=1.0, opening="point")
    width = int(res)
    height = int(round(width * (ROOM_Z[1] - ROOM_Z[0]) / (ROOM_X[1] - ROOM_X[0])))
    half = (ROOM_X[1] - ROOM_X[0]) / 2
    centre = ((ROOM_X[0] + ROOM_X[1]) / 2, (ROOM_Z[0] + ROOM_Z[1]) / 2)
    T = mi.ScalarTransform4f()
    sampler = {"type": "stratified", "sample_count": 1, "jitter": False} if spp == 1 else \
        {"type": "independent", "sample_count": spp}
    sensor = mi.load_dict({
        "type": "orthographic", "near_clip": 1e-3, "far_clip": 10.0,
        "to_world": T.look_at([centre[0], CAMERA_HEIGHT, centre[1]],
                              [centre[0], 0.0, centre[1]], [0, 0, -1]).scale([half, half, 1]),
        "film": {"type": "hdrfilm", "width": width, "height": height,
                 "pixel_format": "luminance", "rfilter": {"type": "box"}},
        "sampler": sampler,
    })
    plane = ((0.0, WORK_PLANE_HEIGHT, 0.0), (0.0, 1.0, 0.0))
    luxmap = render_lux(scene, spp, seed=seed, plane=plane, max_depth=max_depth,
                        sensor=sensor)
    x, z = _pixel_centres(sensor, width, height)
    area = (ROOM_X[1] - ROOM_X[0]) * (ROOM_Z[1] - ROOM_Z[0]) / (width * height)
    return WorkPlane(luxmap, x, z, area)


def _pixel_centres(sensor, width: int, height: int):
    """x of the pixel columns and z of the rows: the camera rays through the pixel centres
    (they are vertical)."""
    import mitsuba as mi

    u = ((np.arange(width) + 0.5) / width).astype(np.float32)
    v = ((np.arange(height) + 0.5) / height).astype(np.float32)
    ray_u, _ = sensor.sample_ray(0.0, 0.5, mi.Point2f(u, np.full_like(u, 0.5)), mi.Point2f(0.5))
    ray_v, _ = sensor.sample_ray(0.0, 0.5, mi.Point2f(np.full_like(v, 0.5), v), mi.Point2f(0.5))
    return np.array(ray_u.o.x, np.float64), np.array(ray_v.o.z, np.float64)


def task_area(plane: WorkPlane, border: float = BORDER) -> np.ndarray:
    """(H, W) mask of the work plane without the border zone (``border`` m from the walls)."""
    xx, zz = np.meshgrid(plane.x, plane.z)
    return ((xx > ROOM_X[0] + border) & (xx < ROOM_X[1] - border)
            & (zz > ROOM_Z[0] + border) & (zz < ROOM_Z[1] - border))


def uniformity(plane: WorkPlane, mask=None) -> tuple[float, float, float]:
    """(E_min, E_mean, U0) over the pixels with data (and in ``mask``)."""
    valid = plane.luxmap.valid if mask is None else plane.luxmap.valid & mask
    values = plane.luxmap.lux[valid].astype(np.float64)
    low, mean = float(values.min()), float(values.mean())
    return low, mean, (low / mean if mean > 0 else math.nan)


def utilisation_factor(plane: WorkPlane, luminaires) -> float:
    """Lumens on the work plane over the lumens the luminaires emit."""
    return plane.flux / sum(lum.flux for lum in luminaires)
