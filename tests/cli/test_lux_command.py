"""``spectrace lux`` end to end: the EXR in lux and the PNG, the printed statistics, the
work plane, and the one-line errors that write nothing."""

from __future__ import annotations

import os

import numpy as np
import pytest
from error_checks import assert_one_line_error

from spectrace.cli import main

EXIT_USAGE = 2
#: A float32 render against a float64 formula (RGB variant, sample at the pixel centre).
RTOL_EXACT = 2e-4
RES = 16
HALF_WIDTH = 2.0

#: A floor seen straight from above (orthographic, 4 m wide, one sample at each pixel
#: centre), a 100 cd pointlight 1 m above its centre; $light replaces the light.
SCENE = """<scene version="3.0.0">
    <default name="res" value="{res}"/>
    <integrator type="path"/>
    {sensor}
    <shape type="rectangle">
        <transform name="to_world"><scale value="10"/><rotate x="1" angle="-90"/></transform>
    </shape>
    {light}
</scene>
"""
SENSOR = """<sensor type="orthographic">
        <transform name="to_world">
            <scale x="2" y="2"/><lookat origin="0, 8, 0" target="0, 0, 0" up="0, 0, 1"/>
        </transform>
        <sampler type="stratified"><integer name="sample_count" value="1"/>
            <boolean name="jitter" value="false"/></sampler>
        <film type="hdrfilm"><integer name="width" value="$res"/>
            <integer name="height" value="$res"/></film>
    </sensor>"""
LIGHT = """<emitter type="pointlight">
        <point name="position" x="0" y="1" z="0"/>
        <float name="luminous_intensity" value="100"/>
    </emitter>"""


def write_scene(tmp_path, sensor=SENSOR, light=LIGHT, name="floor.xml"):
    path = tmp_path / name
    path.write_text(SCENE.format(res=RES, sensor=sensor, light=light))
    return path


def pixel_centres(res: int = RES) -> tuple[np.ndarray, np.ndarray]:
    """|x| and |z| (m) of the floor points at the pixel centres (the view is symmetric)."""
    c = (np.arange(res) + 0.5) / res * 2 * HALF_WIDTH - HALF_WIDTH
    return np.meshgrid(np.abs(c), np.abs(c))


