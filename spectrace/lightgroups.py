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
``lightgroups`` keeps it. A ``local`` scene keeps its integrator, whose loop over the lights
adds each light's term to its group (``LocalLightGroups`` in the ``lightgroups`` plugin's
module), with one more layer, ``ambient``: its ambient term and fog colour. An
``illuminance`` scene keeps its integrator too, whose loop over the lights adds each
light's lux to its group (``IlluminanceLightGroups``): per-light lux layers, R = G = B =
lux, with one more layer, ``indirect``, the interreflected light. Other integrators
(``volpath``, ...),
films with a sensor response (``specfilm``) and polarized variants are refused for now.

Spectral layers
---------------
With ``band_wavelengths`` (``--film spectral``) the integrator's layers are N hat bands per
group (the bands of :mod:`spectrace.spectral_film`) on the scene's RGB film, as Mitsuba
3.9's ``specfilm`` cannot hold AOVs; :func:`write_spectral_layers_exr` writes the
spectral beauty (their sum) as ``S0.<wl>nm`` channels in the layout of Fichet et al. 2021
beside ``<group>.S0.<wl>nm`` layers, with each group's lamp spectrum probed from its
emitters (:func:`group_spectra`, band-averaged, peak 1; absent when the group's emitters
differ) in the header attribute ``<group>.spectrum``.

Relighting
----------
:func:`relight` scales each layer (dimming): ``sum_g s_g L_g``; groups not named keep
scale 1. :func:`relight_spectral` also gives a group a new lamp spectrum: its spectral
layer times S_new / S_old band by band, S_new scaled to the same luminous output, exact up
to the band discretisation. On RGB layers a new spectrum is refused
(:class:`~spectrace.errors.ParameterError`): scaling the RGB of a layer by the new lamp's
RGB over the old one is wrong for coloured surfaces (metamerism).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping
from pathlib import Path

from spectrace.errors import FileFormatError, ParameterError

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


def integrator_for(scene, light_groups, integrator=None, sensor=0, band_wavelengths=None):
    """A ``lightgroups`` integrator for ``scene`` in place of ``integrator`` (default the
    scene's), with the groups :func:`resolve_groups` makes; ParameterError for an
    integrator it does not replace (see the module docstring) and for a film with a sensor
    response (``specfilm``: Mitsuba 3.9's cannot hold AOVs). ``band_wavelengths``: spectral
    layers of hat bands at these centres (:func:`spectrace.spectral_film.band_centres`)
    instead of RGB ones, on the scene's RGB film."""
    import mitsuba as mi

    from spectrace import registry

    if mi.is_polarized:
        raise ParameterError(f"light groups: polarized variants are not supported (variant "
                             f"{mi.variant()})")
    integrator = scene.integrator() if integrator is None else integrator
    film = (scene.sensors()[sensor] if isinstance(sensor, int) else sensor).film()
    kind = integrator.class_name()
    if kind == "SamplingIntegrator":  # a Python integrator: its class
        kind = type(integrator).__name__
    if film.sensor_response_function() is not None:  # Mitsuba 3.9's specfilm drops AOVs
        raise ParameterError(f"light groups: the film {film.class_name()} has a sensor "
                             "response (a spectral film), which cannot hold layers; use "
                             "hdrfilm (spectral layers: band_wavelengths)")
    if kind in ("LightGroups", "LocalLightGroups", "IlluminanceLightGroups"):  # already one
        emitter_group_indices(scene, integrator.groups)
        return integrator
    if kind == "Local":  # its light loop attributes each light's term (and 'ambient')
        registry.require({"lightgroups"})
        from spectrace.plugins.integrators.lightgroups import LocalLightGroups

        return LocalLightGroups(integrator, resolve_groups(scene, light_groups),
                                band_wavelengths)
    if kind == "Illuminance":  # its light loop attributes each light's lux (and 'indirect')
        registry.require({"lightgroups"})
        from spectrace.plugins.integrators.lightgroups import IlluminanceLightGroups

        if band_wavelengths is not None:
            raise ParameterError("light groups: the illuminance integrator's layers are lux, "
                                 "not spectral (band_wavelengths)")
        return IlluminanceLightGroups(integrator, resolve_groups(scene, light_groups))
    if kind not in REPLACED_INTEGRATORS:
        raise ParameterError(f"light groups need the scene's integrator to be 'path', "
                             f"'direct', 'local' or 'illuminance' (it is {kind}); per-light "
                             "layers of other integrators are not supported yet")
    depths = {k: int(v) for k, v in _DEPTH.findall(str(integrator))}
    max_depth = REPLACED_INTEGRATORS[kind] or depths.get("max_depth", -1)
    registry.require({"lightgroups"})
    props = {
        "type": "lightgroups", "groups": format_groups(resolve_groups(scene, light_groups)),
        "max_depth": max_depth, "rr_depth": depths.get("rr_depth", 5),
        "hide_emitters": bool(integrator.hide_emitters),
    }
    if band_wavelengths is not None:
        props["band_wavelengths"] = ",".join(repr(float(w)) for w in band_wavelengths)
    return mi.load_dict(props)


