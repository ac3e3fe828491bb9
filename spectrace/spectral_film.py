"""Spectral film for ``spectrace render --film spectral --bands N``.

:func:`replace_film` swaps every sensor's film in a parsed Mitsuba scene for Mitsuba's
``specfilm`` with N band response functions; :func:`bands_to_linear_srgb` turns the rendered
(H, W, N) band image into linear sRGB through :mod:`spectrace.spectral`. The render path:

    centres = replace_film(root, bands)             # root: ElementTree of the scene XML
    raw = mi.render(mi.load_string(ET.tostring(root, encoding="unicode")))
    bands = film_to_bands(raw, centres)             # band-averaged spectral radiance
    rgb = bands_to_linear_srgb(bands, centres)      # (H, W, 3) linear sRGB
    write_spectral_exr(path, bands, centres, preview=rgb)

Band response functions (why hats, not boxes): for N >= 2 the bands are the N "hat"
functions of piecewise-linear interpolation at the centres c_i = linspace(lo, hi, N):
hat_i(l) = max(0, 1 - |l - c_i| / d) with d = (hi - lo) / (N - 1), the two end bands being
half hats. specfilm gets the hats themselves (peak 1). They sum to 1 over [lo, hi], so its
combined response (the density it samples wavelengths from, and divides by) is flat: every
wavelength in [lo, hi] is sampled alike, as with the hdrfilm, and all bands share all
samples (no extra spectral noise). Both the flat sum and the unit peak matter: with
unit-area hats (sum sloped at the ends) or with hats scaled to peak 1/d (flat sum of
0.06), Mitsuba 3.9's specfilm was measured to be off by up to 35% in most bands whenever
its internal sampling grid (step = the finest response interval, rounded up) misses the
knots, e.g. 18 or 19 bands over 400-700 nm; peak-1 hats are exact (to the noise) for every
N tried (tests/spectral/test_spectral_film.py). A raw channel is integral L hat_i (the
radiance unit times nm); :func:`film_to_bands` divides it by integral hat_i (d, d/2 for the
end bands) into

    B_i = integral L(l) hat_i(l) dl / integral hat_i(l) dl,

a local average of the spectral radiance around c_i in the film's unit (W m^-2 sr^-1 nm^-1
for Mitsuba's emitters). N = 1 is one box over [lo, hi] with response 1 / (hi - lo), so its
raw channel is already the average; its centre is (lo + hi) / 2.

Reconstruction (:func:`bands_to_linear_srgb`): L is modelled as the piecewise-linear
function sum_j l_j hat_j through the centres. Its band averages are B = G l with the
banded Gram matrix G_ij = integral hat_i hat_j / integral hat_i (rows 1/6, 2/3, 1/6; ends
2/3, 1/3), so l = G^-1 B, and l goes through :func:`spectrace.spectral.spectral_image_to_xyz`
(linear interpolation between the centres, constant beyond: CIE 015 extrapolation) and
:func:`spectrace.spectral.xyz_to_linear_srgb`. All of it is linear, so it is applied as one
precomputed (N, 3) matrix G^-T W M^T. Reading B as samples directly (skipping G^-1) blurs
the spectrum twice and costs up to 1.3 CIEDE2000 on the ColorChecker at 16 bands; with it
the band quantisation error is < 0.25 at 16 bands over 400-700 nm, the rest of it from
the radiance outside [lo, hi], which is not rendered (tests/spectral/test_spectral_film.py).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np

from spectrace.errors import ParameterError
from spectrace.spectral import apply_spectral_weights, xyz_weights
from spectrace.spectral.colorimetry import _M_XYZ_TO_RGB, check_wavelengths

__all__ = [
    "band_centres",
    "band_gram_matrix",
    "band_responses",
    "bands_to_linear_srgb",
    "bands_to_xyz",
    "film_to_bands",
    "replace_film",
]

BAND_NAME = "band{:03d}"  # zero-padded: specfilm orders channels by name, = wavelength order


def band_centres(bands: int, wavelength_range=(400.0, 700.0)) -> np.ndarray:
    """Centre wavelengths (nm) of the N bands: linspace(lo, hi, N), or the middle for N = 1."""
    lo, hi = _check(bands, wavelength_range)
    if bands == 1:
        return np.array([(lo + hi) / 2])
    return np.linspace(lo, hi, bands)


def band_responses(
    bands: int, wavelength_range=(400.0, 700.0)
) -> list[tuple[np.ndarray, np.ndarray]]:
    """(wavelengths, values) of the specfilm response of each band: hat_i, peak 1.

    The responses sum to 1 everywhere in [lo, hi] (see the module notes); N = 1: a box of
    height 1 / (hi - lo) (1/nm).
    """
    lo, hi = _check(bands, wavelength_range)
    if bands == 1:
        return [(np.array([lo, hi]), np.full(2, 1.0 / (hi - lo)))]
    c = np.linspace(lo, hi, bands)
    return [
        (c[max(i - 1, 0) : i + 2], (c[max(i - 1, 0) : i + 2] == c[i]).astype(np.float64))
        for i in range(bands)
    ]


def film_to_bands(image, wavelengths) -> np.ndarray:
    """Band-averaged spectral radiance (H, W, N) float32 from a :func:`replace_film` render.

    ``wavelengths``: the centres :func:`replace_film` returned. Divides channel i by
    integral hat_i: d = the centre spacing, d/2 for the two end bands (half hats); one band
    (a box already normalised) is kept. The result B_i = integral L hat_i / integral hat_i is
    in the radiance unit of the scene per nm (W m^-2 sr^-1 nm^-1), what
    :func:`bands_to_linear_srgb` and :func:`spectrace.spectral.write_spectral_exr` expect.
    """
    c = check_wavelengths(wavelengths, "film_to_bands")
    img = np.array(image, dtype=np.float32)  # a copy: the render's tensor stays as it is
    if img.ndim < 1 or img.shape[-1] != c.size:
        raise ParameterError(
            f"film_to_bands: image has shape {img.shape}, expected (..., {c.size}) channels "
            "(mismatched lengths)"
        )
    if c.size > 1:
        d = np.diff(c)
        if not np.allclose(d, d[0], rtol=1e-9, atol=0):
            raise ParameterError(
                "film_to_bands: band centres must be evenly spaced (replace_film's)")
        widths = np.full(c.size, d[0])
        widths[[0, -1]] = d[0] / 2
        img /= widths.astype(np.float32)
    return img


def _check(bands, wavelength_range):
    if isinstance(bands, bool) or not isinstance(bands, (int, np.integer)) or bands < 1:
        raise ParameterError(f"bands must be an integer >= 1 (got {bands!r})")
    try:
        lo, hi = (float(x) for x in wavelength_range)
    except (TypeError, ValueError):
        raise ParameterError(
            f"wavelength range must be two numbers in nm (got {wavelength_range!r})"
        ) from None
    if not (np.isfinite(lo) and np.isfinite(hi) and 0 < lo < hi):
        raise ParameterError(
            f"wavelength range must satisfy 0 < lo < hi nm (got {wavelength_range!r})")
    return lo, hi


def _numbers(a) -> str:
    return ", ".join(np.format_float_positional(float(x), trim="-") for x in a)


def _specfilm(sensor: ET.Element, bands, wavelength_range) -> ET.Element:
    from spectrace.scene import new_film

    film = new_film(sensor, "specfilm", keep_rfilter=True)
    ET.SubElement(film, "string", {"name": "component_format", "value": "float32"})
    for i, (wl, values) in enumerate(band_responses(bands, wavelength_range)):
        srf = ET.SubElement(film, "spectrum", {"type": "irregular", "name": BAND_NAME.format(i)})
        ET.SubElement(srf, "string", {"name": "wavelengths", "value": _numbers(wl)})
        ET.SubElement(srf, "string", {"name": "values", "value": _numbers(values)})
    return film


def replace_film(root: ET.Element, bands: int = 16, wavelength_range=(400.0, 700.0)) -> np.ndarray:
    """Make every sensor in the scene tree ``root`` render ``bands`` spectral bands.

    Modifies ``root`` in place: each ``<sensor>``'s ``<film>`` (or Mitsuba's default film
    when it has none) becomes a ``specfilm`` with the band responses of the module notes,
    float32 output, keeping the original film's id, width, height, crop and sample_border
    parameters and its ``<rfilter>`` (values such as ``$res`` are copied verbatim). Needs a
    spectral variant (``llvm_ad_spectral``). ``mi.render`` then returns an (H, W, N) image
    of the band responses, bands in increasing wavelength; :func:`film_to_bands` turns it into
    band-averaged spectral radiance. Returns the band centres (nm).
    Raises :class:`~spectrace.errors.SpectraceError` for bands < 1, a bad range, or no sensor.
    """
    centres = band_centres(bands, wavelength_range)
    sensors = list(root.iter("sensor"))
    if not sensors:
        raise ParameterError("the scene has no <sensor>: a spectral film needs one")
    for sensor in sensors:
        _specfilm(sensor, bands, wavelength_range)
    return centres


def band_gram_matrix(wavelengths) -> np.ndarray:
    """G with B = G l: band averages B of the piecewise-linear spectrum through (c_j, l_j).

    G_ij = integral hat_i hat_j / integral hat_i for hats on the (sorted) centres
    ``wavelengths``, closed form: G_ii = 2/3, G_i,i+1 = d_i / (3 (d_i-1 + d_i)),
    G_i,i-1 = d_i-1 / (3 (d_i-1 + d_i)), d_i = c_i+1 - c_i (d = 0 beyond the ends).
    One centre: [[1]] (a box band of a constant spectrum).
    """
    c = check_wavelengths(wavelengths, "band_gram_matrix")
    n = c.size
    g = np.eye(n)
    if n == 1:
        return g
    d = np.diff(c)
    left = np.r_[0.0, d]  # d_{i-1}
    right = np.r_[d, 0.0]  # d_i
    g *= 2.0 / 3.0
    i = np.arange(n)
    g[i[:-1], i[:-1] + 1] = right[:-1] / (3 * (left[:-1] + right[:-1]))
    g[i[1:], i[1:] - 1] = left[1:] / (3 * (left[1:] + right[1:]))
    return g


def _band_matrix(wavelengths, to_rgb: bool) -> np.ndarray:
    c = check_wavelengths(wavelengths, "bands_to_linear_srgb")
    w = np.linalg.solve(band_gram_matrix(c).T, xyz_weights(c))
    return w @ _M_XYZ_TO_RGB.T if to_rgb else w


def bands_to_xyz(image, wavelengths) -> np.ndarray:
    """CIE 1931 XYZ (H, W, 3) float32 of band-averaged radiance; see bands_to_linear_srgb."""
    return apply_spectral_weights(np.asarray(image, np.float32), _band_matrix(wavelengths, False))


def bands_to_linear_srgb(image, wavelengths) -> np.ndarray:
    """Linear sRGB (H, W, 3) float32 of band-averaged radiance (:func:`film_to_bands`).

    ``wavelengths``: the band centres that :func:`replace_film` returned. The bands are
    deconvolved into samples of the spectral radiance at the centres (l = G^-1 B, see the
    module notes) and converted as by ``xyz_to_linear_srgb(spectral_image_to_xyz(l, c))``
    (emissive: X = integral L xbar / integral ybar, CIE 1931 2 degree, constant extension
    outside the bands), all as one precomputed (N, 3) matrix applied in one pass.
    This is the scale of Mitsuba's hdrfilm in ``llvm_ad_spectral``, which converts radiance
    to XYZ with the same normalisation (1 / integral ybar) and then to linear sRGB: a white
    diffuse surface under a ``d65`` environment gives (1, 1, 1) in both, and the same scene
    agrees up to noise and band quantisation.
    """
    return apply_spectral_weights(np.asarray(image, np.float32), _band_matrix(wavelengths, True))
