"""`spectrace spd`: colorimetry of an SPD file or dataset, checked against colour-science."""

from __future__ import annotations

import os
import re
import stat

import colour
import numpy as np
import pytest

from spectrace.cli import main

# colour-science warns when it resamples the oracle data; expected here.
pytestmark = pytest.mark.filterwarnings("ignore::colour.utilities.ColourRuntimeWarning")

XYZ_RTOL = 1e-3  # printed with 6 significant digits; linear vs Sprague resampling of 5 nm data
CCT_ATOL_K = 2.0
CRI_ATOL = 0.05  # printed with one decimal


def run(capsys, *argv):
    rc = main(["spd", *argv])
    out, err = capsys.readouterr()
    return rc, out, err


def numbers(out, label):
    line = next(line for line in out.splitlines() if line.startswith(label))
    return [float(x) for x in re.findall(r"[-+]?\d+\.?\d*(?:[eE][-+]?\d+)?", line[len(label) :])]


@pytest.mark.parametrize("name", ["D65", "A", "FL2"])
def test_illuminant_numbers_match_colour(capsys, name):
    """XYZ (emissive, integral S xbar / integral ybar), xy, CCT and CRI of a CIE illuminant
    agree with colour-science's sd_to_XYZ / 100, XYZ_to_xy, CCT (Ohno 2013) and CRI."""
    rc, out, err = run(capsys, name)
    assert rc == 0 and err == ""
    sd = colour.SDS_ILLUMINANTS[name]
    xyz = colour.sd_to_XYZ(sd, method="Integration") / 100
    np.testing.assert_allclose(numbers(out, "XYZ"), xyz, rtol=XYZ_RTOL)
    np.testing.assert_allclose(numbers(out, "xy"), colour.XYZ_to_xy(xyz), atol=1e-4)
    cct = colour.temperature.uv_to_CCT_Ohno2013(colour.xy_to_UCS_uv(colour.XYZ_to_xy(xyz)))[0]
    assert numbers(out, "CCT")[0] == pytest.approx(cct, abs=CCT_ATOL_K)
    assert numbers(out, "CRI Ra")[0] == pytest.approx(
        colour.colour_rendering_index(sd), abs=CRI_ATOL
    )


def test_d65_is_white_and_csv_equals_dataset(capsys, tmp_path):
    """D65's colour is sRGB white #ffffff; the same SPD from a CSV file prints the same XYZ."""
    rc, out, _ = run(capsys, "D65")
    assert "#ffffff" in out
    sd = colour.SDS_ILLUMINANTS["D65"]
    path = tmp_path / "d65.csv"
    path.write_text(
        "wavelength,value\n"
        + "".join(f"{w},{v}\n" for w, v in zip(sd.wavelengths, sd.values, strict=True))
    )
    rc2, out2, _ = run(capsys, str(path))
    assert rc2 == 0
    assert numbers(out2, "XYZ") == numbers(out, "XYZ")


def test_reflectance_under_d65(capsys):
    """--reflectance: a ColorChecker patch's XYZ under D65 (white Y = 1) = colour's / 100."""
    rc, out, _ = run(capsys, "dark skin", "--reflectance")
    assert rc == 0 and "CCT" not in out
    sd = colour.SDS_COLOURCHECKERS["ColorChecker N Ohta"]["dark skin"]
    xyz = colour.sd_to_XYZ(sd, illuminant=colour.SDS_ILLUMINANTS["D65"], method="Integration") / 100
    np.testing.assert_allclose(numbers(out, "XYZ")[:3], xyz, rtol=XYZ_RTOL)


def test_plot_writes_png_with_the_umask_mode(capsys, tmp_path):
    """--plot writes a PNG file whose mode follows the umask like every other output
    (not mkstemp's 0600)."""
    png = tmp_path / "a.png"
    old = os.umask(0o022)
    try:
        rc, out, _ = run(capsys, "A", "--plot", str(png))
    finally:
        os.umask(old)
    assert rc == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert stat.S_IMODE(png.stat().st_mode) == 0o644


def test_reflectance_dataset_is_described_as_a_reflectance(capsys):
    """A ColorChecker patch is a reflectance: without --reflectance it is still shown under
    D65 (same XYZ as with it), and no CCT or CRI (which describe light sources) is printed."""
    rc, out, _ = run(capsys, "dark skin")
    rc2, out2, _ = run(capsys, "dark skin", "--reflectance")
    assert rc == rc2 == 0
    assert "CCT" not in out and "CRI" not in out and "reflectance" in out
    assert numbers(out, "XYZ")[:3] == numbers(out2, "XYZ")[:3]


def test_bad_plot_path_writes_nothing(capsys, tmp_path):
    """--plot to a non-PNG name is refused before anything is computed or written."""
    rc, out, err = run(capsys, "A", "--plot", str(tmp_path / "a.jpg"))
    assert rc == 2 and err.startswith("error: --plot") and not list(tmp_path.iterdir())


@pytest.mark.parametrize(
    "content,message",
    [
        (None, "no such file"),
        ("wavelength,value\n400,1\n450,abc\n", "not a number"),
        ("400,1\n400,2\n", "duplicate"),
        ("400,-1\n500,-2\n", "negative value -1 at 400 nm"),
        ("400,1\n500,-0.5\n600,1\n", "negative value -0.5 at 500 nm"),
        ("0.40,1\n0.55,2\n0.70,1\n", "must be in nm; 0.4-0.7 look like micrometres"),
        ("4e-07,1\n5.5e-07,2\n7e-07,1\n", "look like metres"),
        ("1000,1\n1100,2\n", "do not overlap the CIE range"),
        ("400,0\n500,0\n", "every value is 0"),
    ],
)
def test_bad_files_exit_2_with_one_line(capsys, tmp_path, content, message):
    """A missing or malformed file gives exit status 2 and one 'error: ...' line, no traceback."""
    path = tmp_path / "spd.csv"
    if content is not None:
        path.write_text(content)
    rc, out, err = run(capsys, str(path))
    assert rc == 2
    assert err.startswith("error: ") and err.count("\n") == 1 and message in err
    assert "Traceback" not in err


def test_unknown_dataset_name_exits_2(capsys):
    """A name that is neither a file nor a dataset is a user error."""
    rc, _, err = run(capsys, "D99")
    assert rc == 2 and err.startswith("error: ")
