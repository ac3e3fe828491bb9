"""Tests of the distance falloff laws shared by ``pointlight`` and ``spotlight``
(``plugins/emitters/falloff.py``): closed-form radiometry on a lit plane, the parameter
checks, and the scene ``scenes/falloff_laws.xml``."""

from __future__ import annotations

from pathlib import Path

import emitter_checks as checks
import numpy as np
import pytest

SCENE = Path(__file__).resolve().parents[2] / "scenes" / "falloff_laws.xml"
#: Light position above the plane (the view spans x, z in [-2, 2]; r from 1.5 to 3.4).
P_LIGHT = (0.4, 1.5, -0.3)
INTENSITY = 3.0

#: Each law: its XML parameters and the formula, written out here in numpy (the oracle).
LAWS = {
    "inverse_square": ({}, lambda r: 1.0 / r**2),
    "inverse_square_epsilon": ({"epsilon": 0.7}, lambda r: 1.0 / (r + 0.7) ** 2),
    "polynomial": ({"kc": 1.0, "kl": 0.5, "kq": 0.25},
                   lambda r: 1.0 / (1.0 + 0.5 * r + 0.25 * r**2)),
    "windowed": ({"radius": 2.5, "epsilon": 0.1},
                 lambda r: np.clip(1.0 - (r / 2.5) ** 4, 0.0, 1.0) ** 2
                 / np.maximum(r**2, 0.1**2)),
    "none": ({}, lambda r: np.ones_like(r)),
}


@pytest.fixture(scope="module")
def plane_positions():
    """World positions at the pixel centres (the same in every variant)."""
    import spectrace

    spectrace.set_variant("llvm_ad_rgb")
    return checks.positions()


@pytest.mark.parametrize("law", LAWS)
def test_law_on_lit_plane(variant, plane_positions, law):
    """A diffuse plane under a point light with each law has the radiance
    rho/pi * I * falloff(r) * cos(theta) at every pixel (RGB: in absolute terms; both
    variants: relative to Mitsuba's ``point`` with the same samples, which carries 1/r^2)."""
    params, formula = LAWS[law]
    light = {"type": "pointlight", "position": list(P_LIGHT), "intensity": INTENSITY,
             "falloff": law, **params}
    image = checks.render(light)
    reference = checks.builtin_point(P_LIGHT, INTENSITY)
    r = np.linalg.norm(plane_positions - np.asarray(P_LIGHT), axis=-1)
    checks.assert_image_close(image, reference * (formula(r) * r**2)[..., None])
    if variant == "llvm_ad_rgb":
        expected = checks.closed_form(plane_positions, P_LIGHT,
                                      lambda d, r: INTENSITY * formula(r))
        checks.assert_image_close(image, expected)


def test_windowed_is_exactly_zero_beyond_radius(variant_rgb, plane_positions):
    """The windowed law reaches exactly zero at r >= R: far lights cost nothing."""
    light = {"type": "spotlight", "intensity": INTENSITY, "falloff": "windowed",
             "radius": 2.5, "umbra_angle": 90.0, "penumbra_angle": 90.0,
             "to_world": checks.transform().look_at(list(P_LIGHT), [0.4, 0, -0.3], [0, 0, 1])}
    image = checks.render(light)
    r = np.linalg.norm(plane_positions - np.asarray(P_LIGHT), axis=-1)
    assert np.any(r >= 2.5) and np.any(r < 2.4)
    assert np.all(image[r >= 2.5] == 0.0)
    assert np.all(image[r < 2.4] > 0.0)


INVALID = [
    ({"falloff": "inverse_cube"}, "falloff"),
    ({"falloff": "polynomial", "kc": 0.0, "kl": 0.0, "kq": 0.0}, "kq"),
    ({"falloff": "polynomial", "kl": -1.0}, "kl"),
    ({"falloff": "polynomial", "kc": -0.5}, "kc"),
    ({"falloff": "windowed"}, "radius"),
    ({"falloff": "windowed", "radius": 0.0}, "radius"),
    ({"falloff": "windowed", "radius": -2.0}, "radius"),
    ({"falloff": "windowed", "radius": 2.0, "epsilon": 0.0}, "epsilon"),
    ({"falloff": "inverse_square_epsilon", "epsilon": -0.1}, "epsilon"),
    ({"intensity": -1.0}, "intensity"),
    ({"power": -2.0}, "power"),
    ({"intensity": 1.0, "power": 2.0}, "power"),
]


