"""Phong against energy-conserving BSDFs: the study of ``notebooks/phong_vs_energy.ipynb``.

:func:`albedo_curves`: directional albedo (white furnace, :mod:`spectrace.furnace`) of a
family of BSDFs (:data:`ENERGY_FAMILIES`) over incident angles; :func:`bounce_series`:
the brightness of a closed box lined with one BSDF as the path length grows (it converges
when the albedo is below 1 and diverges when the BSDF creates energy);
:func:`sphere_grid_scene`: spheres of each family across exponents, in a white furnace or
under a point light, measured sphere by sphere with :func:`shape_labels`,
:func:`grid_position` and :func:`label_means`.

An exponent m is matched to a Beckmann roughness alpha = sqrt(2 / (m + 2)) (Walter,
Marschner, Li, Torrance (2007), "Microfacet models for refraction through rough
surfaces", EGSR). Phong (1975), "Illumination for computer generated pictures", CACM 18(6);
Lewis (1994), "Making shaders more physically plausible", Computer Graphics Forum 13(2)
(the normalized lobes).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np

from spectrace.studies import aov, budget, display, load_scene, luminance, save_figure, text_table

__all__ = ["ENERGY_FAMILIES", "albedo_curves", "beckmann_alpha", "bounce_series", "budget",
           "classic_phong_albedo_normal", "closed_box_scene", "display", "grid_position",
           "label_means", "load_scene", "luminance", "save_figure", "shape_labels",
           "sphere_grid_scene", "text_table"]


def beckmann_alpha(exponent) -> np.ndarray:
    """Beckmann roughness matching a Blinn-Phong exponent: alpha = sqrt(2 / (m + 2)).

    Walter et al., "Microfacet models for refraction through rough surfaces", EGSR 2007.
    """
    return np.sqrt(2.0 / (np.asarray(exponent, np.float64) + 2.0))


#: The BSDF families of the energy study: label -> exponent m -> Mitsuba BSDF dict. The
#: Phong lobes are pure (rho = 0, rho_s = 1) so their albedo is the lobe's; roughplastic
#: is a white plastic (diffuse 1) of matching Beckmann roughness; roughconductor a perfect
#: (reflectance 1) rough mirror, the microfacet counterpart of a pure lobe.
ENERGY_FAMILIES: Mapping[str, Callable[[float], dict]] = {
    "classic Phong": lambda m: {"type": "phong", "exponent": float(m), "normalized": False,
                                "diffuse_reflectance": 0.0, "specular_reflectance": 1.0},
    "normalized Phong": lambda m: {"type": "phong", "exponent": float(m), "normalized": True,
                                   "diffuse_reflectance": 0.0, "specular_reflectance": 1.0},
    "normalized Blinn-Phong": lambda m: {"type": "blinnphong", "exponent": float(m),
                                         "normalized": True, "diffuse_reflectance": 0.0,
                                         "specular_reflectance": 1.0},
    "roughplastic (white)": lambda m: {"type": "roughplastic", "distribution": "beckmann",
                                       "alpha": float(beckmann_alpha(m)),
                                       "diffuse_reflectance": 1.0},
    "roughconductor (perfect)": lambda m: {"type": "roughconductor", "distribution": "beckmann",
                                           "alpha": float(beckmann_alpha(m)),
                                           "material": "none"},
}


def albedo_curves(exponents: Sequence[float], angles, families=None, samples: int = 1 << 16,
                  seed: int = 0) -> dict[str, np.ndarray]:
    """Directional albedo (white furnace) per family: label -> array (len(exponents), len(angles)).

    Under the active variant; the mean over channels (RGB) or wavelengths (spectral) of
    :func:`spectrace.furnace.directional_albedo` with ``samples`` per angle.
    """
    from spectrace.furnace import directional_albedo

    families = ENERGY_FAMILIES if families is None else families
    out = {}
    for label, make in families.items():
        rows = [directional_albedo(make(m), angles, samples, seed).albedo.mean(axis=1)
                for m in exponents]
        out[label] = np.asarray(rows)
    return out


def classic_phong_albedo_normal(exponent) -> np.ndarray:
    """Albedo of the classic Phong lobe (r.v)^m at normal incidence: 2 pi / (m + 2)."""
    return 2.0 * np.pi / (np.asarray(exponent, np.float64) + 2.0)


# --------------------------------------------------------------------------- renders


def sphere_grid_scene(families: Mapping[str, Callable[[float], dict]], exponents: Sequence[float],
                      res: int = 128, spp: int = 16, environment: float = 0.25,
                      light: float | None = 40.0, max_depth: int = 6) -> dict:
    """Spheres in rows (families, top to bottom) and columns (exponents, left to right).

    Lit by a uniform ``environment`` radiance and, unless ``light`` is None, a Mitsuba
    ``point`` light of that intensity (W/sr) up and to the right of the camera. With
    ``light=None`` and ``environment=1`` it is a white furnace: a sphere that conserves
    energy looks no brighter than the background. ``path`` integrator of ``max_depth``;
    orthographic camera, 1 unit per sphere cell. Shape k is row k // len(exponents).
    """
    import mitsuba as mi

    T = mi.ScalarTransform4f
    rows, cols = len(families), len(exponents)
    half = max(rows, cols) / 2
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": max_depth},
        "sensor": {
            "type": "orthographic",
            "to_world": T().look_at(origin=[0, 0, 10], target=[0, 0, 0], up=[0, 1, 0])
            @ T().scale([cols / 2, cols / 2, 1]),
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {"type": "hdrfilm", "width": res, "height": max(1, res * rows // cols),
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        },
        "environment": {"type": "constant", "radiance": {"type": "rgb", "value": environment}},
    }
    if light is not None:
        scene["light"] = {"type": "point", "position": [2.0 * half, 2.0 * half, 6.0],
                          "intensity": {"type": "rgb", "value": light}}
    for i, make in enumerate(families.values()):
        for j, m in enumerate(exponents):
            scene[f"sphere_{i}_{j}"] = {
                "type": "sphere", "radius": 0.42,
                "center": [j + 0.5 - cols / 2, rows / 2 - i - 0.5, 0.0],
                "bsdf": make(m),
            }
    return scene


def shape_labels(scene, tolerance: float = 1e-3) -> tuple[np.ndarray, np.ndarray]:
    """Which sphere-like shape each pixel sees: labels (H, W) (-1: none) and the centres.

    Label k is ``scene.shapes()[k]``, whose bounding-box centre is ``centres[k]`` (n, 3).

    A pixel belongs to shape k when its first hit (``position`` AOV) lies on the sphere
    inscribed in shape k's bounding box (within ``tolerance`` of its radius): exact for
    ``sphere`` shapes, whose hits are on that sphere (``tolerance`` is relative to the
    radius).
    """
    position = aov(scene, "position")
    labels = np.full(position.shape[:2], -1)
    centres = []
    for k, shape in enumerate(scene.shapes()):
        box = shape.bbox()
        lo, hi = np.array(box.min, np.float64).ravel(), np.array(box.max, np.float64).ravel()
        centre, radius = (lo + hi) / 2, float(np.min(hi - lo)) / 2
        on = np.abs(np.linalg.norm(position - centre, axis=-1) - radius) <= tolerance * radius
        labels[on & (labels < 0)] = k
        centres.append(centre)
    return labels, np.asarray(centres)


def grid_position(centres) -> tuple[np.ndarray, np.ndarray]:
    """Row (top to bottom, by decreasing y) and column (by increasing x) of each centre."""
    centres = np.asarray(centres, np.float64)
    ys = np.unique(np.round(centres[:, 1], 6))[::-1]
    xs = np.unique(np.round(centres[:, 0], 6))
    rows = np.searchsorted(-ys, -np.round(centres[:, 1], 6))
    cols = np.searchsorted(xs, np.round(centres[:, 0], 6))
    return rows, cols


def label_means(image, labels, count: int) -> np.ndarray:
    """Mean of ``image`` (H, W, C) over the pixels of each label 0..count-1 (NaN if none)."""
    image = np.asarray(image, np.float64)
    out = np.full((count, image.shape[-1]), np.nan)
    for k in range(count):
        mask = labels == k
        if mask.any():
            out[k] = image[mask].mean(axis=0)
    return out


def closed_box_scene(bsdf: dict, res: int = 32, spp: int = 16, max_depth: int = 2) -> dict:
    """The inside of a closed cube (side 2 m) lined with ``bsdf``, a 1 W/sr point light in it.

    Light cannot escape, so with path tracing every bounce adds the reflected light of the
    previous one: the image brightness after k bounces is a partial sum of a series whose
    ratio is (about) the walls' albedo. An energy-conserving BSDF (albedo <= 1) converges
    as max_depth grows; one reflecting more than it receives diverges. The camera (a
    pinhole at the centre, fov 90 degrees) looks at a wall; ``rr_depth`` is set past
    ``max_depth`` so that Russian roulette does not add noise.
    """
    import mitsuba as mi

    T = mi.ScalarTransform4f
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": max_depth, "rr_depth": max_depth + 1},
        "sensor": {
            "type": "perspective", "fov": 90.0,
            "to_world": T().look_at(origin=[0, 0, 0], target=[0, 0, -1], up=[0, 1, 0]),
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {"type": "hdrfilm", "width": res, "height": res,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        },
        "box": {"type": "cube", "flip_normals": True, "bsdf": bsdf},
        "light": {"type": "point", "position": [0.3, 0.5, 0.2],
                  "intensity": {"type": "rgb", "value": 1.0}},
    }


def bounce_series(bsdf: dict, depths: Sequence[int], res: int = 32, spp: int = 16,
                  seed: int = 0) -> np.ndarray:
    """Mean luminance of :func:`closed_box_scene` for each ``max_depth`` in ``depths``."""
    import mitsuba as mi

    import spectrace

    out = []
    for depth in depths:
        scene = mi.load_dict(closed_box_scene(bsdf, res, spp, depth))
        out.append(luminance(spectrace.render(scene, spp=spp, seed=seed).image).mean())
    return np.asarray(out)
