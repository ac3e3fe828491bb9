"""Tests of the typed-parameter helpers (plugins/params.py) and of the plugins that use them.

The contract: a parameter of the wrong XML type is an error, never coerced (an integer for
a float excepted, as Mitsuba does); a value out of range is an error; a reflectance
texture is checked, and one that cannot be checked is refused; every message is one line
naming the plugin, the parameter, what was expected and what came.
"""

from __future__ import annotations

import math

import mitsuba as mi
import pytest
from spectrace.plugins import params

PLUGIN = "probe"


def props(**values):
    """A Properties object holding ``values`` with their Python types (bool -> boolean,
    int -> integer, float -> float, str -> string)."""
    p = mi.Properties(PLUGIN)
    for name, value in values.items():
        p[name] = value
    return p


def one_line_error(call, *fragments):
    """``call`` raises a one-line ValueError that contains every fragment."""
    with pytest.raises(ValueError) as info:
        call()
    message = str(info.value)
    assert "\n" not in message
    for fragment in fragments:
        assert fragment in message, message
    return message


# -- scalars --------------------------------------------------------------------------


def test_float_accepts_float_and_integer(variant_rgb):
    """A float parameter reads <float> and, as Mitsuba does, <integer>; absent: default."""
    p = props(a=1.5, b=3)
    assert params.read_float(p, PLUGIN, "a", 0.0) == 1.5
    assert params.read_float(p, PLUGIN, "b", 0.0) == 3.0
    assert params.read_float(p, PLUGIN, "absent", 7.25) == 7.25


@pytest.mark.parametrize("value, given", [("abc", 'a string "abc"'), (True, "a boolean true")])
def test_float_refuses_other_types(variant_rgb, value, given):
    """A string or boolean where a float belongs is an error naming what came."""
    one_line_error(lambda: params.read_float(props(x=value), PLUGIN, "x", 1.0),
                   f"{PLUGIN}: parameter 'x'", "must be a float", given)


def test_float_bounds(variant_rgb):
    """Bounds are inclusive unless strict; NaN is never in range; ``finite`` refuses inf."""
    p = props(zero=0.0, big=2.0, nan=math.nan, inf=math.inf)
    assert params.read_float(p, PLUGIN, "zero", 1.0, minimum=0.0) == 0.0
    one_line_error(lambda: params.read_float(p, PLUGIN, "zero", 1.0, minimum=0.0,
                                             strict_minimum=True), "'zero' must be > 0")
    one_line_error(lambda: params.read_float(p, PLUGIN, "big", 1.0, maximum=1.0),
                   "'big' must be <= 1", "(got 2)")
    one_line_error(lambda: params.read_float(p, PLUGIN, "nan", 1.0), "'nan'", "nan")
    assert params.read_float(p, PLUGIN, "inf", 1.0, minimum=0.0) == math.inf
    one_line_error(lambda: params.read_float(p, PLUGIN, "inf", 1.0, finite=True),
                   "'inf' must be a finite float")


def test_int_refuses_float(variant_rgb):
    """An integer parameter reads <integer> only: a <float value="2"/> is refused."""
    p = props(n=4, f=2.0)
    assert params.read_int(p, PLUGIN, "n", 1, minimum=1) == 4
    one_line_error(lambda: params.read_int(p, PLUGIN, "f", 1), "'f' must be an integer",
                   "a float 2")
    one_line_error(lambda: params.read_int(p, PLUGIN, "n", 1, minimum=5), "'n' must be >= 5")


@pytest.mark.parametrize("value, given", [("no", 'a string "no"'), (0, "an integer 0"),
                                          ("true", 'a string "true"')])
def test_bool_refuses_strings_and_integers(variant_rgb, value, given):
    """<string value="no"/> or <integer value="0"/> for a boolean is an error, not a truth
    value."""
    one_line_error(lambda: params.read_bool(props(b=value), PLUGIN, "b", True),
                   "'b' must be a boolean", given)


def test_bool_string_choice(variant_rgb):
    """Booleans, strings and choices read their own XML type; a choice outside the
    options is named with the options."""
    p = props(b=False, s="hello", c="linear")
    assert params.read_bool(p, PLUGIN, "b", True) is False
    assert params.read_string(p, PLUGIN, "s", "") == "hello"
    assert params.read_choice(p, PLUGIN, "c", "none", ("none", "linear")) == "linear"
    one_line_error(lambda: params.read_choice(p, PLUGIN, "c", "none", ("none", "exp")),
                   "'c' must be one of none, exp", "'linear'")
    one_line_error(lambda: params.read_string(props(s=1.0), PLUGIN, "s", ""),
                   "'s' must be a string", "a float 1")