@pytest.mark.parametrize("plugin", ["pointlight", "spotlight"])
@pytest.mark.parametrize(("params", "name"), INVALID)
def test_invalid_parameters_fail_at_load(variant_rgb, plugin, params, name):
    """Invalid distance-law and emission parameters fail at load, naming the parameter."""
    import mitsuba as mi

    with pytest.raises(Exception, match=f"{plugin}: .*'{name}'") as info:
        mi.load_dict({"type": plugin, **params})
    assert "ParameterError" in str(info.value) or isinstance(info.value, ValueError)


def test_negative_rgb_intensity_fails_at_load(variant_rgb):
    """An RGB power with a negative channel is a negative power too (RGB variants; spectral
    ones upsample RGB to a non-negative spectrum)."""
    import mitsuba as mi

    with pytest.raises(Exception, match="'power' must be >= 0"):
        mi.load_dict({"type": "spotlight", "power": {"type": "rgb", "value": [1.0, -0.5, 0.2]}})


def test_unused_law_parameter_is_reported(variant_rgb):
    """A parameter of another law (here ``radius`` with ``inverse_square``) is not silently
    ignored: Mitsuba reports it as unreferenced, by name."""
    import mitsuba as mi

    with pytest.raises(Exception, match="radius"):
        mi.load_dict({"type": "pointlight", "radius": 3.0})


def test_falloff_laws_scene_renders(variant):
    """scenes/falloff_laws.xml loads and renders at tiny size: each lane lit by its own law."""
    import mitsuba as mi

    scene = mi.load_file(str(SCENE), res=24, spp=4)
    image = np.array(mi.render(scene, seed=1))
    assert image.shape == (24, 24, 3)
    assert np.all(np.isfinite(image)) and image.max() > 0.0
    laws = {str(e).split("falloff=")[1].split("(")[0].rstrip("]")
            for e in scene.emitters()}
    assert laws == set(LAWS)


def test_reference_page():
    """The module docstring of ``falloff`` follows the one reference-page format and
    lists every law's parameters."""
    from spectrace.plugins.emitters import falloff

    table = checks.parse_reference_page(falloff.__doc__, "falloff")
    assert set(table) == {"falloff", "epsilon", "kc", "kl", "kq", "radius"}
    assert all(name in table["falloff"]["description"] for name in LAWS)


WRONG_TYPES = [
    ({"falloff": "windowed", "radius": "far"}, "'radius' must be a float (got a string"),
    ({"falloff": "polynomial", "kq": "1"}, "'kq' must be a float (got a string"),
    ({"falloff": 2.0}, "'falloff' must be one of inverse_square,"),
    ({"umbra_angle": "wide"}, "'umbra_angle' must be a float (got a string"),
    ({"cone_falloff": 1.0}, "'cone_falloff' must be one of quadratic,"),
]


@pytest.mark.parametrize(("params", "message"), WRONG_TYPES)
def test_wrong_xml_type_fails_in_one_line(variant_rgb, params, message):
    """A value of the wrong XML type (a string where a float belongs, a float where a law
    is named) is never converted: one line names the parameter, what was expected and
    what came."""
    import mitsuba as mi

    plugin = "spotlight" if any("cone" in k or "umbra" in k for k in params) else "pointlight"
    with pytest.raises(Exception) as info:
        mi.load_dict({"type": plugin, **params})
    line = next(l for l in str(info.value).splitlines() if f"{plugin}: " in l)
    assert message in line, line


def test_integer_distances_are_accepted(variant_rgb):
    """An ``<integer>`` where a float belongs is accepted as Mitsuba accepts it: radius 3
    as an integer gives the same light as radius 3.0."""
    import mitsuba as mi

    a = mi.load_dict({"type": "pointlight", "falloff": "windowed", "radius": 3})
    b = mi.load_dict({"type": "pointlight", "falloff": "windowed", "radius": 3.0})
    assert str(a) == str(b)


def test_position_must_be_a_point(variant_rgb):
    """``position`` given as a float (which Mitsuba would broadcast to (v, v, v)) fails."""
    import mitsuba as mi

    with pytest.raises(Exception, match="'position' must be a point"):
        mi.load_dict({"type": "pointlight", "position": 1.0})
