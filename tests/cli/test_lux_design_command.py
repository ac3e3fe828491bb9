"""``spectrace lux`` for lighting design end to end: ``--grid`` (CSV, plan PNG, printed
Em / Emin / Emax / U0, ``--maintenance-factor``, ``--task``), ``--points`` (CSV round trip,
kinds), ``--luminance`` and ``--ugr``, ``--report``; and the one-line errors that write
nothing.

Oracles: E = MF I h / r^3 of an off-centre 1000 cd point light at the grid's and the
points' exact positions; the Markdown report's own text."""

from __future__ import annotations

import os

import numpy as np
import pytest
from error_checks import assert_one_line_error

from spectrace.cli import main

EXIT_USAGE = 2
#: Exact measurements (one sample per point) against float64 closed forms.
RTOL_EXACT = 1e-5
LIGHT = np.array([1.3, 2.4, -0.9])

#: A closed 6 m x 4 m x 3 m room (plan x 0..6, y 0..4: scene z 0..-4), a 1000 cd light
#: off-centre, a camera at eye height looking north (-Z) and a small area light ahead.
ROOM = """<scene version="3.0.0">
    <default name="res" value="24"/>
    <sensor type="perspective">
        <float name="fov" value="90"/>
        <transform name="to_world"><lookat origin="3, 1.2, -0.5" target="3, 1.2, -2"
            up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        <film type="hdrfilm"><integer name="width" value="$res"/>
            <integer name="height" value="$res"/></film>
    </sensor>
    <shape type="cube">
        <boolean name="flip_normals" value="true"/>
        <transform name="to_world"><scale x="3" y="1.5" z="2"/>
            <translate x="3" y="1.5" z="-2"/></transform>
    </shape>
    <emitter type="pointlight">
        <point name="position" x="1.3" y="2.4" z="-0.9"/>
        <float name="luminous_intensity" value="1000"/>
    </emitter>
    {extra}
</scene>
"""
LAMP = """<shape type="rectangle">
        <transform name="to_world"><scale value="0.2"/><rotate x="1" angle="90"/>
            <translate x="3.3" y="2.5" z="-3"/></transform>
        <emitter type="area"><rgb name="radiance" value="5"/></emitter>
    </shape>"""


def write_room(tmp_path, extra=""):
    path = tmp_path / "room.xml"
    path.write_text(ROOM.format(extra=extra))
    return path


def law(p, mf=1.0, normal=(0.0, 1.0, 0.0)):
    v = LIGHT - np.asarray(p, dtype=np.float64)
    return mf * 1000.0 * np.maximum(v @ np.asarray(normal), 0.0) / np.linalg.norm(v, axis=1) ** 3


