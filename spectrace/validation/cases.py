"""The validation cases: CIE 171:2006's analytical case families as small scenes with their
closed-form answers.

CIE 171:2006 *Test cases to assess the accuracy of lighting computer programs* is not freely
available, so every reference value here is derived from the physics of the case's family
(the formulas and their sources are in :mod:`spectrace.validation.reference`), and each case
is named by the family it belongs to (the section numbers are those of CIE 171's families).
Each case's scene is a file of ``spectrace.scenes`` (``scenes/validation/``) that a user can
render with ``spectrace render``; :data:`CASES` maps a case's name to the function that
measures it, :data:`FAMILIES` gives each family its tolerance and why.

A point passes when |measured - reference| <= tolerance * |reference| + NOISE_SIGMAS *
stderr: the family's tolerance is the systematic error its method may carry (float32
geometry, a tabulated distribution, a quadrature), and the Monte Carlo noise at the sample
count used is allowed for separately, from the spread of the samples (so that a correct
renderer fails about one point in 16 000 and a 1 % bias cannot hide behind noise once the
sample count makes the noise smaller than it).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from spectrace.validation import reference as ref

#: Standard errors of the mean a measured point may lie off its reference, besides the
#: family's tolerance.
NOISE_SIGMAS = 4.0
#: The luminance of the validation area sources (cd/m^2).
SOURCE_LUMINANCE = 1000.0


def folder() -> Path:
    """The folder of the validation scenes (package data of ``spectrace.scenes``)."""
    from spectrace import scenes

    return scenes.FOLDER / "validation"


@dataclass(frozen=True)
class Family:
    """A family of cases: CIE 171 section, name, relative tolerance and its justification."""

    section: str
    name: str
    tolerance: float
    why: str


FAMILIES: dict[str, Family] = {
    "point": Family("5.2", "point sources", 0.005,
                    "float32 geometry (1e-6) and, for the file, bilinear interpolation of the "
                    "analytic distribution at 2.5 x 5 degree steps (< 0.15 %)"),
    "area": Family("5.3", "area sources", 0.005,
                   "float32 geometry; the reference is exact (contour integral)"),
    "flux": Family("5.4", "luminous flux conservation", 0.005,
                   "Gauss-Legendre quadrature over the walls (< 0.05 % at 24 x 24 nodes a "
                   "wall) and the file's tabulation of the distribution (< 0.15 %)"),
    "glass": Family("5.5", "directional transmittance of clear glass", 0.01,
                    "CIE 171 compares transmittances to two decimals; Mitsuba's thin "
                    "dielectric is a model of an ideal pane"),
    "reflection": Family("5.6-5.7", "diffuse reflection", 0.005,
                         "the light's illuminance is uniform over the reflector to 1e-6; "
                         "the reference is exact (configuration-factor algebra)"),
    "interreflection": Family("5.8", "internal reflected component", 0.005,
                              "the reference is exact for a sphere (Goebel 1967)"),
    "daylight": Family("5.9-5.14", "daylight", 0.005,
                       "the sky is evaluated analytically; Gauss-Legendre quadrature of the "
                       "overcast reference (< 1e-6 at 64 x 64 nodes; the masks' edges: "
                       "< 0.2 % at 160 x 160)"),
}


@dataclass(frozen=True)
class Settings:
    """How a case runs: ``quick`` (small grids, few samples, for the test suite), ``seed``,
    and ``params``: XML parameters that override the case's own in its scene (a deliberately
    wrong setting, say), never its reference."""

    quick: bool = False
    seed: int = 0
    params: dict[str, str] = field(default_factory=dict)


@dataclass
class Result:
    """One case's measurement against its reference at every point."""

    name: str
    family: str
    title: str
    quantity: str
    x: np.ndarray = field(default_factory=lambda: np.zeros(0))
    xlabel: str = "point"
    reference: np.ndarray = field(default_factory=lambda: np.zeros(0))
    measured: np.ndarray = field(default_factory=lambda: np.zeros(0))
    stderr: np.ndarray = field(default_factory=lambda: np.zeros(0))
    spp: int = 0
    reason: str = ""  # why a case cannot be modelled (then nothing is measured)

    @property
    def modelled(self) -> bool:
        return not self.reason

    @property
    def tolerance(self) -> float:
        return FAMILIES[self.family].tolerance

    @property
    def relative_error(self) -> np.ndarray:
        scale = np.maximum(np.abs(self.reference), 1e-3 * np.max(np.abs(self.reference)))
        return np.abs(self.measured - self.reference) / scale

    @property
    def passed(self) -> bool:
        if not self.modelled:
            return False
        allowed = self.tolerance * np.abs(self.reference) + NOISE_SIGMAS * self.stderr
        return bool(np.all(np.abs(self.measured - self.reference) <= allowed))


