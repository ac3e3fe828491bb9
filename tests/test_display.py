"""The display pipeline (spectrace.display) against independent oracles: colour-science for
the colorimetry (primaries, Planckian locus, chromatic adaptation), OpenColorIO's own
processor for the ACES view, exposure arithmetic by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from spectrace import display
from spectrace.display import DisplaySettings, develop
from spectrace.errors import ParameterError

#: one 8-bit or 16-bit code: what rounding may move
CODE_TOL = 1
#: IEC 61966-2-1 tabulates both of its sRGB matrices to 4 digits: they are each other's
#: inverse to about 1e-4 (colour-science's XYZ_to_RGB uses the tabulated inverse)
IEC_TABLE_TOL = 5e-4


@pytest.fixture(scope="module")
def colour():
    return pytest.importorskip("colour")


@pytest.fixture
def rgb():
    rng = np.random.default_rng(1)
    return rng.uniform(0.0, 2.0, (6, 5, 3)).astype(np.float32)


def test_primary_matrices_match_colour_science(colour):
    """The RGB -> XYZ matrices of sRGB (IEC 61966-2-1's table) and Display P3 (derived from
    its primaries) are colour-science's."""
    for name, theirs in (("srgb", "sRGB"), ("display-p3", "Display P3")):
        expected = colour.RGB_COLOURSPACES[theirs].matrix_RGB_to_XYZ
        np.testing.assert_allclose(display.rgb_to_xyz_matrix(name), expected, atol=1e-7)


@pytest.mark.parametrize("cct", [1700.0, 2222.0, 3000.0, 4000.0, 6504.0, 12000.0])
def test_planckian_xy_is_kang_2002(colour, cct):
    """The Planckian chromaticity is colour-science's Kang et al. 2002 fit."""
    expected = colour.temperature.CCT_to_xy_Kang2002(cct)
    np.testing.assert_allclose(display.planckian_xy(cct), expected, atol=1e-12)


@pytest.mark.parametrize("method", list(display.CAT_METHODS))
def test_adaptation_matrix_matches_colour_science(colour, method):
    """The von Kries matrix from 3000 K to D65 is colour-science's, for each transform
    (CAT16 and Bradford)."""
    source = display.xy_to_XYZ(display.planckian_xy(3000.0))
    target = display.xy_to_XYZ(display.D65_XY)
    expected = colour.adaptation.matrix_chromatic_adaptation_VonKries(source, target,
                                                                      transform=method)
    np.testing.assert_allclose(display.adaptation_matrix(source, target, method), expected,
                               rtol=1e-10, atol=1e-12)


def test_white_balance_makes_the_light_neutral(colour):
    """--white-balance 3000K: a white surface lit by a 3000 K Planckian light (its linear
    sRGB from colour-science) comes out neutral (R = G = B), with its luminance kept."""
    xy = colour.temperature.CCT_to_xy_Kang2002(3000.0)
    white = colour.XYZ_to_RGB(colour.xy_to_XYZ(xy), "sRGB")  # Y = 1, linear sRGB
    M = display.white_balance_matrix(white[None, None, :], "3000K")
    out = M @ white
    np.testing.assert_allclose(out, np.full(3, out[1]), rtol=IEC_TABLE_TOL)
    assert out @ np.array([0.2126, 0.7152, 0.0722]) == pytest.approx(1.0, rel=1e-3)


def test_white_balance_d65_and_none_change_nothing(rgb):
    """D65 is the render's own white: its adaptation is the identity; none is no matrix."""
    np.testing.assert_array_equal(display.white_balance_matrix(rgb, "D65"), np.eye(3))
    assert display.white_balance_matrix(rgb, "none") is None


def test_grey_world_white_balance_neutralises_the_mean(rgb):
    """auto (grey world): the image's mean colour becomes neutral."""
    tinted = rgb * np.array([1.0, 0.7, 0.4], np.float32)
    M = display.white_balance_matrix(tinted, "auto")
    mean = M @ tinted.reshape(-1, 3).mean(axis=0)
    np.testing.assert_allclose(mean, np.full(3, mean[1]), rtol=1e-6)


def test_exposure_arithmetic_by_hand(rgb):
    """EV: 2^EV. auto: 0.18 / exp(mean(ln Y)). EV100 N: 683 * 106.857 / (1.2 * 2^N) (78 / (100
    * 0.65) = 1.2)."""
    scale, _ = display.exposure_scale(rgb, DisplaySettings(exposure=-1.5))
    assert scale == 2.0**-1.5
    Y = (rgb.astype(np.float64) @ np.array([0.2126, 0.7152, 0.0722])).ravel()
    scale, line = display.exposure_scale(rgb, DisplaySettings(exposure="auto"))
    assert scale == pytest.approx(0.18 / math.exp(np.log(Y).mean()), rel=1e-12)
    assert "auto" in line
    scale, _ = display.exposure_scale(rgb, DisplaySettings(ev100=8.0))
    assert scale == pytest.approx(683.0 * 106.857 / (1.2 * 256.0), rel=1e-12)
    scale, _ = display.exposure_scale(rgb, DisplaySettings(ev100=8.0, exposure=1.0))
    assert scale == pytest.approx(2 * 683.0 * 106.857 / (1.2 * 256.0), rel=1e-12)


