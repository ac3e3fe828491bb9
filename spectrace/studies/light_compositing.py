"""Light compositing: the study of ``notebooks/light_compositing.ipynb``.

Light adds up linearly: the image with all lights on is the sum of the images of each
light alone, and a light dimmed to s scales its image by s. The study renders the
luminaires room of ``scenes/luminaires.xml`` with the path tracer (its ``local``
integrator replaced: :func:`room_tree`) once with one light-group layer per luminaire
(:func:`render_layers`), and each luminaire alone in renders of its own
(:func:`render_alone`); it compares their sums with the all-on image
(:func:`linearity_rows`) and composes light scenes from the layers without rendering
(:func:`light_scenes`, :func:`spectrace.lightgroups.relight`). Then it changes the lamps'
spectrum after the render (3000 K LED to 4000 K LED to FL2): from spectral layers
(:func:`render_spectral_layers`, :func:`spectrace.lightgroups.relight_spectral`), from RGB
layers by the lamps' RGB ratio (:func:`rgb_relight`, the shortcut that spectrace refuses),
against a fresh render with the new lamps (:func:`room_with_lamps`), in CIEDE2000
(:func:`lamp_change_rows`).

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

__all__ = ["LAMPS", "LIGHTS", "LIGHT_SCENES", "ROOM", "budget", "display", "lamp_change_rows",
           "lamp_rgb", "light_scenes", "linearity_rows", "load_room", "luminance",
           "render_alone", "render_layers", "render_spectral_layers", "rgb_relight",
           "room_tree", "save_figure", "spectral_relight", "text_table"]

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


def room_tree(max_depth: int = 3, lights: Sequence[str] | None = None,
              lamp: str | None = None) -> ET.Element:
    """The parsed luminaires room with the path tracer (``max_depth``) in place of its
    ``local`` integrator, its luminaires named :data:`LIGHTS`, only those in ``lights``
    kept (all when None), and with the spectrum ``lamp`` (an SPD file or colour-science
    name, :func:`spectrace.spectral.load_spd`) in place of their 3000 K LED when given."""
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
        if lamp is not None:
            old_spectrum = element.find("spectrum[@name='spectrum']")
            element.insert(list(element).index(old_spectrum), _spectrum_element(lamp))
            element.remove(old_spectrum)
        if lights is not None and name not in lights:
            root.remove(element)
    return root


def _spectrum_element(source: str) -> ET.Element:
    from spectrace.spectral import load_spd, to_mitsuba_spectrum_xml

    wl, values, _ = load_spd(source)
    return ET.fromstring(to_mitsuba_spectrum_xml("spectrum", wl, values))


def load_room(res: int, spp: int, max_depth: int = 3, lights: Sequence[str] | None = None,
              lamp: str | None = None):
    """The room of :func:`room_tree` loaded at ``res`` x ``res`` pixels and ``spp``, its
    luminaires points (``opening`` point: the light groups' study of relighting is about
    superposition, and the points keep the path tracer's noise at the test sizes)."""
    from spectrace.scene import load_scene

    return load_scene(scene_path(ROOM), {"res": res, "spp": spp, "opening": "point"},
                      root=room_tree(max_depth, lights, lamp))


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


#: The lamps of the spectrum study: the room's own LED, then colour-science's names.
LAMPS = {"3000 K LED": str(scene_path(ROOM).parent / "luminaires" / "led_3000k.spd"),
         "4000 K LED": "LED-B3", "FL2": "FL2"}


def render_spectral_layers(scene, spp: int, bands: int = 16, seed: int = 0):
    """``(wavelengths, {light: (H, W, bands) band averages}, {light: lamp spectrum})`` of
    one render with spectral layers (what ``render --film spectral --light-groups``
    writes)."""
    import spectrace
    from spectrace.spectral_film import band_centres, film_to_bands

    wl = band_centres(bands)
    integrator = lightgroups.integrator_for(scene, True, band_wavelengths=wl)
    result = spectrace.render(scene, spp=spp, seed=seed, integrator=integrator,
                              light_groups=True)
    _, raw = lightgroups.split(result.image, result.light_groups, per_layer=bands)
    layers = {g: film_to_bands(v, wl) for g, v in raw.items()}
    return wl, layers, lightgroups.group_spectra(scene, integrator.groups, wl)


def spectral_relight(layers, wavelengths, spectra, lamp: str):
    """Linear sRGB of the spectral layers with every light given the spectrum ``lamp``."""
    from spectrace.spectral import load_spd
    from spectrace.spectral_film import bands_to_linear_srgb

    new = load_spd(lamp)[:2]
    image, _ = lightgroups.relight_spectral(layers, wavelengths, {},
                                            {g: new for g in layers}, spectra)
    return bands_to_linear_srgb(image, wavelengths)


def lamp_rgb(source: str) -> np.ndarray:
    """The linear sRGB of a lamp spectrum at luminance Y = 1."""
    from spectrace.spectral import load_spd, spd_to_xyz, xyz_to_linear_srgb

    wl, values, _ = load_spd(source)
    xyz = spd_to_xyz(wl, values)
    return xyz_to_linear_srgb(xyz / xyz[1])


def rgb_relight(rgb_image, old: str, new: str) -> np.ndarray:
    """The RGB shortcut: the image's channels scaled by the new lamp's RGB over the old
    one's (same luminance). Wrong for coloured surfaces: what a reflectance does to a
    spectrum is not a per-channel product."""
    return np.asarray(rgb_image) * (lamp_rgb(new) / lamp_rgb(old))


def lamp_change_rows(relit: Mapping[str, Mapping[str, np.ndarray]],
                     fresh: Mapping[str, np.ndarray]) -> list[tuple[str, ...]]:
    """Rows (lamp, method, mean and 95th percentile CIEDE2000 against the fresh render)
    for ``relit[lamp][method]`` images. The images are exposed alike (the fresh render's
    99th percentile luminance to 0.8) and encoded to sRGB first."""
    from spectrace.spectral import delta_e_2000

    rows = []
    for lamp, methods in relit.items():
        scale = 0.8 / max(float(np.percentile(luminance(fresh[lamp]), 99)), 1e-12)
        ref = display(fresh[lamp] * scale)
        for method, image in methods.items():
            de = delta_e_2000(display(image * scale), ref)
            rows.append((lamp, method, f"{de.mean():.2f}", f"{np.percentile(de, 95):.2f}"))
    return rows
