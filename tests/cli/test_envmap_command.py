"""``spectrace envmap convert``: layouts between files, photometric scale, bad input."""

from __future__ import annotations

import numpy as np
import pytest

from spectrace import envmaps
from spectrace.cli import main
from spectrace.images import read_exr, write_exr

EXIT_USAGE = 2


@pytest.fixture
def latlong(tmp_path):
    """A smooth 64 x 128 latlong map (brighter towards the zenith) as EXR."""
    d = envmaps.latlong_to_direction(envmaps.texel_uv(64, 128, "latlong"))
    image = np.repeat((1.0 + d[..., 1])[..., None], 3, axis=-1).astype(np.float32)
    path = tmp_path / "sky.exr"
    write_exr(path, image)
    return path, image


@pytest.mark.parametrize("to, shape", [("cube", (96, 128)), ("sphere", (96, 96)),
                                       ("latlong", (96, 192))])
def test_convert_and_back(latlong, tmp_path, capsys, to, shape):
    """A map converted to another layout has that layout's shape, and converted back to
    latlong it is the map again (within resampling error)."""
    path, image = latlong
    out = tmp_path / f"out_{to}.exr"
    assert main(["envmap", "convert", str(path), str(out), "--to", to, "--size", "96"]) == 0
    converted = read_exr(out)[0]
    assert converted.shape[:2] == shape
    back = tmp_path / "back.exr"
    assert main(["envmap", "convert", str(out), str(back), "--to", "latlong",
                 "--size", "64"]) == 0
    d = envmaps.latlong_to_direction(envmaps.texel_uv(64, 128, "latlong"))
    keep = np.abs(d[..., 2] + 1) > 0.1
    np.testing.assert_allclose(read_exr(back)[0][keep], image[keep], atol=0.05)
    assert "lx" in capsys.readouterr().out


#: Bilinear resampling error of the smooth map below (a 32-row latlong map).
ATOL_RESAMPLE = 0.005


def test_latlong_output_is_what_mitsuba_reads(variant_rgb, tmp_path, rng):
    """A smooth sky L = 1 + 0.5 y + x written by ``--to latlong`` at 32 rows and loaded by
    Mitsuba's ``envmap`` gives L itself from random directions, to the bilinear resampling
    error (rows written at pixel centres would be read half a row off near the poles:
    about 0.05 here)."""
    import drjit as dr
    import mitsuba as mi

    d = envmaps.latlong_to_direction(envmaps.texel_uv(128, 256, "latlong"))
    sky = np.repeat((1 + 0.5 * d[..., 1] + d[..., 0])[..., None], 3, axis=-1)
    path, out = tmp_path / "fine.exr", tmp_path / "coarse.exr"
    write_exr(path, sky.astype(np.float32))
    assert main(["envmap", "convert", str(path), str(out), "--to", "latlong",
                 "--size", "32"]) == 0
    assert read_exr(out)[0].shape[:2] == (32, 64)
    emitter = mi.load_dict({"type": "envmap", "filename": str(out)})
    w = rng.normal(size=(2000, 3))
    w /= np.linalg.norm(w, axis=1, keepdims=True)
    si = dr.zeros(mi.SurfaceInteraction3f, len(w))
    si.wi = mi.Vector3f(*(-w[:, i].astype(np.float32) for i in range(3)))
    L = np.array(emitter.eval(si), dtype=np.float64)[0]
    np.testing.assert_allclose(L, 1 + 0.5 * w[:, 1] + w[:, 0], rtol=0, atol=ATOL_RESAMPLE)


def test_illuminance_scale(latlong, tmp_path):
    """``--illuminance`` scales the map to that many lux on a horizontal plane."""
    path, _ = latlong
    out = tmp_path / "scaled.hdr"
    assert main(["envmap", "convert", str(path), str(out), "--to", "latlong",
                 "--illuminance", "10000"]) == 0
    scaled = envmaps.read_map(out)
    # RGBE keeps 8 bits of mantissa: 0.5 % per texel at most
    assert envmaps.horizontal_illuminance(scaled, "latlong") == pytest.approx(10000, rel=5e-3)


@pytest.mark.parametrize("shape, args, words", [
    ((50, 75), [], "no environment map layout"),
    ((60, 60), ["--from", "cube"], "cube cross must be 4:3"),
])
def test_bad_input(tmp_path, capsys, shape, args, words):
    """An image of no layout, or a cross of the wrong aspect: one line, exit 2, nothing
    written."""
    path = tmp_path / "bad.exr"
    write_exr(path, np.ones(shape + (3,), dtype=np.float32))
    out = tmp_path / "out.exr"
    assert main(["envmap", "convert", str(path), str(out), "--to", "latlong", *args]) \
        == EXIT_USAGE
    err = capsys.readouterr().err.strip()
    assert err.startswith("error:") and words in err and len(err.splitlines()) == 1
    assert not out.exists()


def test_missing_file(tmp_path, capsys):
    out = tmp_path / "out.exr"
    assert main(["envmap", "convert", str(tmp_path / "none.exr"), str(out),
                 "--to", "cube"]) == EXIT_USAGE
    assert "no such file" in capsys.readouterr().err
    assert not out.exists()


def test_six_faces(latlong, tmp_path):
    """``--to faces`` writes six face files; read back through ``{face}`` they convert to
    the same latlong map as the cross does."""
    path, image = latlong
    pattern = tmp_path / "face_{face}.exr"
    assert main(["envmap", "convert", str(path), str(pattern), "--to", "faces",
                 "--size", "96"]) == 0
    assert sorted(p.name for p in tmp_path.glob("face_*.exr")) == sorted(
        f"face_{tag}.exr" for tag in envmaps.FACE_TAGS)
    cross = tmp_path / "cross.exr"
    assert main(["envmap", "convert", str(path), str(cross), "--to", "cube",
                 "--size", "96"]) == 0
    a, b = tmp_path / "a.exr", tmp_path / "b.exr"
    assert main(["envmap", "convert", str(pattern), str(a), "--to", "latlong"]) == 0
    assert main(["envmap", "convert", str(cross), str(b), "--to", "latlong"]) == 0
    np.testing.assert_array_equal(read_exr(a)[0], read_exr(b)[0])
