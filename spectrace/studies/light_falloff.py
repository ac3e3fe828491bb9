"""Light falloff: the study of ``notebooks/light_falloff.ipynb``.

Closed-form distance laws and cone falloffs (:data:`DISTANCE_LAWS`,
:data:`CONE_FALLOFFS`, written from the formulas independently of the plugins so that the
renders can be checked against them), :func:`floor_irradiance` (a light above a white
Lambertian floor seen from straight above by an orthographic camera, whose pixels give the
irradiance E = pi L / rho along the floor), the fog laws of the ``local`` integrator
(:data:`FOG_LAWS`) and :func:`fog_fraction`, which measures them on a render.

Sources: distance and cone laws as documented by the ``pointlight`` and ``spotlight``
plugins (smoothstep: Pharr, Jakob, Humphreys (2023), Physically Based Rendering 4th ed.,
sec. 12.2.1; windowed: Karis (2013), "Real shading in Unreal Engine 4", SIGGRAPH course);
fog: Segal and Akeley (2003), The OpenGL Graphics System 1.5, sec. 3.10.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from spectrace.errors import ParameterError
from spectrace.studies import aov, budget, display, load_scene, luminance, save_figure, text_table

__all__ = ["CONE_FALLOFFS", "DISTANCE_LAWS", "FLOOR_ALBEDO", "FOG_LAWS", "SUBPIXELS",
           "FloorProfile", "aov", "budget", "display", "floor_irradiance", "fog_fraction",
           "load_scene", "luminance", "save_figure", "text_table"]


def _inverse_square(r, **_):
    return 1.0 / np.square(r)


def _inverse_square_epsilon(r, epsilon=0.01, **_):
    return 1.0 / np.square(r + epsilon)


def _polynomial(r, kc=0.0, kl=0.0, kq=1.0, **_):
    return 1.0 / (kc + kl * r + kq * np.square(r))


def _windowed(r, radius=1.0, epsilon=0.01, **_):
    window = np.square(np.clip(1.0 - (r / radius) ** 4, 0.0, 1.0))
    return window / np.maximum(np.square(r), epsilon**2)


def _none(r, **_):
    return np.ones_like(np.asarray(r, np.float64))


#: Distance laws of the lights' ``falloff`` parameter (their reference pages), closed form
#: in numpy: name -> f(r, **parameters), the factor with E = I f(r) on a surface facing
#: the light.
DISTANCE_LAWS: Mapping[str, Callable[..., np.ndarray]] = {
    "inverse_square": _inverse_square,
    "inverse_square_epsilon": _inverse_square_epsilon,
    "polynomial": _polynomial,
    "windowed": _windowed,
    "none": _none,
}


def _cone_t(alpha, umbra, penumbra):
    cu, cp = np.cos(np.radians(umbra)), np.cos(np.radians(penumbra))
    return np.clip((np.cos(alpha) - cu) / (cp - cu), 0.0, 1.0)


def _quadratic(alpha, umbra, penumbra):
    return np.square(_cone_t(alpha, umbra, penumbra))


def _smoothstep(alpha, umbra, penumbra):
    t = _cone_t(alpha, umbra, penumbra)
    return t * t * (3.0 - 2.0 * t)


def _linear_angle(alpha, umbra, penumbra):
    u, p = np.radians(umbra), np.radians(penumbra)
    return np.clip((u - np.asarray(alpha, np.float64)) / (u - p), 0.0, 1.0)


#: Cone falloffs of ``spotlight`` (its reference page): name -> f(alpha in rad, umbra deg,
#: penumbra deg) in [0, 1]: 1 inside the penumbra half-angle, 0 outside the umbra half-angle.
CONE_FALLOFFS: Mapping[str, Callable[..., np.ndarray]] = {
    "quadratic": _quadratic,
    "smoothstep": _smoothstep,
    "linear_angle": _linear_angle,
}


# --------------------------------------------------------------------------- floor irradiance


@dataclass
class FloorProfile:
    """Irradiance on the floor along the line y = 0 through the light's foot point."""

    x: np.ndarray  # floor position of each pixel centre (m)
    measured: np.ndarray  # E = pi Y / rho from the render (W/m^2 per unit intensity)
    expected: np.ndarray  # I f(r) cone(alpha) cos(theta), the formula
    image: np.ndarray  # the whole render (H, W, 3), linear sRGB


#: Reflectance of the measurement floor.
FLOOR_ALBEDO = 0.5


#: Formula samples per pixel side when averaging it over a pixel's footprint.
SUBPIXELS = 8