def split(pixels, names: list[str], per_layer: int = 3):
    """``(beauty, {group: layer})`` of a ``lightgroups`` render's pixels: the film's
    channels (the beauty, as (H, W, 3) RGB when ``per_layer`` is 3), then ``per_layer``
    channels per group in ``names`` order (3: R, G, B; N: the bands of spectral layers)."""
    import numpy as np

    from spectrace.images import as_rgb

    image = np.asarray(pixels, dtype=np.float32)
    n = per_layer
    base = image.shape[-1] - n * len(names)
    if base < 1:
        raise ParameterError(f"split: {image.shape[-1]} channels cannot hold a beauty image "
                             f"and {len(names)} layers of {n}")
    layers = {g: image[..., base + n * i: base + n * (i + 1)] for i, g in enumerate(names)}
    beauty = image[..., :base]
    return (as_rgb(beauty) if n == 3 else beauty), layers


# -- files -------------------------------------------------------------------------------

def _layer_channels(beauty, layers: Mapping, names: list[str]) -> dict:
    """Float32 channels: ``names`` of the beauty, ``<group>.<name>`` of each layer."""
    import numpy as np

    channels = {}
    for prefix, image in [("", beauty), *((f"{check_group_name(k)}.", v)
                                          for k, v in layers.items())]:
        image = np.asarray(image, dtype=np.float32)
        for i, name in enumerate(names):
            channels[prefix + name] = np.ascontiguousarray(image[..., i])
    return channels


def _write_channels(path, channels: dict, attributes: dict, header: Mapping | None,
                    groups) -> Path:
    """The channels as a ZIP-compressed scanline EXR with the attributes, the extra header
    and ``lightGroups``, atomically (:func:`spectrace.images.write_exr_channels`)."""
    from spectrace.images import write_exr_channels

    path = Path(path)
    write_exr_channels(path, channels,
                       {**attributes, **(header or {}), "lightGroups": ",".join(groups)})
    return path


def write_layers_exr(path, beauty, layers: Mapping, header: Mapping | None = None) -> Path:
    """Write float32 channels R, G, B (the beauty) and ``<group>.R/G/B`` for each layer
    (each (H, W, 3) linear sRGB) with extra header attributes, atomically; the header's
    ``lightGroups`` attribute lists the groups in order."""
    return _write_channels(path, _layer_channels(beauty, layers, CHANNELS), {}, header, layers)


def read_layers_exr(path):
    """``(beauty (H, W, 3), {group: (H, W, 3)}, header)`` of a layered EXR (groups in the
    order of its ``lightGroups`` attribute, else sorted). FileAccessError for a missing file,
    FileFormatError for one without R, G, B or without layers."""
    import numpy as np

    from spectrace.images import read_exr_channels

    path = Path(path)
    channels, header = read_exr_channels(path)
    channels = {k: np.asarray(v, dtype=np.float32) for k, v in channels.items()}
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


# -- spectral layers ---------------------------------------------------------------------

#: Step (nm) of the grid on which lamp spectra are probed and averaged over the bands.
PROBE_STEP_NM = 1.0


def band_averages(wavelengths, values, centres):
    """The hat-band averages sum S hat_j / sum hat_j of the spectrum (``wavelengths``,
    ``values``; linear interpolation, 0 outside) on a :data:`PROBE_STEP_NM` grid over the
    bands at ``centres`` (evenly spaced; half hats at the ends, as the layers' bands)."""
    import numpy as np

    c = np.asarray(centres, np.float64)
    grid = np.arange(c[0], c[-1] + PROBE_STEP_NM / 2, PROBE_STEP_NM)
    S = np.interp(grid, wavelengths, values, left=0.0, right=0.0)
    hats = np.maximum(1.0 - np.abs(grid[None, :] - c[:, None]) / (c[1] - c[0]), 0.0)
    return hats @ S / hats.sum(axis=1)