def test_an_office_at_ev100_8_to_9_is_well_exposed():
    """A wall of reflectance 0.5 under 500 lux (L = E rho / pi = 79.6 cd/m^2) shows at
    display value 0.26 at EV100 8 and 0.13 at EV100 9: mid-tones, neither black nor
    clipped."""
    L = 500.0 * 0.5 / math.pi
    Y = L / display.LUMINANCE_PER_Y
    wall = np.full((2, 2, 3), Y, np.float32)
    for ev100, expected in ((8.0, 0.259), (9.0, 0.130)):
        scale, _ = display.exposure_scale(wall, DisplaySettings(ev100=ev100))
        assert scale * Y == pytest.approx(expected, abs=0.001)


def test_luminance_per_y_is_the_luminous_plugins_convention():
    """LUMINANCE_PER_Y is K_m times integral V dlambda as the luminous plugins compute it."""
    import spectrace

    spectrace.set_variant("llvm_ad_rgb")
    from spectrace.plugins.emitters import luminous

    assert display.LUMINANCE_PER_Y == pytest.approx(
        luminous.KM * luminous.v_integral(), rel=1e-5)


def test_standard_view_is_the_plain_png(rgb):
    """The default settings give the codes of today's PNG (spectrace.images.encode_srgb_8bit)."""
    from spectrace.images import encode_srgb_8bit

    np.testing.assert_array_equal(develop(rgb).codes, encode_srgb_8bit(rgb))


def test_sixteen_bits_and_exposure_by_hand(rgb, colour):
    """16-bit codes are round(65535 * sRGB(clip(2^EV x))), the sRGB curve colour-science's."""
    out = develop(rgb, DisplaySettings(exposure=-2.0, png_bits=16)).codes
    assert out.dtype == np.uint16
    expected = np.round(65535 * colour.cctf_encoding(np.clip(rgb * 0.25, 0, 1), "sRGB"))
    np.testing.assert_allclose(out, expected, atol=CODE_TOL)


def test_display_p3_encoding_matches_colour_science(rgb, colour):
    """display-p3: linear sRGB converted to P3-D65 by colour-science, clipped, sRGB curve."""
    rgb = rgb / 4.0
    out = develop(rgb, DisplaySettings(display="display-p3", png_bits=16)).codes
    p3 = colour.RGB_to_RGB(rgb.astype(np.float64), "sRGB", "Display P3")
    expected = np.round(65535 * colour.cctf_encoding(np.clip(p3, 0, 1), "sRGB"))
    np.testing.assert_allclose(out, expected, atol=CODE_TOL)


def test_aces_view_matches_ocio_from_aces2065_1(rgb, colour):
    """aces: the same codes as OCIO's ACES 2.0 SDR view applied to the image converted to
    ACES2065-1 by colour-science (Bradford from D65 to the ACES white): the linear sRGB is
    mapped to ACES2065-1 properly."""
    ocio = pytest.importorskip("PyOpenColorIO")
    config = ocio.Config.CreateFromBuiltinConfig(display.OCIO_CONFIG)
    processor = config.getProcessor("ACES2065-1", *display.OCIO_ACES_VIEWS["srgb"],
                                    ocio.TRANSFORM_DIR_FORWARD).getDefaultCPUProcessor()
    aces = colour.RGB_to_RGB(rgb.astype(np.float64), "sRGB", "ACES2065-1",
                             chromatic_adaptation_transform="Bradford").astype(np.float32)
    processor.applyRGB(aces)
    expected = np.round(np.clip(aces, 0, 1) * 255)
    out = develop(rgb, DisplaySettings(view="aces")).codes
    np.testing.assert_allclose(out, expected, atol=CODE_TOL)
    assert not np.array_equal(out, develop(rgb).codes)  # a tone curve, not the clip


def test_false_colour_maps_luminance_on_a_log_scale():
    """false-colour: a pixel of L cd/m^2 gets the colour map's value at (log10 L - log10
    low) / decades; the colour bar is added on the right; exposure does not apply."""
    from matplotlib import colormaps

    L = np.array([[10.0, 100.0], [1000.0, 5000.0]])
    rgb = np.repeat((L / display.LUMINANCE_PER_Y)[..., None], 3, axis=-1).astype(np.float32)
    out = develop(rgb, DisplaySettings(view="false-colour"))
    low, high = display.false_colour_range(L)
    assert (low, high) == (1.0, 1e4)
    assert out.codes.shape[1] == 2 + display.LEGEND_MIN_PX
    t = np.log10(L) / display.FALSE_COLOUR_DECADES
    expected = np.round(colormaps[display.FALSE_COLOUR_MAP](t)[..., :3] * 255)
    np.testing.assert_allclose(out.codes[:, :2], expected, atol=CODE_TOL)
    exposed = develop(rgb, DisplaySettings(view="false-colour", exposure=3.0))
    np.testing.assert_array_equal(exposed.codes, out.codes)


