"""Luminance in cd/m^2: of a camera's view (``spectrace lux --luminance``) or along given
rays (``--luminance --points``).

L_v = K_m integral V(lambda) L(lambda) dlambda of the radiance L arriving along a ray,
with the photometric convention of ``spectrace help illuminance`` (K_m = 683 lm/W, one
integral V dlambda = 106.857 nm; RGB and mono variants K_m Y(L) integral V), so that the
numbers do not pass through Mitsuba's film and its own normalisation (106.750 nm). L
comes from Mitsuba's ``path`` integrator, called directly on rays whose wavelengths are
drawn from V (four stratified hero wavelengths); ``max_depth`` counts as in ``lux``: 1 is
the direct light on the surfaces seen (``path``'s max_depth 2), K > 1 adds K - 1
reflections, -1 no limit. Emitters seen directly (area lights, environments) are
included: what a luminance camera sees.

:func:`luminance_image` renders the scene's sensor pixel by pixel (uniform jitter in each
pixel, the mean over ``spp`` samples) and returns the per-pixel directions and solid
angles that glare ratings need (:mod:`~spectrace.lighting.glare`): the pixel's solid
angle is that of the spherical quadrilateral of its four corner rays (two triangles,
Van Oosterom and Strackee 1983), exact for any central projection (perspective, and
Mitsuba's other pinhole cameras).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from spectrace.errors import ParameterError

__all__ = ["LuminanceImage", "luminance_along", "luminance_image", "write_luminance_exr",
           "path_depth"]

#: At most this many lanes (rays x samples) per Dr.Jit evaluation.
MAX_LANES = 1 << 21


def path_depth(max_depth: int) -> int:
    """Mitsuba ``path``'s max_depth for a luminance of ``max_depth`` (as in ``lux``)."""
    if max_depth == 0 or max_depth < -1:
        raise ParameterError(f"max_depth must be >= 1, or -1 for no limit (got {max_depth})")
    return -1 if max_depth == -1 else max_depth + 1


def _path(max_depth: int):
    import mitsuba as mi

    return mi.load_dict({"type": "path", "max_depth": path_depth(max_depth)})


def _luminance(integrator, scene, sampler, ray_o, ray_d, active):
    """K_m integral V L along the rays, wavelengths drawn from V."""
    import drjit as dr
    import mitsuba as mi

    from spectrace.plugins.emitters import luminous

    wavelengths = mi.Color0f()
    if mi.is_spectral:
        V = luminous.photopic_spectrum()
        si = dr.zeros(mi.SurfaceInteraction3f)
        wavelengths, _ = V.sample_spectrum(si, mi.sample_shifted(sampler.next_1d(active)),
                                           active)
    ray = mi.RayDifferential3f(mi.Ray3f(ray_o, ray_d, 0.0, wavelengths))
    L, _, _ = integrator.sample(scene, sampler, ray, None, active)
    value = luminous.illuminance_lux(L, luminous.v_integral())
    return dr.select(dr.isfinite(value), value, 0.0)