def test_grid_csv_plan_statistics_and_task(tmp_path, capsys):
    """--grid '0,0 6,4 @ 0.8' --maintenance-factor 0.8 --task office: OUT.csv has
    x,y,z,lux,stderr at the EN 12464-1 points with MF x 1000 h / r^3 each; the plan PNG is
    beside it; Em, Emin, Emax, U0 and the task's pass/fail are printed."""
    scene = write_room(tmp_path)
    out = tmp_path / "grid.csv"
    code = main(["lux", str(scene), "--grid", "0,0 6,4 @ 0.8", "--maintenance-factor", "0.8",
                 "--task", "office", "-o", str(out), "--variant", "llvm_ad_spectral", "-q"])
    assert code == 0
    lines = out.read_text().splitlines()
    assert lines[0] == "x,y,z,lux,stderr" and len(lines) == 1 + 9 * 6
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    expected = law(data[:, :3], 0.8)
    np.testing.assert_allclose(data[:, 3], expected, rtol=RTOL_EXACT)
    assert np.all(data[:, 4] == 0.0) and np.allclose(data[:, 1], 0.8)
    assert out.with_suffix(".png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    printed = capsys.readouterr().out
    u0 = expected.min() / expected.mean()
    for text in (f"Em {expected.mean():.4g} lx", f"Emin {expected.min():.4g} lx",
                 f"Emax {expected.max():.4g} lx", f"U0 = Emin/Em {u0:.3f}",
                 "9 x 6 points", "Em >= 500 lx FAIL"):
        assert text in printed, (text, printed)


def test_grid_named_by_a_default_of_the_scene(tmp_path, capsys):
    """--grid workplane, where the scene has <default name="workplane" value="0,0 6,4 @
    0.8"/>: the same 9 x 6 points and lux as the grid written out; -D workplane=... replaces
    it as it replaces any <default>."""
    scene = write_room(tmp_path, "")
    scene.write_text(scene.read_text().replace(
        '<default name="res" value="24"/>',
        '<default name="res" value="24"/><default name="workplane" value="0,0 6,4 @ 0.8"/>'))
    out = tmp_path / "named.csv"
    base = ["lux", str(scene), "-o", str(out), "--variant", "llvm_ad_rgb", "-q"]
    assert main([*base, "--grid", "workplane"]) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert data.shape == (9 * 6, 5) and np.allclose(data[:, 1], 0.8)
    np.testing.assert_allclose(data[:, 3], law(data[:, :3]), rtol=RTOL_EXACT)
    assert "9 x 6 points" in capsys.readouterr().out
    assert main([*base, "--grid", "workplane", "-D", "workplane=1,1 5,3 @ 0.5"]) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert np.allclose(data[:, 1], 0.5) and data[:, 0].min() > 1.0
    np.testing.assert_allclose(data[:, 3], law(data[:, :3]), rtol=RTOL_EXACT)


def test_points_round_trip_and_kinds(tmp_path, capsys):
    """--points: the output repeats the input columns and adds lux and stderr (horizontal
    and vertical points of the closed form); --kind cylindrical gives I sin / (pi r^2)."""
    scene = write_room(tmp_path)
    source = tmp_path / "sensors.csv"
    rows = [(1.0, 0.8, -1.0, 0, 1, 0), (4.0, 1.2, -3.0, -1, 0, 0), (2.0, 0.0, -2.5, 0, 2, 0)]
    source.write_text("x,y,z,nx,ny,nz\n" + "\n".join(",".join(map(str, r)) for r in rows))
    out = tmp_path / "lux.csv"
    base = ["lux", str(scene), "--points", str(source), "-o", str(out), "--variant",
            "llvm_ad_rgb", "-q"]
    assert main(base) == 0
    assert out.read_text().splitlines()[0] == "x,y,z,nx,ny,nz,lux,stderr"
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, :6], rows)
    n = data[:, 3:6] / np.linalg.norm(data[:, 3:6], axis=1)[:, None]
    expected = [law(data[i:i + 1, :3], normal=n[i])[0] for i in range(3)]
    np.testing.assert_allclose(data[:, 6], expected, rtol=RTOL_EXACT)
    assert main([*base, "--kind", "cylindrical"]) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    v = LIGHT - data[:, :3]
    r = np.linalg.norm(v, axis=1)
    sin = np.linalg.norm(v[:, [0, 2]], axis=1) / r
    np.testing.assert_allclose(data[:, 6], 1000.0 * sin / (np.pi * r**2), rtol=RTOL_EXACT)


def test_one_random_sample_says_its_error_is_unknown(tmp_path, capsys):
    """With an area light, one sample per point has no spread to estimate an error from:
    the stderr column is nan and a note says how to get it; with 4 samples it is a
    number and nothing is said."""
    scene = write_room(tmp_path, LAMP)
    source = tmp_path / "sensors.csv"
    source.write_text("1,0.8,-1,0,1,0\n4,0.8,-3,0,1,0\n")
    out = tmp_path / "lux.csv"
    base = ["lux", str(scene), "--points", str(source), "-o", str(out), "--variant",
            "llvm_ad_rgb", "-q"]
    assert main([*base, "--spp", "1"]) == 0
    assert np.isnan(np.loadtxt(out, delimiter=",", skiprows=1)[:, 7]).all()
    assert "standard error is nan" in capsys.readouterr().err
    assert main([*base, "--spp", "4"]) == 0
    assert np.isfinite(np.loadtxt(out, delimiter=",", skiprows=1)[:, 7]).all()
    assert "standard error" not in capsys.readouterr().err


def test_luminance_ugr_and_report(tmp_path, capsys):
    """--grid with --ugr and --report: the luminance EXR (Y in cd/m^2) and PNG, the UGR
    printed, and a Markdown report whose luminaire table, grid results, pass/fail and
    figure links are there and point at files that exist."""
    import OpenEXR

    scene = write_room(tmp_path, LAMP)
    out = tmp_path / "study" / "room.csv"
    report = tmp_path / "study" / "room.md"
    code = main(["lux", str(scene), "--grid", "0,0 6,4 @ 0.8", "--task", "corridor",
                 "--ugr", "--report", str(report), "-o", str(out), "--variant",
                 "llvm_ad_rgb", "-q", "--spp", "4"])
    assert code == 0
    printed = capsys.readouterr().out
    assert "UGR " in printed and "corridor" in printed
    with OpenEXR.File(str(tmp_path / "study" / "room.luminance.exr")) as f:
        assert f.header()["units"] == "cd/m^2"
        assert f.channels()["Y"].pixels.max() > 1000.0  # the lamp, 5 x 683 x 106.9 cd/m^2
    text = report.read_text()
    for part in ("## Luminaires", "| pointlight |", "| AreaLight |", "## Calculation grid",
                 "E_m (lx)", "circulation areas: corridors", "## Luminance and glare", "UGR"):
        assert part in text, part
    for link in ("room.png", "room.luminance.png"):
        assert f"]({link})" in text and (report.parent / link).is_file()


