"""Tests of the daylight factor (``spectrace.daylight``): closed forms of the sky component
and the EN 17037 targets."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from spectrace import daylight
from spectrace.errors import ParameterError

sys.path.insert(0, str(Path(__file__).resolve().parent / "plugins"))
import daylight_checks as day  # noqa: E402

#: Monte Carlo estimate of the sky component (2^18 meter samples: 0.4 % binomial noise).
RTOL_MC = 0.016


def test_daylight_factor_under_a_roof_opening(variant_rgb):
    """Under a horizontal a x b opening at height c and a uniform sky, the daylight factor
    below its centre is 100 F, F the configuration factor of the rectangle: E_in is read by
    Mitsuba's irradiancemeter, E_out comes from the scene's ciesky (not rendered)."""
    import mitsuba as mi

    a, b, c = 1.0, 1.0, 1.0
    light = {"type": "ciesky", "sky_type": "uniform", "horizontal_illuminance": 20000.0}
    scene = mi.load_dict({"type": "scene", "light": light})
    E_out = daylight.sky_horizontal_illuminance(scene)
    assert E_out == pytest.approx(20000.0, rel=1e-12)
    E_in = day.meter_lux(light, day.roof_with_opening(c, a, b), spp=2**18)
    df = daylight.daylight_factor(E_in, E_out)
    assert df == pytest.approx(100 * day.rectangle_configuration_factor(a, b, c), rel=RTOL_MC)


def test_configuration_factor_limits():
    """The configuration factor of the rectangle tends to 1 for an infinite opening and to
    A / (pi c^2) for a small one (the closed form behind the roof tests)."""
    assert day.rectangle_configuration_factor(1e6, 1e6, 1.0) == pytest.approx(1.0, rel=1e-5)
    assert day.rectangle_configuration_factor(1e-3, 2e-3, 1.0) == pytest.approx(
        2e-6 / np.pi, rel=1e-5)


def test_en17037_targets():
    """EN 17037: D = E / E_v,d,med x 100; at 15 000 lx the minimum level asks 2 % on half
    the plane and 0.67 % on 95 % of it."""
    targets = daylight.en17037_targets(15000.0)
    assert targets["minimum"] == pytest.approx((2.0, 100 / 150))
    assert targets["high"] == pytest.approx((5.0, 500 / 150))


def test_statistics():
    """Mean, median, minimum, shares above targets and the EN 17037 verdict of known
    values; NaNs (points off the plane) are ignored."""
    df = np.array([0.5, 1.0, 2.0, 3.0, 4.0, np.nan])
    s = daylight.statistics(df, targets=(2.0,), median_external_illuminance=15000.0)
    assert (s["mean"], s["median"], s["min"], s["max"], s["points"]) == (2.1, 2.0, 0.5, 4.0, 5)
    assert s["share_above"] == {2.0: 0.6}
    assert s["uniformity"] == pytest.approx(0.5 / 2.1)
    assert not s["en17037"]["minimum"]["met"]  # 0.5 % < 0.67 % on a fifth of the plane
    s = daylight.statistics(np.array([1.0, 2.5, 3.0]), median_external_illuminance=15000.0)
    assert s["en17037"]["minimum"]["met"] and not s["en17037"]["medium"]["met"]


def test_no_sky_is_an_error(variant_rgb):
    import mitsuba as mi

    scene = mi.load_dict({"type": "scene", "light": {"type": "constant"}})
    with pytest.raises(ParameterError, match="no ciesky"):
        daylight.sky_horizontal_illuminance(scene)
    with pytest.raises(ParameterError, match="E_outside"):
        daylight.daylight_factor(1.0, 0.0)


@pytest.mark.parametrize("variant_name", ["llvm_ad_rgb", "llvm_ad_spectral"])
def test_sky_component_under_a_roof_opening(variant_name):
    """``sky_component`` below the centre of a horizontal opening under the uniform sky is
    E_out F (F the configuration factor), within its own standard error, in RGB and
    spectral variants."""
    import mitsuba as mi

    import spectrace

    spectrace.set_variant(variant_name)
    a, b, c = 2.0, 1.0, 1.5
    light = {"type": "ciesky", "sky_type": "uniform", "horizontal_illuminance": 10000.0}
    scene = mi.load_dict({"type": "scene", "light": light, **day.roof_with_opening(c, a, b)})
    E, stderr = daylight.sky_component(scene, [[0, 0, 0]], spp=2**16)
    expected = 10000.0 * day.rectangle_configuration_factor(a, b, c)
    assert abs(E[0] - expected) < 4 * stderr[0] + 1e-3 * expected
    assert stderr[0] < 0.02 * expected  # a test that can tell 4 % apart


def test_fisheye_orientation(variant_rgb):
    """The fisheye image has the zenith luminance at its centre, NaN outside the circle,
    and (seen from below, north up) the sun of azimuth 90 degrees on the left."""
    import mitsuba as mi

    sky = mi.load_dict({"type": "ciesky", "sky_type": 12, "zenith_luminance": 2000.0,
                        "sun_azimuth": 90.0, "sun_elevation": 30.0})
    image = daylight.fisheye_luminance(sky, 65)
    assert image[32, 32] == pytest.approx(2000.0, rel=1e-4)
    assert np.isnan(image[0, 0]) and np.isfinite(image[32, 0])
    assert np.nanargmax(image) // 65 == 32 and np.nanargmax(image) % 65 < 32


def test_lux_daylight_factor_flag(tmp_path, capsys):
    """``spectrace lux --daylight-factor E_MED`` prints the DF statistics against the sky's
    E_out and EN 17037's verdicts; a scene without a ciesky is one error line, exit 2,
    before anything is rendered or written."""
    from spectrace.cli import main

    scene = Path(__file__).resolve().parents[1] / "scenes" / "daylight_room.xml"
    out = tmp_path / "room.exr"
    assert main(["lux", str(scene), "-o", str(out), "--plane", "0,0.85,0 0,1,0",
                 "-D", "res=16", "--spp", "16", "-q", "--daylight-factor", "15000"]) == 0
    text = capsys.readouterr().out
    assert "E_out 10000 lx" in text and "DF_median" in text and "EN 17037 minimum" in text
    other = Path(__file__).resolve().parents[1] / "scenes" / "closed_box.xml"
    out = tmp_path / "box.exr"
    assert main(["lux", str(other), "-o", str(out), "-D", "res=8", "--spp", "4", "-q",
                 "--daylight-factor"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error:") and "no ciesky" in err and len(err.splitlines()) == 1
    assert not out.exists()
