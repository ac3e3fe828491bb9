"""Light groups: one render, one image layer per group of lights, and relighting.

Light adds up linearly: the image of a scene is the sum of the images of its lights. The
``lightgroups`` integrator (``spectrace help lightgroups``) renders that sum and its terms
from one set of paths; this module names the groups, puts the integrator in place of the
scene's, writes and reads the layered EXR and recombines the layers with new intensities.

Groups
------
* ``True`` (``--light-groups``): one group per emitter, named after it (:func:`emitter_names`:
  its ``id``; ``emitter<k>`` for an emitter without one (k its index in
  ``scene.emitters()``), ``environment`` for an environment emitter without one);
* a mapping ``{name: [emitter names]}`` or a list of ``"name=id1,id2"`` strings
  (``--light-group``): those groups; emitters in none of them form one more group,
  :data:`REST_GROUP`, so that the layers always sum to the beauty image.

A group name is letters, digits, ``_`` and ``-`` (:data:`GROUP_NAME`); it names the EXR
layer ``<name>.R``, ``<name>.G``, ``<name>.B`` (Cycles' and Nuke's naming).

When the render replaces the integrator (:func:`integrator_for`): a scene whose
integrator is ``path`` keeps its ``max_depth``, ``rr_depth`` and ``hide_emitters``;
``direct`` becomes the same path tracer with ``max_depth`` 2 (direct light and the emitters
seen directly: the same image in expectation, with its own noise); a scene already using
``lightgroups`` keeps it. Other integrators (``local``, ``illuminance``, ``volpath``, ...)
are refused for now.

Relighting
----------
:func:`relight` scales each layer (dimming): ``sum_g s_g L_g``; groups not named keep
scale 1. Changing a light's *spectrum* after the render needs spectral layers; on these
RGB layers it is refused (:class:`~spectrace.errors.ParameterError`): scaling the RGB of a
layer by the new lamp's RGB over the old one is wrong for coloured surfaces (metamerism).
"""

from __future__ import annotations

import math
import os
import re
import tempfile
from collections.abc import Iterable, Mapping
from pathlib import Path

from spectrace.errors import FileAccessError, FileFormatError, ParameterError

#: A group (layer) name.
GROUP_NAME = re.compile(r"[A-Za-z0-9_-]+")
#: The group of the emitters that no given group names.
REST_GROUP = "rest"
#: The name of an environment emitter that has no ``id``.
ENVIRONMENT = "environment"
#: The integrators that :func:`integrator_for` replaces, and the path depth each becomes
#: (None: the scene integrator's own ``max_depth``).
REPLACED_INTEGRATORS = {"PathIntegrator": None, "DirectIntegrator": 2}
#: The channels of a layer.
CHANNELS = ("R", "G", "B")
_DEPTH = re.compile(r"(max_depth|rr_depth)\s*=\s*(-?\d+)")


# -- groups ------------------------------------------------------------------------------

def check_group_name(name: str) -> str:
    if not GROUP_NAME.fullmatch(name or ""):
        raise ParameterError(f"light group name {name!r}: use letters, digits, '_' and '-' "
                             "(it names the EXR layer <name>.R, <name>.G, <name>.B)")
    return name


def parse_groups(text: str) -> dict[str, list[str]]:
    """``"name=id1,id2;name2=id3"`` (the ``lightgroups`` plugin's ``groups``) -> dict.

    Each emitter in at most one group; names checked (:func:`check_group_name`)."""
    return make_groups(item for item in text.split(";") if item.strip())


def make_groups(items: Iterable[str] | Mapping[str, Iterable[str]]) -> dict[str, list[str]]:
    """Groups from ``{name: emitters}`` or ``["name=id1,id2", ...]``: ParameterError for a
    malformed item, a bad or repeated name, an empty group, an emitter in two groups."""
    if isinstance(items, Mapping):
        pairs = [(str(k), [str(e) for e in v]) for k, v in items.items()]
    else:
        pairs = []
        for item in items:
            name, sep, members = str(item).partition("=")
            if not sep:
                raise ParameterError(f"light group {item!r}: expected NAME=id1,id2,...")
            pairs.append((name.strip(), [m.strip() for m in members.split(",") if m.strip()]))
    groups: dict[str, list[str]] = {}
    owner: dict[str, str] = {}
    for name, members in pairs:
        check_group_name(name)
        if name in groups:
            raise ParameterError(f"light group {name!r} is given twice")
        if not members:
            raise ParameterError(f"light group {name!r} has no emitters")
        for m in members:
            if m in owner:
                raise ParameterError(f"emitter {m!r} is in two light groups: "
                                     f"{owner[m]!r} and {name!r}")
            owner[m] = name
        groups[name] = members
    if not groups:
        raise ParameterError("no light groups given")
    return groups


