"""Spectral OpenEXR files in the layout of Fichet, Pacanowski & Wilkie 2021.

Source: A. Fichet, R. Pacanowski, A. Wilkie, "An OpenEXR Layout for Spectral Images",
JCGT 10(3), 2021. The layout used here:

* one float channel per wavelength, named ``S0.<wavelength>nm`` for emissive images
  (Stokes component 0, i.e. unpolarised radiance) or ``T.<wavelength>nm`` for reflective
  ones (reflectance / transmittance), with a comma as decimal separator:
  ``S0.412,5nm``; the reader also accepts the other SI prefixes and ``Hz`` of the paper;
* header attributes ``spectralLayoutVersion = "1.0"`` and, for emissive images,
  ``emissiveUnits`` (default ``"W.m^-2.sr^-1"``, the value colour-science writes);
* an RGB preview in channels ``R``, ``G``, ``B``: linear sRGB of the spectral values through
  :func:`spectrace.spectral.spectral_image_to_linear_srgb` (emissive: as is, no exposure
  change, so the preview is on the radiometric scale of the data; reflective: under D65,
  white = (1, 1, 1)).

Files are written and read by :mod:`spectrace.images` (the ``OpenEXR`` package, atomic
writes); this module maps the layout's channel names to wavelengths. Read back by
colour-science's ``colour.io.read_spectral_image_Fichet2021``, and its files read here
(tests/spectral/test_spectral_exr.py). colour-science's reader and writer are not used at
run time: they need OpenImageIO (a large binary package that spectrace uses only in tests)
and colour-science's import (about 2 s), where OpenEXR, which every render already uses,
does the same in a few lines.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from spectrace.errors import FileFormatError, ParameterError

from .colorimetry import check_spd
from .image import spectral_image_to_linear_srgb

__all__ = ["read_spectral_exr", "spectral_channel_name", "write_spectral_exr"]

LAYOUT_VERSION = "1.0"
DEFAULT_EMISSIVE_UNITS = "W.m^-2.sr^-1"

#: kind -> channel prefix
KINDS = {"emissive": "S0", "reflective": "T"}

#: SI prefix -> factor (Fichet 2021, section 3.1)
_PREFIX = {
    "Y": 1e24, "Z": 1e21, "E": 1e18, "P": 1e15, "T": 1e12, "G": 1e9, "M": 1e6, "k": 1e3,
    "h": 1e2, "da": 1e1, "": 1.0, "d": 1e-1, "c": 1e-2, "m": 1e-3, "u": 1e-6, "n": 1e-9,
    "p": 1e-12, "f": 1e-15, "a": 1e-18, "z": 1e-21, "y": 1e-24,
}  # fmt: skip
_SPEED_OF_LIGHT = 299792458.0
_CHANNEL = re.compile(r"^(S0|T)\.(\d*,?\d*(?:[eE][-+]?\d+)?)(da|[YZEPTGMkhdcmunpfazy])?(m|Hz)$")


def spectral_channel_name(wavelength: float, kind: str = "emissive") -> str:
    """``S0.550nm``, ``S0.412,5nm``: the shortest exact decimal with a comma separator."""
    text = np.format_float_positional(np.float64(wavelength), trim="-")
    return f"{KINDS[kind]}.{text.replace('.', ',')}nm"


def _channel_to_nm(name: str):
    m = _CHANNEL.match(name)
    if m is None:
        return None
    component, number, prefix, unit = m.groups()
    value = float(number.replace(",", "."))
    if unit == "m" and prefix == "n":
        return component, value  # the usual case, kept exact
    value *= _PREFIX[prefix or ""]
    metres = value if unit == "m" else _SPEED_OF_LIGHT / value
    return component, metres * 1e9


def write_spectral_exr(
    path,
    image,
    wavelengths,
    kind: str = "emissive",
    emissive_units: str = DEFAULT_EMISSIVE_UNITS,
    preview=True,
    half: bool = False,
    attributes: dict | None = None,
) -> Path:
    """Write ``image`` (H, W, N) with ``wavelengths`` (N, nm) as a Fichet 2021 spectral EXR.

    ``kind``: "emissive" (``S0.*`` channels, values e.g. spectral radiance in
    ``emissive_units``) or "reflective" (``T.*`` channels, unitless). ``preview``: True adds
    R, G, B linear sRGB channels computed from the spectra (see module notes), False none,
    or an (H, W, 3) array to store as R, G, B (e.g. the band-deconvolved linear sRGB of
    :func:`spectrace.spectral_film.bands_to_linear_srgb`, so the preview matches the RGB
    output). ``half`` stores float16 instead of
    float32. ``attributes``: extra header entries (e.g. the sample count). Values are
    written as given; NaN/inf raise ``ParameterError`` (a ``ValueError``). Returns the path.
    """
    if kind not in KINDS:
        raise ParameterError(
            f"write_spectral_exr: kind must be one of {', '.join(KINDS)} (got {kind!r})"
        )
    wl, img = check_spd(wavelengths, image, "write_spectral_exr")
    if img.ndim != 3:
        raise ParameterError(
            f"write_spectral_exr: image must have shape (H, W, N) (got {img.shape})")
    dtype = np.float16 if half else np.float32
    channels = {spectral_channel_name(w, kind): img[..., i] for i, w in enumerate(wl)}
    if isinstance(preview, bool):
        rgb = None
        if preview:
            illuminant = None if kind == "emissive" else "D65"
            rgb = spectral_image_to_linear_srgb(img.astype(np.float32, copy=False), wl, illuminant)
    else:
        rgb = np.asarray(preview)
        if rgb.shape != img.shape[:2] + (3,):
            raise ParameterError(
                f"write_spectral_exr: preview must have shape {img.shape[:2] + (3,)} "
                f"(got {rgb.shape})"
            )
    if rgb is not None:
        for c, name in enumerate("RGB"):
            channels[name] = rgb[..., c]
    header = {"spectralLayoutVersion": LAYOUT_VERSION}
    if kind == "emissive":
        header["emissiveUnits"] = emissive_units
    header.update(attributes or {})
    from spectrace.images import write_exr_channels

    path = Path(path)
    write_exr_channels(path, channels, header, dtype=dtype)
    return path


def read_spectral_exr(path, kind: str | None = None, with_header: bool = False):
    """Read a Fichet 2021 spectral EXR; returns ``(image (H, W, N) float32, wavelengths nm)``.

    Channels are sorted by wavelength (OpenEXR stores them alphabetically). ``kind``:
    "emissive" (``S0.*``), "reflective" (``T.*``) or None (emissive if present, else
    reflective). Polarised (S1-S3) and bispectral channels are ignored. With ``with_header``
    also returns the header dict. A missing or unreadable file, or one without spectral
    channels, raises :class:`~spectrace.errors.FileAccessError` or
    :class:`~spectrace.errors.FileFormatError` naming the path.
    """
    from spectrace.images import read_exr_channels

    channels, header = read_exr_channels(path)
    found = {}
    for name, pixels in channels.items():
        parsed = _channel_to_nm(name)
        if parsed is not None:
            found.setdefault(parsed[0], []).append((parsed[1], pixels))
    prefixes = [KINDS[kind]] if kind is not None else ["S0", "T"]
    component = next((p for p in prefixes if p in found), None)
    if component is None:
        wanted = " or ".join(p + ".*" for p in prefixes)
        raise FileFormatError(f"{path}: no spectral channels ({wanted})")
    entries = sorted(found[component], key=lambda e: e[0])
    wavelengths = np.array([e[0] for e in entries])
    image = np.stack([np.asarray(e[1], np.float32) for e in entries], axis=-1)
    return (image, wavelengths, header) if with_header else (image, wavelengths)
