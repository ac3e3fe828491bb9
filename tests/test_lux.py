"""Tests of ``spectrace.lux``: lux maps of whole views (the luminous flux a floor catches
from a spotlight and an IES downlight), the work plane and its pixels without data,
statistics and U0, the EXR and PNG files, the scene tree prepared for the command and
the one-line errors.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pytest

from spectrace.errors import ParameterError

#: Luminous flux summed over the floor: pixel means of FLUX_SPP samples over FLUX_RES^2
#: pixels (measured error 0.1-0.3 %).
RTOL_FLUX = 1e-2
FLUX_SPP = 16
FLUX_RES = 32
#: Half-width (m) of the floor square seen by the orthographic camera from above.
HALF_WIDTH = 2.0
HEIGHT = 1.0
RES = 16
#: A float32 render against a float64 formula.
RTOL_EXACT = 2e-4


def top_view(objects: dict, res: int = RES, spp: int = 1) -> dict:
    """A floor y = 0 seen straight from above by an orthographic camera over 2 HALF_WIDTH
    metres (box filter; spp 1: one sample at each pixel centre), with ``objects``."""
    import mitsuba as mi

    T = mi.ScalarTransform4f()
    sampler = {"type": "stratified", "sample_count": 1, "jitter": False} if spp == 1 else \
        {"type": "independent", "sample_count": spp}
    return {
        "type": "scene",
        "integrator": {"type": "path"},  # replaced by render_lux
        "sensor": {"type": "orthographic",
                   "to_world": T.look_at([0, 8, 0], [0, 0, 0], [0, 0, 1]).scale(
                       [HALF_WIDTH, HALF_WIDTH, 1]),
                   "film": {"type": "hdrfilm", "width": res, "height": res,
                            "rfilter": {"type": "box"}},
                   "sampler": sampler},
        "floor": {"type": "rectangle", "to_world": T.rotate([1, 0, 0], -90).scale(10)},
        **objects,
    }


def pixel_area(res: int) -> float:
    return (2.0 * HALF_WIDTH / res) ** 2


def load(scene: dict):
    import mitsuba as mi

    return mi.load_dict(scene)


# -- parsing -----------------------------------------------------------------------------------

def test_parse_plane():
    """A point and a normal separated by white space; the normal comes back of length 1."""
    from spectrace.lux import parse_plane

    point, normal = parse_plane("0,0.85,0  0,2,0")
    assert point == (0.0, 0.85, 0.0) and normal == (0.0, 1.0, 0.0)


@pytest.mark.parametrize("text", ["0,0.85,0", "0,0.85 0,1,0", "a,b,c 0,1,0", "0,1,0 0,1,0 1",
                                  "0,1,0 0,nan,1", "0,1,0 0,0,0", ""])
def test_malformed_plane_is_a_user_error(text):
    """Anything else is a one-line ParameterError naming the parameter (plane, or the name
    the caller gives: the command line's flag) and showing the expected form."""
    from spectrace.lux import parse_plane

    with pytest.raises(ParameterError, match="^plane ") as info:
        parse_plane(text)
    assert "\n" not in str(info.value) and "--" not in str(info.value)
    with pytest.raises(ParameterError, match="^work_plane "):
        parse_plane(text, name="work_plane")


def test_parse_plane_extreme_numbers():
    """A normal of huge or tiny components is normalised without overflow or underflow
    (1e300,1e300,0 became the zero normal, 'parallel to the view'); a point beyond float32,
    which the renderer would make infinite, is a one-line ParameterError naming plane."""
    from spectrace.lux import parse_plane

    _, normal = parse_plane("0,0,0 1e300,1e300,0")
    np.testing.assert_allclose(normal, (np.sqrt(0.5), np.sqrt(0.5), 0.0), rtol=1e-12)
    _, normal = parse_plane("0,0,0 0,1e-320,0")
    assert normal == (0.0, 1.0, 0.0)
    with pytest.raises(ParameterError, match="^plane .*float32"):
        parse_plane("1e308,0,0 0,1,0")


def test_parse_range():
    """MIN,MAX with 0 <= MIN < MAX; log needs MIN > 0. The messages name the parameters
    value_range and log (or the names the caller gives)."""
    from spectrace.lux import parse_range

    assert parse_range("0,500") == (0.0, 500.0)
    assert parse_range("10,1e4", log=True) == (10.0, 1e4)
    for text, log in (("500,0", False), ("5", False), ("-1,5", False), ("0,5", True),
                      ("x,5", False), ("1,inf", False)):
        with pytest.raises(ParameterError, match="^value_range ") as info:
            parse_range(text, log)
        assert "--" not in str(info.value)
    with pytest.raises(ParameterError, match="^value_range '0,5': log needs MIN > 0"):
        parse_range("0,5", log=True)
    with pytest.raises(ParameterError, match="^scale '0,5': logarithmic needs MIN > 0"):
        parse_range("0,5", log=True, names=("scale", "logarithmic"))


def test_statistics_and_uniformity():
    """E_min, E_mean, E_max over the pixels with data only; U0 = E_min / E_mean."""
    from spectrace.lux import lux_statistics

    lux = np.array([[100.0, 300.0], [200.0, 0.0]])
    valid = np.array([[True, True], [True, False]])
    low, mean, high, u0 = lux_statistics(lux, valid)
    assert (low, mean, high) == (100.0, 200.0, 300.0) and u0 == pytest.approx(0.5)
    assert np.isnan(lux_statistics(np.zeros((2, 2)), np.ones((2, 2), bool))[3])
    with pytest.raises(ParameterError, match="no pixel"):
        lux_statistics(lux, np.zeros((2, 2), bool))


# -- flux ----------------------------------------------------------------------------------------

def test_spotlight_flux_reaches_the_floor(variant):
    """A spotlight of luminous_flux Phi_v aimed straight down 1 m above the floor (umbra
    45 degrees: the cone ends 1 m from its axis, inside the view): the lux integrated over
    the floor (sum of the pixel means times the pixel area) is Phi_v, in RGB and spectral
    variants."""
    import mitsuba as mi

    from spectrace.lux import render_lux

    flux = 1000.0
    T = mi.ScalarTransform4f()
    light = {"type": "spotlight", "luminous_flux": flux, "umbra_angle": 45.0,
             "penumbra_angle": 25.0,
             "to_world": T.look_at([0.1, HEIGHT, -0.2], [0.1, 0.0, -0.2], [0, 0, 1])}
    luxmap = render_lux(load(top_view({"light": light}, FLUX_RES, FLUX_SPP)), FLUX_SPP, seed=1)
    assert luxmap.valid.all() and luxmap.lux[0, 0] == 0.0
    np.testing.assert_allclose(luxmap.lux.sum() * pixel_area(FLUX_RES), flux, rtol=RTOL_FLUX)


def test_ies_downlight_flux_reaches_the_floor(variant_rgb, tmp_path):
    """An ``ieslight`` downlight, I = I0 cos^10(gamma) (flux 2 pi I0 / 11, 99.95 % of it
    within 60 degrees of the nadir) written as an IES file, 1 m above the floor: the lux
    integrated over the floor is the file's luminous flux."""
    import mitsuba as mi
    from spectrace.photometry import generate

    from spectrace.lux import render_lux

    I0, n = 500.0, 10.0
    path = generate.write_ies_function(tmp_path / "down.ies", generate.cos_power(I0, n),
                                       vertical_angles=np.arange(0.0, 180.001, 2.5))
    T = mi.ScalarTransform4f()
    light = {"type": "ieslight", "filename": str(path),
             "to_world": T.look_at([0.0, HEIGHT, 0.0], [0.0, 0.0, 0.0], [0, 0, 1])}
    luxmap = render_lux(load(top_view({"light": light}, FLUX_RES, FLUX_SPP)), FLUX_SPP, seed=2)
    np.testing.assert_allclose(luxmap.lux.sum() * pixel_area(FLUX_RES),
                               2 * np.pi * I0 / (n + 1), rtol=RTOL_FLUX)


# -- the work plane ----------------------------------------------------------------------------

def test_work_plane_pixels_without_data(variant_rgb):
    """A perspective camera looking horizontally at a horizontal work plane below it: the
    upper half of the view never crosses it (no data, 0 in the map, left out of the
    statistics), the lower half measures it, at most I / h^2 (under the light, in view);
    no NaN anywhere."""
    import mitsuba as mi

    from spectrace.lux import render_lux

    T = mi.ScalarTransform4f()
    scene = top_view({"light": {"type": "pointlight", "position": [0.0, 2.0, 3.0],
                                "luminous_intensity": 100.0}})
    scene["sensor"].update({"type": "perspective", "fov": 60,
                            "to_world": T.look_at([0, 1.5, 0], [0, 1.5, 1], [0, 1, 0])})
    luxmap = render_lux(load(scene), 1, plane=((0.0, 0.85, 0.0), (0.0, 1.0, 0.0)))
    assert np.isfinite(luxmap.lux).all()
    assert not luxmap.valid[: RES // 2 - 1].any() and luxmap.valid[RES // 2 + 1:].all()
    assert np.all(luxmap.lux[~luxmap.valid] == 0.0)
    values = luxmap.lux[luxmap.valid]
    assert luxmap.minimum == values.min() > 0.0 and luxmap.maximum == values.max()
    assert luxmap.uniformity == pytest.approx(values.min() / values.mean(), rel=1e-6)
    peak = 100.0 / (2.0 - 0.85) ** 2  # right under the light
    assert 0.5 * peak < luxmap.maximum <= peak * (1.0 + RTOL_EXACT)


def test_plane_parallel_to_the_view_is_a_user_error(variant_rgb):
    """An orthographic camera looking horizontally never meets a horizontal plane: a
    one-line ParameterError before rendering; a plane behind a perspective camera too."""
    import mitsuba as mi

    from spectrace.lux import render_lux

    T = mi.ScalarTransform4f()
    scene = top_view({"light": {"type": "pointlight", "position": [0.0, 2.0, 0.0]}})
    scene["sensor"]["to_world"] = T.look_at([0, 1.5, 0], [0, 1.5, 1], [0, 1, 0])
    with pytest.raises(ParameterError, match="^plane .*parallel to the view"):
        render_lux(load(scene), 1, plane=((0.0, 0.85, 0.0), (0.0, 1.0, 0.0)))
    scene["sensor"] = {"type": "perspective", "fov": 40,
                       "to_world": T.look_at([0, 1.5, 0], [0, 0, 0], [0, 0, 1])}
    with pytest.raises(ParameterError, match="^plane .*behind the camera"):
        render_lux(load(scene), 1, plane=((0.0, 3.0, 0.0), (0.0, 1.0, 0.0)))


# -- files and the scene tree --------------------------------------------------------------------

def test_exr_and_png(variant_rgb, tmp_path):
    """The EXR holds one float32 channel Y equal to the map, in lux, with the statistics
    in its header; the PNG is a PNG; contour levels lie strictly inside the colour range;
    no temporary file is left."""
    from spectrace.lux import plot_lux, read_lux_exr, render_lux, write_lux_exr

    scene = top_view({"light": {"type": "pointlight", "position": [0.0, HEIGHT, 0.0],
                                "luminous_intensity": 100.0}})
    luxmap = render_lux(load(scene), 1)
    write_lux_exr(tmp_path / "m.exr", luxmap, {"scene": "top"})
    Y, header = read_lux_exr(tmp_path / "m.exr")
    assert Y.dtype == np.float32 and Y.shape == (RES, RES)
    np.testing.assert_array_equal(Y, luxmap.lux)
    assert header["units"] == "lux" and header["scene"] == "top"
    assert header["E_max"] == pytest.approx(luxmap.maximum)
    assert header["U0"] == pytest.approx(luxmap.uniformity)
    for log in (False, True):
        levels = plot_lux(tmp_path / "m.png", luxmap, value_range=(1.0, 100.0), log=log)
        assert levels.size >= 2 and levels.min() > 1.0 and levels.max() < 100.0
        assert (tmp_path / "m.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.exr", "m.png"]


def test_scene_tree_for_the_command():
    """The integrators become one ``illuminance``; each sensor's film a box-filtered
    hdrfilm keeping its id and size parameters verbatim ($res); no sensor: ParameterError."""
    from spectrace.lux import lux_scene_tree

    root = ET.fromstring(
        '<scene version="3.0.0"><integrator type="path"/>'
        '<sensor type="perspective"><film type="specfilm" id="f">'
        '<integer name="width" value="$res"/><integer name="height" value="24"/>'
        '<rfilter type="gaussian"/><spectrum name="band0" value="1"/></film></sensor></scene>')
    lux_scene_tree(root)
    assert [i.get("type") for i in root.iter("integrator")] == ["illuminance"]
    film = root.find("sensor/film")
    assert film.get("type") == "hdrfilm" and film.get("id") == "f"
    assert film.find("integer[@name='width']").get("value") == "$res"
    assert [r.get("type") for r in film.iter("rfilter")] == ["box"]
    assert film.find("spectrum") is None
    with pytest.raises(ParameterError, match="no <sensor>"):
        lux_scene_tree(ET.fromstring('<scene version="3.0.0"/>'))


def test_display_exposure_is_set_to_one_for_true_lux():
    """A scene's display `exposure` multiplies its lights: a lux map sets it to 1 (true
    units) unless the user chose it; a scene without one is left alone."""
    from spectrace.lux import true_units

    with_exposure = ET.fromstring('<scene version="3.0.0"><default name="exposure" '
                                  'value="600"/><emitter type="point"><float name="scale" '
                                  'value="$exposure"/></emitter></scene>')
    without = ET.fromstring('<scene version="3.0.0"><default name="res" value="8"/></scene>')
    assert true_units(with_exposure, {}) == {"exposure": "1"}
    assert true_units(with_exposure, {"exposure": "2"}) == {"exposure": "2"}
    assert true_units(without, {"res": "4"}) == {"res": "4"}


def test_display_exposure_declared_but_unused_is_left_alone():
    """A scene that declares `exposure` but never uses $exposure: setting it would make
    Mitsuba refuse an unused parameter that the user never gave, so it is not set; a use
    inside a longer value (value="2*$exposure" style) counts, $exposure_x does not."""
    from spectrace.lux import true_units

    unused = ET.fromstring('<scene version="3.0.0"><default name="exposure" value="600"/>'
                           '<emitter type="point"><float name="scale" value="$exposure_x"/>'
                           '</emitter></scene>')
    used = ET.fromstring('<scene version="3.0.0"><default name="exposure" value="600"/>'
                         '<emitter type="point"><rgb name="intensity" value="$exposure, 1, 1"/>'
                         '</emitter></scene>')
    assert true_units(unused, {}) == {}
    assert true_units(used, {}) == {"exposure": "1"}


def test_seed_range():
    """Seeds are stored as 32-bit EXR integers: outside that range a ParameterError (the header
    wrapped 99999999999 to 1215752191)."""
    from spectrace.passes import check_seed

    assert check_seed(-(2**31)) == -(2**31) and check_seed(2**31 - 1) == 2**31 - 1
    with pytest.raises(ParameterError, match=r"seed must be between .* \(got 99999999999\)"):
        check_seed(99999999999)
