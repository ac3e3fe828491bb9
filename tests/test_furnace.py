"""Tests of the white-furnace measurement (spectrace/furnace.py), of the energy behaviour
of the classic and normalized Phong lobes it shows, and of scenes/phong_vs_energy.xml."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from spectrace.cli import main
from spectrace.errors import ParameterError
from spectrace.furnace import directional_albedo, load_bsdf

SCENE = Path(__file__).resolve().parents[1] / "scenes" / "phong_vs_energy.xml"
#: Samples per incident angle in these tests, and the accepted deviation in standard errors.
SAMPLES = 1 << 16
SIGMAS = 4.0
#: Incident angles (degrees) at which energy conservation is checked.
ANGLES = (0.0, 20.0, 40.0, 60.0, 75.0, 85.0)
#: Extra absolute slack on "albedo <= 1" (float32 accumulation).
SLACK = 1e-4


def lobe_only(plugin, m, normalized):
    return {"type": plugin, "exponent": m, "normalized": normalized,
            "diffuse_reflectance": 0.0, "specular_reflectance": 1.0}


def assert_close(result, expected, index=0):
    tolerance = SIGMAS * result.stderr[index].max() + SLACK
    np.testing.assert_allclose(result.albedo[index], expected, atol=tolerance)


def assert_conserves_energy(result):
    assert np.all(result.albedo <= 1.0 + SIGMAS * result.stderr + SLACK), result.table()


def test_diffuse_albedo_is_its_reflectance(variant):
    """Oracle for the furnace itself: Mitsuba's Lambertian `diffuse` reflects exactly rho
    at every incident angle (its sample weights are constant)."""
    result = directional_albedo({"type": "diffuse", "reflectance": 0.6}, ANGLES, SAMPLES)
    np.testing.assert_allclose(result.albedo, 0.6, rtol=1e-5)
    assert not result.exceeds_one().any()


@pytest.mark.parametrize("m", [1.0, 2.0, 4.0])
def test_classic_phong_gains_energy(variant, m):
    """The classic Phong lobe with rho_s = 1 reflects 2 pi/(m+2) at normal incidence:
    more than it receives for m < 2 pi - 2 (pi/2 for m = 2)."""
    result = directional_albedo(lobe_only("phong", m, False), (0.0,), SAMPLES)
    assert_close(result, 2 * np.pi / (m + 2))
    assert result.exceeds_one()[0]


def test_classic_blinnphong_gains_energy(variant):
    """The classic Blinn-Phong lobe with m = 2, rho_s = 1 reflects
    8 pi (2^-1 + 2)/(4 * 6) = 5 pi/6 at normal incidence."""
    result = directional_albedo(lobe_only("blinnphong", 2.0, False), (0.0,), SAMPLES)
    assert_close(result, 5 * np.pi / 6)
    assert result.exceeds_one()[0]


@pytest.mark.parametrize("plugin", ["phong", "blinnphong"])
@pytest.mark.parametrize("m", [1.0, 8.0, 100.0])
def test_normalized_lobes_conserve_energy(variant, plugin, m):
    """A normalized lobe with rho_s = 1 reflects exactly 1 at normal incidence and at
    most 1 at every angle; with rho + rho_s = 1 the whole BSDF stays <= 1."""
    result = directional_albedo(lobe_only(plugin, m, True), ANGLES, SAMPLES)
    assert_close(result, 1.0)
    assert_conserves_energy(result)
    mixed = {"type": plugin, "exponent": m, "normalized": True,
             "diffuse_reflectance": 0.4, "specular_reflectance": 0.6}
    result = directional_albedo(mixed, ANGLES, SAMPLES)
    assert_close(result, 1.0)
    assert_conserves_energy(result)


@pytest.mark.parametrize("xml", [
    '<bsdf type="roughplastic"><float name="alpha" value="0.3"/>'
    '<rgb name="diffuse_reflectance" value="1, 1, 1"/></bsdf>',
    '<bsdf type="roughplastic"><float name="alpha" value="0.05"/>'
    '<float name="diffuse_reflectance" value="1"/></bsdf>',
    '<bsdf type="plastic"><rgb name="diffuse_reflectance" value="1, 1, 1"/></bsdf>',
])
def test_mitsuba_plastics_conserve_energy(variant, xml):
    """Mitsuba's energy-conserving plastics (given as XML strings) stay at or below 1
    even with a white substrate (plastic's delta coat is counted through sample())."""
    result = directional_albedo(xml, ANGLES, SAMPLES)
    assert_conserves_energy(result)
    assert result.albedo.min() > 0.5


def test_xml_file_and_errors(variant_rgb, tmp_path):
    """A BSDF can come from an XML file; a bad parameter or a non-BSDF is a ParameterError
    naming the problem."""
    path = tmp_path / "b.xml"
    path.write_text('<bsdf version="3.0.0" type="diffuse">'
                    '<float name="reflectance" value="0.25"/></bsdf>')
    np.testing.assert_allclose(directional_albedo(str(path), (30.0,), 1024).albedo, 0.25, rtol=1e-5)
    with pytest.raises(ParameterError, match="'exponent'"):
        load_bsdf({"type": "phong", "exponent": -2.0})
    with pytest.raises(ParameterError):
        load_bsdf("no such thing")
    with pytest.raises(ParameterError):
        directional_albedo({"type": "diffuse"}, (95.0,), 16)


def test_cli_furnace(variant_rgb, capsys):
    """`spectrace furnace` prints the albedo table, flags energy gain, exits 0; a bad
    parameter exits 2 with one error line naming it."""
    code = main(["furnace", "phong", "-p", "exponent=2", "-p", "specular_reflectance=1",
                 "-p", "diffuse_reflectance=0", "--angles", "0,60", "--samples", "20000",
                 "--variant", "llvm_ad_rgb"])
    out = capsys.readouterr().out
    assert code == 0
    lines = out.strip().splitlines()
    assert lines[1].split()[:2] == ["angle", "albedo"]
    zero = lines[2].split()
    assert float(zero[1]) == pytest.approx(np.pi / 2, rel=0.02) and "> 1" in lines[2]
    code = main(["furnace", "blinnphong", "-p", "exponent=nan", "--variant", "llvm_ad_rgb"])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: ") and "'exponent'" in err
    assert len(err.strip().splitlines()) == 1


def test_phong_vs_energy_scene_renders(variant):
    """scenes/phong_vs_energy.xml loads and renders at tiny size, and the classic m = 2
    sphere (top left) is brighter than the normalized one below it, which receives the
    same light but reflects at most what it receives."""
    import mitsuba as mi

    res = 32
    scene = mi.load_file(str(SCENE), res=res, spp=16)
    image = np.array(mi.render(scene, seed=1))
    assert image.shape[:2] == (res, res)
    assert np.all(np.isfinite(image)) and image.min() >= 0
    half_width = 9 * np.tan(np.radians(15))  # camera at z = 9, fov 30

    def patch(x, y):
        col = int((x / half_width + 1) / 2 * res)
        row = int((1 - y / half_width) / 2 * res)
        return image[row - 1 : row + 2, col - 1 : col + 2].mean()

    assert patch(-1.5, 1.5) > 1.1 * patch(-1.5, 0.5)