def _load(name: str, settings: Settings, **params):
    from spectrace.scene import load_scene

    values = {k: str(v) for k, v in params.items()}
    values.update(settings.params)
    return load_scene(folder() / f"{name}.xml", values)


def _measure(result: Result, scene, points, normals, spp, settings, max_depth=1):
    """The illuminance at the points as ``spectrace lux --points`` measures it
    (:func:`spectrace.lighting.points.measure_points`: at the points themselves, no pixel
    footprint; one sample a point where every light is exact)."""
    from spectrace.lighting.points import measure_points

    result.measured, result.stderr, result.spp = measure_points(
        scene, points, normals, spp=spp, seed=settings.seed, max_depth=max_depth)
    return result


def _grid(a0, a1, b0, b1, n):
    a, b = np.meshgrid(np.linspace(a0, a1, n), np.linspace(b0, b1, n), indexing="ij")
    return a.ravel(), b.ravel()


def _n(settings: Settings, quick: int, full: int) -> int:
    return quick if settings.quick else full


# -- 5.2 point sources -------------------------------------------------------------------

POINT_INTENSITY = 1000.0  # cd
POINT_HEIGHT = 2.0  # m


def _point_plane(settings, name, title, tilt, centre, spp=(16, 64), family="point",
                 source_radius=0.0):
    """Points on the plane of point_source.xml tilted by ``tilt`` degrees about x."""
    t = np.radians(tilt)
    normal = np.array([0.0, np.cos(t), np.sin(t)])
    along = np.array([0.0, np.sin(t), -np.cos(t)])  # the rectangle's local y in the world
    n = _n(settings, 5, 11)
    u, v = _grid(-3.0, 3.0, 0.2, 3.8, n) if tilt == 90 else _grid(-3.0, 3.0, -3.0, 3.0, n)
    points = np.asarray(centre) + u[:, None] * [1.0, 0.0, 0.0] + v[:, None] * along
    normals = np.broadcast_to(normal, points.shape)
    result = Result(name, family, title, "E (lx)", x=np.arange(len(points)))
    result.reference = ref.point_illuminance(points, normals, [0.0, POINT_HEIGHT, 0.0],
                                             POINT_INTENSITY)
    scene = _load("point_source", settings, intensity=POINT_INTENSITY, height=POINT_HEIGHT,
                  tilt=tilt, px=centre[0], py=centre[1], pz=centre[2],
                  source_radius=source_radius)
    return _measure(result, scene, points, normals, _n(settings, *spp), settings)


def point_horizontal(settings: Settings) -> Result:
    """Isotropic point source over a horizontal plane: E = I h / d^3."""
    return _point_plane(settings, "point_horizontal", "isotropic point, horizontal plane",
                        0.0, (0.0, 0.0, 0.0))


def point_vertical(settings: Settings) -> Result:
    """Isotropic point source beside a vertical plane: E = I cos(theta) / d^2."""
    return _point_plane(settings, "point_vertical", "isotropic point, vertical plane",
                        90.0, (0.0, 0.0, -3.0))