def test_nan_and_infinite_values_show_black():
    """A NaN or infinite pixel (never in a render, possible in a file) shows as 0."""
    rgb = np.array([[[np.nan, np.inf, -np.inf]]], np.float32)
    assert develop(rgb, DisplaySettings(exposure="auto")).codes.tolist() == [[[0, 0, 0]]]


@pytest.mark.parametrize("settings, message", [
    ({"view": "filmic"}, "unknown view"),
    ({"exposure": "nan"}, "finite"),
    ({"exposure": float("inf")}, "finite"),
    ({"ev100": float("nan")}, "ev100"),
    ({"white_balance": "0K"}, "colour temperature"),
    ({"white_balance": "warm"}, "white_balance"),
    ({"display": "rec2020"}, "unknown display"),
    ({"png_bits": 12}, "png_bits"),
    ({"exposure": "auto", "ev100": 8.0}, "exclude"),
])
def test_bad_settings_name_the_parameter(settings, message):
    """Bad settings raise ParameterError naming the setting."""
    with pytest.raises(ParameterError, match=message):
        DisplaySettings(**settings)


def test_photometric_scene_detection():
    """A scene with an ieslight or a luminous_* parameter is photometric; the showcase is not."""
    import xml.etree.ElementTree as ET
    from pathlib import Path

    scenes = Path(__file__).resolve().parents[1] / "scenes"
    assert display.photometric_scene(ET.parse(scenes / "luminaires.xml").getroot())
    assert not display.photometric_scene(ET.parse(scenes / "showcase.xml").getroot())
    point = ET.fromstring('<scene><emitter type="pointlight"><float name="luminous_flux" '
                          'value="800"/></emitter></scene>')
    assert display.photometric_scene(point)


PLANE_SCENE = """<scene version="3.0.0">
<integrator type="direct"/>
<sensor type="perspective"><float name="fov" value="4"/>
<transform name="to_world"><lookat origin="0, 0, 1" target="0, 0, 0" up="0, 1, 0"/></transform>
<sampler type="independent"><integer name="sample_count" value="16"/></sampler>
<film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
</sensor>
<emitter type="pointlight"><point name="position" x="0" y="0" z="1"/>
<float name="luminous_intensity" value="100"/></emitter>
<shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
</scene>"""
#: the plane's luminance varies by cos^4 over the 4-degree view, and 16 spp of direct light
PHOTOMETRIC_RTOL = 0.01


@pytest.mark.parametrize("variant", ["llvm_ad_rgb", "llvm_ad_spectral"])
def test_luminance_per_y_end_to_end(tmp_path, variant):
    """100 cd at 1 m over a grey (0.5) Lambertian plane: E = 100 lx, L = E rho / pi = 15.92
    cd/m^2; the render's Y times LUMINANCE_PER_Y gives that luminance (the false-colour
    view's and --ev100's scale), in RGB and spectral variants."""
    from spectrace.cli import main
    from spectrace.images import read_exr

    scene = tmp_path / "plane.xml"
    scene.write_text(PLANE_SCENE)
    out = tmp_path / "plane.exr"
    assert main(["render", str(scene), "-o", str(out), "-q", "--variant", variant]) == 0
    rgb, _ = read_exr(out)
    L = display.luminance(rgb.astype(np.float64)).mean() * display.LUMINANCE_PER_Y
    assert L == pytest.approx(100 * 0.5 / math.pi, rel=PHOTOMETRIC_RTOL)


def test_neutral_view_by_hand():
    """Khronos PBR Neutral, worked by hand: (0.5, 0.3, 0.2) is below the compression start:
    minus the offset 0.04 -> (0.46, 0.26, 0.16); (2, 1, 0.5): offset 0.04, peak 1.96,
    new peak 1 - 0.24^2 / (1.96 + 0.24 - 0.76) = 0.96, desaturation g = 1 - 1 / (0.15 (1.96
    - 0.96) + 1) = 0.1304; white (10, 10, 10) stays neutral and below 1."""
    from spectrace.spectral.srgb import decode_srgb

    rgb = np.array([[[0.5, 0.3, 0.2], [2.0, 1.0, 0.5], [10.0, 10.0, 10.0]]])
    out = decode_srgb(display.view_neutral(rgb, "srgb"))[0]
    np.testing.assert_allclose(out[0], [0.46, 0.26, 0.16], rtol=1e-12)
    peak, new_peak = 1.96, 1 - 0.24**2 / 1.44
    g = 1 - 1 / (0.15 * (peak - new_peak) + 1)
    expected = np.array([1.96, 0.96, 0.46]) * new_peak / peak * (1 - g) + new_peak * g
    np.testing.assert_allclose(out[1], expected, rtol=1e-12)
    assert out[2][0] == pytest.approx(out[2][1]) == pytest.approx(out[2][2])
    assert 0.99 < out[2][0] < 1.0