def floor_irradiance(light: Mapping, height: float = 1.0, half_width: float = 5.0,
                     res: int = 128, spp: int = 4, cone: tuple | None = None) -> FloorProfile:
    """Render a light ``height`` m above a Lambertian floor (reflectance 0.5) from straight above.

    ``light``: the emitter's parameters besides its placement (``type`` ``pointlight``,
    ``spotlight`` or Mitsuba's ``point`` / ``spot``, a scalar ``intensity`` I, ``falloff``
    and its parameters, the cone parameters); it is put at (0, 0, height), a spot pointing
    straight down. The floor z = 0 is seen by an orthographic camera over
    [-half_width, half_width]^2 with the ``direct`` integrator, so a pixel's luminance is
    Y = rho E / pi and the measured irradiance is E = pi Y / rho. Expected along y = 0:
    E = I f(r) cone(alpha) cos(theta) with r = sqrt(x^2 + h^2), cos(theta) = h / r and
    alpha = theta for a spot (``cone`` = (name, umbra, penumbra) to include it; taken from
    ``light`` by default), averaged over each pixel's footprint. Works in RGB and spectral
    variants (Y of a constant spectrum c is c).
    """
    import mitsuba as mi

    T = mi.ScalarTransform4f
    light = dict(light)
    if light.get("type") in ("spotlight", "spot"):
        light["to_world"] = T().look_at(origin=[0, 0, height], target=[0, 0, 0], up=[0, 1, 0])
        if cone is None and light["type"] == "spotlight":
            cone = (light.get("cone_falloff", "quadratic"), light.get("umbra_angle", 30.0),
                    light.get("penumbra_angle", 20.0))
        elif cone is None:  # Mitsuba's spot: linear in the angle, beam_width = 3/4 cutoff
            cutoff = light.get("cutoff_angle", 20.0)
            cone = ("linear_angle", cutoff, light.get("beam_width", 0.75 * cutoff))
    else:
        light["position"] = [0.0, 0.0, float(height)]
    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "direct", "bsdf_samples": 0},
        "sensor": {
            "type": "orthographic",
            "to_world": T().look_at(origin=[0, 0, height + 1.0], target=[0, 0, 0], up=[0, 1, 0])
            @ T().scale([half_width, half_width, 1]),
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {"type": "hdrfilm", "width": res, "height": res,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        },
        "floor": {"type": "rectangle", "to_world": T().scale(2.0 * half_width),
                  "bsdf": {"type": "diffuse", "reflectance": FLOOR_ALBEDO}},
        "light": light,
    })
    from spectrace import render

    image = render(scene, spp=spp, seed=0).image
    Y = luminance(image)
    pixel = 2.0 * half_width / res
    rows = slice(res // 2 - 1, res // 2 + 1)  # the two pixel rows around y = 0
    measured = np.pi * Y[rows].mean(axis=0) / FLOOR_ALBEDO
    x = -half_width + (np.arange(res) + 0.5) * pixel
    # The formula averaged over each pixel's footprint (what a pixel measures), on a
    # SUBPIXELS^2 grid per pixel over the two rows y in [-pixel, pixel].
    sub = (np.arange(SUBPIXELS) + 0.5) / SUBPIXELS - 0.5
    xs = x[:, None, None] + pixel * sub[None, :, None]
    ys = 2.0 * pixel * sub[None, None, :]
    r = np.sqrt(xs**2 + ys**2 + height**2)
    cos_theta = height / r
    law = DISTANCE_LAWS[light.get("falloff", "inverse_square")]
    params = {k: float(v) for k, v in light.items()
              if k in ("epsilon", "kc", "kl", "kq", "radius")}
    expected = float(light.get("intensity", 1.0)) * law(r, **params) * cos_theta
    if cone is not None:
        name, umbra, penumbra = cone
        expected = expected * CONE_FALLOFFS[name](np.arccos(cos_theta), umbra, penumbra)
    expected = expected.mean(axis=(1, 2))
    return FloorProfile(x, measured, expected, image)


# --------------------------------------------------------------------------- fog


def _fog_none(d, start=0.0, end=1.0, density=1.0):
    return np.ones_like(np.asarray(d, np.float64))


def _fog_linear(d, start=0.0, end=1.0, density=1.0):
    return np.clip((end - np.asarray(d, np.float64)) / (end - start), 0.0, 1.0)


def _fog_exponential(d, start=0.0, end=1.0, density=1.0):
    return np.exp(-density * np.asarray(d, np.float64))


def _fog_exponential_squared(d, start=0.0, end=1.0, density=1.0):
    return np.exp(-np.square(density * np.asarray(d, np.float64)))


#: Fog laws of ``local`` (OpenGL 1.5, sec. 3.10): name -> f(d, start, end, density), the
#: fraction of a surface's radiance left at camera distance d (m).
FOG_LAWS: Mapping[str, Callable[..., np.ndarray]] = {
    "none": _fog_none,
    "linear": _fog_linear,
    "exponential": _fog_exponential,
    "exponential_squared": _fog_exponential_squared,
}


def fog_fraction(fogged, clear, depth, min_contrast: float = 0.02) -> np.ndarray:
    """f = (L - L_fog) / (L_clear - L_fog) per pixel: the fraction of surface radiance left.

    ``fogged``, ``clear``: (H, W, 3) renders with and without fog; ``depth`` (H, W) the
    ``depth`` AOV (0 where no surface is hit). The fog colour L_fog is measured as the
    mean of the fogged render where nothing is hit (the background takes the fog colour).
    Luminances are used; pixels where L_clear is within ``min_contrast`` of L_fog (f is
    ill-conditioned there), and background pixels, are NaN. Pixels on silhouettes mix
    surfaces at different distances and scatter around the law.
    """
    depth = np.asarray(depth, np.float64).reshape(np.shape(fogged)[:2])
    background = depth <= 0
    if not background.any():
        raise ParameterError("fog_fraction: no background pixel shows the fog colour")
    y_fog = luminance(np.asarray(fogged, np.float64)[background]).mean()
    num = luminance(fogged) - y_fog
    den = luminance(clear) - y_fog
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where((np.abs(den) > min_contrast) & ~background, num / den, np.nan)
