"""Dimming sweeps: a swept ``<default>`` that only scales lights is relit, not rendered.

Light adds up linearly, so the image of a scene whose lamp has intensity ``v`` is
``rest + v * L``, where ``L`` is the image of that lamp at intensity 1 and ``rest`` the
image of the other lights. A parameter is a *dimming* parameter (:func:`dimming_emitters`)
when every use of ``$name`` in the scene's XML is the whole ``value`` of an emitter's own
intensity parameter (:data:`DIMMING_NAMES`, or a ``luminous_*`` one), a ``float``,
``spectrum`` or ``rgb`` element directly inside an ``<emitter>``. When every swept
parameter is one (:func:`dimming_plan`: numbers >= 0, each emitter scaled by one
parameter, an integrator that :func:`spectrace.lightgroups.integrator_for` replaces, an
RGB or spectral variant), the sweep renders one light-group render per variant and seed
(:func:`render_dimming_layers`: the swept parameters at 1, one layer per parameter and
``rest``) and makes each image by :func:`spectrace.lightgroups.relight`. The images equal
the rendered sweep's within Monte Carlo noise (the light-group integrator takes other
random numbers than ``path``); ``results.csv`` and the DataArray are the same.
"""

from __future__ import annotations

import math
import re
import time

from spectrace.errors import SpectraceError

#: The parameters of an emitter that scale its emission linearly (besides ``luminous_*``).
DIMMING_NAMES = ("intensity", "radiance", "irradiance", "scale", "power", "flux")
_VALUE_TAGS = ("float", "spectrum", "rgb")
#: Integrators of which a light-group render makes layers (spectrace.lightgroups).
_INTEGRATORS = ("path", "direct", "lightgroups", "local")
#: Layers a light-group render may add besides the swept ones: no swept name may be one.
_OTHER_LAYERS = ("rest", "ambient")
#: The EXR layer name of the swept parameter of index i (names must be GROUP_NAME safe).
_LAYER = "dim{}"
_ID = "spectrace-dim-{}-{}"


def _is_dimming_name(name: str) -> bool:
    return name in DIMMING_NAMES or name.startswith("luminous")


def dimming_emitters(root, name: str) -> list | None:
    """The ``<emitter>`` elements of the scene ``root`` whose intensity is ``$name``, or
    None when ``$name`` is used anywhere else (or nowhere)."""
    use = re.compile(rf"\${re.escape(name)}(?!\w)")
    parents = {child: parent for parent in root.iter() for child in parent}
    emitters = []
    for element in root.iter():
        for key, value in element.attrib.items():
            if not use.search(value):
                continue
            parent = parents.get(element)
            if not (key == "value" and value.strip() == f"${name}"
                    and element.tag in _VALUE_TAGS and parent is not None
                    and parent.tag == "emitter"
                    and _is_dimming_name(element.get("name", ""))):
                return None
            if parent not in emitters:
                emitters.append(parent)
    return emitters or None


def dimming_plan(grid) -> dict[str, int] | None:
    """``{parameter: number of emitters it scales}`` when every swept parameter of
    ``grid`` is a dimming parameter that can be relit (see the module docstring), else
    None (the sweep renders every combination)."""
    from spectrace.scene import read_scene_xml

    if not grid.params or any("mono" in v or "polarized" in v for v in grid.variants):
        return None
    root = read_scene_xml(grid.scene)
    integrators = [e for e in root.iter("integrator")]
    if len(integrators) > 1 or any(e.get("type") not in _INTEGRATORS for e in integrators):
        return None
    plan, seen = {}, set()
    for name, values in grid.params.items():
        if name in _OTHER_LAYERS or not all(_number(v) is not None for v in values):
            return None
        emitters = dimming_emitters(root, name)
        if emitters is None or any(id(e) in seen for e in emitters):
            return None  # used elsewhere, or an emitter scaled by two parameters
        seen.update(id(e) for e in emitters)
        plan[name] = len(emitters)
    return plan


def _number(value) -> float | None:
    try:
        x = float(str(value).strip())
    except ValueError:
        return None
    return x if math.isfinite(x) and x >= 0 else None


def render_dimming_layers(path: str, names: list[str], variant: str, spp: int | None,
                          seed: int, spp_per_pass: int | None) -> dict:
    """Task: the light-group render of the scene at ``path`` with the dimming parameters
    ``names`` at 1: ``{"layers": {name: (H, W, 3)
    float32, ..., "rest": ...}, "spp", "seconds"}`` (linear sRGB, ``rest`` only when other
    emitters light the scene; a ``local`` scene also has ``ambient``), or
    ``{"error": message}`` for a user's mistake."""
    import numpy as np

    from spectrace import lightgroups
    from spectrace.cluster import ensure_variant
    from spectrace.passes import render_passes, scene_spp
    from spectrace.scene import load_scene, read_scene_xml

    start = time.perf_counter()
    try:
        ensure_variant(variant)
        root = read_scene_xml(path)
        groups = {}
        for i, name in enumerate(names):
            ids = []
            for k, emitter in enumerate(dimming_emitters(root, name) or []):
                if not emitter.get("id"):  # a name the light groups can refer to
                    emitter.set("id", _ID.format(i, k))
                ids.append(emitter.get("id"))
            groups[_LAYER.format(i)] = ids
        scene = load_scene(path, {name: "1" for name in names}, root=root)
        result = render_passes(scene, spp or scene_spp(scene), seed=seed,
                               spp_per_pass=spp_per_pass, light_groups=groups)
    except SpectraceError as e:
        return {"error": str(e)}
    _, layers = lightgroups.split(result.image, result.light_groups)
    layer_names = {_LAYER.format(i): name for i, name in enumerate(names)}
    named = {layer_names.get(g, g): np.array(v) for g, v in layers.items()}
    return {"layers": named, "spp": result.spp, "seconds": time.perf_counter() - start}


def relit_image(layers: dict, combo):
    """The image of ``combo`` from the layers of :func:`render_dimming_layers`: each
    parameter's layer times its value, plus ``rest``."""
    from spectrace.lightgroups import relight

    scales = {name: float(value) for name, value in combo.defines.items()}
    image, _ = relight(layers, scales)
    return image