def test_lux_writes_exr_png_and_prints_statistics(tmp_path, capsys):
    """OUT.exr holds one float32 channel Y: 100 h / r^3 lux at the pixel centres (h = 1 m);
    OUT.png is beside it; min / mean / max lux and U0 = min / mean are printed and agree
    with the map."""
    from spectrace.lux import read_lux_exr

    scene = write_scene(tmp_path)
    out = tmp_path / "map.exr"
    code = main(["lux", str(scene), "-o", str(out), "--variant", "llvm_ad_rgb", "-q"])
    assert code == 0
    Y, header = read_lux_exr(out)
    x, z = pixel_centres()
    r = np.sqrt(x**2 + z**2 + 1.0)
    np.testing.assert_allclose(np.sort(Y.ravel()), np.sort((100.0 / r**3).ravel()),
                               rtol=RTOL_EXACT)
    assert header["variant"] == "llvm_ad_rgb" and header["spp"] == 1
    assert out.with_suffix(".png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    printed = capsys.readouterr().out
    u0 = Y.min() / Y.mean()
    for text in (f"E_min {Y.min():.4g} lx", f"E_mean {Y.mean():.4g} lx",
                 f"E_max {Y.max():.4g} lx", f"U0 = E_min/E_mean {u0:.3f}"):
        assert text in printed, (text, printed)


def test_lux_on_a_work_plane_with_default_output(tmp_path, monkeypatch):
    """--plane '0,0.5,0 0,1,0' measures 100 h / r^3 with h = 0.5 m; without -o the map goes
    to out/<scene>.lux.exr (and .png); -D reaches the scene; --log and --range are taken."""
    from spectrace.lux import read_lux_exr

    scene = write_scene(tmp_path)
    monkeypatch.chdir(tmp_path)
    code = main(["lux", str(scene), "--variant", "llvm_ad_rgb", "-q", "-D", "res=8",
                 "--plane", "0,0.5,0 0,1,0", "--log", "--range", "5,500"])
    assert code == 0
    Y, header = read_lux_exr(tmp_path / "out" / "floor.lux.exr")
    assert (tmp_path / "out" / "floor.lux.png").is_file()
    x, z = pixel_centres(8)
    r = np.sqrt(x**2 + z**2 + 0.25)
    np.testing.assert_allclose(np.sort(Y.ravel()), np.sort((50.0 / r**3).ravel()),
                               rtol=RTOL_EXACT)
    assert header["plane"] == "0,0.5,0 0,1,0"


NO_SENSOR = """<scene version="3.0.0"><shape type="sphere"/>
    <emitter type="pointlight"><float name="luminous_intensity" value="1"/></emitter></scene>"""
HORIZONTAL = SENSOR.replace('origin="0, 8, 0" target="0, 0, 0" up="0, 0, 1"',
                            'origin="0, 1, 0" target="0, 1, 1" up="0, 1, 0"')
ERRORS = {
    "malformed_plane": (["--plane", "0,0.85,0"], {}, "--plane"),
    "plane_letters": (["--plane", "0,a,0 0,1,0"], {}, "x,y,z nx,ny,nz"),
    "zero_normal": (["--plane", "0,1,0 0,0,0"], {}, "normal must not be zero"),
    "parallel_plane": (["--plane", "0,0.85,0 0,1,0"], {"sensor": HORIZONTAL},
                       "parallel to the view"),
    "no_sensor": ([], {"text": NO_SENSOR}, "no <sensor>"),
    "bad_range": (["--range", "500,0"], {}, "--range"),
    "range_text": (["--range", "low,high"], {}, "--range"),
    "log_range_zero": (["--range", "0,500", "--log"], {}, "--log needs MIN > 0"),
    "hidden_plane": (["--plane", "0,-0.5,0 0,1,0"], {},
                     "--plane: plane '0,-0.5,0 0,1,0': no pixel sees the plane"),
    "max_depth": (["--max-depth", "0"], {}, "--max-depth"),
    "two_quantities": ([], {"light": LIGHT.replace(
        "</emitter>", '<float name="luminous_flux" value="5"/></emitter>')},
        "'luminous_intensity' and 'luminous_flux'"),
    "negative_candela": ([], {"light": LIGHT.replace('value="100"', 'value="-100"')},
                         "'luminous_intensity' must be >= 0"),
    "not_exr": (["-o", "map.png"], {}, "must end in .exr"),
}


@pytest.mark.parametrize("case", sorted(ERRORS))
def test_errors_exit_2_in_one_line_and_write_nothing(tmp_path, capsys, monkeypatch, case):
    """A malformed, invisible or hidden (below the floor) work plane, a scene without a
    sensor, a bad --range or --max-depth, a light with two luminous quantities or a
    negative one: exit status 2, one line 'error: ...' naming the problem by its flag, no
    file written."""
    args, scene, words = ERRORS[case]
    monkeypatch.chdir(tmp_path)
    if "text" in scene:
        path = tmp_path / "floor.xml"
        path.write_text(scene["text"])
    else:
        path = write_scene(tmp_path, **scene)
    before = set(os.listdir(tmp_path))
    argv = ["lux", str(path), "--variant", "llvm_ad_rgb", "-q", *args]
    if "-o" not in args:
        argv += ["-o", str(tmp_path / "out" / "map.exr")]
    assert main(argv) == EXIT_USAGE
    assert_one_line_error(capsys, words)
    after = set(os.listdir(tmp_path))
    assert after - before <= {"out"}
    assert not (tmp_path / "out").exists() or not list((tmp_path / "out").iterdir())


def test_invisible_plane_and_bad_seed_create_no_output_folder(tmp_path, capsys):
    """A work plane behind the camera is found before the output's folder is made (an empty
    folder was left behind), and a seed beyond 32 bits, which the EXR header wrapped, is
    refused: exit 2, one line, no folder."""
    scene = write_scene(tmp_path)
    out = tmp_path / "new" / "map.exr"
    base = ["lux", str(scene), "-o", str(out), "--variant", "llvm_ad_rgb", "-q"]
    assert main([*base, "--plane", "0,9,0 0,1,0"]) == EXIT_USAGE
    assert_one_line_error(capsys, "--plane", "sees no point")
    assert main([*base, "--seed", "99999999999"]) == EXIT_USAGE
    assert_one_line_error(capsys, "--seed")
    assert not out.parent.exists()


def test_missing_ies_names_the_folders_and_no_string_line(tmp_path, capsys, monkeypatch):
    """An ieslight whose relative filename is not beside the scene: the one-line error says
    where it was looked for (the scene's folder), and carries no 'At string (line ...)'
    of the rewritten tree, whose line numbers are not the file's."""
    scene_dir = tmp_path / "scenes"
    scene_dir.mkdir()
    light = '<emitter type="ieslight"><string name="filename" value="lum/none.ies"/></emitter>'
    scene = write_scene(scene_dir, light=light)
    monkeypatch.chdir(tmp_path)
    code = main(["lux", str(scene), "-o", str(tmp_path / "map.exr"), "--variant",
                 "llvm_ad_rgb", "-q"])
    assert code == EXIT_USAGE
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert err.startswith("error: ") and "At string" not in err, err
    assert "no such file 'lum/none.ies'" in err and str(scene_dir) in err, err
    assert not (tmp_path / "map.exr").exists()


@pytest.mark.parametrize("how", ["raised", "swallowed"])
def test_ctrl_c_while_loading_is_an_interrupt(tmp_path, capsys, how):
    """Ctrl-C while Mitsuba builds the plugins comes back as a plugin error: either the
    KeyboardInterrupt inside a RuntimeError, or (swallowed, e.g. by a half-done import) a
    later error. Both are exit 130 'interrupted', not exit 2 with that message. A Python
    emitter whose constructor gets the Ctrl-C stands in for a slow plugin."""
    import signal

    import spectrace

    spectrace.set_variant("llvm_ad_rgb")
    import mitsuba as mi

    class Interrupted(mi.Emitter):
        def __init__(self, props):
            super().__init__(props)
            if how == "raised":
                raise KeyboardInterrupt
            try:
                signal.raise_signal(signal.SIGINT)
            except KeyboardInterrupt:
                pass
            raise AttributeError("module 'colour' has no attribute 'colorimetry'")

    mi.register_emitter("test_interrupted", lambda props: Interrupted(props))
    scene = write_scene(tmp_path, light='<emitter type="test_interrupted"/>')
    code = main(["lux", str(scene), "-o", str(tmp_path / "map.exr"), "--variant",
                 "llvm_ad_rgb", "-q"])
    assert code == 130
    assert capsys.readouterr().err.strip().splitlines()[-1] == "interrupted"
    assert not (tmp_path / "map.exr").exists()
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_measurements_are_never_denoised(tmp_path, capsys):
    """Denoising is for pictures: lux takes no --denoise (one line, exit 2, nothing
    written), so a measurement is never a denoised image."""
    scene = write_scene(tmp_path)
    out = tmp_path / "map.exr"
    with pytest.raises(SystemExit) as info:  # argparse's one line
        main(["lux", str(scene), "-o", str(out), "--denoise", "-q"])
    assert info.value.code == 2
    assert_one_line_error(capsys, "--denoise")
    assert not out.exists()
