"""``spectrace view`` and the display options of ``spectrace render``: the PNG changes, the
EXR never does; Mitsuba habits (-m, -t, -o OUT.png); render until clean (--noise, --time)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from error_checks import assert_one_line_error
from PIL import Image

from spectrace.cli import main
from spectrace.images import read_exr

ROOT = Path(__file__).resolve().parents[2]
SHOWCASE = ROOT / "scenes" / "showcase.xml"
LUMINAIRES = ROOT / "scenes" / "luminaires.xml"
TINY = ["-D", "res=24", "--spp", "4", "--spp-per-pass", "4", "-q", "--variant", "llvm_ad_rgb"]
EXIT_USAGE = 2
#: A sensible mean of an 8-bit PNG (0-255): neither near black nor washed out.
WELL_EXPOSED = (50, 170)
#: --noise: the true relative error at the stop is within this fraction of the target.
NOISE_TOLERANCE = 0.2
#: Seconds a render of -t 1 may take before the test calls it hung.
THREADS_TIMEOUT_S = 240

DISPLAY_OPTIONS = [
    ["--exposure", "2"],
    ["--exposure", "auto", "--white-balance", "3000K"],
    ["--ev100", "9", "--view", "aces", "--display", "display-p3"],
    ["--view", "false-colour", "--png-bits", "16"],
    ["--view", "neutral", "--display-exr"],
]


MITSUBA_SCENE = """<scene version="3.0.0"><integrator type="path"/>
<sensor type="perspective"><transform name="to_world"><lookat origin="0, 0, 5"
target="0, 0, 0" up="0, 1, 0"/></transform><film type="hdrfilm"><integer name="width" value="16"/>
<integer name="height" value="16"/></film><sampler type="independent">
<integer name="sample_count" value="4"/></sampler></sensor>
<shape type="sphere"/><emitter type="constant"/></scene>"""


def png_pixels(path) -> np.ndarray:
    with Image.open(path) as im:
        return np.asarray(im.convert("RGB"))


@pytest.fixture(scope="module")
def plain(tmp_path_factory):
    """A plain render of the showcase (no display option), on one thread: the film's atomic
    additions then come in one order, and equal seeds give equal bits."""
    out = tmp_path_factory.mktemp("plain") / "img.exr"
    assert main(["render", str(SHOWCASE), "-o", str(out), *TINY, "-t", "1"]) == 0
    return out


@pytest.mark.parametrize("options", DISPLAY_OPTIONS, ids=lambda o: " ".join(o))
def test_display_options_leave_the_exr_bit_identical(tmp_path, plain, options):
    """Every display option changes the PNG and never the EXR: same seed, same EXR bits
    (pixels and header) as the plain render."""
    out = tmp_path / "img.exr"
    assert main(["render", str(SHOWCASE), "-o", str(out), *TINY, "-t", "1", *options]) == 0
    a, header_a = read_exr(plain)
    b, header_b = read_exr(out)
    assert a.tobytes() == b.tobytes()
    assert {k: repr(v) for k, v in header_a.items()} == {k: repr(v) for k, v in header_b.items()}
    assert not np.array_equal(png_pixels(plain.with_suffix(".png"))[:, :24],
                              png_pixels(out.with_suffix(".png"))[:, :24])


def test_view_redevelops_the_render_png(tmp_path, plain, capsys):
    """spectrace view of a render's EXR with no option writes the render's PNG again; with
    --exposure it prints the exposure used."""
    out = tmp_path / "again.png"
    assert main(["view", str(plain), "-o", str(out)]) == 0
    np.testing.assert_array_equal(png_pixels(out), png_pixels(plain.with_suffix(".png")))
    assert main(["view", str(plain), "-o", str(out), "--exposure", "-1"]) == 0
    assert "exposure: -1.00 EV" in capsys.readouterr().out


def test_display_exr_is_the_png_in_linear_display_values(tmp_path, plain):
    """--display-exr: OUT.display.exr holds the PNG's codes with the sRGB curve undone
    (display-referred, in [0, 1]), its settings in the header."""
    from spectrace.spectral.srgb import decode_srgb

    out = tmp_path / "dev.png"
    assert main(["view", str(plain), "-o", str(out), "--view", "aces", "--display-exr"]) == 0
    linear, header = read_exr(tmp_path / "dev.display.exr")
    np.testing.assert_allclose(linear, decode_srgb(png_pixels(out) / 255.0), atol=1e-6)
    assert header["view"] == "aces" and 0 <= linear.min() and linear.max() <= 1


def test_view_writes_sixteen_bit_png(tmp_path, plain):
    """--png-bits 16 writes a 16-bit PNG whose codes are the 8-bit ones times 257, give or
    take one 8-bit code (read back by OpenImageIO, an independent PNG reader)."""
    oiio = pytest.importorskip("OpenImageIO")
    out = tmp_path / "deep.png"
    assert main(["view", str(plain), "-o", str(out), "--png-bits", "16"]) == 0
    image = oiio.ImageInput.open(str(out))
    spec = image.spec()
    assert spec.format == oiio.UINT16 and (spec.width, spec.height, spec.nchannels) == (24, 24, 3)
    deep = image.read_image(oiio.UINT16)
    image.close()
    eight = png_pixels(plain.with_suffix(".png")).astype(np.float64)
    np.testing.assert_allclose(deep / 257.0, eight, atol=1.0)


def test_view_reads_a_spectral_exr(tmp_path):
    """A Fichet 2021 spectral EXR written by colour-science is developed: a flat (equal
    energy) emissive spectrum is uniform and, warmer than D65, comes out neutral grey of
    middle-grey luminance with --white-balance auto --exposure auto."""
    colour = pytest.importorskip("colour")
    pytest.importorskip("OpenImageIO")
    wl = np.arange(380.0, 781.0, 5.0)
    flat = np.ones((4, 4, wl.size), np.float32)
    path = tmp_path / "spectral.exr"
    spec = colour.io.Specification_Fichet2021(is_emissive=True)
    colour.io.write_spectral_image_Fichet2021({"S0": (wl, flat)}, str(path), "float32", spec)
    out = tmp_path / "spectral.png"
    assert main(["view", str(path), "-o", str(out), "--exposure", "auto"]) == 0
    pixels = png_pixels(out).astype(float)
    assert np.all(pixels == pixels[0, 0]) and pixels[0, 0, 0] > pixels[0, 0, 2] + 8
    assert main(["view", str(path), "-o", str(out), "--exposure", "auto",
                 "--white-balance", "auto"]) == 0
    pixels = png_pixels(out).astype(float)
    assert np.ptp(pixels) <= 1
    assert pixels.mean() == pytest.approx(118, abs=1)  # sRGB(0.18) = 0.461 -> code 118


def test_view_reads_mitsubas_exr(tmp_path):
    """The half-float EXR that Mitsuba's own ``mitsuba`` writes for a scene develops."""
    mitsuba = Path(sys.executable).with_name("mitsuba")
    if not mitsuba.is_file():
        pytest.skip("no mitsuba executable")
    exr = tmp_path / "mitsuba.exr"
    scene = tmp_path / "builtin.xml"  # Mitsuba's own plugins only
    scene.write_text(MITSUBA_SCENE)
    done = subprocess.run([str(mitsuba), "-m", "llvm_ad_rgb", "-o", str(exr), str(scene)],
                          capture_output=True, text=True, timeout=THREADS_TIMEOUT_S)
    if done.returncode != 0:
        pytest.skip(f"mitsuba cannot render the scene: {done.stderr[-300:]}")
    out = tmp_path / "mitsuba.png"
    assert main(["view", str(exr), "-o", str(out), "--exposure", "auto"]) == 0
    rgb, _ = read_exr(exr)
    assert rgb.mean() > 0.1
    assert png_pixels(out).mean() > 10


