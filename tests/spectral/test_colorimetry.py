"""spectrace.spectral colorimetry against colour-science as the oracle, plus invariants."""

from __future__ import annotations

import colour
import numpy as np
import pytest

from spectrace import spectral as S

# Tolerances, named once.
#: our integration vs colour-science's on the same (linearly interpolated) SPD: they differ only
#: in the quadrature (trapezoid on the union grid vs 1 nm Riemann sum after resampling).
XYZ_RTOL_LINEAR = 2e-4
#: vs colour-science's default Sprague interpolation of smooth SPDs sampled every 5 nm.
XYZ_RTOL_DEFAULT = 1e-3
#: D65 white -> linear sRGB (1, 1, 1): the CIE D65 table vs the sRGB white's rounded xy.
WHITE_ATOL = 5e-4
ROUND_TRIP_ATOL = 1e-12
MATRIX_RTOL = 3e-4  # exact inverse of the IEC RGB->XYZ matrix vs its rounded inverse
ADAPT_ATOL = 1e-12
PLANCK_RTOL = 1e-12
CCT_ATOL_K = 1.0
CRI_ATOL = 1e-6
DE_ATOL = 1e-9

# colour-science warns that irregular oracle SPDs are not uniform; that is the point.
pytestmark = pytest.mark.filterwarnings("ignore::colour.utilities.ColourRuntimeWarning")

OBSERVERS = [S.CIE_1931_2, S.CIE_1964_10]
LINEAR = {
    "interpolator": colour.LinearInterpolator,
    "extrapolator_kwargs": {"method": "Constant", "left": None, "right": None},
}


def random_smooth_spd(rng, n=60, lo=None, hi=None):
    """An irregular grid over a random range and a smooth positive SPD sampled on it."""
    lo = rng.uniform(360, 420) if lo is None else lo
    hi = rng.uniform(680, 830) if hi is None else hi
    wl = np.sort(np.r_[lo, hi, rng.uniform(lo, hi, n - 2)])
    centres, widths, heights = (
        rng.uniform(380, 780, 3),
        rng.uniform(40, 150, 3),
        rng.uniform(0.1, 1, 3),
    )
    v = 0.05 + np.sum(heights * np.exp(-0.5 * ((wl[:, None] - centres) / widths) ** 2), axis=1)
    return wl, v


def colour_xyz(wl, v, illuminant=None, observer=S.CIE_1931_2, linear=True):
    """colour-science's XYZ / 100: its interpolation/extrapolation of the SPD onto the 1 nm CMF
    grid, then its ASTM E308 integration."""
    sd = colour.SpectralDistribution(dict(zip(wl, v, strict=True)), **(LINEAR if linear else {}))
    illum = None if illuminant is None else colour.SDS_ILLUMINANTS[illuminant]
    cmfs = colour.MSDS_CMFS[observer]
    sd = colour.SpectralDistribution(sd[cmfs.wavelengths], cmfs.wavelengths)
    return colour.sd_to_XYZ(sd, cmfs=cmfs, illuminant=illum, method="Integration") / 100


@pytest.mark.parametrize("observer", OBSERVERS)
@pytest.mark.parametrize("illuminant", [None, "D65", "A", "FL2"])
def test_random_smooth_spds_match_colour_science(rng, observer, illuminant):
    """On random irregular grids, XYZ is colour-science's sd_to_XYZ / 100 (emissive: integral
    S xbar / integral ybar; reflective: Y of white = 1), same interpolation and extrapolation."""
    for _ in range(5):
        wl, v = random_smooth_spd(rng)
        ours = S.spd_to_xyz(wl, v, illuminant, observer)
        np.testing.assert_allclose(
            ours, colour_xyz(wl, v, illuminant, observer), rtol=XYZ_RTOL_LINEAR
        )


@pytest.mark.parametrize("illuminant", [None, "D65", "A"])
def test_regular_smooth_spds_match_colour_default_interpolation(rng, illuminant):
    """On a regular 5 nm grid over 360-830 nm, linear interpolation of a smooth SPD gives the
    XYZ of colour-science's default (Sprague) interpolation, up to their interpolation gap."""
    wl = np.arange(360.0, 831.0, 5.0)
    for _ in range(3):
        _, v = wl, np.interp(wl, *random_smooth_spd(rng, n=200, lo=360.0, hi=830.0))
        default = colour_xyz(wl, v, illuminant, linear=False)
        np.testing.assert_allclose(S.spd_to_xyz(wl, v, illuminant), default, rtol=XYZ_RTOL_DEFAULT)


