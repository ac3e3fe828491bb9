"""What ``spectrace spd`` reports of one SPD: XYZ, xy, CCT, CRI and its sRGB colour.

:func:`describe_spd` validates the SPD for colorimetry (wavelengths in nm overlapping the
CIE range, no negative value) and returns the numbers as a dict, for the command line and
notebooks. Emissive SPDs (light sources) get XYZ with X = integral S xbar / integral ybar
(a constant SPD of 1 has Y = 1), CCT (Ohno 2013) with Duv and CRI Ra (CIE 13.3);
reflectances get XYZ under an illuminant (perfect white Y = 1) and no CCT or CRI, which
describe light sources only.
"""

from __future__ import annotations

import numpy as np

from spectrace.errors import ParameterError

from .colorimetry import check_spd

#: The CIE colour matching functions' range (nm): an SPD must overlap it.
CIE_RANGE_NM = (360.0, 830.0)


def check_visible_nm(wavelengths, where: str) -> np.ndarray:
    """``wavelengths`` as float64 if they are nm overlapping :data:`CIE_RANGE_NM`.

    Wavelengths given in micrometres (0.36-0.83) or metres (3.6e-7-8.3e-7) are recognised
    and named in the ``ValueError``, since a factor 1000 or 1e9 is the usual mistake.
    """
    wl = np.asarray(wavelengths, dtype=np.float64)
    top = float(np.max(wl))
    lo, hi = CIE_RANGE_NM
    for unit, factor in (("metres", 1e-9), ("micrometres", 1e-3)):
        if lo * factor * 0.5 <= top <= hi * factor * 2.0:
            raise ParameterError(
                f"{where}: wavelengths must be in nm; {wl[0]:g}-{top:g} look like {unit} "
                f"(multiply by {1 / factor:g})"
            )
    if top <= lo or wl[0] >= hi:
        raise ParameterError(
            f"{where}: wavelengths {wl[0]:g}-{top:g} nm do not overlap the CIE range "
            f"{lo:g}-{hi:g} nm (wavelengths must be in nm)"
        )
    return wl


def check_non_negative(wavelengths, values, where: str) -> None:
    """``ValueError`` naming the first negative value and its wavelength."""
    negative = np.flatnonzero(np.asarray(values) < 0)
    if negative.size:
        i = int(negative[0])
        raise ParameterError(
            f"{where}: negative value {values[i]:g} at {wavelengths[i]:g} nm "
            f"({negative.size} negative in all): an SPD is non-negative"
        )


def describe_spd(wavelengths, values, observer: str = "CIE 1931 2 Degree Standard Observer",
                 reflectance: bool = False, illuminant: str = "D65", where: str = "SPD") -> dict:
    """XYZ, xy and sRGB of an SPD; CCT, Duv and CRI Ra too when it is emissive.

    ``reflectance``: the values are a reflectance seen under ``illuminant`` (XYZ with a
    perfect white at Y = 1). ``sRGB`` is the encoded colour, scaled so that an emissive
    SPD's largest linear component is 1 (a reflectance keeps its absolute level), clipped
    to [0, 1]. Raises ``ValueError`` naming ``where`` for a bad SPD.
    """
    from . import colorimetry as C

    wl, v = check_spd(wavelengths, values, where)
    check_visible_nm(wl, where)
    check_non_negative(wl, v, where)
    if not np.max(v) > 0:
        raise ParameterError(f"{where}: every value is 0: no light or reflectance to describe")
    xyz = C.spd_to_xyz(wl, v, illuminant if reflectance else None, observer=observer)
    if not xyz[1] > 0 and not reflectance:
        raise ParameterError(f"{where}: no luminance (Y = 0): the SPD is outside the visible range")
    out = {"XYZ": xyz, "xy": xyz[:2] / xyz.sum()}
    linear = C.xyz_to_linear_srgb(xyz)
    if not reflectance:
        cct, duv = C.cct(wl, v, return_duv=True)
        out["CCT"], out["Duv"] = float(cct), float(duv)
        out["CRI"] = C.cri(wl, v)
        linear = linear / max(float(linear.max()), 1e-300)
    out["sRGB"] = C.encode_srgb(np.clip(linear, 0.0, 1.0))
    return out