def emitter_names(scene) -> list[str]:
    """The name of each of ``scene.emitters()``: its ``id``; for an emitter without one, or
    whose ``id`` another emitter shares (``mi.load_dict`` names every nested area emitter
    ``emitter``), ``environment`` for the scene's environment emitter, else ``emitter<k>``
    (k its index)."""
    env = scene.environment()
    ids = [e.id() for e in scene.emitters()]
    names = []
    for k, (e, name) in enumerate(zip(scene.emitters(), ids, strict=True)):
        if not name or name.startswith("_unnamed") or ids.count(name) > 1:
            name = ENVIRONMENT if env is not None and e == env else f"emitter{k}"
        names.append(name)
    return names


def emitter_group_indices(scene, groups: Mapping[str, list[str]]) -> list[int]:
    """For each of ``scene.emitters()``, the index of its group in ``groups``: every
    emitter in exactly one group (ParameterError naming an unknown or missing one)."""
    names = emitter_names(scene)
    where = {m: i for i, members in enumerate(groups.values()) for m in members}
    unknown = [m for m in where if m not in names]
    if unknown:
        raise ParameterError(f"light groups: no emitter {unknown[0]!r} in the scene (its "
                             f"emitters: {', '.join(names) or 'none'})")
    missing = [n for n in names if n not in where]
    if missing:
        raise ParameterError(f"light groups: emitter {missing[0]!r} is in no group")
    return [where[n] for n in names]


def resolve_groups(scene, light_groups) -> dict[str, list[str]]:
    """The groups of ``scene`` for ``light_groups`` (see the module docstring): True, a
    mapping, a list of ``"name=ids"`` strings, or a ``parse_groups`` string."""
    names = emitter_names(scene)
    if not names:
        raise ParameterError("light groups: the scene has no emitters")
    if light_groups is True:
        return make_groups({check_group_name(n): [n] for n in names})
    if isinstance(light_groups, str):
        groups = parse_groups(light_groups)
    else:
        groups = make_groups(light_groups)
    rest = [n for n in names
                                  if n not in {m for v in groups.values() for m in v}]
    if rest:
        if REST_GROUP in groups:
            raise ParameterError(f"light group {REST_GROUP!r} is reserved for the emitters "
                                 "in no group")
        groups[REST_GROUP] = rest
    emitter_group_indices(scene, groups)  # unknown names
    return groups


def format_groups(groups: Mapping[str, list[str]]) -> str:
    """The ``lightgroups`` plugin's ``groups`` string."""
    return ";".join(f"{k}={','.join(v)}" for k, v in groups.items())


def integrator_for(scene, light_groups, integrator=None, sensor=0):
    """A ``lightgroups`` integrator for ``scene`` in place of ``integrator`` (default the
    scene's), with the groups :func:`resolve_groups` makes; ParameterError for an
    integrator it does not replace (see the module docstring) and for a film with a sensor
    response (``specfilm``: spectral layers are not supported yet)."""
    import mitsuba as mi

    from spectrace import registry

    if mi.is_polarized:
        raise ParameterError(f"light groups: polarized variants are not supported (variant "
                             f"{mi.variant()})")
    integrator = scene.integrator() if integrator is None else integrator
    film = (scene.sensors()[sensor] if isinstance(sensor, int) else sensor).film()
    if film.sensor_response_function() is not None:
        raise ParameterError(f"light groups: the film {film.class_name()} has a sensor "
                             "response (a spectral film); light-group layers need an RGB "
                             "film (hdrfilm)")
    kind = integrator.class_name()
    if kind == "SamplingIntegrator":  # a Python integrator: its class
        kind = type(integrator).__name__
    if kind == "LightGroups":
        emitter_group_indices(scene, integrator.groups)
        return integrator
    if kind not in REPLACED_INTEGRATORS:
        raise ParameterError(f"light groups need the scene's integrator to be 'path' or "
                             f"'direct' (it is {kind}); per-light layers of other "
                             "integrators are not supported yet")
    depths = {k: int(v) for k, v in _DEPTH.findall(str(integrator))}
    max_depth = REPLACED_INTEGRATORS[kind] or depths.get("max_depth", -1)
    registry.require({"lightgroups"})
    return mi.load_dict({
        "type": "lightgroups", "groups": format_groups(resolve_groups(scene, light_groups)),
        "max_depth": max_depth, "rr_depth": depths.get("rr_depth", 5),
        "hide_emitters": bool(integrator.hide_emitters),
    })


def split(pixels, names: list[str]):
    """``(beauty (H, W, 3), {group: (H, W, 3)})`` of a ``lightgroups`` render's pixels
    (the film's channels, then three per group in ``names`` order)."""
    import numpy as np

    from spectrace.images import as_rgb

    image = np.asarray(pixels, dtype=np.float32)
    base = image.shape[-1] - 3 * len(names)
    if base < 1:
        raise ParameterError(f"split: {image.shape[-1]} channels cannot hold a beauty image "
                             f"and {len(names)} layers of 3")
    layers = {n: image[..., base + 3 * i: base + 3 * i + 3] for i, n in enumerate(names)}
    return as_rgb(image[..., :base]), layers


# -- files -------------------------------------------------------------------------------