def point_tilted(settings: Settings) -> Result:
    """Isotropic point source over a plane tilted by 30 degrees: E = I cos(theta) / d^2."""
    return _point_plane(settings, "point_tilted", "isotropic point, plane tilted 30 deg",
                        30.0, (0.0, 0.0, 0.0))


ASYMMETRIC_FLUX = 800.0 * np.pi  # lm: integral of asymmetric_intensity over the sphere


def asymmetric_intensity(gamma_deg, c_deg):
    """The asymmetric distribution of ``asymmetric.ies`` (cd): 500 (1 + 0.5 sin(gamma)
    cos C) cos^1.5(gamma) + 100 for gamma < 90 degrees, 100 above (one value at the pole,
    where every C plane meets). Its flux is 800 pi lm: 2 pi 500 / 2.5 (the cos C term
    integrates to 0 over C) plus 4 pi 100."""
    g, c = np.radians(gamma_deg), np.radians(c_deg)
    down = np.clip(np.cos(g), 0.0, None) ** 1.5
    return 500.0 * (1.0 + 0.5 * np.sin(g) * np.cos(c)) * down + 100.0


def write_asymmetric_ies(path) -> Path:
    """Write ``asymmetric.ies``: :func:`asymmetric_intensity` tabulated every 2.5 degrees of
    gamma and 5 degrees of C (no symmetry), LM-63-2002."""
    from spectrace.photometry.generate import write_ies

    v = np.arange(0.0, 180.001, 2.5)
    h = np.arange(0.0, 360.001, 5.0)
    G, C = np.meshgrid(v, h)
    return write_ies(path, v, h, asymmetric_intensity(G, C),
                     keywords={"TEST": "spectrace validation", "MANUFAC": "spectrace",
                               "LUMINAIRE": "asymmetric analytic distribution"})


def _ies_direction_intensity(light_direction):
    """I of asymmetric.ies aimed straight down (lookat up +z) for world directions (..., 3)
    from the light: local x = world +x, local y = world +z, local z = world -y; gamma from
    local +z, C from local +x towards local -y (LM-63 Type C)."""
    d = np.asarray(light_direction)
    gamma = np.degrees(np.arccos(np.clip(-d[..., 1], -1.0, 1.0)))
    c = np.degrees(np.arctan2(-d[..., 2], d[..., 0])) % 360.0
    return asymmetric_intensity(gamma, c)


IES_HEIGHT = 2.5  # m


def point_asymmetric(settings: Settings) -> Result:
    """A luminaire with an asymmetric distribution (IES file) over the floor:
    E = I(gamma, C) cos(theta) / d^2 with I the analytic function the file tabulates."""
    n = _n(settings, 5, 11)
    x, z = _grid(-3.0, 3.0, -3.0, 3.0, n)
    points = np.stack([x, np.zeros_like(x), z], axis=-1)
    normals = np.broadcast_to([0.0, 1.0, 0.0], points.shape)
    result = Result("point_asymmetric", "point", "asymmetric IES luminaire, floor", "E (lx)",
                    x=np.arange(len(points)))
    result.reference = ref.point_illuminance(points, normals, [0.0, IES_HEIGHT, 0.0],
                                             _ies_direction_intensity)
    scene = _load("ies_point", settings, height=IES_HEIGHT)
    return _measure(result, scene, points, normals, _n(settings, 16, 64), settings)


# -- 5.3 area sources --------------------------------------------------------------------

def _radiance(luminance: float) -> float:
    """The radiance value (a flat spectrum, or grey) whose luminance is ``luminance``."""
    from spectrace.plugins.emitters import luminous

    return luminance / (luminous.KM * luminous.v_integral())


RECT_LENGTH, RECT_WIDTH, RECT_HEIGHT, WALL_X = 2.0, 1.0, 2.0, 1.5


