"""``spectrace render`` end to end: outputs, determinism, bad input, Ctrl-C."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from error_checks import assert_one_line_error
from PIL import Image

from spectrace.cli import main
from spectrace.images import encode_srgb_8bit, read_exr

ROOT = Path(__file__).resolve().parents[2]
SHOWCASE = ROOT / "scenes" / "showcase.xml"
TINY = ["-D", "res=24", "--spp", "8", "--spp-per-pass", "4", "-q"]  # ldsampler: powers of 4
EXIT_USAGE = 2
# The film accumulates samples with parallel atomic adds, so equal seeds agree up to the
# order of float additions, not bit for bit.
SAME_SEED_RTOL = 1e-5
SAME_SEED_ATOL = 1e-6
EXIT_INTERRUPTED = 130


def render(tmp_path, *extra, name="img.exr"):
    out = tmp_path / name
    code = main(["render", str(SHOWCASE), "-o", str(out), *TINY, *extra])
    return code, out


def test_render_writes_exr_and_png_with_header(tmp_path):
    """The EXR holds finite float32 R, G, B with spp/variant/seed/scene/film; beside it the
    PNG holds the same pixels as 8-bit sRGB codes; the files have the umask's mode."""
    code, out = render(tmp_path, "--variant", "llvm_ad_rgb", "--seed", "5")
    assert code == 0
    rgb, header = read_exr(out)
    assert rgb.shape == (24, 24, 3) and rgb.dtype == np.float32
    assert np.isfinite(rgb).all() and rgb.mean() > 0
    assert header["spp"] == 8 and header["seed"] == 5
    assert header["variant"] == "llvm_ad_rgb" and header["scene"].endswith("showcase.xml")
    assert header["film"] == "rgb"
    png = out.with_suffix(".png")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with Image.open(png) as im:  # the PNG is the EXR's pixels, sRGB-encoded to 8 bits
        np.testing.assert_array_equal(np.asarray(im.convert("RGB")), encode_srgb_8bit(rgb))
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temp files
    umask = os.umask(0)
    os.umask(umask)
    assert (out.stat().st_mode & 0o777) == 0o666 & ~umask  # not mkstemp's private 0600


def test_render_is_deterministic_for_a_seed(tmp_path):
    """Same seed, same pixels; another seed, other noise (spectral variant, the default)."""
    _, a = render(tmp_path, "--seed", "1", name="a.exr")
    _, b = render(tmp_path, "--seed", "1", name="b.exr")
    _, c = render(tmp_path, "--seed", "2", name="c.exr")
    np.testing.assert_allclose(read_exr(a)[0], read_exr(b)[0], rtol=SAME_SEED_RTOL,
                               atol=SAME_SEED_ATOL)
    assert not np.allclose(read_exr(a)[0], read_exr(c)[0], rtol=0.01, atol=0.01)


def test_scene_parameters_reach_the_scene(tmp_path):
    """-D res=24 sets the film size through the scene's <default name="res">."""
    code, out = render(tmp_path, "-D", "res=16")
    assert code == 0 and read_exr(out)[0].shape == (16, 16, 3)


BAD_SCENES = {
    "malformed": ('<scene version="3.0.0"><shape type="sphere"></scene>', "malformed XML"),
    "unknown_plugin": ('<scene version="3.0.0"><bsdf type="nosuchbsdf"/></scene>',
                       "nosuchbsdf"),
    "bad_parameter": ('<scene version="3.0.0"><shape type="sphere">'
                      '<float name="radius" value="abc"/></shape></scene>', "abc"),
    "unused_parameter": ('<scene version="3.0.0"><shape type="sphere">'
                         '<float name="bogus" value="1"/></shape></scene>', "bogus"),
    "no_sensor": ('<scene version="3.0.0"><integrator type="path"/><shape type="sphere"/>'
                  '</scene>', "no <sensor>"),
    "no_integrator": ('<scene version="3.0.0"><shape type="sphere"/><sensor type="perspective">'
                      '</sensor></scene>', "no <integrator>"),
}