@pytest.mark.parametrize("args, words", [
    (["--view", "filmic"], ["--view", "unknown view"]),
    (["--exposure", "nan"], ["--exposure", "finite"]),
    (["--white-balance", "0K"], ["--white-balance", "colour temperature"]),
    (["--png-bits", "12"], ["--png-bits"]),
])
def test_view_bad_options_one_line_nothing_written(tmp_path, plain, capsys, args, words):
    """A bad display option: one line naming the flag, exit 2, no PNG."""
    out = tmp_path / "bad.png"
    assert main(["view", str(plain), "-o", str(out), *args]) == EXIT_USAGE
    assert_one_line_error(capsys, *words)
    assert not out.exists()


def test_view_bad_files(tmp_path, capsys):
    """A missing or broken EXR: one line naming the file, exit 2, nothing written."""
    out = tmp_path / "x.png"
    assert main(["view", str(tmp_path / "missing.exr"), "-o", str(out)]) == EXIT_USAGE
    assert_one_line_error(capsys, "missing.exr", "no such file")
    junk = tmp_path / "junk.exr"
    junk.write_text("not an exr")
    assert main(["view", str(junk), "-o", str(out)]) == EXIT_USAGE
    assert_one_line_error(capsys, "junk.exr")
    assert not out.exists()