def test_leading_shape_is_kept(rng):
    """Values of shape (2, 3, N) give XYZ of shape (2, 3, 3), each equal to the 1-D result."""
    wl, _ = random_smooth_spd(rng)
    v = rng.uniform(0, 1, (2, 3, wl.size))
    xyz = S.spd_to_xyz(wl, v, "D65")
    assert xyz.shape == (2, 3, 3)
    np.testing.assert_allclose(xyz[1, 2], S.spd_to_xyz(wl, v[1, 2], "D65"), rtol=1e-12)


@pytest.mark.parametrize("observer", OBSERVERS)
def test_constant_spd_has_luminance_equal_to_its_value(observer):
    """Emissive normalisation: Y = integral c ybar / integral ybar = c (also tests each CMF's
    integral: X and Z of an equal-energy spectrum are integral xbar / integral ybar)."""
    cmfs = colour.MSDS_CMFS[observer]
    xyz = S.spd_to_xyz([500.0, 600.0], [2.5, 2.5], observer=observer)
    integrals = np.trapezoid(cmfs.values, cmfs.wavelengths, axis=0)
    np.testing.assert_allclose(xyz, 2.5 * integrals / integrals[1], rtol=1e-6)


def test_zero_extrapolation_cuts_the_spd_outside_its_range():
    """extrapolation='zero': a box SPD over 500-600 nm has Y = int_500^600 ybar / int ybar."""
    cmfs = colour.MSDS_CMFS[S.CIE_1931_2]
    wl = np.asarray(cmfs.wavelengths)
    ybar = cmfs.values[:, 1]
    inside = (wl >= 500) & (wl <= 600)
    expected = np.trapezoid(ybar[inside], wl[inside]) / np.trapezoid(ybar, wl)
    y = S.spd_to_xyz([500.0, 600.0], [1.0, 1.0], extrapolation="zero")[1]
    assert y == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("illuminant", ["D65", "A", "FL2", "D50"])
def test_perfect_white_has_unit_luminance(illuminant):
    """Reflective normalisation: a perfect reflector (R = 1) under any illuminant has Y = 1."""
    assert S.spd_to_xyz([380.0, 780.0], [1.0, 1.0], illuminant)[1] == pytest.approx(1.0, abs=1e-12)


def test_d65_white_is_linear_srgb_one():
    """IEC 61966-2-1: the D65 white (Y = 1) maps to linear sRGB (1, 1, 1), and encodes to 1."""
    rgb = S.xyz_to_linear_srgb(S.spd_to_xyz([380.0, 780.0], [1.0, 1.0], "D65"))
    np.testing.assert_allclose(rgb, 1.0, atol=WHITE_ATOL)
    np.testing.assert_allclose(S.encode_srgb(np.ones(3)), 1.0, atol=1e-15)


def test_illuminant_as_pair_equals_name():
    """An illuminant given as (wavelengths, values) gives the same XYZ as its name."""
    wl, v = S.illuminant("A")
    refl = np.linspace(0.2, 0.8, 41)
    grid = np.linspace(380, 780, 41)
    np.testing.assert_allclose(
        S.spd_to_xyz(grid, refl, (wl, v)), S.spd_to_xyz(grid, refl, "A"), rtol=1e-12
    )


def test_srgb_matrices_and_transfer_match_colour(rng):
    """Linear sRGB <-> XYZ and the transfer functions agree with colour-science's sRGB."""
    xyz = rng.uniform(0, 1, (50, 3))
    np.testing.assert_allclose(
        S.xyz_to_linear_srgb(xyz),
        colour.XYZ_to_RGB(xyz, "sRGB", apply_cctf_encoding=False),
        rtol=MATRIX_RTOL,
        atol=MATRIX_RTOL,
    )
    rgb = rng.uniform(0, 1, (50, 3))
    np.testing.assert_allclose(
        S.linear_srgb_to_xyz(rgb), colour.RGB_to_XYZ(rgb, "sRGB"), rtol=1e-12
    )
    np.testing.assert_allclose(S.encode_srgb(rgb), colour.cctf_encoding(rgb, "sRGB"), atol=1e-12)
    np.testing.assert_allclose(S.decode_srgb(rgb), colour.cctf_decoding(rgb, "sRGB"), atol=1e-12)
    np.testing.assert_allclose(S.xyz_to_srgb(xyz), S.encode_srgb(S.xyz_to_linear_srgb(xyz)), atol=0)


