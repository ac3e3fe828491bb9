"""Measuring a loaded scene at given points, the way a lighting program reports them.

Each point is measured by rays that arrive at it along the reverse of its normal, from just
in front of it: the scene's ``illuminance`` integrator then measures the surface (or the
integrator's virtual work plane) exactly at that point with that normal, and a radiance
integrator returns the radiance arriving at the point from the direction of its normal.
The rays go to the integrator's ``sample`` method directly (no sensor, no pixel
footprint), ``spp`` rays per point with an ``independent`` sampler; the standard error of
each point's mean comes from the spread of its samples.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from spectrace.errors import ParameterError

#: Distance in front of a point from which its rays start (m): small against every case's
#: geometry, large against float32 rounding of the hit point.
RAY_OFFSET = 1e-3
#: In-plane shift (m) of a point whose rays missed its surface: a ray that meets a mesh
#: exactly on an edge shared by two triangles can pass between them (the diagonal of a
#: face, where symmetric grids of points put some of theirs).
EDGE_NUDGE = 1e-5
#: Most rays traced in one launch (memory stays below a few hundred MB).
MAX_RAYS_PER_LAUNCH = 1 << 22


@dataclass(frozen=True)
class Measurement:
    """Mean and standard error of the mean at each point."""

    value: np.ndarray
    stderr: np.ndarray


def _vector(cls, array, index):
    import drjit as dr
    import mitsuba as mi

    columns = [mi.Float(np.ascontiguousarray(array[:, k], np.float32)) for k in range(3)]
    return dr.gather(cls, cls(*columns), index)


def _trace(scene, integrator, origins, directions, spp, seed, kind):
    import drjit as dr
    import mitsuba as mi

    n = len(origins)
    index = dr.arange(mi.UInt32, n * spp) // spp
    o = _vector(mi.Point3f, origins, index)
    d = _vector(mi.Vector3f, directions, index)
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(seed, n * spp)
    ray = mi.RayDifferential3f(o, d)
    if kind == "illuminance":  # a surface or plane farther than the point is not it
        ray.maxt = 2.0 * RAY_OFFSET
    if mi.is_spectral:  # equal-energy wavelengths over the visible range
        u = sampler.next_1d()
        count = dr.size_v(mi.Spectrum)
        ray.wavelengths = type(ray.wavelengths)(
            *[400.0 + 300.0 * ((u + k / count) - dr.floor(u + k / count)) for k in range(count)]
        )
    spec, valid, aovs = integrator.sample(scene, sampler, ray, None, mi.Bool(True))
    if kind == "illuminance":
        if not aovs:
            raise ParameterError("measure: the scene's integrator must be 'illuminance' for "
                                 "illuminance points")
        values, measured = aovs[0], aovs[1] > 0.5
    else:
        spec = mi.unpolarized_spectrum(spec)
        values = dr.mean(spec) if dr.size_v(mi.Spectrum) != 1 else spec[0]
        measured = mi.Bool(valid) | True
    dr.eval(values, measured)
    values = np.asarray(values, np.float64).reshape(n, spp)
    measured = np.asarray(measured, bool).reshape(n, spp)
    return values, measured


def _tangent(normals):
    """A unit vector perpendicular to each normal."""
    helper = np.where(np.abs(normals[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    t = np.cross(normals, helper)
    return t / np.linalg.norm(t, axis=-1, keepdims=True)


def measure(scene, points, normals, *, spp: int, seed: int = 0, kind: str = "illuminance",
            integrator=None) -> Measurement:
    """Illuminance (lux, ``kind="illuminance"``: the scene's ``illuminance`` integrator) or
    the radiance arriving along each normal (``kind="radiance"``, averaged over the colour
    channels or, in spectral variants, over wavelengths drawn evenly in 400-700 nm: for
    spectrally flat scenes) at ``points`` (N, 3) with unit ``normals`` (N, 3)."""
    points = np.atleast_2d(np.asarray(points, np.float64))
    normals = np.atleast_2d(np.asarray(normals, np.float64))
    if points.shape != normals.shape or points.shape[-1] != 3:
        raise ParameterError(f"measure: points and normals must both be (N, 3) arrays (got "
                             f"{points.shape} and {normals.shape})")
    if not (isinstance(spp, int) and spp >= 2):
        raise ParameterError(f"measure: spp must be an integer >= 2 (got {spp!r})")
    normals = normals / np.linalg.norm(normals, axis=-1, keepdims=True)
    integrator = scene.integrator() if integrator is None else integrator
    origins = points + RAY_OFFSET * normals
    per_launch = max(1, MAX_RAYS_PER_LAUNCH // spp)
    means, errors = [], []
    for k, start in enumerate(range(0, len(points), per_launch)):
        part = slice(start, start + per_launch)
        values, measured = _trace(scene, integrator, origins[part], -normals[part], spp,
                                  seed * 7919 + k, kind)
        missed = ~measured.all(axis=1)
        if missed.any():  # again, nudged off the edge they may lie on
            nudged = origins[part][missed] + EDGE_NUDGE * _tangent(normals[part][missed])
            values[missed], measured[missed] = _trace(
                scene, integrator, nudged, -normals[part][missed], spp, seed * 7919 + k, kind)
        if not measured.all():
            bad = points[part][~measured.all(axis=1)][0]
            raise ParameterError(
                f"measure: the point {tuple(round(float(c), 4) for c in bad)} is not on a "
                "measured surface or work plane")
        means.append(values.mean(axis=1))
        errors.append(values.std(axis=1, ddof=1) / np.sqrt(spp))
    return Measurement(np.concatenate(means), np.concatenate(errors))
