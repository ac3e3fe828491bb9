"""``spectrace render --light-groups`` / ``--light-group`` and ``spectrace relight`` end to
end: the layered EXR, relighting, and bad input (one line, exit 2, nothing written)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from error_checks import assert_one_line_error

from spectrace import lightgroups
from spectrace.cli import main
from spectrace.images import read_exr

ROOT = Path(__file__).resolve().parents[2]
SHOWCASE = ROOT / "scenes" / "showcase.xml"
TINY = ["-D", "res=16", "--spp", "4", "-q", "--variant", "llvm_ad_rgb"]
EXIT_USAGE = 2
#: Layers against the beauty of the same render, float32 (relative to the largest value).
SUM_RTOL = 1e-5
SHOWCASE_GROUPS = ["emitter0", "emitter1", "environment"]  # point, spot, sky: no ids


@pytest.fixture
def layered(tmp_path):
    out = tmp_path / "layers.exr"
    assert main(["render", str(SHOWCASE), "-o", str(out), "--light-groups", *TINY]) == 0
    return out


def test_render_writes_beauty_and_one_layer_per_emitter(layered):
    """--light-groups: R, G, B as without it, plus <group>.R/G/B per emitter (unnamed ones
    emitter<k>, the sky 'environment'), summing to the beauty; the PNG beside it."""
    beauty, layers, header = lightgroups.read_layers_exr(layered)
    assert list(layers) == SHOWCASE_GROUPS and header["spp"] == 4
    np.testing.assert_allclose(sum(layers.values()), beauty, rtol=0,
                               atol=SUM_RTOL * beauty.max())
    np.testing.assert_array_equal(read_exr(layered)[0], beauty)  # the usual RGB reader
    assert layered.with_suffix(".png").is_file()


def test_named_groups_on_the_command_line(tmp_path):
    """--light-group NAME=ids (repeated); the emitters in none form 'rest'."""
    out = tmp_path / "g.exr"
    assert main(["render", str(SHOWCASE), "-o", str(out), *TINY,
                 "--light-group", "lamps=emitter0,emitter1"]) == 0
    assert list(lightgroups.read_layers_exr(out)[1]) == ["lamps", "rest"]


def test_relight_dims_one_layer(layered, tmp_path, capsys):
    """-L emitter1=0.3: the beauty becomes the other layers plus 30 % of that one; the
    output holds the scaled layers (it can be relit again) and a PNG."""
    out = tmp_path / "relit.exr"
    assert main(["relight", str(layered), "-L", "emitter1=0.3", "-o", str(out)]) == 0
    assert "relit 3 layers" in capsys.readouterr().out
    _, layers, _ = lightgroups.read_layers_exr(layered)
    image, scaled, header = lightgroups.read_layers_exr(out)
    expected = layers["emitter0"] + 0.3 * layers["emitter1"] + layers["environment"]
    np.testing.assert_allclose(image, expected, rtol=1e-6, atol=1e-7)
    np.testing.assert_allclose(scaled["emitter1"], 0.3 * layers["emitter1"], rtol=1e-6)
    assert header["relight"] == "emitter1=0.3"
    assert out.with_suffix(".png").is_file()


@pytest.mark.parametrize(("light", "words"), [
    ("nope=0.5", "no light group 'nope'"),
    ("emitter1=-0.5", "'emitter1' must be a finite number >= 0"),
    ("emitter1=nan", "'emitter1' must be"),
    ("emitter1=1,FL2", "needs the spectral layers"),
])
def test_relight_bad_input_writes_nothing(layered, tmp_path, capsys, light, words):
    """A group not in the file, a scale < 0 or NaN, a spectrum for RGB layers: one line
    naming it, exit 2, no output."""
    out = tmp_path / "bad.exr"
    assert main(["relight", str(layered), "-L", light, "-o", str(out)]) == EXIT_USAGE
    assert_one_line_error(capsys, words)
    assert not out.exists() and not out.with_suffix(".png").exists()


def test_relight_of_a_file_without_layers(tmp_path, capsys):
    """A plain render has no layers: one line naming the file, exit 2."""
    plain = tmp_path / "plain.exr"
    assert main(["render", str(SHOWCASE), "-o", str(plain), *TINY]) == 0
    capsys.readouterr()
    assert main(["relight", str(plain), "-L", "x=1", "-o", str(tmp_path / "o.exr")]) == 2
    assert_one_line_error(capsys, "plain.exr", "no light-group layers")


@pytest.mark.parametrize(("options", "words"), [
    (["--light-group", "key=emitter0,lamp9"], "no emitter 'lamp9'"),
    (["--light-group", "a=emitter0", "--light-group", "b=emitter0"],
     "'emitter0' is in two light groups"),
    (["--light-group", "a.b=emitter0"], "letters, digits"),
])
def test_render_bad_groups_write_nothing(tmp_path, capsys, options, words):
    """An unknown emitter id, the same emitter in two groups, a bad group name: one line
    naming it, exit 2, nothing written."""
    out = tmp_path / "x.exr"
    assert main(["render", str(SHOWCASE), "-o", str(out), *TINY, *options]) == EXIT_USAGE
    assert_one_line_error(capsys, words)
    assert not out.exists() and not out.with_suffix(".png").exists()


def test_render_refuses_integrators_it_cannot_split(tmp_path, capsys):
    """A scene of the volpath integrator: light groups refused naming the integrator."""
    out = tmp_path / "x.exr"
    code = main(["render", str(ROOT / "scenes" / "fog_volpath.xml"), "-o", str(out),
                 "--spp", "1", "-q", "--variant", "llvm_ad_rgb", "--light-groups"])
    assert code == EXIT_USAGE
    assert_one_line_error(capsys, "'path', 'direct', 'local' or 'illuminance'", "Volumetric")
    assert not out.exists()


def test_a_local_scene_has_a_layer_per_light_and_ambient(tmp_path):
    """falloff_laws (integrator local, five lights): their layers and 'ambient' sum to the
    beauty."""
    out = tmp_path / "local.exr"
    assert main(["render", str(ROOT / "scenes" / "falloff_laws.xml"), "-o", str(out),
                 *TINY, "--light-groups"]) == 0
    beauty, layers, _ = lightgroups.read_layers_exr(out)
    assert list(layers) == [f"emitter{k}" for k in range(5)] + ["ambient"]
    np.testing.assert_allclose(sum(layers.values()), beauty, rtol=0,
                               atol=SUM_RTOL * beauty.max())


OWN_INTEGRATOR = """<scene version="3.0.0">
  <integrator type="lightgroups"><string name="groups" value="key=lamp;sky=environment"/>
  </integrator>
  <sensor type="perspective"><transform name="to_world"><lookat origin="0, 0, 3"
      target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>
    </film></sensor>
  <shape type="rectangle"/>
  <emitter type="pointlight" id="lamp"><point name="position" x="0" y="0" z="1"/>
    <float name="intensity" value="1"/></emitter>
  <emitter type="constant"><float name="radiance" value="0.2"/></emitter>
