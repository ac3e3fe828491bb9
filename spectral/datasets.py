"""SPD sources (CSV files, colour-science datasets) and the bridge to Mitsuba spectra.

* :func:`read_spd_csv`: two-column text file, wavelength in nm and value per row.
* :func:`illuminant`, :func:`colorchecker`: colour-science's ``SDS_ILLUMINANTS`` /
  ``SDS_LIGHT_SOURCES`` and ``SDS_COLOURCHECKERS`` (never hand-typed tables).
* :func:`load_spd`: a file path or a dataset name, for the command line.
* :func:`to_mitsuba_spectrum` / :func:`to_mitsuba_spectrum_xml`: a Mitsuba ``regular`` or
  ``irregular`` spectrum for ``mi.load_dict`` or a scene XML.
"""

from __future__ import annotations

import re
from pathlib import Path
from xml.sax.saxutils import quoteattr

import colour
import numpy as np

from spectrace.errors import FileAccessError, FileFormatError, ParameterError

from .colorimetry import check_spd

__all__ = [
    "MITSUBA_WAVELENGTH_RANGE",
    "colorchecker",
    "illuminant",
    "is_reflectance_dataset",
    "load_spd",
    "read_spd_csv",
    "to_mitsuba_spectrum",
    "to_mitsuba_spectrum_xml",
]

#: Mitsuba's spectral range in nm (MI_CIE_MIN, MI_CIE_MAX): wavelengths it samples.
MITSUBA_WAVELENGTH_RANGE = (360.0, 830.0)
DEFAULT_CHART = "ColorChecker N Ohta"
_SPLIT = re.compile(r"[,;\s]+")


