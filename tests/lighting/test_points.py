"""Tests of ``spectrace.lighting.points``: illuminance at sensor points of every kind
(horizontal, vertical, cylindrical, semi-cylindrical) against the closed forms of a point
source, exact at one sample in RGB and spectral variants; a shadow; an area light's
estimate and its standard error; the CSV files and their errors.

Oracles: closed forms written here (E = I cos / r^2; E_z = I sin(theta) / (pi r^2); E_sc =
I (sin(theta) + d_h . f) / (pi r^2)) and the on-axis illuminance of a Lambertian disk.
"""

from __future__ import annotations

import numpy as np
import pytest

#: Exact measurements (one sample) against float64 closed forms.
RTOL_EXACT = 1e-5
#: An area light's estimate must lie within this many standard errors of the truth.
STDERR_SPAN = 4.0
AREA_SPP = 4096
KM = 683.0
LIGHT = np.array([0.3, 2.0, -0.4])
INTENSITY = 1000.0
TABULATED = {"type": "spectrum", "value": [(400.0, 1.0), (550.0, 3.0), (700.0, 2.0)]}


def point_scene(extra: dict | None = None):
    import mitsuba as mi

    scene = {"type": "scene", "light": {"type": "pointlight", "position": LIGHT.tolist(),
                                        "luminous_intensity": INTENSITY,
                                        "spectrum": TABULATED}}
    scene.update(extra or {})
    return mi.load_dict(scene)


def closed_forms(p: np.ndarray, f: np.ndarray) -> dict[str, np.ndarray]:
    """The four kinds at points p (N, 3) for the light LIGHT; f (N, 3) the horizontal unit
    facing directions of the vertical and semi-cylindrical ones."""
    v = LIGHT - p
    r = np.linalg.norm(v, axis=1)
    d = v / r[:, None]
    d_h = d.copy()
    d_h[:, 1] = 0.0
    sin = np.linalg.norm(d_h, axis=1)
    E_normal = INTENSITY / r**2
    return {
        "horizontal": E_normal * np.maximum(d[:, 1], 0.0),
        "vertical": E_normal * np.maximum(np.sum(d * f, axis=1), 0.0),
        "cylindrical": E_normal * sin / np.pi,
        "semicylindrical": E_normal * (sin + np.sum(d_h * f, axis=1)) / np.pi,
    }


def test_every_kind_against_closed_forms(any_variant, rng):
    """In every variant, a 1000 cd point source of a non-flat spectrum: horizontal,
    vertical, cylindrical
    and semi-cylindrical illuminance at random points below it equal their closed forms
    to RTOL_EXACT with one sample per point and standard error 0."""
    from spectrace.lighting.points import measure_points

    scene = point_scene()
    p = np.column_stack([rng.uniform(-3, 3, 40), rng.uniform(0, 1.5, 40), rng.uniform(-3, 3, 40)])
    angle = rng.uniform(0, 2 * np.pi, 40)
    f = np.column_stack([np.cos(angle), np.zeros(40), np.sin(angle)])
    expected = closed_forms(p, f)
    up = np.tile([0.0, 1.0, 0.0], (40, 1))
    cases = {"horizontal": ("planar", up), "vertical": ("planar", f),
             "cylindrical": ("cylindrical", up), "semicylindrical": ("semicylindrical", f)}
    for name, (kind, normals) in cases.items():
        lux, stderr, samples = measure_points(scene, p, normals, kind=kind)
        assert samples == 1 and np.all(stderr == 0.0)
        np.testing.assert_allclose(lux, expected[name], rtol=RTOL_EXACT,
                                   atol=RTOL_EXACT * expected[name].max(), err_msg=name)
    assert expected["vertical"].min() == 0.0 < expected["vertical"].max()  # both sides


def test_occluder_casts_a_shadow(variant_rgb):
    """A square occluder between the light and a point: 0 lux there, the closed form
    beside it (the shadow ray is traced from the point itself)."""
    import mitsuba as mi

    from spectrace.lighting.points import measure_points

    T = mi.ScalarTransform4f
    scene = point_scene({"occluder": {"type": "rectangle", "to_world": T().translate(
        [0.3, 1.0, -0.4]).rotate([1, 0, 0], 90).scale(0.2)}})
    p = np.array([[0.3, 0.0, -0.4], [2.0, 0.0, 1.0]])
    up = np.tile([0.0, 1.0, 0.0], (2, 1))
    lux, _, _ = measure_points(scene, p, up)
    assert lux[0] == 0.0
    np.testing.assert_allclose(lux[1], closed_forms(p, up)["horizontal"][1], rtol=RTOL_EXACT)


