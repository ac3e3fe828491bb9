"""Light compositing: the study of ``notebooks/light_compositing.ipynb``.

Light adds up linearly: the image with all lights on is the sum of the images of each
light alone, and a light dimmed to s scales its image by s. The study renders the
luminaires room of ``scenes/luminaires.xml`` with the path tracer (its ``local``
integrator replaced: :func:`room_tree`) once with one light-group layer per luminaire
(:func:`render_layers`), and each luminaire alone in renders of its own
(:func:`render_alone`); it compares their sums with the all-on image
(:func:`linearity_rows`) and composes light scenes from the layers without rendering
(:func:`light_scenes`, :func:`spectrace.lightgroups.relight`).

Sources: the superposition of light (Maxwell's equations are linear; in rendering terms,
the rendering equation is linear in the emitted radiance: Kajiya (1986), "The rendering
equation", SIGGRAPH); light scenes and dimming groups as in lighting-design software.
"""

from __future__ import annotations

import copy
import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence

import numpy as np

from spectrace import lightgroups
from spectrace.studies import budget, display, luminance, save_figure, scene_path, text_table

__all__ = ["LIGHTS", "LIGHT_SCENES", "ROOM", "budget", "display", "light_scenes",
           "linearity_rows", "load_room", "luminance", "render_alone", "render_layers",
           "room_tree", "save_figure", "text_table"]

#: The scene of the study.
ROOM = "luminaires"
#: The ids given to the room's four luminaires, in the scene file's order.
LIGHTS = ("table_left", "table_right", "washer_left", "washer_right")
#: Light scenes: name -> scale per light (lights not named stay at 1).
LIGHT_SCENES: dict[str, dict[str, float]] = {
    "all on": {},
    "work (tables only)": {"washer_left": 0.0, "washer_right": 0.0},
    "evening (wall washed, tables at 20 %)": {"table_left": 0.2, "table_right": 0.2},
    "left half": {"table_right": 0.0, "washer_right": 0.0},
}


def room_tree(max_depth: int = 3, lights: Sequence[str] | None = None) -> ET.Element:
    """The parsed luminaires room with the path tracer (``max_depth``) in place of its
    ``local`` integrator, its luminaires named :data:`LIGHTS`, only those in ``lights``
    kept (all when None)."""
    from spectrace.scene import read_scene_xml

    root = copy.deepcopy(read_scene_xml(scene_path(ROOM)))
    old = root.find("integrator")
    integrator = ET.Element("integrator", type="path")
    ET.SubElement(integrator, "integer", name="max_depth", value=str(max_depth))
    root.insert(list(root).index(old), integrator)
    root.remove(old)
    emitters = root.findall("emitter")
    if len(emitters) != len(LIGHTS):
        raise ValueError(f"room_tree: the room has {len(emitters)} emitters, expected "
                         f"{len(LIGHTS)}")
    for element, name in zip(emitters, LIGHTS, strict=True):
        element.set("id", name)
        if lights is not None and name not in lights:
            root.remove(element)
    return root


def load_room(res: int, spp: int, max_depth: int = 3, lights: Sequence[str] | None = None):
    """The room of :func:`room_tree` loaded at ``res`` x ``res`` pixels and ``spp``."""
    from spectrace.scene import load_scene

    return load_scene(scene_path(ROOM), {"res": res, "spp": spp},
                      root=room_tree(max_depth, lights))


def render_layers(scene, spp: int, seed: int = 0):
    """``(beauty, {light: layer})`` of one render with one layer per luminaire."""
    import spectrace

    result = spectrace.render(scene, spp=spp, seed=seed, light_groups=True)
    return lightgroups.split(result.image, result.light_groups)


def render_alone(res: int, spp: int, seed: int = 1, max_depth: int = 3) -> dict:
    """Each luminaire alone in a render of its own (the other three removed): light ->
    (H, W, 3) linear sRGB."""
    import spectrace

    images = {}
    for k, name in enumerate(LIGHTS):
        scene = load_room(res, spp, max_depth, lights=[name])
        images[name] = spectrace.render(scene, spp=spp, seed=seed + k).image[..., :3]
    return images


def light_scenes(layers: Mapping[str, np.ndarray],
                 settings: Mapping[str, Mapping[str, float]] = LIGHT_SCENES) -> dict:
    """Each light scene of ``settings`` composed from the layers: name -> image."""
    return {name: lightgroups.relight(layers, scales)[0] for name, scales in settings.items()}


def linearity_rows(beauty, layers: Mapping, alone: Mapping) -> list[tuple[str, str]]:
    """Rows (comparison, relative difference of the mean luminance, relative RMS of the
    pixel difference) of: the layers' sum against the beauty of the same render, and the
    sum of the separate renders against it."""
    rows = []
    Y = luminance(beauty)
    for label, image in (("sum of the layers (same render)", sum(layers.values())),
                         ("sum of the separate renders", sum(alone.values()))):
        d = luminance(image) - Y
        rows.append((label, f"{d.mean() / Y.mean():+.2e}",
                     f"{np.sqrt(np.mean(d ** 2)) / Y.mean():.2e}"))
    return rows