def _atomic_write(path: Path, write) -> None:
    """``write(tmp)`` to a temporary file beside ``path``, then renamed over it."""
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=".tmp.exr", dir=path.parent)
    os.close(fd)
    try:
        write(tmp)
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(tmp, 0o666 & ~mask)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def write_layers_exr(path, beauty, layers: Mapping, header: Mapping | None = None) -> Path:
    """Write float32 channels R, G, B (the beauty) and ``<group>.R/G/B`` for each layer
    (each (H, W, 3) linear sRGB) with extra header attributes, atomically; the header's
    ``lightGroups`` attribute lists the groups in order."""
    import numpy as np
    import OpenEXR

    path = Path(path)
    channels = {}
    for prefix, image in [("", beauty), *((f"{check_group_name(k)}.", v)
                                          for k, v in layers.items())]:
        image = np.asarray(image, dtype=np.float32)
        for c, name in enumerate(CHANNELS):
            channels[prefix + name] = np.ascontiguousarray(image[..., c])
    hdr = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    hdr.update(header or {})
    hdr["lightGroups"] = ",".join(layers)

    def write(tmp):
        with OpenEXR.File(hdr, channels) as f:
            f.write(tmp)

    _atomic_write(path, write)
    return path


def read_layers_exr(path):
    """``(beauty (H, W, 3), {group: (H, W, 3)}, header)`` of a layered EXR (groups in the
    order of its ``lightGroups`` attribute, else sorted). FileAccessError for a missing file,
    FileFormatError for one without R, G, B or without layers."""
    import numpy as np
    import OpenEXR

    path = Path(path)
    if not path.is_file():
        raise FileAccessError(f"{path}: no such file")
    try:
        with OpenEXR.File(str(path), separate_channels=True) as f:
            header = dict(f.header())
            channels = {k: np.asarray(v.pixels, dtype=np.float32)
                        for k, v in f.channels().items()}
    except Exception as e:  # OpenEXR raises RuntimeError/OSError on broken files
        raise FileFormatError(f"{path}: not a readable OpenEXR file ({e})") from None
    if not all(c in channels for c in CHANNELS):
        raise FileFormatError(f"{path}: no R, G, B channels")
    beauty = np.stack([channels[c] for c in CHANNELS], axis=-1)
    found = sorted({k.rpartition(".")[0] for k in channels if "." in k
                    and k.rpartition(".")[2] in CHANNELS})
    order = [g for g in str(header.get("lightGroups", "")).split(",") if g in found]
    order += [g for g in found if g not in order]
    layers = {}
    for g in order:
        if not all(f"{g}.{c}" in channels for c in CHANNELS):
            raise FileFormatError(f"{path}: layer {g!r} lacks one of {g}.R, {g}.G, {g}.B")
        layers[g] = np.stack([channels[f"{g}.{c}"] for c in CHANNELS], axis=-1)
    if not layers:
        raise FileFormatError(f"{path}: no light-group layers (<group>.R, .G, .B); render "
                              "it with light groups")
    return beauty, layers, header


# -- relighting --------------------------------------------------------------------------

def parse_scale(text: str) -> tuple[str, float, str | None]:
    """``"name=scale[,spectrum]"`` -> (name, scale, spectrum or None); ParameterError
    for a malformed item or a scale that is negative or not finite."""
    name, sep, rest = text.partition("=")
    value, _, spectrum = rest.partition(",")
    if not sep or not name.strip():
        raise ParameterError(f"relight {text!r}: expected GROUP=SCALE[,SPECTRUM]")
    try:
        scale = float(value)
    except ValueError:
        raise ParameterError(f"relight {text!r}: scale {value!r} is not a number") from None
    check_scale(name.strip(), scale)
    return name.strip(), scale, spectrum.strip() or None


def check_scale(group: str, scale: float) -> float:
    if not (math.isfinite(scale) and scale >= 0.0):
        raise ParameterError(f"relight: the scale of light group {group!r} must be a "
                             f"finite number >= 0 (got {scale})")
    return scale


def relight(layers: Mapping, scales: Mapping[str, float], spectra: Mapping | None = None):
    """``sum_g s_g L_g`` over the (H, W, 3) layers, ``s_g`` from ``scales`` (1 for groups
    not in it) as float32; the scaled layers too: ``(image, {group: s_g L_g})``.

    ParameterError for a group not in ``layers``, a scale < 0 or not finite, and for any
    entry of ``spectra`` (a new spectrum needs spectral layers; see the module docstring)."""
    import numpy as np

    for g, s in scales.items():
        if g not in layers:
            raise ParameterError(f"relight: no light group {g!r} in the layers (they are: "
                                 f"{', '.join(layers)})")
        check_scale(g, float(s))
    for g in spectra or {}:
        raise ParameterError(f"relight: light group {g!r}: a new spectrum needs spectral "
                             "layers, these are RGB (scaling RGB by a lamp's colour is wrong "
                             "for coloured surfaces)")
    out = {}
    total = None
    for g, layer in layers.items():
        s = np.float32(scales.get(g, 1.0))
        scaled = np.multiply(layer, s, dtype=np.float32)
        out[g] = scaled
        total = scaled.copy() if total is None else np.add(total, scaled, out=total)
    return total, out