</scene>
"""


def test_a_scene_of_the_lightgroups_integrator_writes_its_layers(tmp_path):
    """A scene that names ``lightgroups`` itself gets its layers in the EXR without the
    option, in the order of its ``groups``, summing to the beauty."""
    scene = tmp_path / "own.xml"
    scene.write_text(OWN_INTEGRATOR)
    out = tmp_path / "own.exr"
    assert main(["render", str(scene), "-o", str(out), "--spp", "4", "-q",
                 "--variant", "llvm_ad_rgb"]) == 0
    beauty, layers, _ = lightgroups.read_layers_exr(out)
    assert list(layers) == ["key", "sky"] and layers["key"].max() > 0
    np.testing.assert_allclose(sum(layers.values()), beauty, rtol=0,
                               atol=SUM_RTOL * beauty.max())


def test_spectral_layers_and_a_new_lamp_spectrum(tmp_path, capsys):
    """--film spectral --light-groups: OUT.spectral.exr holds the spectral beauty (read by
    the Fichet reader) and <group>.S0.* layers summing to it, with each group's probed
    lamp spectrum; OUT.exr their RGB. relight -L g=s,FL2 on it writes the three outputs,
    records FL2 for the group; an unknown SPD is one line, nothing written."""
    from spectrace.spectral import read_spectral_exr

    out = tmp_path / "s.exr"
    assert main(["render", str(SHOWCASE), "-o", str(out), "-D", "res=16", "--spp", "4",
                 "-q", "--light-groups", "--film", "spectral", "--bands", "8"]) == 0
    spectral = tmp_path / "s.spectral.exr"
    bands, layers, wl, spectra, _ = lightgroups.read_spectral_layers_exr(spectral)
    assert bands.shape == (16, 16, 8) and list(layers) == SHOWCASE_GROUPS
    np.testing.assert_allclose(sum(layers.values()), bands, rtol=1e-5, atol=1e-7)
    np.testing.assert_array_equal(read_spectral_exr(spectral)[0], bands)
    assert all(s is not None and s.max() == 1.0 for s in spectra.values())
    rgb, rgb_layers, _ = lightgroups.read_layers_exr(out)
    np.testing.assert_allclose(sum(rgb_layers.values()), rgb, rtol=0, atol=SUM_RTOL * rgb.max())

    relit = tmp_path / "r.exr"
    assert main(["relight", str(spectral), "-L", "emitter1=0.5,FL2", "-o", str(relit)]) == 0
    for p in (relit, relit.with_suffix(".png"), tmp_path / "r.spectral.exr"):
        assert p.is_file(), p
    _, _, _, new_spectra, header = lightgroups.read_spectral_layers_exr(
        tmp_path / "r.spectral.exr")
    assert not np.allclose(new_spectra["emitter1"], spectra["emitter1"])
    assert header["relight"] == "emitter1=0.5;emitter1:FL2"
    capsys.readouterr()
    bad = tmp_path / "bad.exr"
    assert main(["relight", str(spectral), "-L", "emitter1=1,NOPE", "-o", str(bad)]) == 2
    assert_one_line_error(capsys, "NOPE")
    assert not bad.exists() and not (tmp_path / "bad.spectral.exr").exists()


def test_relight_display_options_change_the_png_only(layered, tmp_path, capsys):
    """--exposure/--view make the PNG through the display pipeline: the relit EXR is
    bit-identical to the one without them, the PNG differs."""
    plain, shown = tmp_path / "plain.exr", tmp_path / "shown.exr"
    assert main(["relight", str(layered), "-L", "emitter1=0.3", "-o", str(plain)]) == 0
    assert main(["relight", str(layered), "-L", "emitter1=0.3", "-o", str(shown),
                 "--exposure", "2", "--view", "neutral"]) == 0
    assert plain.read_bytes() == shown.read_bytes()
    assert plain.with_suffix(".png").read_bytes() != shown.with_suffix(".png").read_bytes()


def test_relight_bad_display_option_writes_nothing(layered, tmp_path, capsys):
    """An unknown view: one line naming the flag, exit 2, nothing written."""
    out = tmp_path / "bad.exr"
    assert main(["relight", str(layered), "-L", "emitter1=0.3", "-o", str(out),
                 "--view", "nosuch"]) == EXIT_USAGE
    assert_one_line_error(capsys, "--view")
    assert not out.exists() and not out.with_suffix(".png").exists()