def _rectangle_vertices():
    a, b = RECT_LENGTH / 2, RECT_WIDTH / 2
    return np.array([[-a, RECT_HEIGHT, -b], [a, RECT_HEIGHT, -b], [a, RECT_HEIGHT, b],
                     [-a, RECT_HEIGHT, b]])


def _area_case(settings, name, title, points, normals, factor, scene_name):
    """E = pi L F at the points, against the scene ``scene_name`` at luminance L."""
    result = Result(name, "area", title, "E (lx)", x=np.arange(len(points)))
    result.reference = np.pi * SOURCE_LUMINANCE * factor
    scene = _load(scene_name, settings, radiance=repr(_radiance(SOURCE_LUMINANCE)))
    return _measure(result, scene, points, normals, _n(settings, 1024, 8192), settings)


def area_rectangle_parallel(settings: Settings) -> Result:
    """A Lambertian rectangle over a parallel plane: E = pi L F (parallel rectangle)."""
    n = _n(settings, 5, 11)
    x, z = _grid(-2.5, 1.4, -2.0, 2.0, n)
    points = np.stack([x, np.zeros_like(x), z], axis=-1)
    normals = np.broadcast_to([0.0, 1.0, 0.0], points.shape)
    return _area_case(settings, "area_rectangle_parallel",
                      "Lambertian rectangle, parallel plane", points, normals,
                      ref.polygon_irradiance_factor(points, normals, _rectangle_vertices()),
                      "area_rectangle")


def area_rectangle_perpendicular(settings: Settings) -> Result:
    """A Lambertian rectangle beside a perpendicular plane: E = pi L F (perpendicular)."""
    n = _n(settings, 5, 11)
    y, z = _grid(0.1, 1.9, -2.0, 2.0, n)
    points = np.stack([np.full_like(y, WALL_X), y, z], axis=-1)
    normals = np.broadcast_to([-1.0, 0.0, 0.0], points.shape)
    return _area_case(settings, "area_rectangle_perpendicular",
                      "Lambertian rectangle, perpendicular plane", points, normals,
                      ref.polygon_irradiance_factor(points, normals, _rectangle_vertices()),
                      "area_rectangle")


DISK_RADIUS, DISK_HEIGHT = 0.5, 1.5


def area_disk_parallel(settings: Settings) -> Result:
    """A Lambertian disk over a parallel plane, along a line from its axis outwards:
    E = pi L F with Howell's B-13 factor."""
    offset = np.linspace(0.0, 2.5, _n(settings, 6, 26))
    points = np.stack([offset, np.zeros_like(offset), np.zeros_like(offset)], axis=-1)
    normals = np.broadcast_to([0.0, 1.0, 0.0], points.shape)
    result = _area_case(settings, "area_disk_parallel", "Lambertian disk, parallel plane",
                        points, normals, ref.disk_parallel_factor(DISK_RADIUS, DISK_HEIGHT,
                                                                  offset), "area_disk")
    result.x, result.xlabel = offset, "distance from the axis (m)"
    return result


SPHERE_SOURCE_RADIUS = 0.3  # m, below the light's height: whole above every floor point


def area_sphere(settings: Settings) -> Result:
    """A uniform Lambertian sphere (spectrace's pointlight with ``source_radius``) over a
    horizontal plane, wholly above every point's horizon: it lights the plane exactly as
    the point of the same intensity at its centre, E = I h / d^3 (Howell's configuration
    factor of a sphere, B-25 family, for a sphere wholly visible)."""
    return _point_plane(settings, "area_sphere", "Lambertian sphere (sized pointlight), "
                        "horizontal plane", 0.0, (0.0, 0.0, 0.0), spp=(256, 4096),
                        family="area", source_radius=SPHERE_SOURCE_RADIUS)


# -- 5.4 flux conservation ---------------------------------------------------------------

ROOM = (4.0, 3.0, 5.0)  # width (x), height (y), depth (z), m
ROOM_LIGHT = (0.5, 2.0, -0.5)