def read_spd_csv(path) -> tuple[np.ndarray, np.ndarray]:
    """Read a two-column SPD file: ``wavelength_nm, value`` per line.

    Separators: comma, semicolon, tab or spaces. Blank lines and lines starting with ``#``
    are skipped; a first line that is not numeric is taken as a header. Rows must be sorted
    by increasing wavelength without duplicates. Returns float64 arrays. Any problem (missing
    file, wrong column count, non-numeric value, NaN, bad wavelengths) raises
    :class:`~spectrace.errors.SpectraceError` with the file name and line number.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise FileAccessError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as e:
        raise FileAccessError(f"{path}: cannot read ({e})") from None
    rows, first = [], True
    for lineno, line in enumerate(text.splitlines(), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        fields = [f for f in _SPLIT.split(line) if f]
        try:
            numbers = [float(f) for f in fields]
        except ValueError:
            if first:
                first = False
                continue  # header line
            raise FileFormatError(f"{path}:{lineno}: not a number in {line!r}") from None
        first = False
        if len(numbers) != 2:
            raise FileFormatError(
                f"{path}:{lineno}: expected 2 columns (wavelength nm, value), got {len(numbers)}"
            )
        rows.append(numbers)
    if not rows:
        raise FileFormatError(f"{path}: no data rows (expected 'wavelength_nm, value' lines)")
    data = np.asarray(rows, np.float64)
    try:
        wl, v = check_spd(data[:, 0], data[:, 1], str(path))
    except ValueError as e:
        raise FileFormatError(str(e)) from None
    return wl, v


def illuminant(name: str) -> tuple[np.ndarray, np.ndarray]:
    """(wavelengths, values) of a CIE illuminant or light source from colour-science.

    Looks in ``colour.SDS_ILLUMINANTS`` ("D65", "D50", "A", "E", "FL2", "LED-B3", ...) then
    ``colour.SDS_LIGHT_SOURCES``. Values as tabulated (relative, D65 = 100 at 560 nm).
    """
    for table in (colour.SDS_ILLUMINANTS, colour.SDS_LIGHT_SOURCES):
        if name in table:
            sd = table[name]
            return np.asarray(sd.wavelengths, np.float64), np.asarray(sd.values, np.float64)
    raise KeyError(name)


def colorchecker(chart: str = DEFAULT_CHART):
    """The 24 ColorChecker reflectances: ``(wavelengths, values (24, N), patch names)``.

    ``chart``: a key of ``colour.SDS_COLOURCHECKERS`` ("ColorChecker N Ohta" by default,
    "BabelColor Average"). Reflectance factors in [0, 1], patches in chart order.
    """
    try:
        sds = colour.SDS_COLOURCHECKERS[chart]
    except KeyError:
        raise ParameterError(
            f"colorchecker: unknown chart {chart!r}; one of "
            f"{', '.join(k for k in colour.SDS_COLOURCHECKERS if ' ' in k)}"
        ) from None
    names = list(sds)
    wl = np.asarray(sds[names[0]].wavelengths, np.float64)
    values = np.stack([np.asarray(sds[n].values, np.float64) for n in names])
    return wl, values, names


def _colorchecker_patch(source: str):
    """The colour-science ColorChecker patch named by ``source`` ("dark skin" or
    "BabelColor Average:dark skin"), or None."""
    chart, _, patch = source.rpartition(":")
    chart = chart or DEFAULT_CHART
    if chart in colour.SDS_COLOURCHECKERS and patch in colour.SDS_COLOURCHECKERS[chart]:
        return colour.SDS_COLOURCHECKERS[chart][patch]
    return None


def is_reflectance_dataset(source: str) -> bool:
    """Whether ``source`` names a reflectance dataset (a ColorChecker patch), not a light."""
    return not Path(source).exists() and _colorchecker_patch(source) is not None


def load_spd(source: str) -> tuple[np.ndarray, np.ndarray, str]:
    """Resolve an SPD by file path or dataset name; returns ``(wavelengths, values, label)``.

    In order: an existing file (or a name ending in .csv/.txt/.spd) -> :func:`read_spd_csv`;
    an illuminant / light source name (:func:`illuminant`); a ColorChecker patch,
    "dark skin" (ColorChecker N Ohta) or "BabelColor Average:dark skin".
    Unknown names raise :class:`~spectrace.errors.SpectraceError`.
    """
    path = Path(source)
    if path.exists() or path.suffix.lower() in (".csv", ".txt", ".spd"):
        wl, v = read_spd_csv(path)
        return wl, v, path.name
    try:
        wl, v = illuminant(source)
        return wl, v, source
    except KeyError:
        pass
    sd = _colorchecker_patch(source)
    if sd is not None:
        return np.asarray(sd.wavelengths, np.float64), np.asarray(sd.values, np.float64), source
    raise ParameterError(
        f"{source!r}: no such file and not a known dataset name (e.g. D65, A, FL2, "
        f"'dark skin', 'BabelColor Average:dark skin')"
    )


def _numbers(a) -> str:
    return ", ".join(np.format_float_positional(float(x), trim="-") for x in a)


def to_mitsuba_spectrum(wavelengths, values, extrapolation: str = "constant") -> dict:
    """A Mitsuba spectrum dict for ``mi.load_dict`` (any variant) from an SPD.

    Mitsuba's ``regular``/``irregular`` spectra interpolate linearly (like
    :func:`spd_to_xyz`) but are zero outside their range. With ``extrapolation="constant"``
    (default, this module's convention) the end values are repeated out to Mitsuba's range
    360-830 nm by adding end points, so a render sees the same SPD that :func:`spd_to_xyz`
    integrates; ``"zero"`` keeps the samples as they are. Evenly spaced samples covering
    the range give ``{"type": "regular", "wavelength_min", "wavelength_max", "values"}``,
    others ``{"type": "irregular", "wavelengths", "values"}`` (comma-separated strings, what
    the plugins parse). Values are passed unscaled.
    """
    wl, v = check_spd(wavelengths, values, "to_mitsuba_spectrum")
    if v.ndim != 1:
        raise ParameterError(f"to_mitsuba_spectrum: values must be 1-D (got shape {v.shape})")
    if extrapolation not in ("constant", "zero"):
        raise ParameterError(f"to_mitsuba_spectrum: unknown extrapolation {extrapolation!r}")
    v = np.asarray(v, np.float64)
    if wl.size == 1:
        wl, v = np.array([wl[0], wl[0] + 1.0]), np.repeat(v, 2)
    if extrapolation == "constant":
        lo, hi = MITSUBA_WAVELENGTH_RANGE
        if wl[0] > lo:
            wl, v = np.r_[lo, wl], np.r_[v[0], v]
        if wl[-1] < hi:
            wl, v = np.r_[wl, hi], np.r_[v, v[-1]]
    d = np.diff(wl)
    if np.allclose(d, d[0], rtol=1e-9, atol=0):
        return {
            "type": "regular",
            "wavelength_min": float(wl[0]),
            "wavelength_max": float(wl[-1]),
            "values": _numbers(v),
        }
    return {"type": "irregular", "wavelengths": _numbers(wl), "values": _numbers(v)}


def to_mitsuba_spectrum_xml(name: str, wavelengths, values, extrapolation: str = "constant") -> str:
    """The same spectrum as :func:`to_mitsuba_spectrum`, as a scene XML element string.

    e.g. ``<spectrum type="irregular" name="reflectance"><string name="wavelengths" .../>
    <string name="values" .../></spectrum>``.
    """
    spec = to_mitsuba_spectrum(wavelengths, values, extrapolation)
    tags = {str: "string", float: "float"}
    inner = "".join(
        f'<{tags[type(val)]} name="{key}" value={quoteattr(str(val))}/>'
        for key, val in spec.items()
        if key != "type"
    )
    return f'<spectrum type="{spec["type"]}" name={quoteattr(name)}>{inner}</spectrum>'