def test_required(variant_rgb):
    """REQUIRED turns a missing parameter into an error naming it."""
    one_line_error(lambda: params.read_float(props(), PLUGIN, "radius", params.REQUIRED),
                   "parameter 'radius' is required")


# -- textures through a plugin ---------------------------------------------------------


def phong(**reflectance):
    return mi.load_dict({"type": "phong", **reflectance})


def load_error(plugin_dict):
    """The message of the load error of ``plugin_dict``."""
    with pytest.raises(Exception) as info:  # Mitsuba wraps the ValueError in its own
        mi.load_dict(plugin_dict)
    return str(info.value)


def test_reflectance_texture_checked_without_max(variant):
    """A checkerboard (no Texture::max()) is checked by evaluation: 2 is refused, colours
    in [0, 1] are accepted."""
    phong(diffuse_reflectance={"type": "checkerboard", "color0": 0.1, "color1": 0.9})
    message = load_error({"type": "phong", "diffuse_reflectance": {
        "type": "checkerboard", "color0": 0.1, "color1": 2.0}})
    assert "phong: parameter 'diffuse_reflectance' must be a reflectance in [0, 1]" in message
    assert "Checkerboard" in message


def test_reflectance_bitmap_above_one_refused(variant_rgb):
    """A raw bitmap with a texel of 1.5 is not a reflectance."""
    data = mi.TensorXf([[[0.2], [1.5]], [[0.2], [0.2]]])
    message = load_error({"type": "phong", "specular_reflectance": {
        "type": "bitmap", "data": data, "raw": True, "filter_type": "nearest"}})
    assert "'specular_reflectance' must be a reflectance in [0, 1]" in message


def test_reflectance_that_cannot_be_checked_is_refused(variant_rgb):
    """A blackbody cannot be evaluated in an RGB variant: refused, not accepted unchecked,
    with the message that it needs a spectral variant."""
    message = load_error({"type": "phong", "diffuse_reflectance": {
        "type": "blackbody", "temperature": 3000}})
    assert "phong: parameter 'diffuse_reflectance'" in message
    assert "BlackBodySpectrum needs a spectral variant" in message


def test_reflectance_rgb_checked_by_value(variant_spectral):
    """An <rgb> reflectance is checked on the values as written, in spectral variants too."""
    message = load_error({"type": "phong", "diffuse_reflectance": {
        "type": "rgb", "value": [0.2, 0.4, 1.2]}})
    assert "must be a reflectance in [0, 1] (got 0.2, 0.4, 1.2)" in message


XML_MISTAKES = [
    ('<integrator type="local"><string name="shadows" value="no"/></integrator>',
     "local: parameter 'shadows' must be a boolean", 'a string "no"'),
    ('<bsdf type="phong"><string name="exponent" value="abc"/></bsdf>',
     "phong: parameter 'exponent' must be a float", 'a string "abc"'),
    ('<bsdf type="blinnphong"><string name="normalized" value="yes"/></bsdf>',
     "blinnphong: parameter 'normalized' must be a boolean", 'a string "yes"'),
    ('<emitter type="pointlight"><string name="kq" value="1"/>'
     '<string name="falloff" value="polynomial"/></emitter>',
     "pointlight: parameter 'kq' must be a float", 'a string "1"'),
    ('<emitter type="spotlight"><integer name="cone_falloff" value="1"/></emitter>',
     "spotlight: parameter 'cone_falloff' must be one of", "an integer 1"),
]


@pytest.mark.parametrize("xml, expected, given", XML_MISTAKES,
                         ids=["local-shadows", "phong-exponent", "blinnphong-normalized",
                              "pointlight-kq", "spotlight-cone"])
def test_plugins_refuse_wrong_xml_types(variant_rgb, xml, expected, given):
    """The mistakes of issue 14 item 2, written as XML, fail at load with one message that
    names plugin, parameter, expected type and what came."""
    with pytest.raises(Exception) as info:
        mi.load_string(xml.replace(">", ' version="3.0.0">', 1))
    assert expected in str(info.value)
    assert given in str(info.value)