BAD = {
    "grid_outside": (["--grid", "0,0 9,4 @ 0.8"], "lie outside the scene"),
    "grid_above": (["--grid", "0,0 6,4 @ 3.5"], "lie outside the scene"),
    "grid_malformed": (["--grid", "0,0 6,4"], "--grid"),
    "grid_unknown_name": (["--grid", "desk"],
                          "--grid: grid 'desk': the scene has no <default name='desk'>"),
    "grid_name_no_grid": (["--grid", "res"], "--grid: <default name='res'>: grid '24'"),
    "zero_spacing": (["--grid", "0,0 6,4 @ 0.8", "--spacing", "0"], "--spacing must be > 0"),
    "mf_above_one": (["--grid", "0,0 6,4 @ 0.8", "--maintenance-factor", "1.2"],
                     "--maintenance-factor"),
    "mf_zero": (["--grid", "0,0 6,4 @ 0.8", "--maintenance-factor", "0"],
                "--maintenance-factor"),
    "unknown_task": (["--grid", "0,0 6,4 @ 0.8", "--task", "kitchen"], "--task 'kitchen'"),
    "missing_column": (["--points", "{bad_points}"], "line 2: expected six finite numbers"),
    "grid_and_points": (["--grid", "0,0 6,4 @ 0.8", "--points", "{bad_points}"],
                        "give one of them"),
    "semicylindrical_grid": (["--grid", "0,0 6,4 @ 0.8", "--kind", "semicylindrical"],
                             "needs a facing direction"),
    "report_not_md": (["--grid", "0,0 6,4 @ 0.8", "--report", "{tmp}/r.txt"], "must end in .md"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_input_exits_2_in_one_line_and_writes_nothing(tmp_path, capsys, monkeypatch, case):
    """A grid outside the scene or malformed, zero spacing, MF > 1 or <= 0, an unknown task,
    a points file with a missing column: exit 2, one line 'error: ...', nothing written."""
    args, words = BAD[case]
    monkeypatch.chdir(tmp_path)
    scene = write_room(tmp_path)
    bad_points = tmp_path / "bad.csv"
    bad_points.write_text("x,y,z,nx,ny,nz\n0,0.8,-1,0,1\n")
    args = [a.format(bad_points=bad_points, tmp=tmp_path) for a in args]
    before = set(os.listdir(tmp_path))
    out = tmp_path / "out" / "x.csv"
    argv = ["lux", str(scene), *args, "-o", str(out), "--variant", "llvm_ad_rgb", "-q",
            "--report", str(tmp_path / "out" / "r.md")] if "--report" not in args else \
        ["lux", str(scene), *args, "-o", str(out), "--variant", "llvm_ad_rgb", "-q"]
    assert main(argv) == EXIT_USAGE
    assert_one_line_error(capsys, words)
    assert set(os.listdir(tmp_path)) == before


def test_luminance_at_points(tmp_path):
    """--luminance --points: the six columns are a point and a view direction; looking at
    the area lamp (RGB radiance 5, seen directly) gives 5 K_m integral V cd/m^2, and the
    output has the columns x,y,z,dx,dy,dz,luminance,stderr."""
    from spectrace.plugins.emitters import luminous

    scene = write_room(tmp_path, LAMP)
    source = tmp_path / "views.csv"
    source.write_text("3.3,1.2,-3,0,1,0\n3.3,1.2,-3,0,3,0.01\n")
    out = tmp_path / "L.csv"
    assert main(["lux", str(scene), "--luminance", "--points", str(source), "-o", str(out),
                 "--variant", "llvm_ad_rgb", "-q", "--spp", "4"]) == 0
    assert out.read_text().splitlines()[0] == "x,y,z,dx,dy,dz,luminance,stderr"
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 6], 5 * 683.0 * luminous.v_integral(), rtol=RTOL_EXACT)