@pytest.mark.parametrize("case", sorted(BAD_SCENES))
def test_bad_scene_is_a_one_line_error(tmp_path, capsys, case):
    """Malformed XML, unknown plugins and bad parameters: exit 2, one line, no output."""
    text, word = BAD_SCENES[case]
    scene = tmp_path / f"{case}.xml"
    scene.write_text(text)
    out = tmp_path / "out.exr"
    code = main(["render", str(scene), "-o", str(out), "-q", "--variant", "llvm_ad_rgb"])
    assert code == EXIT_USAGE
    assert_one_line_error(capsys, word)
    assert not out.exists() and not out.with_suffix(".png").exists()


@pytest.mark.parametrize(
    ("args", "word"),
    [
        (["--spp", "0"], "--spp"),
        (["--spp", "-3"], "--spp"),
        (["--spp-per-pass", "0"], "--spp-per-pass"),
        (["--variant", "llvm_ad_nonsense"], "llvm_ad_nonsense"),
        (["-D", "nosuchparam=1"], "nosuchparam"),
        (["-D", "novalue"], "novalue"),
        (["-D", "res=abc"], "abc"),
        (["--film", "spectral", "--variant", "llvm_ad_rgb"], "spectral"),
        (["--seed", str(2**31)], "--seed"),  # the EXR header's seed is a 32-bit integer
    ],
)
def test_bad_option_is_a_one_line_error(tmp_path, capsys, args, word):
    """Bad options exit 2 with one line naming the option and write nothing."""
    out = tmp_path / "out.exr"
    code = main(["render", str(SHOWCASE), "-o", str(out), "-q", "-D", "res=8", *args])
    assert code == EXIT_USAGE
    assert_one_line_error(capsys, word)
    assert not out.exists()


def test_unusable_variant_is_an_error_not_a_traceback(tmp_path, capsys):
    """A CUDA variant renders where a GPU exists; elsewhere it is a one-line error, exit 2,
    and not even the output folder is made."""
    out = tmp_path / "new" / "o.exr"
    code = main(["render", str(SHOWCASE), "-o", str(out), "-q", "-D", "res=8", "--spp", "1",
                 "--variant", "cuda_ad_rgb"])
    if code == 0:
        assert out.exists()
    else:
        assert code == EXIT_USAGE
        assert_one_line_error(capsys, "cuda_ad_rgb")
        assert not out.parent.exists()


def test_missing_scene(tmp_path, capsys):
    """A scene path that does not exist is named in the error."""
    code = main(["render", str(tmp_path / "nope.xml"), "-o", str(tmp_path / "o.exr")])
    assert code == EXIT_USAGE
    assert_one_line_error(capsys, "nope.xml", "no such file")


def test_unwritable_output(tmp_path, capsys):
    """An output under a regular file (not a folder) cannot be written: exit 2, before rendering."""
    blocker = tmp_path / "file"
    blocker.write_text("x")
    code = main(["render", str(SHOWCASE), "-o", str(blocker / "o.exr"), "-q"])
    assert code == EXIT_USAGE
    assert_one_line_error(capsys, "cannot write output")


def test_output_must_be_exr_or_png(tmp_path, capsys):
    """-o takes .exr or .png (issue 19: the other is written beside it), nothing else."""
    code = main(["render", str(SHOWCASE), "-o", str(tmp_path / "o.jpg"), "-q"])
    assert code == EXIT_USAGE
    assert_one_line_error(capsys, ".exr")


def run_cli(*args, **kwargs):
    return subprocess.Popen([sys.executable, "-m", "spectrace.cli", *args],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            cwd=kwargs.get("cwd"))