@pytest.mark.parametrize("args, words", [
    (["--view", "filmic"], ["--view"]),
    (["--exposure", "nan"], ["--exposure"]),
    (["--white-balance", "0K"], ["--white-balance"]),
    (["--noise", "0"], ["--noise"]),
    (["--time", "-1"], ["--time"]),
    (["-t", "0"], ["--threads"]),
])
def test_render_bad_options_one_line_nothing_written(tmp_path, capsys, args, words):
    """render with a bad display or stopping option: one line, exit 2, nothing written."""
    out = tmp_path / "bad.exr"
    assert main(["render", str(SHOWCASE), "-o", str(out), *TINY, *args]) == EXIT_USAGE
    assert_one_line_error(capsys, *words)
    assert not list(tmp_path.iterdir())


def test_photometric_scene_is_well_exposed_by_default(tmp_path, capsys):
    """The luminaires room (ieslights) renders a PNG of sensible mean with no option, at
    the scene's photometric scale too (exposure=1: 600 times darker lights), and says the
    exposure it used."""
    means = []
    for exposure in ("600", "1"):
        out = tmp_path / f"room{exposure}.exr"
        assert main(["render", str(LUMINAIRES), "-o", str(out), "-q", "--variant",
                     "llvm_ad_rgb", "-D", "res=32", "-D", "spp=4", "-D",
                     f"exposure={exposure}"]) == 0
        assert "exposure: auto" in capsys.readouterr().out
        means.append(png_pixels(out.with_suffix(".png")).mean())
    assert all(WELL_EXPOSED[0] < m < WELL_EXPOSED[1] for m in means), means
    assert means[0] == pytest.approx(means[1], abs=2)  # auto exposure: scale-free


def test_plain_scene_png_is_unchanged(plain):
    """A plain Mitsuba scene's PNG is still the EXR clipped and sRGB-encoded (no exposure)."""
    from spectrace.images import encode_srgb_8bit

    rgb, _ = read_exr(plain)
    np.testing.assert_array_equal(png_pixels(plain.with_suffix(".png")), encode_srgb_8bit(rgb))


def test_output_png_writes_the_exr_beside_it(tmp_path):
    """-o OUT.png (and -m for the variant) writes OUT.png and OUT.exr."""
    out = tmp_path / "pic.png"
    assert main(["render", str(SHOWCASE), "-o", str(out), *TINY[:-2], "-m", "llvm_ad_rgb"]) == 0
    assert out.is_file() and out.with_suffix(".exr").is_file()
    assert read_exr(out.with_suffix(".exr"))[1]["variant"] == "llvm_ad_rgb"


def test_one_thread_render_finishes(tmp_path):
    """-t 1 renders and writes its EXR and PNG (Mitsuba's EXR writer deadlocks with a
    one-thread pool; spectrace writes with two): a fresh process, with a time-out."""
    out = tmp_path / "one.exr"
    done = subprocess.run([sys.executable, "-m", "spectrace.cli", "render", str(SHOWCASE),
                           "-o", str(out), *TINY, "-t", "1"],
                          capture_output=True, text=True, timeout=THREADS_TIMEOUT_S)
    assert done.returncode == 0, done.stderr[-2000:]
    assert out.is_file() and out.with_suffix(".png").is_file()


def relative_rms(image, reference) -> float:
    return float(np.sqrt(np.mean((image - reference) ** 2) / np.mean(reference**2)))


def test_noise_target_stops_near_the_true_error(tmp_path):
    """--noise 0.03: the render stops when the between-pass estimate falls below 0.03; its
    true relative RMS error against a 4096-spp reference of the same scene (another seed)
    is within 20 % of the target, and the header records the estimate and the spp."""
    scene = ["-D", "res=24", "--variant", "llvm_ad_rgb", "-q", "--spp-per-pass", "1"]
    reference = tmp_path / "reference.exr"
    assert main(["render", str(SHOWCASE), "-o", str(reference), *scene, "--spp", "4096",
                 "--seed", "99", "--spp-per-pass", "64"]) == 0
    ref, _ = read_exr(reference)
    out = tmp_path / "clean.exr"
    target = 0.03
    assert main(["render", str(SHOWCASE), "-o", str(out), *scene, "--noise", str(target)]) == 0
    image, header = read_exr(out)
    estimate = float(np.ravel(header["noise"])[0])  # Mitsuba stores a double attribute
    # E|M - R|^2 = var M + var R: take the reference's own noise (the estimate scaled to its
    # 4096 spp) out in quadrature
    ref_error = estimate * np.sqrt(header["spp"] / 4096)
    true_error = np.sqrt(max(relative_rms(image, ref) ** 2 - ref_error**2, 0.0))
    assert estimate < target
    print(f"--noise {target}: estimate {estimate:.4f}, true {true_error:.4f}, "
          f"{header['spp']} spp")
    assert abs(true_error - target) <= NOISE_TOLERANCE * target, (true_error, header["spp"])


