"""Tests of ``spectrace.lighting.grids``: EN 12464-1's spacing rule, the points of a grid
(cell centres, border band excluded, plan-to-scene axes), the grid measured at exact
positions against E = I h / r^3 of an off-centre point light, the statistics and
maintenance factor, the task check, the CSV and the figure, and the errors.

Oracles: the formula p = 0.2 x 5^log10(d) evaluated here and the examples of it that
lighting manufacturers tabulate (5 m: 0.6 m, 10 m: 1 m, 50 m: 3 m); closed forms.
"""

from __future__ import annotations

import numpy as np
import pytest

#: Exact measurements (one sample) against float64 closed forms.
RTOL_EXACT = 1e-5
#: Published examples are rounded (50 m: 3.08 m is tabulated as 3 m).
ATOL_TABULATED = 0.1
LIGHT = np.array([1.3, 2.4, -0.9])  # off-centre in the 6 x 4 room below
INTENSITY = 1000.0


def room(variant_name=None):
    """A closed 6 m x 4 m x 3 m box (plan x in [0, 6], y in [0, 4], scene z in [-4, 0]) with
    a 1000 cd point light inside it."""
    import mitsuba as mi

    T = mi.ScalarTransform4f
    return mi.load_dict({
        "type": "scene",
        "room": {"type": "cube", "flip_normals": True,
                 "to_world": T().translate([3.0, 1.5, -2.0]).scale([3.0, 1.5, 2.0])},
        "light": {"type": "pointlight", "position": LIGHT.tolist(),
                  "luminous_intensity": INTENSITY},
    })


def test_spacing_rule():
    """p = 0.2 x 5^log10(d): 0.2 m at 1 m, 1 m at 10 m, 5 m at 100 m, the tabulated 0.6 m
    at 5 m and 3 m at 50 m, and at most 10 m."""
    from spectrace.lighting.grids import grid_spacing

    assert grid_spacing(1.0) == pytest.approx(0.2)
    assert grid_spacing(10.0) == pytest.approx(1.0)
    assert grid_spacing(100.0) == pytest.approx(5.0)
    assert grid_spacing(5.0) == pytest.approx(0.6, abs=ATOL_TABULATED)
    assert grid_spacing(50.0) == pytest.approx(3.0, abs=ATOL_TABULATED)
    assert grid_spacing(1e6) == 10.0


def test_grid_points_are_cell_centres_inside_the_border():
    """'0,0 6,4 @ 0.8' with the 0.5 m band: a 5 x 3 m area, d = 5 m, p = 0.617 m, so
    ceil(5 / p) = 9 columns and ceil(3 / (5 / 9)) = 6 rows at the centres of equal cells;
    spacing never above p; plan (x, y) is the scene's (x, h, -y)."""
    from spectrace.lighting.grids import grid_spacing, make_grid, parse_grid

    rectangle, h = parse_grid(" 6,4  0,0 @0.8")  # corners in any order
    assert rectangle == (0.0, 0.0, 6.0, 4.0) and h == 0.8
    grid = make_grid(rectangle, h)
    p = grid_spacing(5.0)
    assert grid.shape == (6, 9)
    np.testing.assert_allclose(grid.xs, 0.5 + (np.arange(9) + 0.5) * 5.0 / 9)
    np.testing.assert_allclose(grid.ys, 0.5 + (np.arange(6) + 0.5) * 3.0 / 6)
    assert np.diff(grid.xs).max() <= p and np.diff(grid.ys).max() <= p
    points = grid.points()
    assert points.shape == (54, 3)
    np.testing.assert_allclose(points[1], [grid.xs[1], 0.8, -grid.ys[0]])
    np.testing.assert_allclose(points[9], [grid.xs[0], 0.8, -grid.ys[1]])
    wide = make_grid(rectangle, h, border=0.0, spacing=2.0)
    assert wide.shape == (2, 3)


def test_grid_at_exact_positions(variant):
    """The grid measured at its points: maintained illuminance MF x 1000 h / r^3 (h the
    light's height above the plane) at each point to RTOL_EXACT, one sample each, and
    E_m, E_min, E_max, U0, E_min/E_max those of the closed form."""
    from spectrace.lighting.grids import make_grid, measure_grid

    grid = make_grid((0.0, 0.0, 6.0, 4.0), 0.8)
    result = measure_grid(room(), grid, maintenance_factor=0.8)
    p = grid.points()
    v = LIGHT - p
    expected = 0.8 * INTENSITY * v[:, 1] / np.linalg.norm(v, axis=1) ** 3
    assert result.samples == 1 and np.all(result.stderr == 0.0)
    np.testing.assert_allclose(result.lux.ravel(), expected, rtol=RTOL_EXACT)
    s = result.stats
    np.testing.assert_allclose([s["E_m"], s["E_min"], s["E_max"], s["U0"], s["E_min/E_max"]],
                               [expected.mean(), expected.min(), expected.max(),
                                expected.min() / expected.mean(),
                                expected.min() / expected.max()], rtol=RTOL_EXACT)