def room_quadrature(n: int):
    """Gauss-Legendre nodes, inward normals and weights (m^2) on the six walls of the room
    of flux_room.xml: sum(w E) is the flux arriving on the walls."""
    W, H, D = ROOM
    faces = []
    for axis, lo, hi in ((0, -W / 2, W / 2), (1, 0.0, H), (2, -D / 2, D / 2)):
        others = [k for k in range(3) if k != axis]
        bounds = {0: (-W / 2, W / 2), 1: (0.0, H), 2: (-D / 2, D / 2)}
        a, b, w = ref.gauss_legendre_grid(*bounds[others[0]], *bounds[others[1]], n)
        for plane, inward in ((lo, 1.0), (hi, -1.0)):
            p = np.zeros((len(a), 3))
            p[:, axis], p[:, others[0]], p[:, others[1]] = plane, a, b
            normal = np.zeros(3)
            normal[axis] = inward
            faces.append((p, np.broadcast_to(normal, p.shape), w))
    points, normals, weights = (np.concatenate(parts) for parts in zip(*faces, strict=True))
    return points, normals, weights


def flux_closed_room(settings: Settings) -> Result:
    """The asymmetric luminaire in a closed black room: the flux arriving on all walls
    (illuminance integrated over them) equals the luminaire's flux, 800 pi lm."""
    points, normals, weights = room_quadrature(24)
    result = Result("flux_closed_room", "flux", "luminaire in a closed black room",
                    "flux (lm)", x=np.zeros(1), xlabel="")
    result.reference = np.array([ASYMMETRIC_FLUX])
    scene = _load("flux_room", settings, lx=ROOM_LIGHT[0], ly=ROOM_LIGHT[1], lz=ROOM_LIGHT[2])
    spp = _n(settings, 4, 16)
    _measure(result, scene, points, normals, spp, settings)
    result.stderr = np.array([np.sqrt(np.sum((weights * result.stderr) ** 2))])
    result.measured = np.array([np.sum(weights * result.measured)])
    return result


# -- 5.5 clear glass ---------------------------------------------------------------------

GLASS_IOR = 1.5
GLASS_DEPTH = 12  # path length through the pane: its internal reflections fade as R^2


def glass_transmittance(settings: Settings) -> Result:
    """The radiance of a uniform ceiling seen through a clear 6 mm pane, against the same
    ceiling seen past it: the pane's directional transmittance T(theta) (Fresnel, internal
    reflections summed). Glass transmits the two polarizations differently (at 80 degrees
    0.75 against 0.17 for each face), and averaging their reflectances before summing the
    internal reflections, as an unpolarized renderer must, underestimates T by up to 4 %
    (Mitsuba's ``thindielectric`` and a ``dielectric`` slab alike, measured): the case runs
    in the polarized form of the variant (``spectrace.scene.polarized_variant``), which
    carries each polarization through both faces, and switches back after."""
    import mitsuba as mi

    import spectrace
    from spectrace.lighting.luminance import luminance_along
    from spectrace.scene import polarized_variant

    angles = np.arange(0.0, 80.001, 20.0 if settings.quick else 10.0)
    t = np.radians(angles)
    up = np.stack([np.zeros_like(t), np.cos(t), np.sin(t)], axis=-1)
    below = np.broadcast_to([0.0, 0.2, 0.0], up.shape)  # under the pane (at y = 1)
    above = np.broadcast_to([0.0, 1.5, 0.0], up.shape)  # the same ceiling, no pane between
    variant = mi.variant()
    result = Result("glass_transmittance", "glass",
                    f"clear 6 mm pane, n = 1.5 ({polarized_variant(variant, True)})", "T",
                    x=angles, xlabel="incidence angle (degrees)")
    result.reference = ref.thin_pane_transmittance(angles, GLASS_IOR)
    spp = _n(settings, 4096, 65536)
    spectrace.set_variant(polarized_variant(variant, True))
    try:
        scene = _load("glass_pane", settings, ior=GLASS_IOR, radiance=1.0)
        through, through_se = luminance_along(scene, below, up, spp=spp, seed=settings.seed,
                                              max_depth=GLASS_DEPTH)
        past, past_se = luminance_along(scene, above, up, spp=spp, seed=settings.seed,
                                        max_depth=GLASS_DEPTH)
    finally:
        spectrace.set_variant(variant)
    result.measured = through / past
    result.stderr = result.measured * np.hypot(through_se / through, past_se / past)
    result.spp = spp
    return result