def emitter_spectrum(emitter, centres):
    """The relative emission spectrum of ``emitter`` averaged over the hat bands at
    ``centres`` (:func:`band_averages`), peak 1, or None when it cannot be probed (no light
    found). Probed at one emitted direction: a ray from ``sample_ray``, then
    ``sample_direction`` towards the emitter from a point on that ray, at every wavelength
    of the grid with the same 2D sample (the spatial factors are the same at every
    wavelength); a spatially varying spectrum gives the spectrum there."""
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    n = 16
    u = (np.arange(n) + 0.5) / n
    ray, weight = emitter.sample_ray(0.0, mi.Float(0.5), mi.Point2f(u, u[::-1]),
                                     mi.Point2f(u[::-1], u), True)
    strength = np.asarray(dr.max(mi.unpolarized_spectrum(weight))).ravel()
    lane = int(np.argmax(strength))
    if not strength[lane] > 0.0:
        return None

    def at_lane(v):  # a (3, width) array, width 1 when it is the same for every lane
        a = np.asarray(v, np.float64).reshape(3, -1)
        return a[:, min(lane, a.shape[1] - 1)]

    p = at_lane(ray.o) + 0.5 * at_lane(ray.d)
    c = np.asarray(centres, np.float64)
    grid = np.arange(c[0], c[-1] + PROBE_STEP_NM / 2, PROBE_STEP_NM)
    width = len(mi.Spectrum(0.0))  # wavelengths per sample (4)
    padded = np.concatenate([grid, np.full((-len(grid)) % width, grid[-1])])
    lanes = padded.reshape(-1, width).T  # (4, m): the wavelengths of m samples
    it = dr.zeros(mi.Interaction3f, lanes.shape[1])
    it.p = mi.Point3f(*(float(x) for x in p))
    it.wavelengths = mi.Spectrum(*(mi.Float(row) for row in lanes))
    _, w = emitter.sample_direction(it, mi.Point2f(0.37, 0.61), True)
    values = np.stack([np.asarray(w[i]) for i in range(width)]).T.ravel()[:len(grid)]
    if not (np.all(np.isfinite(values)) and values.max() > 0.0):
        return None
    bands = band_averages(grid, values, c)
    return bands / bands.max()


def group_spectra(scene, groups: Mapping[str, list[str]], wavelengths,
                  rtol: float = 1e-3) -> dict:
    """group -> the relative emission spectrum its emitters share, averaged over the bands
    at ``wavelengths`` (peak 1), or None when it cannot be probed or its emitters' spectra
    differ (by ``rtol``)."""
    import numpy as np

    emitters = dict(zip(emitter_names(scene), scene.emitters(), strict=True))
    out = {}
    for g, members in groups.items():
        spectra = [emitter_spectrum(emitters[m], wavelengths) for m in members]
        same = all(s is not None for s in spectra) and all(
            np.allclose(s, spectra[0], rtol=rtol, atol=rtol) for s in spectra)
        out[g] = spectra[0] if same else None
    return out


def _spectrum_attribute(values) -> str:
    return ",".join(f"{v:.9g}" for v in values)


def write_spectral_layers_exr(path, bands, layers: Mapping, wavelengths, preview,
                              spectra: Mapping | None = None,
                              header: Mapping | None = None) -> Path:
    """The spectral beauty (H, W, N band averages) as ``S0.<wl>nm`` channels (Fichet 2021)
    with its linear sRGB ``preview`` as R, G, B, and each group's bands as
    ``<group>.S0.<wl>nm``, float32, atomically. Header: the layout's attributes,
    ``lightGroups``, and ``<group>.spectrum``: the group's relative lamp spectrum at the
    band centres where known (``spectra``), what :func:`relight` needs for a new one."""
    from spectrace.spectral.exr import DEFAULT_EMISSIVE_UNITS, LAYOUT_VERSION, spectral_channel_name

    channels = _layer_channels(bands, layers, [spectral_channel_name(w) for w in wavelengths])
    channels.update(_layer_channels(preview, {}, CHANNELS))
    attributes = {"spectralLayoutVersion": LAYOUT_VERSION,
                  "emissiveUnits": DEFAULT_EMISSIVE_UNITS,
                  "bandWavelengths": ",".join(repr(float(w)) for w in wavelengths)}  # exact
    for g, values in (spectra or {}).items():
        if values is not None:
            attributes[f"{g}.spectrum"] = _spectrum_attribute(values)
    return _write_channels(path, channels, attributes, header, layers)