def test_time_limit_stops_at_a_pass_boundary(tmp_path, capsys):
    """--time: the render stops at the first pass after the limit, well before its --spp."""
    out = tmp_path / "timed.exr"
    assert main(["render", str(SHOWCASE), "-o", str(out), "-D", "res=24", "-q", "--variant",
                 "llvm_ad_rgb", "--spp-per-pass", "4", "--spp", "100000", "--time",
                 "0.5"]) == 0
    _, header = read_exr(out)
    assert 0 < header["spp"] < 100000 and header["spp"] % 4 == 0
    assert "stopped by time" in capsys.readouterr().out


def test_view_reads_a_one_channel_exr(tmp_path):
    """A one-channel Y EXR (a lux map) develops as grey."""
    from spectrace.images import write_exr_channels

    path = tmp_path / "y.exr"
    write_exr_channels(path, {"Y": np.full((3, 3), 0.5, np.float32)})
    out = tmp_path / "y.png"
    assert main(["view", str(path), "-o", str(out)]) == 0
    assert np.all(png_pixels(out) == 188)  # sRGB(0.5) = 0.7354 -> 188


def test_compare_develops_both_sides_alike(tmp_path, capsys):
    """compare --exposure auto: the exposure found for A applies to B as well, so B = 2 A
    still differs by +100 % in mean luminance (an exposure per side would hide it)."""
    from spectrace.images import write_exr

    rng = np.random.default_rng(3)
    a = rng.uniform(0.01, 0.05, (8, 8, 3)).astype(np.float32)
    write_exr(tmp_path / "a.exr", a)
    write_exr(tmp_path / "b.exr", 2 * a)
    out = tmp_path / "cmp.png"
    assert main(["compare", str(tmp_path / "a.exr"), str(tmp_path / "b.exr"), "-o", str(out),
                 "--exposure", "auto"]) == 0
    printed = capsys.readouterr().out
    assert "exposure: auto" in printed and "(B - A) / A: +1.0000" in printed
    assert main(["compare", str(tmp_path / "a.exr"), str(tmp_path / "b.exr"), "-o", str(out),
                 "--white-balance", "0K"]) == EXIT_USAGE


def test_denoise_writes_a_picture_and_keeps_the_noisy_exr(tmp_path, plain):
    """--denoise: OUT.exr is the noisy render, bit for bit; OUT.denoised.exr is closer to a
    256-spp reference than the noisy image (showcase, 4 spp), and the PNG is made from it."""
    pytest.importorskip("pyoidn")
    out = tmp_path / "img.exr"
    assert main(["render", str(SHOWCASE), "-o", str(out), *TINY, "-t", "1", "--denoise"]) == 0
    assert read_exr(out)[0].tobytes() == read_exr(plain)[0].tobytes()
    denoised, header = read_exr(out.with_suffix(".denoised.exr"))
    assert header["denoiser"].startswith("Open Image Denoise")
    reference = tmp_path / "ref.exr"
    assert main(["render", str(SHOWCASE), "-o", str(reference), *TINY, "--spp", "256",
                 "--spp-per-pass", "64", "--seed", "7"]) == 0
    ref = read_exr(reference)[0]
    assert relative_rms(denoised, ref) < relative_rms(read_exr(out)[0], ref)
    from spectrace.images import encode_srgb_8bit

    np.testing.assert_array_equal(png_pixels(out.with_suffix(".png")),
                                  encode_srgb_8bit(denoised))


def test_denoise_without_the_library(tmp_path, capsys, monkeypatch):
    """--denoise without pyoidn: one line naming --denoise and the package, exit 2, nothing
    written."""
    monkeypatch.setitem(sys.modules, "pyoidn", None)  # import pyoidn raises ImportError
    out = tmp_path / "img.exr"
    assert main(["render", str(SHOWCASE), "-o", str(out), *TINY, "--denoise"]) == EXIT_USAGE
    assert_one_line_error(capsys, "--denoise", "pyoidn")
    assert not list(tmp_path.iterdir())