# -- 5.6, 5.7 diffuse reflection -----------------------------------------------------------

RHO = 0.5
REFLECTOR_HALF = 1.0
LIGHT_INTENSITY, LIGHT_HEIGHT = 1e9, 1000.0  # cd, m: E1 = 1000 lx on the reflector
PLANE_HEIGHT = 1.0
OBSTRUCTION_HALF, OBSTRUCTION_HEIGHT = 0.4, 0.5


def _square(cx, cz, half):
    return (cx - half, cx + half, cz - half, cz + half)


def _intersect(a, b):
    r = (max(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), min(a[3], b[3]))
    return r if r[0] < r[1] and r[2] < r[3] else None


def _factor(p, rect):
    if rect is None:
        return 0.0
    x0, x1, z0, z1 = rect
    vertices = np.array([[x0, 0, z0], [x1, 0, z0], [x1, 0, z1], [x0, 0, z1]], float)
    return float(ref.polygon_irradiance_factor(p, [0.0, -1.0, 0.0], vertices)[0])


def reflected_illuminance(points, obstructed: bool):
    """E = rho E1 F(visible lit part of the reflector) at points of the plane y = h facing
    down; with the obstruction, the lit part loses its shadow S (the obstruction's
    projection from the light) and the visible part loses H (its projection from the
    point): F(R \\ (S u H)) = F(R) - F(R n S) - F(R n H) + F(R n S n H)."""
    E1 = LIGHT_INTENSITY / LIGHT_HEIGHT**2
    R = _square(0.0, 0.0, REFLECTOR_HALF)
    out = []
    for p in np.atleast_2d(points):
        F = _factor(p, R)
        if obstructed:
            k_light = LIGHT_HEIGHT / (LIGHT_HEIGHT - OBSTRUCTION_HEIGHT)
            S = _intersect(R, _square(0.0, 0.0, OBSTRUCTION_HALF * k_light))
            k = p[1] / (p[1] - OBSTRUCTION_HEIGHT)
            Hd = _intersect(R, _square(p[0] * (1 - k), p[2] * (1 - k), OBSTRUCTION_HALF * k))
            both = _intersect(S, Hd) if S is not None and Hd is not None else None
            F -= _factor(p, S) + _factor(p, Hd) - _factor(p, both)
        out.append(RHO * E1 * F)
    return np.array(out)


def _reflection(settings, name, title, obstructed):
    n = _n(settings, 4, 9)
    x, z = _grid(-1.5, 1.5, -1.5, 1.5, n)
    points = np.stack([x, np.full_like(x, PLANE_HEIGHT), z], axis=-1)
    normals = np.broadcast_to([0.0, -1.0, 0.0], points.shape)
    result = Result(name, "reflection", title, "E (lx)", x=np.arange(len(points)))
    result.reference = reflected_illuminance(points, obstructed)
    scene = _load("diffuse_reflection", settings, rho=RHO, half_size=REFLECTOR_HALF,
                  intensity=LIGHT_INTENSITY, light_height=LIGHT_HEIGHT,
                  plane_height=PLANE_HEIGHT, obstruction=OBSTRUCTION_HALF,
                  obstruction_height=OBSTRUCTION_HEIGHT if obstructed else -100.0)
    return _measure(result, scene, points, normals, _n(settings, 1 << 15, 1 << 20), settings,
                    max_depth=2)


