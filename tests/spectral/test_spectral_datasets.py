"""SPD sources (CSV, colour-science datasets) and the Mitsuba spectrum bridge."""

from __future__ import annotations

import colour
import numpy as np
import pytest

from spectrace import spectral as S
from spectrace.errors import FileAccessError, FileFormatError, ParameterError

MITSUBA_RTOL = 1e-5  # Mitsuba stores spectra in float32


def test_read_spd_csv(tmp_path):
    """A CSV with a header, comments, blank lines and mixed separators reads as written."""
    path = tmp_path / "spd.csv"
    path.write_text("# lamp\nwavelength,value\n400, 0.5\n\n450;0.75\n500\t1.0\n")
    wl, v = S.read_spd_csv(path)
    np.testing.assert_array_equal(wl, [400, 450, 500])
    np.testing.assert_array_equal(v, [0.5, 0.75, 1.0])


@pytest.mark.parametrize(
    "text,message",
    [
        ("400,1\n450,x\n", r":2: not a number"),
        ("400,1,2\n", "expected 2 columns"),
        ("400,1\n400,2\n", "duplicate wavelength"),
        ("500,1\n400,2\n", "sorted"),
        ("-400,1\n500,2\n", "positive"),
        ("400,nan\n500,2\n", "NaN"),
        ("wavelength,value\n", "no data rows"),
    ],
)
def test_malformed_csv_raises_user_error(tmp_path, text, message):
    """Malformed SPD files raise FileFormatError naming the file (and line) and the problem."""
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(FileFormatError, match=message) as err:
        S.read_spd_csv(path)
    assert "bad.csv" in str(err.value)
    with pytest.raises(FileAccessError, match="no such file"):
        S.read_spd_csv(tmp_path / "missing.csv")


def test_datasets_by_name():
    """Illuminants, light sources and ColorChecker patches come from colour-science's datasets."""
    wl, v, _ = S.load_spd("D65")
    np.testing.assert_array_equal(v, colour.SDS_ILLUMINANTS["D65"].values)
    wl, v, _ = S.load_spd("dark skin")
    np.testing.assert_array_equal(
        v, colour.SDS_COLOURCHECKERS["ColorChecker N Ohta"]["dark skin"].values
    )
    wl, v, _ = S.load_spd("BabelColor Average:dark skin")
    np.testing.assert_array_equal(
        v, colour.SDS_COLOURCHECKERS["BabelColor Average"]["dark skin"].values
    )
    wl, values, names = S.colorchecker()
    assert values.shape == (24, wl.size) and names[0] == "dark skin"
    with pytest.raises(ParameterError, match="not a known dataset"):
        S.load_spd("D99")


def test_mitsuba_spectrum_forms():
    """Regular grids covering 360-830 nm give 'regular', others 'irregular' padded to 360-830
    with the end values (constant extrapolation), unless extrapolation='zero'."""
    wl = np.arange(360.0, 831.0, 10.0)
    spec = S.to_mitsuba_spectrum(wl, np.linspace(0, 1, wl.size))
    assert spec["type"] == "regular" and spec["wavelength_min"] == 360.0
    spec = S.to_mitsuba_spectrum([400.0, 500.0, 700.0], [0.1, 0.5, 0.2])
    assert spec == {
        "type": "irregular",
        "wavelengths": "360, 400, 500, 700, 830",
        "values": "0.1, 0.1, 0.5, 0.2, 0.2",
    }
    spec = S.to_mitsuba_spectrum([400.0, 500.0, 700.0], [0.1, 0.5, 0.2], extrapolation="zero")
    assert spec["wavelengths"] == "400, 500, 700"
    xml = S.to_mitsuba_spectrum_xml("reflectance", [400.0, 500.0], [0.1, 0.5])
    assert xml.startswith('<spectrum type="irregular" name="reflectance">')
    with pytest.raises(ValueError, match="1-D"):
        S.to_mitsuba_spectrum([400.0, 500.0], [[0.1, 0.5]])


def test_mitsuba_evaluates_the_same_spd(variant_spectral, rng):
    """Mitsuba's spectrum from to_mitsuba_spectrum evaluates to our piecewise-linear SPD with
    constant extension, at random wavelengths over its whole 360-830 nm range."""
    import drjit as dr
    import mitsuba as mi

    wl, refl, _ = S.colorchecker()
    for values in (refl[3], refl[14]):
        tex = mi.load_dict(S.to_mitsuba_spectrum(wl, values))
        lam = rng.uniform(360, 830, (4, 64))
        si = dr.zeros(mi.SurfaceInteraction3f, 64)
        si.wavelengths = mi.Spectrum(*[mi.Float(row) for row in lam])
        got = np.array([np.array(c) for c in tex.eval(si)])
        np.testing.assert_allclose(got, np.interp(lam, wl, values), rtol=MITSUBA_RTOL)