def test_console_script_error_has_no_traceback(tmp_path):
    """Through the real entry point: exit status 2 and a single stderr line."""
    bad = tmp_path / "bad.xml"
    bad.write_text("<scene>")
    proc = run_cli("render", str(bad), "-o", str(tmp_path / "o.exr"))
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == EXIT_USAGE
    assert err.strip().count("\n") == 0 and err.startswith("error: ") and "bad.xml" in err


def test_ctrl_c_saves_the_passes_done(tmp_path):
    """SIGINT stops after the current pass, saves that image with its true spp, exits 130."""
    out = tmp_path / "int.exr"
    proc = run_cli("render", str(SHOWCASE), "-o", str(out), "-D", "res=16", "--spp", "100000",
                   "--spp-per-pass", "1", "--variant", "llvm_ad_rgb", "-q")
    line = proc.stderr.readline()  # printed just before the first pass
    assert line.startswith("rendering"), line
    time.sleep(1.0)
    os.kill(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == EXIT_INTERRUPTED, err
    rgb, header = read_exr(out)
    assert 1 <= header["spp"] < 100000
    assert np.isfinite(rgb).all()
    assert f"saved {header['spp']} of 100000 spp" in err


# Band quantisation (16 boxes over 400-700 nm) and noise at 32 spp: mean colours of the
# spectral-film and hdrfilm renders agree to a few percent.
FILM_MEAN_RTOL = 0.05


def test_spectral_film_writes_bands_and_matching_rgb(tmp_path):
    """--film spectral: OUT.spectral.exr holds N bands; OUT.exr is their sRGB conversion
    and agrees with the scene's own RGB film on average."""
    from spectrace.spectral import read_spectral_exr

    from spectrace.spectral_film import bands_to_linear_srgb

    out = tmp_path / "s.exr"
    args = ["render", str(SHOWCASE), "-D", "res=24", "--spp", "32", "-q"]
    assert main([*args, "-o", str(out), "--film", "spectral", "--bands", "16"]) == 0
    bands, wavelengths = read_spectral_exr(out.with_suffix(".spectral.exr"))
    assert bands.shape == (24, 24, 16) and len(wavelengths) == 16
    assert 400 <= wavelengths.min() < wavelengths.max() <= 700
    rgb, header = read_exr(out)
    assert header["film"] == "spectral" and out.with_suffix(".png").exists()
    np.testing.assert_allclose(rgb, bands_to_linear_srgb(bands, wavelengths), rtol=1e-5,
                               atol=1e-6)
    assert main([*args, "-o", str(tmp_path / "r.exr")]) == 0
    reference = read_exr(tmp_path / "r.exr")[0]
    np.testing.assert_allclose(rgb.mean(axis=(0, 1)), reference.mean(axis=(0, 1)),
                               rtol=FILM_MEAN_RTOL)


def test_spectral_film_bad_bands(tmp_path, capsys):
    code = main(["render", str(SHOWCASE), "-o", str(tmp_path / "o.exr"), "-q",
                 "--film", "spectral", "--bands", "0"])
    assert code == EXIT_USAGE
    assert_one_line_error(capsys, "--bands")


# --------------------------------------------------------------- several scenes, Dask

FOG = ROOT / "scenes" / "fog.xml"


def test_several_scenes_render_into_a_folder(tmp_path, capsys):
    """Two scenes in one call: an EXR + PNG each in the folder, a line each and a total."""
    out = tmp_path / "renders"
    code = main(["render", str(SHOWCASE), str(FOG), "-o", f"{out}/", *TINY,
                 "--variant", "llvm_ad_rgb"])
    assert code == 0
    for name in ("showcase", "fog"):
        assert read_exr(out / f"{name}.exr")[0].shape == (24, 24, 3)
        assert (out / f"{name}.png").is_file()
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[0].startswith("showcase.xml: ") and lines[1].startswith("fog.xml: ")
    assert lines[2].startswith("total: 2 scenes")


def test_several_scenes_need_a_folder(tmp_path, capsys):
    """-o FILE.exr with two scenes: exit 2, one line, nothing written."""
    out = tmp_path / "one.exr"
    code = main(["render", str(SHOWCASE), str(FOG), "-o", str(out), *TINY])
    assert code == EXIT_USAGE
    assert_one_line_error(capsys, "folder")
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_workers_render_the_local_image(tmp_path):
    """--workers 2: the passes on two worker processes, the same image as the local loop."""
    common = ["--variant", "llvm_ad_rgb", "--seed", "4", "--spp", "8"]
    code, local = render(tmp_path, *common, name="local.exr")
    assert code == 0
    code, remote = render(tmp_path, *common, "--workers", "2", name="remote.exr")
    assert code == 0
    assert read_exr(remote)[1]["spp"] == 8
    np.testing.assert_allclose(read_exr(remote)[0], read_exr(local)[0], rtol=SAME_SEED_RTOL,
                               atol=SAME_SEED_ATOL)


def test_ctrl_c_with_workers_saves_the_passes_done(tmp_path):
    """SIGINT during a distributed render cancels what is outstanding, saves the passes
    done with their sample count, exits 130."""
    out = tmp_path / "int.exr"
    proc = run_cli("render", str(SHOWCASE), "-o", str(out), "-D", "res=16", "--spp", "100000",
                   "--spp-per-pass", "4", "--variant", "llvm_ad_rgb", "-q", "--workers", "2")
    line = proc.stderr.readline()  # printed once the workers are up
    assert line.startswith("rendering"), line
    time.sleep(1.5)
    os.kill(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == EXIT_INTERRUPTED, err
    rgb, header = read_exr(out)
    assert 4 <= header["spp"] < 100000 and header["spp"] % 4 == 0
    assert np.isfinite(rgb).all()
    assert f"saved {header['spp']} of 100000 spp" in err and "Traceback" not in err


def test_bands_without_spectral_film_is_refused(tmp_path, capsys):
    """--bands only means something with --film spectral: alone it is a mistake, not ignored."""
    code, out = render(tmp_path, "--variant", "llvm_ad_rgb", "--bands", "8")
    assert code == EXIT_USAGE and not out.exists()
    assert_one_line_error(capsys, "--bands", "--film spectral")


def test_one_pass_is_reported_in_the_singular(tmp_path, capsys):
    """A render of a single pass says "1 pass", not "1 passes"."""
    out = tmp_path / "one.exr"
    code = main(["render", str(SHOWCASE), "-o", str(out), "-D", "res=16", "--spp", "2",
                 "--spp-per-pass", "4", "-q", "--variant", "llvm_ad_rgb"])
    assert code == 0
    assert "in 1 pass," in capsys.readouterr().out


#: Seconds a one-thread render of a small envmap scene may take before it counts as hung.
ONE_THREAD_TIMEOUT_S = 120


def test_threads_option_leaves_the_pool_as_it_was(tmp_path):
    """-t 1 renders with one thread and gives Dr.Jit's pool back as it was: a command run
    in-process leaves no pool of one thread behind (Mitsuba's EXR reader and writer hang
    in one)."""
    import drjit as dr

    before = dr.thread_count()
    assert render(tmp_path, "-t", "1")[0] == 0
    assert dr.thread_count() == before


def test_one_thread_render_of_an_envmap_scene_finishes(tmp_path):
    """-t 1 on a scene whose envmap is an EXR: the image loads before the pool shrinks
    (Mitsuba's bundled OpenEXR reads on the pool and waits forever in a pool of one)."""
    out = tmp_path / "env.exr"
    run = subprocess.run(
        [sys.executable, "-m", "spectrace.cli", "render", str(ROOT / "scenes" / "environment.xml"),
         "-D", "res=16", "--spp", "4", "-t", "1", "-q", "-o", str(out)],
        capture_output=True, text=True, timeout=ONE_THREAD_TIMEOUT_S)
    assert run.returncode == 0, run.stderr
    assert out.is_file()
