"""SPD -> CIE XYZ -> sRGB, chromatic adaptation, Planck's law, CCT, CRI and CIEDE2000.

Conventions shared by every function here:

* Wavelengths in nm, a 1-D array, finite, > 0, strictly increasing (no duplicates).
  Spectral values have the wavelength axis last and any leading shape.
* An SPD given at samples ``(wavelengths, values)`` is the piecewise-linear function through
  them. Outside the sampled range it is extended with its end values (``extrapolation=
  "constant"``, the default, as recommended by CIE 015:2004 section 7.2.2.1 and as
  colour-science's ``SpectralDistribution.align`` does) or taken as zero
  (``extrapolation="zero"``). A single sample is a constant SPD.
* Colour matching functions (CMFs) and illuminants come from colour-science's datasets
  (``colour.MSDS_CMFS``, ``colour.SDS_ILLUMINANTS``): the 1 nm CIE tables over 360-830 nm.
  Integrals run over 360-830 nm (the CMFs are zero outside), by the trapezoidal rule on the
  union of the 1 nm CMF grid and the SPD's own wavelengths, with the CMFs (and illuminant)
  interpolated linearly: for a piecewise-linear SPD this is the exact integral of the product
  up to the CMF's 1 nm linear interpolation.
* Bad input (NaN/inf, negative or zero wavelengths, unsorted or duplicate wavelengths,
  mismatched lengths, empty arrays) raises ``ValueError`` naming the function and problem.

Sources: CIE 015:2004 (colorimetry), IEC 61966-2-1:1999 (sRGB), CIE 13.3-1995 (CRI),
Ohno 2013 (CCT), Sharma, Wu & Dalal 2005 / CIE 142-2001 (CIEDE2000), Lam 1985 (Bradford),
CIE 159:2004 (CAT02), Planck 1901 with CODATA constants.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from functools import lru_cache

import colour
import numpy as np

from spectrace.errors import ParameterError
from spectrace.quadrature import trapezoid_weights

from .srgb import decode_srgb, encode_srgb

__all__ = [
    "CIE_1931_2",
    "CIE_1964_10",
    "OBSERVERS",
    "blackbody",
    "cct",
    "check_spd",
    "check_wavelengths",
    "chromatic_adaptation",
    "cri",
    "decode_srgb",
    "delta_e_2000",
    "encode_srgb",
    "linear_srgb_to_xyz",
    "spd_to_xyz",
    "white_xyz",
    "xyz_to_linear_srgb",
    "xyz_to_srgb",
    "xyz_weights",
]

CIE_1931_2 = "CIE 1931 2 Degree Standard Observer"
CIE_1964_10 = "CIE 1964 10 Degree Standard Observer"
#: Accepted observer names (and short aliases) -> colour-science's ``MSDS_CMFS`` key.
OBSERVERS: Mapping[str, str] = {
    CIE_1931_2: CIE_1931_2,
    CIE_1964_10: CIE_1964_10,
    "2": CIE_1931_2,
    "10": CIE_1964_10,
    "CIE 1931": CIE_1931_2,
    "CIE 1964": CIE_1964_10,
}

#: How an SPD is extended outside its sampled range (see the module notes).
EXTRAPOLATIONS = ("constant", "zero")


# --------------------------------------------------------------------------- validation


def check_wavelengths(wavelengths, where: str = "spectral") -> np.ndarray:
    """Return ``wavelengths`` as a float64 1-D array, or raise ``ValueError`` naming the problem.

    Requirements: 1-D, non-empty, finite, > 0 nm, strictly increasing (no duplicates).
    """
    wl = np.asarray(wavelengths, dtype=np.float64)
    if wl.ndim != 1:
        raise ParameterError(f"{where}: wavelengths must be a 1-D array (got shape {wl.shape})")
    if wl.size == 0:
        raise ParameterError(f"{where}: wavelengths are empty")
    if not np.all(np.isfinite(wl)):
        raise ParameterError(f"{where}: wavelengths contain NaN or infinite values")
    if np.any(wl <= 0):
        raise ParameterError(f"{where}: wavelengths must be positive nm (got min {wl.min():g})")
    d = np.diff(wl)
    if np.any(d == 0):
        dup = wl[1:][d == 0][0]
        raise ParameterError(f"{where}: duplicate wavelength {dup:g} nm")
    if np.any(d < 0):
        i = int(np.argmax(d < 0))
        raise ParameterError(
            f"{where}: wavelengths must be sorted increasingly "
            f"({wl[i]:g} nm before {wl[i + 1]:g} nm)"
        )
    return wl


def check_spd(wavelengths, values, where: str = "spectral", finite: bool = True):
    """Validate an SPD; return ``(wavelengths float64, values as float array)``.

    ``values`` has the wavelength axis last and any leading shape; its last axis must have
    ``len(wavelengths)`` entries. With ``finite`` the values must contain no NaN/inf.
    """
    wl = check_wavelengths(wavelengths, where)
    v = np.asarray(values)
    if v.dtype.kind not in "fiu":
        v = v.astype(np.float64)
    if v.ndim == 0 or v.size == 0:
        raise ParameterError(f"{where}: values are empty (shape {v.shape})")
    if v.shape[-1] != wl.size:
        raise ParameterError(
            f"{where}: values have {v.shape[-1]} samples on their last axis but there are "
            f"{wl.size} wavelengths (mismatched lengths)"
        )
    if finite and v.dtype.kind == "f" and not np.all(np.isfinite(v)):
        raise ParameterError(f"{where}: values contain NaN or infinite values")
    return wl, v


def _observer_key(observer: str) -> str:
    try:
        return OBSERVERS[observer]
    except (KeyError, TypeError):
        raise ParameterError(
            f"unknown observer {observer!r}; one of: {', '.join(OBSERVERS)}") from None


def _check_extrapolation(extrapolation: str) -> str:
    if extrapolation not in EXTRAPOLATIONS:
        raise ParameterError(
            f"unknown extrapolation {extrapolation!r}; one of: {', '.join(EXTRAPOLATIONS)}"
        )
    return extrapolation


# --------------------------------------------------------------------------- integration


def _cmfs(observer_key: str) -> tuple[np.ndarray, np.ndarray]:
    cmfs = colour.MSDS_CMFS[observer_key]
    return np.asarray(cmfs.wavelengths, np.float64), np.asarray(cmfs.values, np.float64)


def _hat_project(wl: np.ndarray, grid: np.ndarray, f: np.ndarray):
    """sum_k hat_i(grid[k]) f[k] for every sample i: (N, C) from f of shape (G, C).

    hat_i is the piecewise-linear basis function of sample i, constant beyond the end
    samples, so this is the quadrature of a piecewise-linear SPD against f (the caller
    restricts the grid for zero extrapolation); O(G), no N x G matrix.
    """
    n = wl.size
    out = np.zeros((n, f.shape[1]))
    if n == 1:
        out[0] = f.sum(axis=0)
        return out
    j = np.clip(np.searchsorted(wl, grid, side="right") - 1, 0, n - 2)
    t = np.clip((grid - wl[j]) / (wl[j + 1] - wl[j]), 0.0, 1.0)[:, None]
    np.add.at(out, j, (1.0 - t) * f)
    np.add.at(out, j + 1, t * f)
    return out


def _interp_const(x, xp, fp):
    """Linear interpolation, constant beyond the ends (CIE 015 extrapolation)."""
    return np.interp(x, xp, fp, left=fp[0], right=fp[-1])


def _illuminant_spd(illuminant) -> tuple[np.ndarray, np.ndarray]:
    """(wavelengths, values) of an illuminant name from ``colour.SDS_ILLUMINANTS`` or a pair."""
    if isinstance(illuminant, str):
        try:
            sd = colour.SDS_ILLUMINANTS[illuminant]
        except KeyError:
            raise ParameterError(
                f"unknown illuminant {illuminant!r}; e.g. D65, D50, A, E, FL2 "
                "(any key of colour.SDS_ILLUMINANTS)"
            ) from None
        return np.asarray(sd.wavelengths, np.float64), np.asarray(sd.values, np.float64)
    try:
        wl, v = illuminant
    except (TypeError, ValueError):
        raise ParameterError(
            "illuminant must be None, a name such as 'D65' or a (wavelengths, values) pair"
        ) from None
    wl, v = check_spd(wl, v, "illuminant")
    if v.ndim != 1:
        raise ParameterError(f"illuminant: values must be 1-D (got shape {v.shape})")
    return wl, v.astype(np.float64)


def _illuminant_key(illuminant):
    if illuminant is None or isinstance(illuminant, str):
        return illuminant
    wl, v = _illuminant_spd(illuminant)
    return (wl.tobytes(), v.tobytes())


@lru_cache(maxsize=64)
def _weights_cached(wl_bytes: bytes, observer_key: str, illum_key, extrapolation: str):
    wl = np.frombuffer(wl_bytes, dtype=np.float64)
    cmf_wl, cmf = _cmfs(observer_key)
    inside = wl[(wl > cmf_wl[0]) & (wl < cmf_wl[-1])]
    grid = np.union1d(cmf_wl, inside)
    cmf_g = np.stack([np.interp(grid, cmf_wl, cmf[:, c]) for c in range(3)], axis=-1)
    if illum_key is None:
        illum_g = np.ones_like(grid)
    else:
        if isinstance(illum_key, str):
            iwl, iv = _illuminant_spd(illum_key)
        else:
            iwl, iv = (np.frombuffer(b, dtype=np.float64) for b in illum_key)
        illum_g = _interp_const(grid, iwl, iv)
    q = trapezoid_weights(grid) * illum_g
    k = 1.0 / np.sum(q * cmf_g[:, 1])
    if extrapolation == "zero":  # the SPD stops at its end samples: integrate only over them
        sub = (grid >= wl[0]) & (grid <= wl[-1])
        grid, illum_g, cmf_g = grid[sub], illum_g[sub], cmf_g[sub]
        q = trapezoid_weights(grid) * illum_g if grid.size > 1 else np.zeros(grid.size)
    weights = _hat_project(wl, grid, q[:, None] * cmf_g) * k
    weights.setflags(write=False)
    return weights


def xyz_weights(
    wavelengths,
    illuminant=None,
    observer: str = CIE_1931_2,
    extrapolation: str = "constant",
) -> np.ndarray:
    """The (N, 3) float64 matrix W with ``XYZ = values @ W`` (cached per arguments).

    W[i] = k * integral hat_i(l) I(l) cmf(l) dl, with hat_i the piecewise-linear basis
    function of sample i (see the module notes), I = 1 (emissive) or the illuminant, and
    k = 1 / integral I(l) ybar(l) dl. Read-only; computed once per wavelength grid,
    observer, illuminant and extrapolation.
    """
    wl = check_wavelengths(wavelengths, "xyz_weights")
    return _weights_cached(
        wl.tobytes(),
        _observer_key(observer),
        _illuminant_key(illuminant),
        _check_extrapolation(extrapolation),
    )


def spd_to_xyz(
    wavelengths,
    values,
    illuminant=None,
    observer: str = CIE_1931_2,
    extrapolation: str = "constant",
) -> np.ndarray:
    """CIE XYZ tristimulus values of SPDs; returns shape ``values.shape[:-1] + (3,)``.

    * Emissive (``illuminant=None``): X = integral S(l) xbar(l) dl / integral ybar(l) dl
      (likewise Y, Z), so a constant SPD S = c has Y = c, and radiance in W/(m^2 sr nm)
      gives Y in the same unit per nm of an equal-energy spectrum (Mitsuba's convention).
    * Reflective (``illuminant`` a name of ``colour.SDS_ILLUMINANTS`` such as "D65", "A",
      "FL2", or a ``(wavelengths, values)`` pair): X = integral R I xbar / integral I ybar,
      so a perfect white (R = 1) has Y = 1 (colour-science's ``sd_to_XYZ`` divided by 100).

    ``observer``: "CIE 1931 2 Degree Standard Observer" (default) or
    "CIE 1964 10 Degree Standard Observer" (aliases "2", "10"). Interpolation, extrapolation
    (``"constant"`` or ``"zero"``) and integration as in the module notes; wavelengths
    outside 360-830 nm contribute nothing (the CIE tables end there).
    Checked against ``colour.sd_to_XYZ`` (tests/spectral/test_colorimetry.py).
    """
    wl, v = check_spd(wavelengths, values, "spd_to_xyz")
    w = xyz_weights(wl, illuminant, observer, extrapolation)
    return np.asarray(v, np.float64) @ w


def white_xyz(white, observer: str = CIE_1931_2) -> np.ndarray:
    """XYZ of a white: an illuminant name (its emissive XYZ scaled to Y = 1) or an XYZ triple."""
    if isinstance(white, str):
        wl, v = _illuminant_spd(white)
        xyz = spd_to_xyz(wl, v, observer=observer)
        return xyz / xyz[1]
    xyz = np.asarray(white, np.float64)
    if xyz.shape[-1:] != (3,) or not np.all(np.isfinite(xyz)):
        raise ParameterError(
            f"white must be an illuminant name or a finite XYZ triple (got {white!r})")
    return xyz


# --------------------------------------------------------------------------- sRGB

# IEC 61966-2-1:1999 linear sRGB -> XYZ (D65), as tabulated by colour-science.
_M_RGB_TO_XYZ = np.asarray(colour.models.RGB_COLOURSPACE_sRGB.matrix_RGB_to_XYZ, np.float64)
_M_XYZ_TO_RGB = np.linalg.inv(_M_RGB_TO_XYZ)


def _check_triples(a, where: str) -> np.ndarray:
    a = np.asarray(a)
    if a.dtype.kind not in "f":
        a = a.astype(np.float64)
    if a.ndim == 0 or a.shape[-1] != 3:
        raise ParameterError(f"{where}: last axis must have 3 components (got shape {a.shape})")
    return a


def xyz_to_linear_srgb(xyz) -> np.ndarray:
    """Linear sRGB (D65 white, scale of Y kept: Y = 1 -> white (1, 1, 1)) from XYZ.

    The exact inverse of the IEC 61966-2-1 RGB->XYZ matrix, so that it round-trips with
    :func:`linear_srgb_to_xyz`; it differs from the standard's rounded inverse by < 2e-4.
    Float32 input stays float32.
    """
    xyz = _check_triples(xyz, "xyz_to_linear_srgb")
    return xyz @ _M_XYZ_TO_RGB.T.astype(xyz.dtype)


def linear_srgb_to_xyz(rgb) -> np.ndarray:
    """XYZ from linear sRGB with the IEC 61966-2-1 matrix (white (1, 1, 1) -> Y = 1)."""
    rgb = _check_triples(rgb, "linear_srgb_to_xyz")
    return rgb @ _M_RGB_TO_XYZ.T.astype(rgb.dtype)


def xyz_to_srgb(xyz, clip: bool = False) -> np.ndarray:
    """Encoded sRGB of XYZ (Y = 1 -> 1.0); ``clip`` clips linear values to [0, 1] first."""
    lin = xyz_to_linear_srgb(xyz)
    if clip:
        lin = np.clip(lin, 0.0, 1.0)
    return encode_srgb(lin)


# --------------------------------------------------------------------------- adaptation

#: Method name -> key of colour-science's ``CHROMATIC_ADAPTATION_TRANSFORMS`` (the XYZ -> cone
#: response matrices: Bradford from Lam 1985, von Kries (Hunt-Pointer-Estevez), CAT02 from
#: CIE 159:2004).
CHROMATIC_ADAPTATION_METHODS: Mapping[str, str] = {
    "Bradford": "Bradford",
    "von Kries": "Von Kries",
    "CAT02": "CAT02",
}


def chromatic_adaptation(xyz, source_white, target_white, method: str = "Bradford"):
    """Von Kries-type adaptation: XYZ_t = M^-1 diag(M w_t / M w_s) M XYZ.

    ``source_white``/``target_white``: XYZ triples, or illuminant names ("D65", "A", ...)
    meaning that illuminant's XYZ scaled to Y = 1. The whites' scale carries over (adapting
    with whites of different Y scales the result). ``method``: "Bradford" (default),
    "von Kries", "CAT02" (linear, no degree of adaptation); the matrix is colour-science's
    ``colour.adaptation.matrix_chromatic_adaptation_VonKries``.
    """
    try:
        transform = CHROMATIC_ADAPTATION_METHODS[method]
    except KeyError:
        raise ParameterError(
            f"chromatic_adaptation: unknown method {method!r}; one of: "
            f"{', '.join(CHROMATIC_ADAPTATION_METHODS)}"
        ) from None
    xyz = _check_triples(xyz, "chromatic_adaptation")
    if not np.all(np.isfinite(xyz)):
        raise ParameterError("chromatic_adaptation: xyz contains NaN or infinite values")
    ws, wt = white_xyz(source_white), white_xyz(target_white)
    cat = colour.adaptation.matrix_chromatic_adaptation_VonKries(ws, wt, transform=transform)
    return np.einsum("...ij,...j->...i", cat, np.asarray(xyz, np.float64))


# --------------------------------------------------------------------------- light sources


def blackbody(wavelengths, temperature) -> np.ndarray:
    """Planck's law: spectral radiance in W / (m^2 sr nm).

    L(l, T) = 2 h c^2 / l^5 / (exp(h c / (l k T)) - 1) with l in metres, times 1e-9 for per nm
    (the unit of Mitsuba's ``blackbody`` spectrum); CODATA constants from colour-science.
    ``temperature`` in kelvin, scalar or array: the result has shape
    ``np.shape(temperature) + (N,)``. Not delegated to ``colour.colorimetry.planck_law``: that
    uses the radiation constants rounded to 7 and 5 digits (c2 = 0.014388 m K), up to 7e-4
    away from the CODATA values that Mitsuba's ``blackbody`` spectrum uses, and
    its result puts the temperature axis last.
    """
    wl = check_wavelengths(wavelengths, "blackbody")
    t = np.asarray(temperature, np.float64)
    if not np.all(np.isfinite(t)) or np.any(t <= 0):
        raise ParameterError(
            f"blackbody: temperature must be finite and > 0 K (got {temperature!r})")
    h = colour.constants.CONSTANT_PLANCK
    c = colour.constants.CONSTANT_LIGHT_SPEED
    k = colour.constants.CONSTANT_BOLTZMANN
    lm = wl * 1e-9
    return 2 * h * c**2 / lm**5 / np.expm1(h * c / (lm * k * t[..., None])) * 1e-9


def _uv_1960(xyz):
    x, y, z = xyz[..., 0], xyz[..., 1], xyz[..., 2]
    d = x + 15 * y + 3 * z
    return np.stack([4 * x / d, 6 * y / d], axis=-1)


def cct(wavelengths, values, return_duv: bool = False):
    """Correlated colour temperature in kelvin (Ohno 2013, colour-science's implementation).

    The SPD's emissive CIE 1931 XYZ -> CIE 1960 uv -> ``colour.temperature.uv_to_CCT_Ohno2013``.
    Scale-invariant. With ``return_duv`` returns ``(CCT, Duv)``; Duv is the signed distance
    from the Planckian locus in CIE 1960 uv. Leading shapes are kept.
    """
    wl, v = check_spd(wavelengths, values, "cct")
    xyz = spd_to_xyz(wl, v)
    if np.any(xyz[..., 1] <= 0):
        raise ParameterError("cct: the SPD has no luminance (Y <= 0)")
    res = np.asarray(colour.temperature.uv_to_CCT_Ohno2013(_uv_1960(xyz)))
    return (res[..., 0], res[..., 1]) if return_duv else res[..., 0]


def _sd(wl, v, name="spd"):
    """colour-science SpectralDistribution with this module's interpolation/extrapolation."""
    return colour.SpectralDistribution(
        dict(zip(wl.tolist(), np.asarray(v, np.float64).tolist(), strict=True)),
        name=name,
        interpolator=colour.LinearInterpolator,
        extrapolator_kwargs={"method": "Constant", "left": None, "right": None},
    )


def cri(wavelengths, values) -> float | np.ndarray:
    """CIE 13.3-1995 general colour rendering index Ra (0-100, perfect = 100).

    Through ``colour.colour_rendering_index`` on the SPD interpolated linearly and extended
    with constant end values (this module's conventions). Scale-invariant. Leading shapes are
    evaluated one SPD at a time (CRI is not a per-pixel quantity).
    """
    wl, v = check_spd(wavelengths, values, "cri")
    flat = np.asarray(v, np.float64).reshape(-1, wl.size)
    if np.any(flat.sum(axis=-1) <= 0):
        raise ParameterError("cri: the SPD has no power (sum of values <= 0)")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", colour.utilities.ColourWarning)
        out = np.array([float(colour.colour_rendering_index(_sd(wl, s))) for s in flat])
    return float(out[0]) if v.ndim == 1 else out.reshape(v.shape[:-1])


# --------------------------------------------------------------------------- difference


def delta_e_2000(srgb_a, srgb_b) -> np.ndarray:
    """CIEDE2000 colour difference of two encoded sRGB colours (values in [0, 1]).

    Each is decoded (IEC 61966-2-1), converted to XYZ, then to CIELAB relative to the sRGB
    white (linear (1, 1, 1), i.e. D65 with Y = 1), and compared with CIEDE2000 (CIE
    142-2001, Sharma et al. 2005) through ``colour.difference.delta_E_CIE2000``
    (kL = kC = kH = 1). A difference of 1 is about one just-noticeable difference.
    """
    a = _check_triples(srgb_a, "delta_e_2000")
    b = _check_triples(srgb_b, "delta_e_2000")
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        raise ParameterError("delta_e_2000: colours contain NaN or infinite values")
    white = linear_srgb_to_xyz(np.ones(3))
    white_xy = white[:2] / white.sum()
    lab_a = colour.XYZ_to_Lab(linear_srgb_to_xyz(decode_srgb(np.asarray(a, np.float64))), white_xy)
    lab_b = colour.XYZ_to_Lab(linear_srgb_to_xyz(decode_srgb(np.asarray(b, np.float64))), white_xy)
    return np.asarray(colour.difference.delta_E_CIE2000(lab_a, lab_b))
