"""Infinite, NaN and float32-overflowing light values and transforms are refused at load,
naming the parameter (issue 18 B3: they rendered a black image with exit 0)."""

from __future__ import annotations

import pytest

from spectrace.cli import main
from spectrace.errors import FileFormatError, ParameterError

SCENE = """<scene version="3.0.0"><integrator type="path"/>
<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/>
<integer name="height" value="4"/></film></sensor>
<default name="x" value="0"/>
{}
</scene>"""
EXIT_USAGE = 2

#: (the scene's emitter, words of the one-line error)
XML_CASES = {
    "intensity_inf": ('<emitter type="pointlight"><float name="intensity" value="inf"/>'
                      "</emitter>", ['<float name="intensity">', "inf"]),
    "luminous_flux_inf": ('<emitter type="pointlight"><float name="luminous_flux" '
                          'value="inf"/></emitter>', ["luminous_flux", "inf"]),
    "power_1e39": ('<emitter type="pointlight"><float name="power" value="1e39"/></emitter>',
                   ["power", "beyond float32"]),
    "rgb_inf": ('<emitter type="point"><rgb name="intensity" value="inf, 0, 0"/></emitter>',
                ["(point)", "intensity", "inf"]),
    "position_nan": ('<emitter type="point"><point name="position" x="nan" y="0" z="0"/>'
                     "</emitter>", ["position", "x='nan'"]),
    "translate_nan": ('<emitter type="point" id="lamp"><transform name="to_world">'
                      '<translate x="$x"/></transform></emitter>', ["'lamp'", "to_world",
                                                                  "translate", "nan"]),
}


@pytest.mark.parametrize("case", sorted(XML_CASES))
def test_scene_with_non_finite_numbers_is_refused(variant_rgb, tmp_path, case):
    """Spectrace's and Mitsuba's own emitters alike: a FileFormatError naming the element
    and its plugin (a $parameter is checked with its value)."""
    from spectrace.scene import load_scene

    text, words = XML_CASES[case]
    path = tmp_path / f"{case}.xml"
    path.write_text(SCENE.format(text))
    with pytest.raises(FileFormatError) as info:
        load_scene(path, {"x": "nan"} if "$x" in text else None)
    message = str(info.value)
    assert "\n" not in message and str(path) in message
    for word in words:
        assert word in message, message


def test_finite_scene_numbers_load(variant_rgb, tmp_path):
    """Ordinary numbers, file names and big but float32 values pass."""
    from spectrace.scene import check_finite_numbers, read_scene_xml

    path = tmp_path / "ok.xml"
    path.write_text(SCENE.format('<emitter type="point"><rgb name="intensity" '
                                 'value="3e38, 1, 0.5"/></emitter>'
                                 '<shape type="sphere"><bsdf type="diffuse"><spectrum '
                                 'name="reflectance" value="400:0.1, 700:0.5"/></bsdf></shape>'))
    check_finite_numbers(read_scene_xml(path), {}, path)


@pytest.mark.parametrize(("value", "word"), [
    ({"intensity": float("inf")}, "'intensity' must be finite (got inf)"),
    ({"luminous_flux": float("inf")}, "'luminous_flux' must be a finite float (got inf)"),
    ({"power": 1e39}, "'power' must be finite (got 1e+39, beyond float32)"),
    ({"intensity": {"type": "rgb", "value": [float("inf"), 0.0, 0.0]}},
     "'intensity' must be finite (got inf, 0, 0)"),
    ({"intensity": {"type": "spectrum", "value": float("inf")}}, "'intensity' must be finite"),
])
def test_plugin_refuses_non_finite_emission(variant_rgb, value, word):
    """The constructors refuse them too (a scene built from a dict skips the XML check)."""
    import mitsuba as mi

    from spectrace.scene import load_error

    with pytest.raises(RuntimeError) as info:
        mi.load_dict({"type": "pointlight", **value})
    error = load_error(info.value)
    assert isinstance(error, ParameterError) and word in str(error), str(error)


def test_blackbody_in_rgb_names_the_spectral_variant(tmp_path, capsys):
    """spotlight_stage.xml in llvm_ad_rgb: its blackbody needs a spectral variant, said so."""
    from pathlib import Path

    scene = Path(__file__).resolve().parents[1] / "scenes" / "spotlight_stage.xml"
    code = main(["render", str(scene), "--variant", "llvm_ad_rgb", "-D", "res=8", "--spp", "1",
                 "-q", "-o", str(tmp_path / "x.exr")])
    err = capsys.readouterr().err.strip()
    assert code == EXIT_USAGE and "\n" not in err
    assert "BlackBodySpectrum needs a spectral variant" in err and ">= 0" not in err


def test_ies_multiplier_beyond_float32_is_refused(tmp_path):
    """A candela multiplier of 1e300 makes intensities no float32 holds: refused, naming the
    file (it printed a 300-digit flux)."""
    from spectrace.photometry import read_photometry

    path = tmp_path / "big.ies"
    path.write_text("IESNA:LM-63-2002\nTILT=NONE\n1 1000 1e300 3 1 1 2 0 0 0\n1 1 100\n"
                    "0 45 90\n0\n100 50 10\n")
    with pytest.raises(FileFormatError, match="beyond any luminaire") as info:
        read_photometry(path)
    assert str(path) in str(info.value)