def test_task_check_csv_and_plan(variant_rgb, tmp_path):
    """The office task (E_m 500 lx, U0 0.60) fails for this room and a corridor's 100 lx
    passes on E_m; the CSV has x,y,z,lux,stderr per point; the plan PNG is written."""
    from spectrace.lighting import grids

    scene = room()
    grid = grids.make_grid((0.0, 0.0, 6.0, 4.0), 0.8)
    result = grids.measure_grid(scene, grid)
    assert result.check(grids.task("office")) == {"E_m": False, "U0": False}
    assert result.check(grids.task("corridor"))["E_m"] is (result.stats["E_m"] >= 100.0)
    out = tmp_path / "grid.csv"
    grids.write_grid_csv(out, result)
    assert out.read_text().splitlines()[0] == "x,y,z,lux,stderr"
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, :3], grid.points(), rtol=1e-7)
    np.testing.assert_allclose(data[:, 3], result.lux.ravel(), rtol=1e-7)
    plan = tmp_path / "plan.png"
    grids.plot_plan(plan, result, grids.room_outline(scene))
    assert plan.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert grids.room_outline(scene) == pytest.approx((0.0, 0.0, 6.0, 4.0))


def test_grid_named_by_a_scene_parameter():
    """A name is looked up in the scene's parameters (<default name="workplane" .../>), so
    'workplane' reads as the grid it holds; spaces around the name are allowed."""
    import xml.etree.ElementTree as ET

    from spectrace.lighting.grids import parse_grid
    from spectrace.scene import scene_defaults

    tree = ET.fromstring('<scene version="3.0.0"><default name="res" value="24"/>'
                         '<default name="workplane" value="6,4 0,0 @ 0.8"/></scene>')
    assert parse_grid(" workplane ", scene_defaults(tree)) == ((0.0, 0.0, 6.0, 4.0), 0.8)


@pytest.mark.parametrize(("call", "message"), [
    (lambda g: g.parse_grid("0,0 6,4"), "expected 'x0,y0 x1,y1 @ h'"),
    (lambda g: g.parse_grid("desk", {"res": "24", "room": "0,0 6,4 @ 0.8"}),
     r"^grid 'desk': the scene has no <default name='desk'> \(its grids: room\)$"),
    (lambda g: g.parse_grid("desk"), r"none of its <default>s holds a grid"),
    (lambda g: g.parse_grid("res", {"res": "24"}),
     r"^<default name='res'>: grid '24': expected 'x0,y0 x1,y1 @ h'"),
    (lambda g: g.parse_grid("0,0 0,4 @ 1"), "no area"),
    (lambda g: g.make_grid((0, 0, 6, 4), 0.8, spacing=0.0), "spacing must be > 0"),
    (lambda g: g.make_grid((0, 0, 1, 1), 0.8), "leaves no calculation area"),
    (lambda g: g.check_maintenance_factor(1.2), "must be > 0 and <= 1"),
    (lambda g: g.check_maintenance_factor(0.0), "must be > 0 and <= 1"),
    (lambda g: g.task("kitchen"), "expected one of office"),
])
def test_bad_grids(call, message):
    """Malformed grids, a grid name the scene's parameters lack or whose value is no grid,
    zero spacing, a border larger than the room, a maintenance factor outside (0, 1] and an
    unknown task: one-line ParameterErrors."""
    from spectrace.errors import ParameterError
    from spectrace.lighting import grids

    with pytest.raises(ParameterError, match=message) as info:
        call(grids)
    assert "\n" not in str(info.value)


def test_grid_outside_the_scene(variant_rgb):
    """A grid that reaches outside the room's bounds, or above its ceiling, is refused."""
    from spectrace.errors import ParameterError
    from spectrace.lighting.grids import check_in_scene, make_grid

    scene = room()
    with pytest.raises(ParameterError, match="lie outside the scene"):
        check_in_scene(make_grid((0.0, 0.0, 9.0, 4.0), 0.8), scene)
    with pytest.raises(ParameterError, match="lie outside the scene"):
        check_in_scene(make_grid((0.0, 0.0, 6.0, 4.0), 3.5), scene)
    check_in_scene(make_grid((0.0, 0.0, 6.0, 4.0), 0.8), scene)
