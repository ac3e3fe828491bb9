"""``spectrace compare``: CIEDE2000 statistics, luminance difference, figure, bad input."""

from __future__ import annotations

from pathlib import Path

import colour
import numpy as np
import pytest

from spectrace.cli import main
from spectrace.comparison import compare_images
from spectrace.images import write_exr, write_png

ROOT = Path(__file__).resolve().parents[2]
SHOWCASE = ROOT / "scenes" / "showcase.xml"
DELTA_E_ATOL = 1e-6
# Lab white: ours is sRGB (1, 1, 1) through the sRGB matrix, colour-science's default is
# D65's chromaticity (0.3127, 0.3290); the two differ in the 4th decimal.
DELTA_E_WHITE_POINT_ATOL = 5e-3
EXIT_USAGE = 2


@pytest.fixture
def images(rng):
    a = rng.uniform(0.05, 0.9, size=(12, 10, 3)).astype(np.float32)
    b = np.clip(a * rng.uniform(0.9, 1.1, size=a.shape), 0, 1).astype(np.float32)
    return a, b


def test_delta_e_matches_colour_science(images):
    """Per-pixel CIEDE2000 is colour-science's, on sRGB-encoded pixels (D65 Lab)."""
    a, b = images
    ours = compare_images(a, b).delta_e
    lab = [colour.XYZ_to_Lab(colour.sRGB_to_XYZ(colour.cctf_encoding(x.astype(np.float64))))
           for x in (a, b)]
    np.testing.assert_allclose(ours, colour.delta_E(*lab, method="CIE 2000"),
                               atol=DELTA_E_WHITE_POINT_ATOL)


def test_identical_images_have_zero_difference(images):
    """An image compared with itself: CIEDE2000 0 everywhere, luminance difference 0."""
    s = compare_images(images[0], images[0]).stats
    assert s["max"] <= DELTA_E_ATOL and s["luminance_rel"] == 0


def test_luminance_difference_of_a_scaled_image(images):
    """B = 1.1 A (linear) has 10 % more luminance, whatever the pixels."""
    a = images[0] * 0.5
    assert compare_images(a, a * 1.1).stats["luminance_rel"] == pytest.approx(0.1, rel=1e-5)


def test_cli_on_two_files_writes_figure(tmp_path, images, capsys):
    """EXR against PNG: prints mean/95th/max and the luminance line, writes the figure."""
    a, b = images
    write_exr(tmp_path / "a.exr", a)
    write_png(tmp_path / "b.png", b)
    out = tmp_path / "cmp.png"
    assert main(["compare", str(tmp_path / "a.exr"), str(tmp_path / "b.png"), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "CIEDE2000" in text and "95th percentile" in text and "luminance" in text
    assert out.read_bytes()[:4] == b"\x89PNG"


def test_cli_one_scene_two_variants(tmp_path, capsys):
    """One scene rendered in RGB and spectral: the two renders differ only a little."""
    out = tmp_path / "v.png"
    code = main(["compare", str(SHOWCASE), "--variants", "llvm_ad_rgb,llvm_ad_spectral",
                 "--spp", "16", "-D", "res=24", "-o", str(out)])
    assert code == 0 and out.exists()
    mean = float(capsys.readouterr().out.split("mean ")[1].split(",")[0])
    assert 0 < mean < 10


def test_bad_spp(tmp_path, capsys):
    """--spp 0 is refused, not silently replaced by the scene's own count."""
    code = main(["compare", str(SHOWCASE), "--variants", "llvm_ad_rgb,llvm_ad_spectral",
                 "--spp", "0", "-o", str(tmp_path / "v.png")])
    assert code == EXIT_USAGE
    assert capsys.readouterr().err.startswith("error: --spp")


def test_mismatched_sizes(tmp_path, capsys):
    write_exr(tmp_path / "a.exr", np.zeros((4, 4, 3)))
    write_exr(tmp_path / "b.exr", np.zeros((4, 5, 3)))
    assert main(["compare", str(tmp_path / "a.exr"), str(tmp_path / "b.exr"),
                 "-o", str(tmp_path / "c.png")]) == EXIT_USAGE
    err = capsys.readouterr().err
    assert err.startswith("error: image sizes differ") and not (tmp_path / "c.png").exists()


@pytest.mark.parametrize("content", [None, b"not an image"])
def test_unreadable_input(tmp_path, capsys, content):
    """A missing or corrupt file is named in a one-line error."""
    bad = tmp_path / "bad.png"
    if content is not None:
        bad.write_bytes(content)
    write_png(tmp_path / "ok.png", np.zeros((4, 4, 3)))
    code = main(["compare", str(bad), str(tmp_path / "ok.png"), "-o", str(tmp_path / "c.png")])
    assert code == EXIT_USAGE
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: ") and "bad.png" in err and "\n" not in err


#: Relative tolerance on the mean luminance ratio of two renders of a lit diffuse plane.
LUMINANCE_RTOL = 0.02

PLANE_SCENE = """<scene version="3.0.0">
    <default name="albedo" value="0.4"/>
    <integrator type="direct"/>
    <sensor type="orthographic">
        <transform name="to_world">
            <lookat origin="0, 0, 2" target="0, 0, 0" up="0, 1, 0"/>
        </transform>
        <film type="hdrfilm">
            <integer name="width" value="8"/><integer name="height" value="8"/>
        </film>
        <sampler type="independent"><integer name="sample_count" value="64"/></sampler>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="4"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="$albedo"/></bsdf>
    </shape>
    <emitter type="constant"/>
</scene>
"""


@pytest.fixture
def plane_scene(tmp_path):
    path = tmp_path / "plane.xml"
    path.write_text(PLANE_SCENE)
    return path


def test_against_compares_two_settings_of_one_scene(plane_scene, tmp_path, capsys):
    """-D before --against sets side A, after it side B: a diffuse plane under a uniform sky
    has radiance rho, so doubling the albedo doubles the mean luminance (B - A) / A = 1."""
    out = tmp_path / "against.png"
    code = main(["compare", str(plane_scene), "--variant", "llvm_ad_rgb", "-D", "albedo=0.3",
                 "--against", "-D", "albedo=0.6", "-o", str(out)])
    text = capsys.readouterr().out
    assert code == 0 and out.exists()
    relative = float(text.split("(B - A) / A:")[1].split()[0])
    assert relative == pytest.approx(1.0, rel=LUMINANCE_RTOL)
    assert "albedo=0.3" in text and "albedo=0.6" in text


@pytest.mark.parametrize("argv", [
    ["-D", "albedo=0.3", "--against", "-D", "albedo=0.3"],  # B sets nothing new
    ["--against"],
    [],  # the scene against itself below
])
def test_nothing_to_compare_is_refused(plane_scene, tmp_path, capsys, argv):
    """Comparing a scene with itself under the same settings would report 0 whatever the
    renderer does: refused in one line, nothing written."""
    out = tmp_path / "same.png"
    inputs = [str(plane_scene)] + ([] if argv else [str(plane_scene)])
    code = main(["compare", *inputs, *argv, "--variant", "llvm_ad_rgb", "-o", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == EXIT_USAGE and "nothing to compare" in err and "\n" not in err
    assert not out.exists()


def test_same_variant_twice_is_refused(plane_scene, tmp_path, capsys):
    """--variants with the same variant on both sides compares nothing."""
    code = main(["compare", str(plane_scene), "--variants", "llvm_ad_rgb,llvm_ad_rgb",
                 "-o", str(tmp_path / "v.png")])
    assert code == EXIT_USAGE and "nothing to compare" in capsys.readouterr().err
