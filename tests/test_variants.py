"""Variants at the edges (issue 14 item 1, issue 12 item 3): scalar variants refused in one
line, one-channel (mono) films written as grey RGB, a scene that needs a polarized variant
names it, a film of size 0 refused, -D of a parameter the scene lacks lists its parameters,
Mitsuba's log lines plain when piped."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import spectrace
from spectrace.cli import main
from spectrace.errors import ParameterError
from spectrace.images import as_rgb, read_exr

ROOT = Path(__file__).resolve().parents[1]
SHOWCASE = ROOT / "scenes" / "showcase.xml"
#: Mono and RGB renders of a grey scene: equal mean luminance up to float rounding.
LUMINANCE_RTOL = 0.01

STOKES = """<scene version="3.0.0">
    <integrator type="stokes"><integrator type="path"/></integrator>
    <sensor type="perspective">
        <film type="hdrfilm">
            <integer name="width" value="8"/><integer name="height" value="8"/>
        </film>
    </sensor>
    <shape type="sphere"><bsdf type="diffuse"/></shape>
    <emitter type="constant"/>
</scene>
"""


@pytest.mark.parametrize("name", ["scalar_rgb", "scalar_spectral"])
def test_scalar_variants_refused_naming_the_supported_ones(name):
    """The plugins are vectorized Dr.Jit code: a scalar variant is refused at set_variant
    with one line that lists the JIT variants."""
    with pytest.raises(ParameterError) as info:
        spectrace.set_variant(name)
    message = str(info.value)
    assert "\n" not in message and name in message
    assert "llvm_ad_rgb" in message and "llvm_ad_spectral_polarized" in message
    assert "scalar_spectral," not in message


def test_scalar_variant_on_the_command_line_exit_2(tmp_path, capsys):
    """``--variant scalar_rgb``: exit 2, one line, nothing written."""
    assert main(["render", str(SHOWCASE), "--variant", "scalar_rgb", "-o",
                 str(tmp_path / "out.exr"), "-q"]) == 2
    assert capsys.readouterr().err.strip().count("\n") == 0
    assert not any(tmp_path.iterdir())


def test_one_channel_images_become_grey():
    """A mono film's luminance (with or without alpha) is written as R = G = B = Y; RGB(A)
    keeps its first three channels."""
    Y = np.arange(6, dtype=np.float32).reshape(2, 3, 1)
    np.testing.assert_array_equal(as_rgb(Y), np.repeat(Y, 3, axis=-1))
    np.testing.assert_array_equal(as_rgb(np.concatenate([Y, Y * 0 + 1], -1)),
                                  np.repeat(Y, 3, axis=-1))
    rgba = np.arange(24, dtype=np.float32).reshape(2, 3, 4)
    np.testing.assert_array_equal(as_rgb(rgba), rgba[..., :3])


@pytest.mark.parametrize("variant", ["llvm_ad_mono", "llvm_ad_mono_polarized"])
def test_mono_render_writes_grey_exr_and_png_with_plain_log(tmp_path, variant):
    """A mono render (a separate process, its stderr piped) writes an EXR whose three
    channels are equal and a PNG; with -v, Mitsuba's warning about the mono film arrives
    once, on one line, without colour escape codes."""
    out = tmp_path / "mono.exr"
    done = subprocess.run(
        [sys.executable, "-m", "spectrace.cli", "render", str(SHOWCASE), "--variant", variant,
         "--spp", "1", "-D", "res=8", "-q", "-v", "-o", str(out)],
        capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    image, _ = read_exr(out)
    assert image.shape == (8, 8, 3) and image.mean() > 0
    np.testing.assert_array_equal(image[..., 0], image[..., 1])
    np.testing.assert_array_equal(image[..., 0], image[..., 2])
    assert out.with_suffix(".png").is_file()
    assert done.stderr.count("mitsuba: [HDRFilm] Monochrome mode") == 1, done.stderr
    assert "\x1b[" not in done.stderr


def test_scene_needing_a_polarized_variant_names_it(tmp_path, capsys):
    """Mitsuba's 'should only be used in polarized mode' comes with the variant to use."""
    scene = tmp_path / "stokes.xml"
    scene.write_text(STOKES)
    assert main(["render", str(scene), "--variant", "llvm_ad_rgb", "-q",
                 "-o", str(tmp_path / "out" / "x.exr")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0
    assert "the variant llvm_ad_spectral_polarized" in err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("defines", [["res=0"]])
def test_film_of_size_zero_is_one_line(tmp_path, capsys, defines):
    """``-D res=0`` (a film of width and height 0): exit 2, one line naming the film's
    size, nothing written."""
    args = ["render", str(SHOWCASE), "--variant", "llvm_ad_rgb", "-q",
            "-o", str(tmp_path / "out" / "x.exr")]
    for define in defines:
        args += ["-D", define]
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "width and height must be > 0" in err and "0x0" in err
    assert not (tmp_path / "out").exists()


def test_unknown_define_lists_the_scene_parameters(tmp_path, capsys):
    """``-D nope=3`` on a scene without parameter ``nope``: one line naming it and listing
    the scene's <default> parameters with their values."""
    assert main(["render", str(SHOWCASE), "--variant", "llvm_ad_rgb", "-q", "-D", "nope=3",
                 "-o", str(tmp_path / "out" / "x.exr")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0
    assert "'nope'" in err and "res=320" in err and "spp=256" in err


def test_compare_mono_against_rgb(tmp_path, capsys):
    """``spectrace compare SCENE --variants llvm_ad_mono,llvm_ad_rgb``: the mono image is
    compared as grey, and the mean luminance of the two agrees (mono renders luminance)."""
    out = tmp_path / "cmp.png"
    assert main(["compare", str(ROOT / "scenes" / "shadow_acne.xml"), "--variants",
                 "llvm_ad_mono,llvm_ad_rgb", "--spp", "4", "-D", "res=16", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert out.is_file() and "CIEDE2000 llvm_ad_mono vs llvm_ad_rgb" in text
    change = float(text.split("(B - A) / A:")[1].split()[0])
    assert abs(change) < LUMINANCE_RTOL


def test_doctor_separates_unsupported_variants(capsys):
    """``spectrace doctor`` lists the JIT variants as usable and the scalar ones apart."""
    assert main(["doctor"]) == 0
    lines = capsys.readouterr().out.splitlines()
    usable = next(line for line in lines if line.startswith("variants:"))
    refused = next(line for line in lines if line.startswith("not supported:"))
    assert "llvm_ad_rgb" in usable and "scalar" not in usable
    assert "scalar_rgb" in refused