def test_round_trips(rng):
    """XYZ -> linear sRGB -> XYZ and decode(encode(x)) return the input, negatives included."""
    xyz = rng.uniform(-0.5, 2, (100, 3))
    np.testing.assert_allclose(
        S.linear_srgb_to_xyz(S.xyz_to_linear_srgb(xyz)), xyz, atol=ROUND_TRIP_ATOL
    )
    x = rng.uniform(-2, 2, 1000)
    np.testing.assert_allclose(S.decode_srgb(S.encode_srgb(x)), x, atol=ROUND_TRIP_ATOL)
    assert S.encode_srgb(np.float32(0.5)).dtype == np.float32


@pytest.mark.parametrize("method,theirs", list(S.CHROMATIC_ADAPTATION_METHODS.items()))
def test_chromatic_adaptation_matches_colour(rng, method, theirs):
    """Von Kries-type adaptation with Bradford / von Kries / CAT02 equals colour-science's."""
    xyz = rng.uniform(0, 1, (20, 3))
    w_d65, w_a = S.white_xyz("D65"), S.white_xyz("A")
    ours = S.chromatic_adaptation(xyz, "D65", "A", method)
    expected = colour.adaptation.chromatic_adaptation_VonKries(xyz, w_d65, w_a, transform=theirs)
    np.testing.assert_allclose(ours, expected, atol=ADAPT_ATOL)
    # the source white goes to the target white
    np.testing.assert_allclose(
        S.chromatic_adaptation(w_d65, w_d65, w_a, method), w_a, atol=ADAPT_ATOL
    )


def test_blackbody_matches_planck_law():
    """Planck's law in W/(m^2 sr nm) = colour's planck_law (W/(m^2 sr m), same constants) * 1e-9."""
    from colour.constants import CONSTANT_BOLTZMANN as k
    from colour.constants import CONSTANT_LIGHT_SPEED as c
    from colour.constants import CONSTANT_PLANCK as h

    wl = np.linspace(300, 1000, 71)
    temps = np.array([1000.0, 2856.0, 6504.0])
    ours = S.blackbody(wl, temps)
    assert ours.shape == (3, 71)
    for t, row in zip(temps, ours, strict=True):
        theirs = colour.colorimetry.planck_law(wl * 1e-9, t, c1=2 * np.pi * h * c**2, c2=h * c / k)
        np.testing.assert_allclose(row, theirs * 1e-9, rtol=PLANCK_RTOL)


def test_blackbody_wien_peak():
    """Wien's displacement law: the peak of a 5000 K blackbody is at b / T = 579.6 nm."""
    wl = np.linspace(400, 800, 40001)
    from scipy.constants import Wien

    assert wl[np.argmax(S.blackbody(wl, 5000.0))] == pytest.approx(Wien / 5000.0 * 1e9, abs=0.05)


@pytest.mark.parametrize("temperature", [2000.0, 4000.0, 6500.0, 10000.0])
def test_cct_of_blackbody_is_its_temperature(temperature):
    """A Planckian radiator's CCT is its temperature and its Duv is 0 (Ohno 2013)."""
    wl = np.arange(360.0, 831.0, 1.0)
    t, duv = S.cct(wl, S.blackbody(wl, temperature), return_duv=True)
    assert t == pytest.approx(temperature, abs=CCT_ATOL_K * temperature / 2000)
    assert abs(duv) < 1e-4


