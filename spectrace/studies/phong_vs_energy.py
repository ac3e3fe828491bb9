"""Phong against energy-conserving BSDFs: the study of ``notebooks/phong_vs_energy.ipynb``.

:func:`albedo_curves`: directional albedo (white furnace, :mod:`spectrace.furnace`) of a
family of BSDFs (:data:`ENERGY_FAMILIES`) over incident angles; :func:`bounce_series`:
the brightness of a closed box (``scenes/closed_box.xml``) lined with one BSDF as the path
length grows (it converges when the albedo is below 1 and diverges when the BSDF creates
energy), the grid of BSDFs x path lengths rendered as one :func:`spectrace.sweep` on Dask;
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

from spectrace.studies import (
    aov,
    budget,
    display,
    load_scene,
    luminance,
    save_figure,
    scene_path,
    text_table,
)

__all__ = ["CLOSED_BOX", "CLOSED_BOX_BSDFS", "ENERGY_FAMILIES", "albedo_curves",
           "beckmann_alpha", "bounce_series", "budget", "classic_phong_albedo_normal",
           "closed_box_bsdf", "display", "grid_position",
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


#: The BSDF ids of ``scenes/closed_box.xml`` (its ``bsdf`` parameter) that line the box
#: with each of the :data:`ENERGY_FAMILIES` (the same BSDF at the same exponent).
CLOSED_BOX_BSDFS: Mapping[str, str] = {
    "classic Phong": "classic_phong",
    "normalized Phong": "normalized_phong",
    "normalized Blinn-Phong": "normalized_blinn_phong",
    "roughplastic (white)": "roughplastic",
    "roughconductor (perfect)": "roughconductor",
}
#: The scene of :func:`bounce_series` (``scenes/closed_box.xml``).
CLOSED_BOX = "closed_box"


def closed_box_bsdf(bsdf: str, exponent: float = 2.0, reflectance: float = 0.5):
    """The BSDF ``bsdf`` (an id of ``scenes/closed_box.xml``) that lines the closed box.

    Loaded from the scene file with ``exponent`` and its matched Beckmann roughness, as
    :func:`bounce_series` renders it (under the active variant).
    """
    scene = load_scene(CLOSED_BOX, **_box_defines(exponent, reflectance), bsdf=bsdf, res="1")
    return scene.shapes()[0].bsdf()


def _box_defines(exponent: float, reflectance: float) -> dict[str, str]:
    return {"exponent": repr(float(exponent)), "alpha": repr(float(beckmann_alpha(exponent))),
            "reflectance": repr(float(reflectance))}


def bounce_series(bsdfs: Sequence[str] | str, depths: Sequence[int], exponent: float = 2.0,
                  res: int = 32, spp: int = 16, seed: int = 0, *, reflectance: float = 0.5,
                  variant: str | None = None, client=None):
    """Mean luminance of ``scenes/closed_box.xml`` lined with each of ``bsdfs`` (ids of the
    scene, e.g. :data:`CLOSED_BOX_BSDFS` values) for each ``max_depth`` in ``depths``.

    The walls' Phong ``exponent`` m (and the matched roughness sqrt(2 / (m + 2)) of the
    microfacet BSDFs; ``reflectance`` of ``diffuse``). Rendered as one
    :func:`spectrace.sweep` over bsdf x max_depth, in ``variant`` (default: the active one)
    with ``seed``, on ``client`` (a ``distributed.Client``; None: a LocalCluster for this
    call). Returns an ``xarray.DataArray`` of dims (bsdf, max_depth) (max_depth as
    integers), in W m^-2 sr^-1 (Y); RuntimeError if an image failed. ``spp``: a power of 4
    or a multiple of 16 (passes of 16; the scene's ``ldsampler`` rounds a pass up to 4^k).
    """
    import sys

    import xarray as xr

    import spectrace

    if isinstance(bsdfs, str):
        bsdfs = [bsdfs]
    if variant is None:  # the active one (mitsuba is imported only after set_variant)
        mi = sys.modules.get("mitsuba")
        variant = (mi.variant() if mi is not None else None) or spectrace.DEFAULT_VARIANT
    fixed = {**_box_defines(exponent, reflectance), "res": str(int(res))}
    images = spectrace.sweep(scene_path(CLOSED_BOX),
                             params={"bsdf": list(bsdfs), "max_depth": [int(d) for d in depths],
                                     **fixed},
                             variants=variant, seeds=seed, spp=spp, client=client)
    if images.attrs["failed"]:
        raise RuntimeError("bounce_series: " + "; ".join(images.attrs["failed"]))
    for dim in ("bsdf", "max_depth"):  # an axis of one value is a scalar coordinate
        if dim not in images.dims:
            images = images.expand_dims(dim)
    images = images.transpose("bsdf", "max_depth", ...)
    Y = luminance(images.values).mean(axis=(-2, -1))  # (bsdf, max_depth)
    attrs = {"spp": images.attrs["spp"], "scene": images.attrs["scene"],
             "seed": int(images.seed), "variant": str(images.variant.values)}
    return xr.DataArray(Y, dims=["bsdf", "max_depth"],
                        coords={"bsdf": list(bsdfs), "max_depth": [int(d) for d in depths]},
                        attrs={**attrs, "exponent": float(exponent)}, name="mean luminance")
