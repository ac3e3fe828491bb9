"""spectrace.images, the one module that owns image files: PNG codes read back by
independent readers (Pillow, OpenImageIO), EXR channels and headers round-trip, Mitsuba's
writer with a one-thread pool, atomic writes."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from spectrace import images
from spectrace.errors import FileAccessError, FileFormatError

#: Seconds a one-thread mi.Bitmap write may take before the test calls it hung.
WRITE_TIMEOUT_S = 120


@pytest.fixture
def codes8():
    return np.random.default_rng(0).integers(0, 256, (5, 7, 3), dtype=np.uint8)


def test_png_codes_read_back_by_pillow(tmp_path, codes8):
    """An 8-bit PNG of write_png_codes holds exactly its codes (Pillow reads them)."""
    path = tmp_path / "a.png"
    images.write_png_codes(path, codes8)
    with Image.open(path) as im:
        assert im.mode == "RGB"
        np.testing.assert_array_equal(np.asarray(im), codes8)


def test_sixteen_bit_png_read_back_by_openimageio(tmp_path):
    """A 16-bit PNG holds its 16-bit codes, and the cICP chunk is there for display-p3."""
    oiio = pytest.importorskip("OpenImageIO")
    codes = np.random.default_rng(1).integers(0, 65536, (4, 6, 3), dtype=np.uint16)
    path = tmp_path / "deep.png"
    images.write_png_codes(path, codes, cicp=bytes((12, 13, 0, 1)))
    image = oiio.ImageInput.open(str(path))
    back = image.read_image(oiio.UINT16)
    image.close()
    np.testing.assert_array_equal(back, codes)
    data = path.read_bytes()
    assert b"cICP\x0c\x0d\x00\x01" in data and b"sRGB" not in data


def test_png_codes_refuse_other_arrays(tmp_path):
    """Floats or a wrong shape are refused, nothing written."""
    with pytest.raises(ValueError, match="uint8 or uint16"):
        images.write_png_codes(tmp_path / "x.png", np.zeros((2, 2, 3), np.float32))
    assert not list(tmp_path.iterdir())


def test_exr_channels_round_trip(tmp_path):
    """Named channels and int/float/str attributes come back as written; float16 on request."""
    y = np.linspace(0, 1, 12, dtype=np.float32).reshape(3, 4)
    path = tmp_path / "y.exr"
    images.write_exr_channels(path, {"Y": y}, {"units": "lux", "spp": 16, "E": 1.5})
    back, header = images.read_channel_exr(path, "Y")
    np.testing.assert_array_equal(back, y)
    assert header["units"] == "lux" and header["spp"] == 16 and header["E"] == 1.5
    images.write_exr_channels(path, {"Y": y}, dtype=np.float16)
    channels, _ = images.read_exr_channels(path)
    assert channels["Y"].dtype == np.float16
    with pytest.raises(FileFormatError, match="no R channel"):
        images.read_channel_exr(path, "R")


def test_exr_reading_errors_name_the_file(tmp_path):
    """Missing: FileAccessError; not an EXR: FileFormatError; both name the file."""
    with pytest.raises(FileAccessError, match="missing.exr: no such file"):
        images.read_exr(tmp_path / "missing.exr")
    junk = tmp_path / "junk.exr"
    junk.write_text("no")
    with pytest.raises(FileFormatError, match="junk.exr"):
        images.read_exr(junk)


def test_numpy_and_tensor_png_writers_agree(tmp_path, variant_rgb):
    """The PNG of a Dr.Jit tensor (mi.Bitmap) and of the same numpy array (write_png_codes)
    hold the same pixels."""
    import mitsuba as mi

    rgb = np.random.default_rng(2).uniform(0, 1.2, (6, 5, 3)).astype(np.float32)
    images.write_png(tmp_path / "np.png", rgb)
    images.write_png(tmp_path / "dr.png", mi.TensorXf(rgb))
    with Image.open(tmp_path / "np.png") as a, Image.open(tmp_path / "dr.png") as b:
        np.testing.assert_array_equal(np.asarray(a.convert("RGB")), np.asarray(b.convert("RGB")))


WRITE_WITH_ONE_THREAD = """
import sys
import spectrace
spectrace.set_variant("llvm_ad_rgb")
import drjit as dr, mitsuba as mi
from spectrace.images import write_exr
dr.set_thread_count(1)
write_exr(sys.argv[1], mi.TensorXf(dr.full(mi.Float, 0.5, 8 * 8 * 3), (8, 8, 3)))
assert dr.thread_count() == 1  # given back
"""


def test_bitmap_write_finishes_with_one_thread(tmp_path):
    """With dr.set_thread_count(1), a bare mi.Bitmap EXR write hangs (OpenEXR's line tasks
    wait on a pool with no worker); spectrace's writer finishes, and keeps the count."""
    path = tmp_path / "one.exr"
    done = subprocess.run([sys.executable, "-c", WRITE_WITH_ONE_THREAD, str(path)],
                          capture_output=True, text=True, timeout=WRITE_TIMEOUT_S)
    assert done.returncode == 0, done.stderr[-2000:]
    rgb, _ = images.read_exr(path)
    assert np.all(rgb == 0.5)