def test_cct_of_d65_and_cri_of_fl2_match_colour():
    """CCT of D65 ~ 6504 K (colour-science, Ohno 2013), CRI of FL2 = colour-science's Ra."""
    wl, v = S.illuminant("D65")
    expected = colour.temperature.uv_to_CCT_Ohno2013(
        colour.xy_to_UCS_uv(colour.XYZ_to_xy(S.spd_to_xyz(wl, v)))
    )[0]
    assert S.cct(wl, v) == pytest.approx(expected, abs=1e-6)
    assert 6495 < S.cct(wl, v) < 6510
    for name in ("FL2", "A", "FL11"):
        wl, v = S.illuminant(name)
        theirs = colour.colour_rendering_index(colour.SDS_ILLUMINANTS[name])
        assert S.cri(wl, v) == pytest.approx(theirs, abs=CRI_ATOL)


def test_cri_is_scale_invariant_and_100_for_incandescent():
    """Illuminant A (a Planckian radiator) renders colours perfectly (Ra = 100) at any scale."""
    wl, v = S.illuminant("A")
    assert S.cri(wl, 7.0 * v) == pytest.approx(100.0, abs=0.05)


def test_delta_e_2000_matches_colour(rng):
    """CIEDE2000 on encoded sRGB equals colour-science's delta_E on the same colours' CIELAB,
    computed entirely with colour-science (sRGB_to_XYZ, XYZ_to_Lab with the D65 white)."""
    a, b = rng.uniform(0, 1, (2, 100, 3))
    white = colour.CCS_ILLUMINANTS[S.CIE_1931_2]["D65"]
    lab = [
        colour.XYZ_to_Lab(colour.sRGB_to_XYZ(x), colour.RGB_COLOURSPACES["sRGB"].whitepoint)
        for x in (a, b)
    ]
    np.testing.assert_allclose(
        S.delta_e_2000(a, b), colour.delta_E(*lab, method="CIE 2000"), rtol=1e-3, atol=1e-3
    )
    assert np.all(S.delta_e_2000(a, a) < DE_ATOL)
    assert white is not None


BAD_SPDS = {
    "NaN": ([400.0, 500.0, 600.0], [1.0, np.nan, 1.0], "NaN"),
    "negative wavelength": ([-400.0, 500.0], [1.0, 1.0], "positive"),
    "unsorted": ([500.0, 400.0, 600.0], [1.0, 1.0, 1.0], "sorted"),
    "duplicate": ([400.0, 500.0, 500.0], [1.0, 1.0, 1.0], "duplicate"),
    "mismatched": ([400.0, 500.0, 600.0], [1.0, 1.0], "mismatched"),
    "empty": ([], [], "empty"),
    "NaN wavelength": ([400.0, np.nan], [1.0, 1.0], "NaN"),
}


@pytest.mark.parametrize("case", list(BAD_SPDS))
@pytest.mark.parametrize(
    "fn",
    [S.spd_to_xyz, S.cct, S.cri, lambda w, v: S.spectral_image_to_xyz(v, w)],
    ids=["spd_to_xyz", "cct", "cri", "spectral_image_to_xyz"],
)
def test_bad_input_raises_value_error_naming_the_problem(case, fn):
    """Bad SPDs never give a number: ValueError whose message names the problem."""
    wl, v, word = BAD_SPDS[case]
    with pytest.raises(ValueError, match=word):
        fn(np.asarray(wl), np.asarray(v))


def test_bad_options_raise():
    """Unknown observer, illuminant, extrapolation, adaptation method or temperature <= 0 raise."""
    with pytest.raises(ValueError, match="observer"):
        S.spd_to_xyz([400.0, 500.0], [1.0, 1.0], observer="CIE 1900")
    with pytest.raises(ValueError, match="illuminant"):
        S.spd_to_xyz([400.0, 500.0], [1.0, 1.0], illuminant="D99")
    with pytest.raises(ValueError, match="extrapolation"):
        S.spd_to_xyz([400.0, 500.0], [1.0, 1.0], extrapolation="mirror")
    with pytest.raises(ValueError, match="method"):
        S.chromatic_adaptation([0.5, 0.5, 0.5], "D65", "A", method="XYZ")
    with pytest.raises(ValueError, match="temperature"):
        S.blackbody([500.0], -5.0)
    with pytest.raises(ValueError, match="NaN"):
        S.delta_e_2000([np.nan, 0, 0], [0, 0, 0])