def test_area_light_estimate_and_standard_error(variant):
    """A Lambertian disk of radiance L and radius R at height h: the mean of AREA_SPP
    samples lies within STDERR_SPAN standard errors of pi L R^2 / (h^2 + R^2) (times
    K_m integral V for a flat spectrum), and the error is small but not zero."""
    import mitsuba as mi
    from spectrace.plugins.emitters import luminous

    from spectrace.lighting.points import measure_points

    L, R, h = 0.5, 0.5, 1.0
    T = mi.ScalarTransform4f
    scene = mi.load_dict({"type": "scene", "disk": {
        "type": "disk", "to_world": T().translate([0, h, 0]).rotate([1, 0, 0], 90).scale(R),
        "emitter": {"type": "area", "radiance": {"type": "uniform", "value": L}}}})
    lux, stderr, samples = measure_points(scene, [[0.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]],
                                          spp=AREA_SPP, seed=3)
    expected = KM * luminous.v_integral() * np.pi * L * R**2 / (h**2 + R**2)
    assert samples == AREA_SPP and 0.0 < stderr[0] < 0.02 * expected
    assert abs(lux[0] - expected) < STDERR_SPAN * stderr[0]


def test_csv_round_trip(tmp_path):
    """Points written and read back are the same numbers; a header line and comments are
    allowed; the output has the columns x,y,z,nx,ny,nz,lux,stderr."""
    from spectrace.lighting.points import (
        OUTPUT_COLUMNS,
        read_points_csv,
        read_points_table,
        write_points_csv,
    )

    source = tmp_path / "points.csv"
    source.write_text("x,y,z,nx,ny,nz\n# a comment\n0,0.8,0, 0,1,0\n1.5,0.8,-2,1,0,0\n\n")
    p, n = read_points_csv(source)
    np.testing.assert_array_equal(p, [[0, 0.8, 0], [1.5, 0.8, -2]])
    np.testing.assert_array_equal(n, [[0, 1, 0], [1, 0, 0]])
    out = tmp_path / "out.csv"
    lux, err = np.array([123.456789, 1e-3]), np.array([0.0, 1.25e-5])
    write_points_csv(out, p, n, lux, err)
    lines = out.read_text().splitlines()
    assert lines[0] == ",".join(OUTPUT_COLUMNS)
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data, np.column_stack([p, n, lux, err]), rtol=1e-8)
    p, n, rows = read_points_table(source)  # the input's text written back as it was
    assert rows == ["0,0.8,0,0,1,0", "1.5,0.8,-2,1,0,0"]
    write_points_csv(out, p, n, lux, err, rows=rows)
    again = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_array_equal(again, data)
    assert out.read_text().splitlines()[1].startswith("0,0.8,0,0,1,0,123.456789,0")
    write_points_csv(out, p, n, lux, np.zeros(2), rows=rows)  # exact: every error 0
    exact = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_array_equal(exact[:, 6], data[:, 6])
    np.testing.assert_array_equal(exact[:, 7], 0.0)


@pytest.mark.parametrize("text", [
    "x,y,z,nx,ny,nz\n0,0.8,0, 0,1,0\n1.5,0.8,-2,1,0,0\n",  # plain: the one-pass reader
    "0,0.8,0, 0,1,0\n1.5,0.8,-2,1,0,0",  # plain, no header, no last newline
    "x,y,z,nx,ny,nz\r\n0,0.8,0, 0,1,0\r\n1.5,0.8,-2,1,0,0\r\n",  # CRLF: the general one
    "0,0.8,0,\t0,1,0\n\n1.5,0.8,-2,1,0,0 # two\n",  # a tab, a blank line, a comment
])
def test_plain_and_general_files_read_alike(tmp_path, text):
    """Whichever reader a file takes (the one-pass reader of plain files or the general
    one), the points, vectors and echoed rows are the same."""
    from spectrace.lighting.points import read_points_table

    path = tmp_path / "points.csv"
    path.write_bytes(text.encode())
    p, n, rows = read_points_table(path)
    np.testing.assert_array_equal(p, [[0, 0.8, 0], [1.5, 0.8, -2]])
    np.testing.assert_array_equal(n, [[0, 1, 0], [1, 0, 0]])
    assert rows == ["0,0.8,0,0,1,0", "1.5,0.8,-2,1,0,0"]