def diffuse_reflection(settings: Settings) -> Result:
    """Light reflected by a Lambertian square onto a parallel plane: E = rho E1 F."""
    return _reflection(settings, "diffuse_reflection", "Lambertian reflector, parallel plane",
                       False)


def diffuse_reflection_obstructed(settings: Settings) -> Result:
    """The same with a black square between: configuration-factor algebra of the parts of
    the reflector that are lit and seen."""
    return _reflection(settings, "diffuse_reflection_obstructed",
                       "Lambertian reflector behind an obstruction", True)


# -- 5.8 internal reflected component ----------------------------------------------------

SPHERE_RADIUS, SPHERE_FLUX = 1.0, 1000.0
SPHERE_LIGHT = (0.3, 0.2, -0.1)


def fibonacci_sphere(n: int, radius: float) -> np.ndarray:
    """``n`` nearly uniform points on a sphere (the Fibonacci lattice)."""
    k = np.arange(n) + 0.5
    y = 1.0 - 2.0 * k / n
    phi = np.pi * (1.0 + 5.0**0.5) * k
    r = np.sqrt(1.0 - y**2)
    return radius * np.stack([r * np.cos(phi), y, r * np.sin(phi)], axis=-1)


def integrating_sphere(settings: Settings) -> Result:
    """A point source inside a Lambertian sphere: E = I cos / d^2 + Phi rho / (S (1 - rho))
    at every point of the wall (all interreflections)."""
    points = fibonacci_sphere(_n(settings, 32, 128), SPHERE_RADIUS)
    normals = -points / SPHERE_RADIUS
    result = Result("integrating_sphere", "interreflection", "integrating sphere, rho = 0.5",
                    "E (lx)", x=np.arange(len(points)))
    direct = ref.point_illuminance(points, normals, SPHERE_LIGHT, SPHERE_FLUX / (4 * np.pi))
    result.reference = direct + ref.sphere_indirect_illuminance(SPHERE_FLUX, SPHERE_RADIUS,
                                                                RHO)
    scene = _load("integrating_sphere", settings, radius=SPHERE_RADIUS, rho=RHO,
                  flux=SPHERE_FLUX, lx=SPHERE_LIGHT[0], ly=SPHERE_LIGHT[1], lz=SPHERE_LIGHT[2])
    return _measure(result, scene, points, normals, _n(settings, 256, 4096), settings,
                    max_depth=-1)


# -- 5.9 - 5.14 daylight ------------------------------------------------------------------

ZENITH_LUMINANCE = 1000.0  # cd/m^2
ROOF_OPENING = (-0.5, 0.5, -1.0, 1.0)  # x0, x1, z0, z1 at y = 3 (daylight_roof.xml)
WINDOW = (-1.0, 1.0, 0.9, 2.4)  # x0, x1, y0, y1 at z = 2 (daylight_facade.xml)
ROOM_HEIGHT, ROOM_HALF = 3.0, 2.0
SKIES = {"uniform": lambda sin_h: np.full_like(sin_h, ZENITH_LUMINANCE),
         "cie_overcast": lambda sin_h: ref.cie_overcast_luminance(sin_h, ZENITH_LUMINANCE)}


def _opening(where: str):
    """(corner, edge_a, edge_b) of the roof opening or the window."""
    if where == "roof":
        x0, x1, z0, z1 = ROOF_OPENING
        return [x0, ROOM_HEIGHT, z0], [x1 - x0, 0, 0], [0, 0, z1 - z0]
    x0, x1, y0, y1 = WINDOW
    return [x0, y0, ROOM_HALF], [x1 - x0, 0, 0], [0, y1 - y0, 0]


#: The external masks of daylight_masks.xml: an overhang over the window and two fins.
MASKS = (([-1.5, 2.4, 2.0], [3.0, 0.0, 0.0], [0.0, 0.0, 0.8]),
         ([-1.0, 0.9, 2.0], [0.0, 1.5, 0.0], [0.0, 0.0, 0.6]),
         ([1.0, 0.9, 2.0], [0.0, 1.5, 0.0], [0.0, 0.0, 0.6]))


