"""Library code of the study notebooks (``notebooks/*.ipynb``), one module per study.

The notebooks only plot; everything they compute comes from these modules, so that it is
tested (``tests/studies/``) and shared:

* :mod:`spectrace.studies.spectral_vs_rgb`: the ColorChecker under six lights, rendered
  spectrally and in RGB against colour-science (``spectral_vs_rgb.ipynb``);
* :mod:`spectrace.studies.phong_vs_energy`: white-furnace albedo and bounce series of
  classic and normalized Phong, Blinn-Phong and microfacet BSDFs (``phong_vs_energy.ipynb``);
* :mod:`spectrace.studies.light_falloff`: distance laws, cone falloffs and fog laws in
  closed form, and the floor-irradiance measurement (``light_falloff.ipynb``);
* :mod:`spectrace.studies.photometry`: the luminaires' polar diagrams, the room's lux map
  on the work plane against the point-by-point hand calculation, uniformity and the
  utilisation factor, the room under a warm LED spectrally and in RGB (``photometry.ipynb``).
* :mod:`spectrace.studies.pictures`: the display chain on one spectral render: gamut,
  view transforms, white balance (``pictures.ipynb``).
* :mod:`spectrace.studies.light_compositing`: one layer per luminaire from one render,
  superposition, light scenes and new lamp spectra by relighting
  (``light_compositing.ipynb``).
* :mod:`spectrace.studies.near_field`: the point approximation's error near lights with a
  size, umbra and penumbra, shadow-sample noise (``near_field.ipynb``).

This package module holds what two or more studies share: the size :func:`budget` (the
environment variable ``SPECTRACE_QUICK=1`` shrinks resolutions and sample counts, what
the notebook tests set), the example scenes (:func:`scene_path`, :func:`load_scene`,
found through :mod:`spectrace.scenes`, so they work from a wheel), display and table
helpers (:func:`display`, :func:`text_table`), :func:`luminance`, single-hit AOVs
(:func:`aov`) and :func:`save_figure` (a notebook's key figures for the README's gallery,
written only when ``make gallery`` sets ``SPECTRACE_GALLERY``). A notebook imports its
study, e.g. ``from spectrace.studies import light_falloff as study``; each study module
also offers the shared helpers it uses under its own name (``study.budget``,
``study.display``).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from spectrace import spectral

#: Environment variable: "1" renders the notebooks at test size.
QUICK_ENV = "SPECTRACE_QUICK"
#: Environment variable: a folder where the notebooks save their key figures
#: (``make gallery`` sets it to ``docs/gallery``); unset, :func:`save_figure` writes nothing.
GALLERY_ENV = "SPECTRACE_GALLERY"
#: Width of a saved gallery figure (pixels).
GALLERY_FIGURE_WIDTH = 800

__all__ = ["GALLERY_ENV", "GALLERY_FIGURE_WIDTH", "QUICK_ENV", "aov", "box_filtered_sensor",
           "budget", "display", "load_scene", "luminance", "quick", "save_figure", "scene_path",
           "text_table"]


def quick() -> bool:
    """Whether the notebooks should render at test size (``SPECTRACE_QUICK=1``)."""
    return os.environ.get(QUICK_ENV, "") == "1"


def budget(normal: int, small: int) -> int:
    """``small`` when :func:`quick`, else ``normal``: resolutions and sample counts."""
    return small if quick() else normal


def save_figure(fig, name: str) -> Path | None:
    """Save a matplotlib figure as ``<name>.png`` in the folder ``$SPECTRACE_GALLERY``.

    What the notebooks call on their key figures: nothing is written (None is returned)
    unless the environment variable is set, as ``make gallery`` does. The PNG is
    :data:`GALLERY_FIGURE_WIDTH` pixels wide, written atomically; the folder must exist.
    """
    folder = os.environ.get(GALLERY_ENV, "")
    if not folder:
        return None
    from spectrace.images import atomic_path

    path = Path(folder) / f"{name}.png"
    width_inches = fig.get_size_inches()[0]
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=GALLERY_FIGURE_WIDTH / width_inches, format="png")
    return path


def scene_path(name: str) -> Path:
    """Path of ``scenes/<name>`` (``.xml`` added when missing); FileNotFoundError if absent."""
    from spectrace import scenes

    path = scenes.path(name)
    if not path.is_file():
        raise FileNotFoundError(f"no scene {path}")
    return path


def display(linear) -> np.ndarray:
    """Encoded sRGB of a linear sRGB image, clipped to [0, 1] first (what imshow shows)."""
    return spectral.encode_srgb(np.clip(np.asarray(linear, np.float64), 0.0, 1.0))


def luminance(linear) -> np.ndarray:
    """Y (CIE 1931) of linear sRGB values: the Y row of the sRGB matrix."""
    return spectral.linear_srgb_to_xyz(np.asarray(linear, np.float64))[..., 1]


def text_table(header: Sequence[str], rows: Sequence[Sequence]) -> str:
    """A plain-text table: columns right-aligned (numbers formatted by the caller)."""
    cells = [list(map(str, header))] + [list(map(str, r)) for r in rows]
    widths = [max(len(r[j]) for r in cells) for j in range(len(header))]
    lines = ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in cells]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def load_scene(name: str, **params):
    """``mi.load_file`` of ``scenes/<name>`` with its ``<default>`` parameters overridden."""
    import mitsuba as mi

    return mi.load_file(str(scene_path(name)), **{k: str(v) if isinstance(v, bool) else v
                                                  for k, v in params.items()})


def box_filtered_sensor(scene):
    """A copy of the scene's first sensor (perspective or orthographic) with a box filter.

    Same placement, field of view, clip planes and film size; a box reconstruction filter
    keeps every sample in its own pixel, so an AOV rendered with one sample per pixel holds
    values of single hits (no blending of neighbours across silhouettes).
    """
    import drjit as dr
    import mitsuba as mi

    sensor = scene.sensors()[0]
    params = mi.traverse(sensor)
    matrix = np.asarray(params["to_world"].matrix, np.float64).reshape(4, 4)
    width, height = (int(v) for v in sensor.film().size())
    spec = {
        "to_world": mi.ScalarTransform4f(matrix),
        "near_clip": float(params["near_clip"]),
        "far_clip": float(params["far_clip"]),
        "film": {"type": "hdrfilm", "width": width, "height": height,
                 "rfilter": {"type": "box"}, "pixel_format": "rgb"},
    }
    if "x_fov" in params:
        spec.update(type="perspective", fov=float(dr.ravel(params["x_fov"])[0]), fov_axis="x")
    else:
        spec["type"] = "orthographic"
    return mi.load_dict(spec)


def aov(scene, kind: str, seed: int = 0) -> np.ndarray:
    """One AOV of ``scene`` (Mitsuba's ``aov`` integrator): (H, W, C) float64.

    e.g. ``depth`` (camera distance of the first hit, 0 where nothing is hit; C = 1) or
    ``position`` (world position of the first hit; C = 3). One sample per pixel through
    :func:`box_filtered_sensor`, so each pixel holds one hit's value.
    """
    import mitsuba as mi

    integrator = mi.load_dict({"type": "aov", "aovs": f"a:{kind}"})
    sensor = box_filtered_sensor(scene)
    return np.asarray(mi.render(scene, spp=1, seed=seed, sensor=sensor, integrator=integrator),
                      np.float64)