@pytest.mark.parametrize(("text", "message"), [
    ("x,y,z,nx,ny,nz\n0,0,0,0,1\n", "line 2: expected six finite numbers"),
    ("0,0,0,0,1,0\n0,0,zero,0,1,0\n", "line 2: expected six numbers"),
    ("x,y,z\n", "no points"),
    ("0,0,nan,0,1,0\n", "line 1: expected six finite numbers"),
    ("0,0,0,0,1,0\n0,0,inf,0,1,0\n", "line 2: expected six finite numbers"),
    ("0,0,0,0,1,0,7\n", "line 1: expected six finite numbers"),
])
def test_bad_points_files(tmp_path, text, message):
    """A line without six finite numbers fails with one line naming the file and line."""
    from spectrace.errors import FileFormatError
    from spectrace.lighting.points import read_points_csv

    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(FileFormatError, match=message) as info:
        read_points_csv(path)
    assert str(path) in str(info.value) and "\n" not in str(info.value)


def test_bad_normals(variant_rgb):
    """A zero normal and a vertical semi-cylinder facing are refused with one line."""
    from spectrace.errors import ParameterError
    from spectrace.lighting.points import measure_points

    scene = point_scene()
    with pytest.raises(ParameterError, match="zero normal"):
        measure_points(scene, [[0, 0, 0]], [[0, 0, 0]])
    with pytest.raises(ParameterError, match="horizontal facing direction"):
        measure_points(scene, [[0, 0, 0]], [[0, 1, 0]], kind="semicylindrical")
    with pytest.raises(ParameterError, match="kind 'spherical'"):
        measure_points(scene, [[0, 0, 0]], [[0, 1, 0]], kind="spherical")


def test_windowed_light_is_exact(variant):
    """A light whose windowed falloff ends before one metre (R = 0.6 m) is still exact:
    E = I cos / r^2 clamp(1 - (r / R)^4, 0, 1)^2 at points 0.3 m below and beside it
    (its luminous factor is read close to it), one sample, standard error 0."""
    import mitsuba as mi

    from spectrace.lighting.points import measure_points

    light = np.array([0.0, 0.3, 0.0])
    scene = mi.load_dict({"type": "scene", "light": {
        "type": "pointlight", "position": light.tolist(), "luminous_intensity": 50.0,
        "spectrum": TABULATED, "falloff": "windowed", "radius": 0.6}})
    x = np.linspace(0.0, 0.6, 7)
    p = np.column_stack([x, np.zeros(7), np.zeros(7)])
    lux, stderr, samples = measure_points(scene, p, np.tile([0.0, 1.0, 0.0], (7, 1)))
    r = np.linalg.norm(light - p, axis=1)
    window = np.clip(1 - (r / 0.6) ** 4, 0, 1) ** 2
    expected = 50.0 * (0.3 / r) / r**2 * window
    assert samples == 1 and np.all(stderr == 0.0)
    np.testing.assert_allclose(lux, expected, rtol=RTOL_EXACT, atol=RTOL_EXACT * expected.max())


#: 9 points on the floor of the roof-opening room: MAX_LANES // 9 = 233016 samples per
#: pass make Dr.Jit arrays of 2097144 floats, 8 short of a packet multiple, whose numpy
#: buffers end 16 bytes before the end of their pages: the case that crashed.
CRASH_POINTS, CRASH_SPP = 9, 233016
CRASH_SCRIPT = r"""
import sys
import numpy as np, spectrace
spectrace.set_variant("llvm_ad_rgb")
from spectrace.lighting.points import measure_points
from spectrace.validation import cases
scene = cases._load("daylight_roof", cases.Settings(), sky_type="uniform")
n, spp = int(sys.argv[1]), int(sys.argv[2])
points = np.stack([np.linspace(-1.6, 1.6, n), np.zeros(n), np.zeros(n)], -1)
lux, stderr, samples = measure_points(scene, points, np.tile([0.0, 1.0, 0.0], (n, 1)), spp=spp)
print(samples, *lux)
"""


def test_many_samples_under_a_python_sky_do_not_crash():
    """measure_points at CRASH_POINTS x CRASH_SPP samples under the ``ciesky`` of the
    roof-opening validation room runs to the end (it died of SIGSEGV: Dr.Jit read past the
    end of the numpy arrays of the points, see ``host_array``) and gives a positive,
    finite illuminance at every point. (A subprocess: a crash fails this test alone.)"""
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", CRASH_SCRIPT, str(CRASH_POINTS),
                           str(CRASH_SPP)], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, f"rc {done.returncode}: {done.stderr[-2000:]}"
    samples, *lux = done.stdout.split()
    assert int(samples) == CRASH_SPP
    assert len(lux) == CRASH_POINTS and all(0.0 < float(v) < float("inf") for v in lux)