def _accumulate(count: int, spp: int, seed: int, evaluate):
    """Mean and standard error over ``spp`` samples of ``evaluate(sampler, k)`` -> (k,
    count) values, in passes of at most MAX_LANES lanes."""
    import mitsuba as mi

    from spectrace.lighting.points import pass_seed, sample_statistics

    per_pass = max(1, min(spp, MAX_LANES // max(count, 1)))
    total, total_sq = np.zeros(count), np.zeros(count)
    sampler = mi.load_dict({"type": "independent"})
    done = 0
    while done < spp:
        k = min(per_pass, spp - done)
        sampler.seed(pass_seed(seed, done), count * k)
        values = evaluate(sampler, k)
        total += values.sum(axis=0)
        total_sq += (values**2).sum(axis=0)
        done += k
    return sample_statistics(total, total_sq, spp, False)


def luminance_along(scene, origins, directions, *, spp: int = 64, seed: int = 0,
                    max_depth: int = 1):
    """(luminance cd/m^2, standard error) (N,) of the light arriving at ``origins`` (N, 3)
    from the view ``directions`` (N, 3) (the radiance travelling against them)."""
    import drjit as dr
    import mitsuba as mi

    from spectrace.plugins.arrays import host_array

    o = np.asarray(origins, dtype=np.float64).reshape(-1, 3)
    d = np.asarray(directions, dtype=np.float64).reshape(-1, 3)
    length = np.linalg.norm(d, axis=1)
    if not np.all(length > 0.0):
        raise ParameterError(f"view directions: point {int(np.argmin(length)) + 1} has a zero "
                             "direction")
    d = d / length[:, None]
    integrator = _path(max_depth)

    def evaluate(sampler, k):
        ray_o = mi.Point3f(*(mi.Float(host_array(np.tile(o[:, i], k))) for i in range(3)))
        ray_d = mi.Vector3f(*(mi.Float(host_array(np.tile(d[:, i], k))) for i in range(3)))
        active = dr.full(mi.Bool, True, len(o) * k)
        value = _luminance(integrator, scene, sampler, ray_o, ray_d, active)
        return np.asarray(value, dtype=np.float64).reshape(k, len(o))

    return _accumulate(len(o), spp, seed, evaluate)


@dataclass
class LuminanceImage:
    """A camera's luminance (H, W) in cd/m^2, with the geometry of its pixels."""

    Y: np.ndarray  # (H, W) cd/m^2
    stderr: np.ndarray  # (H, W)
    directions: np.ndarray  # (H, W, 3) unit view directions of the pixel centres
    solid_angle: np.ndarray  # (H, W) sr
    origin: np.ndarray  # (3,) the eye
    forward: np.ndarray  # (3,) the line of sight (the ray through the film's centre)
    spp: int


def _camera_rays(sensor, u: np.ndarray, v: np.ndarray):
    """Origins and directions (N, 3) of the sensor's rays through film positions (u, v)
    in [0, 1]^2 (no jitter of the aperture: a pinhole's rays)."""
    import mitsuba as mi

    ray, _ = sensor.sample_ray(0.0, 0.5, mi.Point2f(u.astype(np.float32), v.astype(np.float32)),
                               mi.Point2f(0.5))
    return np.asarray(ray.o, dtype=np.float64).T, np.asarray(ray.d, dtype=np.float64).T


def line_of_sight(sensor) -> np.ndarray:
    """The direction of the sensor's ray through the film's centre."""
    _, forward = _camera_rays(sensor, np.array([0.5]), np.array([0.5]))
    return forward[0]


def _triangle_solid_angle(a, b, c):
    """Solid angle of the spherical triangles of unit vectors a, b, c (..., 3)
    (Van Oosterom and Strackee 1983)."""
    numerator = np.abs(np.einsum("...i,...i", a, np.cross(b, c)))
    denominator = 1.0 + np.einsum("...i,...i", a, b) + np.einsum("...i,...i", b, c) + \
        np.einsum("...i,...i", c, a)
    return 2.0 * np.arctan2(numerator, denominator)


def pixel_geometry(sensor):
    """(origin (3,), forward (3,), directions (H, W, 3), solid angles (H, W)) of the
    sensor's pixels (see the module docstring)."""
    width, height = (int(v) for v in sensor.film().size())
    uc, vc = np.meshgrid((np.arange(width) + 0.5) / width, (np.arange(height) + 0.5) / height)
    origins, d = _camera_rays(sensor, uc.ravel(), vc.ravel())
    uk, vk = np.meshgrid(np.arange(width + 1) / width, np.arange(height + 1) / height)
    _, corners = _camera_rays(sensor, uk.ravel(), vk.ravel())
    corners = corners.reshape(height + 1, width + 1, 3)
    a, b = corners[:-1, :-1], corners[:-1, 1:]
    c, e = corners[1:, 1:], corners[1:, :-1]
    omega = _triangle_solid_angle(a, b, c) + _triangle_solid_angle(a, c, e)
    return origins[0], line_of_sight(sensor), d.reshape(height, width, 3), omega


def luminance_image(scene, *, spp: int = 16, seed: int = 0, max_depth: int = 1,
                    sensor=0) -> LuminanceImage:
    """The luminance of the sensor's view, pixel by pixel (see the module docstring)."""
    import drjit as dr
    import mitsuba as mi

    from spectrace.plugins.arrays import host_array

    camera = scene.sensors()[sensor] if isinstance(sensor, int) else sensor
    width, height = (int(v) for v in camera.film().size())
    count = width * height
    integrator = _path(max_depth)
    px, py = np.meshgrid(np.arange(width, dtype=np.float64), np.arange(height, dtype=np.float64))
    px, py = px.ravel(), py.ravel()

    def evaluate(sampler, k):
        active = dr.full(mi.Bool, True, count * k)
        jitter = sampler.next_2d(active)
        u = (mi.Float(host_array(np.tile(px, k))) + jitter.x) / width
        v = (mi.Float(host_array(np.tile(py, k))) + jitter.y) / height
        ray, _ = camera.sample_ray(0.0, 0.5, mi.Point2f(u, v), sampler.next_2d(active), active)
        value = _luminance(integrator, scene, sampler, ray.o, ray.d, active)
        return np.asarray(value, dtype=np.float64).reshape(k, count)

    Y, stderr = _accumulate(count, spp, seed, evaluate)
    origin, forward, directions, omega = pixel_geometry(camera)
    return LuminanceImage(Y.reshape(height, width), stderr.reshape(height, width), directions,
                          omega, origin, forward, spp)


def write_luminance_exr(path, image: LuminanceImage, header: dict | None = None) -> None:
    """One float32 channel ``Y`` in cd/m^2 with ``units`` and ``spp`` attributes; atomic."""
    from spectrace.images import write_exr_channels

    write_exr_channels(path, {"Y": image.Y}, {"units": "cd/m^2", "spp": int(image.spp),
                                             **(header or {})})


def as_map(image: LuminanceImage):
    """The luminance as a :class:`~spectrace.lux.LuxMap` (every pixel with data), for
    :func:`~spectrace.lux.plot_lux`."""
    from spectrace.lux import LuxMap, lux_statistics

    valid = np.ones(image.Y.shape, dtype=bool)
    Y = image.Y.astype(np.float32)
    low, mean, high, u0 = lux_statistics(Y, valid)
    return LuxMap(Y, valid, low, mean, high, u0, image.spp, 0.0)