def read_spectral_layers_exr(path):
    """``(bands (H, W, N), {group: (H, W, N)}, wavelengths, spectra, header)`` of
    :func:`write_spectral_layers_exr`'s file (read once); ``spectra``: group -> relative
    lamp spectrum at the wavelengths, or None. FileAccessError for a missing file,
    FileFormatError for one without spectral layers."""
    import numpy as np

    from spectrace.images import read_exr_channels
    from spectrace.spectral.exr import spectral_channel_name

    path = Path(path)
    channels, header = read_exr_channels(path)
    names = [g for g in str(header.get("lightGroups", "")).split(",") if g]
    text = header.get("bandWavelengths")
    if not names or text is None:
        raise FileFormatError(f"{path}: no spectral light-group layers (<group>.S0.*); "
                              "render it with a spectral film and light groups")
    wavelengths = np.array([float(v) for v in str(text).split(",")])
    bands = {}
    for prefix in ["", *(f"{g}." for g in names)]:
        keys = [prefix + spectral_channel_name(w) for w in wavelengths]
        if not all(k in channels for k in keys):
            raise FileFormatError(f"{path}: spectral layer {prefix or 'beauty'!r} lacks "
                                  "some of its bands")
        bands[prefix] = np.stack([np.asarray(channels.pop(k), np.float32) for k in keys],
                                 axis=-1)
    spectra = {}
    for g in names:
        text = header.get(f"{g}.spectrum")
        spectra[g] = None if text is None else np.array([float(v) for v in str(text).split(",")])
    layers = {g: bands[f"{g}."] for g in names}
    return bands[""], layers, wavelengths, spectra, header


def is_spectral_layers_file(path) -> bool:
    """Whether ``path`` holds spectral light-group layers (``<group>.S0.*`` channels)."""
    from spectrace.images import exr_channel_names

    names = exr_channel_names(path)  # None: unreadable, the readers name the problem
    return names is not None and any(".S0." in k for k in names)


def relight_spectral(layers: Mapping, wavelengths, scales: Mapping[str, float],
                     new_spectra: Mapping | None = None, old_spectra: Mapping | None = None):
    """:func:`relight` of spectral layers (H, W, N band averages at ``wavelengths``), and
    for the groups in ``new_spectra`` (group -> (wavelengths, values) of an SPD) a new lamp
    spectrum: the layer times S_new / S_old band by band (both averaged over each band,
    :func:`band_averages`), S_new scaled to the luminous output of S_old (sum of the band
    averages of V S equal), then times the scale. Exact when the scene's spectral response
    is constant within each band: up to the band discretisation. ParameterError when a
    group's old spectrum is unknown (``old_spectra``) or zero where the new one is not."""
    import numpy as np

    new_spectra = dict(new_spectra or {})
    factors = {}
    for g in new_spectra:
        if g not in layers:
            raise ParameterError(f"relight: no light group {g!r} in the layers (they are: "
                                 f"{', '.join(layers)})")
        old = (old_spectra or {}).get(g)
        if old is None:
            raise ParameterError(f"relight: light group {g!r}: its lamp spectrum is not "
                                 "recorded in the layers (its emitters' spectra differ or "
                                 "could not be probed), so a new one cannot replace it")
        wl_new, v_new = new_spectra[g]
        new = band_averages(wl_new, v_new, wavelengths)
        if np.any(new < 0):
            raise ParameterError(f"relight: light group {g!r}: the new spectrum is negative")
        old = np.asarray(old, np.float64)
        if np.any((old <= 0) & (new > 0)):
            raise ParameterError(f"relight: light group {g!r}: the old lamp spectrum is 0 "
                                 "where the new one is not: no layer data there")
        V = band_averages(*_photopic(), wavelengths)
        if not np.sum(V * new) > 0:
            raise ParameterError(f"relight: light group {g!r}: the new spectrum has no "
                                 "luminous output in the bands")
        new = new * np.sum(V * old) / np.sum(V * new)
        factors[g] = np.where(old > 0, new / np.where(old > 0, old, 1.0), 0.0)
    image, scaled = relight(layers, scales)
    for g, f in factors.items():
        scaled[g] = np.multiply(scaled[g], f.astype(np.float32), dtype=np.float32)
    total = None
    for layer in scaled.values():
        total = layer.copy() if total is None else np.add(total, layer, out=total)
    return total, scaled


def _photopic():
    """(wavelengths, values) of V(lambda), CIE 1924 (colour-science)."""
    import colour

    V = colour.colorimetry.SDS_LEFS_PHOTOPIC["CIE 1924 Photopic Standard Observer"]
    return V.wavelengths, V.values