def _daylight(settings, name, where, sky, title, masks=False):
    n = _n(settings, 3, 7)
    x, z = _grid(-1.6, 1.6, -1.6, 1.6, n)
    points = np.stack([x, np.zeros_like(x), z], axis=-1)
    normals = np.broadcast_to([0.0, 1.0, 0.0], points.shape)
    result = Result(name, "daylight", title, "E (lx)", x=np.arange(len(points)))
    if masks:
        result.reference = ref.sky_opening_illuminance(points, normals, *_opening(where),
                                                        SKIES[sky], masks=MASKS, n=160)
    elif sky == "uniform":  # a closed form: pi L F of the opening's polygon
        corner, a, b = (np.asarray(v, float) for v in _opening(where))
        polygon = np.array([corner, corner + a, corner + a + b, corner + b])
        result.reference = np.pi * ZENITH_LUMINANCE * ref.polygon_irradiance_factor(
            points, normals, polygon)
    else:
        result.reference = ref.sky_opening_illuminance(points, normals, *_opening(where),
                                                        SKIES[sky])
    scene = _load("daylight_masks" if masks else f"daylight_{where}", settings, sky_type=sky,
                  zenith_luminance=ZENITH_LUMINANCE)
    return _measure(result, scene, points, normals, _n(settings, 1 << 18, 1 << 20), settings)


def daylight_roof_uniform(settings: Settings) -> Result:
    """Sky component through a roof opening under the uniform sky: E = pi L F."""
    return _daylight(settings, "daylight_roof_uniform", "roof", "uniform",
                     "roof opening, uniform sky")


def daylight_roof_overcast(settings: Settings) -> Result:
    """Sky component through a roof opening under the CIE overcast sky: the integral of
    L(h) cos cos / r^2 over the opening."""
    return _daylight(settings, "daylight_roof_overcast", "roof", "cie_overcast",
                     "roof opening, CIE overcast sky")


def daylight_facade_uniform(settings: Settings) -> Result:
    """Sky component through a facade window under the uniform sky: E = pi L F."""
    return _daylight(settings, "daylight_facade_uniform", "facade", "uniform",
                     "facade window, uniform sky")


def daylight_facade_overcast(settings: Settings) -> Result:
    """Sky component through a facade window under the CIE overcast sky."""
    return _daylight(settings, "daylight_facade_overcast", "facade", "cie_overcast",
                     "facade window, CIE overcast sky")


def daylight_masks_overcast(settings: Settings) -> Result:
    """Sky component through the facade window behind an overhang and two fins under the
    CIE overcast sky: the integral over the window of what the masks leave visible."""
    return _daylight(settings, "daylight_masks_overcast", "facade", "cie_overcast",
                     "facade window with overhang and fins, CIE overcast sky", masks=True)


#: Every case, by name, in the order of CIE 171's families.
CASES: dict[str, Callable[[Settings], Result]] = {
    "point_horizontal": point_horizontal,
    "point_vertical": point_vertical,
    "point_tilted": point_tilted,
    "point_asymmetric": point_asymmetric,
    "area_rectangle_parallel": area_rectangle_parallel,
    "area_rectangle_perpendicular": area_rectangle_perpendicular,
    "area_disk_parallel": area_disk_parallel,
    "area_sphere": area_sphere,
    "flux_closed_room": flux_closed_room,
    "glass_transmittance": glass_transmittance,
    "diffuse_reflection": diffuse_reflection,
    "diffuse_reflection_obstructed": diffuse_reflection_obstructed,
    "integrating_sphere": integrating_sphere,
    "daylight_roof_uniform": daylight_roof_uniform,
    "daylight_roof_overcast": daylight_roof_overcast,
    "daylight_facade_uniform": daylight_facade_uniform,
    "daylight_facade_overcast": daylight_facade_overcast,
    "daylight_masks_overcast": daylight_masks_overcast,
}
