"""Scenes and oracles shared by the tests of ``pointlight``, ``spotlight`` and their falloff
laws (a plain module).

The radiometric set-up: a diffuse plane y = 0 of albedo RHO, seen straight from above by an
orthographic camera, with one sample per pixel exactly at the pixel centre (``stratified``
sampler without jitter, box filter) and the ``direct`` integrator. A light at ``p_light``
then gives every pixel the radiance

    L = RHO / pi * I(direction) * falloff(r) * cos(theta),   cos(theta) = (p_light.y) / r,

at the point p seen through the pixel (r = |p_light - p|); the points come from Mitsuba's
``aov`` integrator (position AOV) with the same sensor and sampler.

In spectral variants the film's conversion of a sampled spectrum to RGB has its own
wavelength noise, so the tests also compare against Mitsuba's built-in ``point`` light
rendered with the same seed: the two images then differ by exactly the factor
I(direction)/I0 * falloff(r) * r^2 at every pixel, whatever the wavelengths drawn.
"""

from __future__ import annotations

import numpy as np

#: Film side in pixels and plane albedo.
RES = 32
RHO = 0.5
#: Half-width of the orthographic view of the plane (scene units).
HALF_WIDTH = 2.0
#: Relative tolerance of a float32 render against a float64 formula.
RTOL_RENDER = 2e-4
#: Absolute tolerance, relative to the brightest pixel, for pixels that must be dark.
ATOL_RENDER = 1e-6


def transform():
    import mitsuba as mi

    return mi.ScalarTransform4f()


def uniform(value: float) -> dict:
    """A spectrum equal to ``value`` at every wavelength (a plain float is not, in spectral
    variants: Mitsuba turns an emissive float into an illuminant-shaped spectrum)."""
    return {"type": "uniform", "value": value}


def plane_scene(light: dict, integrator: str | dict = "direct", spp: int = 1,
                sensor: str = "orthographic", res: int = RES) -> dict:
    """A diffuse plane y = 0 under ``light`` and above nothing, seen from +y."""
    T = transform()
    if sensor == "orthographic":
        sensor_dict = {
            "type": "orthographic",
            "to_world": T.look_at([0, 8, 0], [0, 0, 0], [0, 0, 1]).scale(
                [HALF_WIDTH, HALF_WIDTH, 1]),
        }
    else:
        sensor_dict = {
            "type": "perspective",
            "fov": 60,
            "to_world": T.look_at([0, 4, 0.01], [0, 0, 0], [0, 1, 0]),
        }
    if spp == 1:
        sampler = {"type": "stratified", "sample_count": 1, "jitter": False}
    else:
        sampler = {"type": "independent", "sample_count": spp}
    sensor_dict["film"] = {"type": "hdrfilm", "width": res, "height": res,
                           "rfilter": {"type": "box"}}
    sensor_dict["sampler"] = sampler
    if isinstance(integrator, str):
        integrator = {"type": integrator}
    return {
        "type": "scene",
        "integrator": integrator,
        "sensor": sensor_dict,
        "plane": {
            "type": "rectangle",
            "to_world": T.rotate([1, 0, 0], -90).scale(10),
            "bsdf": {"type": "diffuse", "reflectance": {"type": "uniform", "value": RHO}},
        },
        "light": light,
    }


def render(light: dict, integrator: str | dict = "direct", seed: int = 0, **kwargs) -> np.ndarray:
    """Render the plane under ``light``: an (H, W, 3) float64 array."""
    import mitsuba as mi

    scene = mi.load_dict(plane_scene(light, integrator, **kwargs))
    return np.array(mi.render(scene, seed=seed), dtype=np.float64)[..., :3]


def positions(res: int = RES) -> np.ndarray:
    """World positions seen at the pixel centres, (H, W, 3), from Mitsuba's ``aov``."""
    light = {"type": "point", "position": [0, 1, 0]}
    return render(light, {"type": "aov", "aovs": "p:position"}, res=res)


def builtin_point(position, intensity: float, **kwargs) -> np.ndarray:
    """The plane under Mitsuba's ``point`` light (the oracle of the 1/r^2 law)."""
    return render({"type": "point", "position": list(position), "intensity": intensity},
                  **kwargs)


def closed_form(p: np.ndarray, p_light, directional) -> np.ndarray:
    """RHO/pi * I(direction) * falloff(r) * cos(theta) per pixel, (H, W).

    ``directional(d, r)`` gives I(direction) * falloff(r) for the unit directions d from the
    light to the points (..., 3) and the distances r.
    """
    v = p - np.asarray(p_light, dtype=np.float64)
    r = np.linalg.norm(v, axis=-1)
    d = v / r[..., None]
    cos_theta = -d[..., 1]
    return RHO / np.pi * directional(d, r) * cos_theta


def assert_image_close(image: np.ndarray, expected: np.ndarray, rtol: float = RTOL_RENDER):
    """Every pixel and channel of ``image`` equals ``expected`` (broadcast over channels)."""
    if expected.ndim == image.ndim - 1:
        expected = np.repeat(expected[..., None], image.shape[-1], axis=-1)
    atol = ATOL_RENDER * float(np.max(np.abs(expected))) + 1e-30
    np.testing.assert_allclose(image, expected, rtol=rtol, atol=atol)


def wavelength_grid(n: int):
    """A SurfaceInteraction3f of n lanes at rest with wavelengths on a 1 nm grid in spectral
    variants (and nothing to set in RGB ones)."""
    import drjit as dr
    import mitsuba as mi

    si = dr.zeros(mi.SurfaceInteraction3f, n)
    if mi.is_spectral:
        w = dr.linspace(mi.Float, 400.0, 700.0, n)
        si.wavelengths = mi.Spectrum(w, w, w, w)
    return si


def eval_intensity(emitter, directions: np.ndarray, distance: float = 1.0) -> np.ndarray:
    """``emitter.eval_direction`` from points at ``distance`` along the unit ``directions``
    (N, 3) leaving the emitter at ``origin``: (N, channels) float64."""
    import drjit as dr
    import mitsuba as mi

    origin = np.array(dr.slice(emitter_position(emitter)))
    n = directions.shape[0]
    it = wavelength_grid(n)
    points = origin[None, :] + distance * directions
    it.p = mi.Point3f(*(points[:, i].astype(np.float32) for i in range(3)))
    ds = dr.zeros(mi.DirectionSample3f, n)
    ds.p = mi.Point3f(*(float(c) for c in origin))
    ds.d = mi.Vector3f(*(-directions[:, i].astype(np.float32) for i in range(3)))
    ds.dist = mi.Float(distance)
    value = emitter.eval_direction(mi.Interaction3f(it), ds)
    return np.array(value, dtype=np.float64).T.reshape(n, -1)


def emitter_position(emitter):
    import mitsuba as mi

    ps, _ = emitter.sample_position(0.0, mi.Point2f(0.5))
    return ps.p


def sphere_quadrature(n_theta: int, n_phi: int):
    """Midpoint rule on the sphere: unit directions (N, 3) and solid-angle weights (N,)."""
    cos_t = 1.0 - (np.arange(n_theta) + 0.5) * (2.0 / n_theta)
    phi = (np.arange(n_phi) + 0.5) * (2.0 * np.pi / n_phi)
    cos_t, phi = np.meshgrid(cos_t, phi, indexing="ij")
    sin_t = np.sqrt(1.0 - cos_t**2)
    d = np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], axis=-1).reshape(-1, 3)
    w = np.full(d.shape[0], 4.0 * np.pi / (n_theta * n_phi))
    return d, w
