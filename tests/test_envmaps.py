"""Tests of the environment-map projectors (``spectrace.envmaps``): every layout maps a
direction to the image and back within half a texel, and latlong is Mitsuba's own."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from spectrace import envmaps
from spectrace.errors import FileFormatError

#: Image height of the round-trip tests (texels).
SIZE = 96


@pytest.mark.parametrize("layout", envmaps.LAYOUTS)
def test_texel_round_trip(layout):
    """Every texel centre of a layout, mapped to its direction and back, lands within half
    a texel of where it started (inside the image area the layout uses)."""
    height, width = envmaps.output_shape(layout, SIZE)
    uv = envmaps.pixel_centres(height, width)
    valid = envmaps.PROJECTORS[layout][2](uv)
    d = envmaps.uv_to_direction(uv[valid], layout)
    np.testing.assert_allclose(np.linalg.norm(d, axis=-1), 1.0, atol=1e-12)
    back = envmaps.direction_to_uv(d, layout)
    error = np.abs(back - uv[valid])
    if layout == "latlong":
        error[:, 0] = np.minimum(error[:, 0], 1 - error[:, 0])  # u wraps around
    assert np.all(error[:, 0] * width <= 0.5) and np.all(error[:, 1] * height <= 0.5)


@pytest.mark.parametrize("layout", envmaps.LAYOUTS)
def test_direction_round_trip(layout, rng):
    """Random directions map to the image and back to themselves (within 1e-9 rad)."""
    d = rng.normal(size=(5000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    if layout == "sphere":  # the point behind the ball is the whole rim
        d = d[d[:, 2] > -0.999]
    back = envmaps.uv_to_direction(envmaps.direction_to_uv(d, layout), layout)
    angle = np.arccos(np.clip(np.sum(back * d, axis=1), -1, 1))
    assert angle.max() < 1e-6


@pytest.mark.parametrize("layout", ["cross_horizontal", "cross_vertical"])
def test_cross_faces_meet_without_seams(layout):
    """Directions just either side of every cube edge land in the two faces that share it
    and come back as the same direction (the unfolding is continuous)."""
    edges = []
    for a in (-1, 1):
        for b in (-1, 1):
            for axis in range(3):
                e = np.zeros(3)
                others = [i for i in range(3) if i != axis]
                e[others[0]], e[others[1]] = a, b
                for t in np.linspace(-0.9, 0.9, 7):
                    e2 = e.copy()
                    e2[axis] = t
                    edges.append(e2)
    d = envmaps._normalize(np.array(edges))
    for shift in (1e-7, -1e-7):
        dd = envmaps._normalize(d + shift * np.roll(d, 1, axis=1))
        back = envmaps.uv_to_direction(envmaps.direction_to_uv(dd, layout), layout)
        np.testing.assert_allclose(back, dd, atol=1e-6)


def test_latlong_is_mitsubas_envmap_convention(variant_rgb):
    """A latlong map with one bright texel: Mitsuba's ``envmap`` is brightest in the
    direction that ``uv_to_direction`` gives for that texel."""
    import drjit as dr
    import mitsuba as mi

    height, width = 32, 64
    image = np.full((height, width, 3), 0.01, dtype=np.float32)
    row, column = 9, 45
    image[row, column] = 100.0
    emitter = mi.load_dict({"type": "envmap", "bitmap": mi.Bitmap(image)})
    # the texel and its 8 neighbours: Mitsuba's bilinear lookup is brightest at the texel
    rows, columns = np.meshgrid(np.arange(row - 1, row + 2), np.arange(column - 1, column + 2),
                                indexing="ij")
    uv = np.stack([(columns.ravel() + 0.5) / width, (rows.ravel() + 0.5) / height], axis=-1)
    d = envmaps.uv_to_direction(uv, "latlong")
    si = dr.zeros(mi.SurfaceInteraction3f, 9)
    si.wi = mi.Vector3f(*(-d[:, i].astype(np.float32) for i in range(3)))
    value = np.array(emitter.eval(si))[0]
    assert np.argmax(value) == 4 and value[4] > 0.5 * 100.0


@pytest.mark.parametrize("layout", ["sphere", "angular", "cross_horizontal", "cross_vertical"])
def test_convert_preserves_a_smooth_map(layout):
    """A smooth latlong map converted to another layout and back is itself (bilinear
    resampling error of a smooth function), and its horizontal illuminance is kept."""
    height, width = 128, 256
    uv = envmaps.pixel_centres(height, width)
    d = envmaps.latlong_to_direction(uv)
    image = np.repeat((1.2 + d[..., 1] + 0.3 * d[..., 0])[..., None], 3, axis=-1)
    other = envmaps.convert(image, "latlong", layout, 192)
    back = envmaps.convert(other, layout, "latlong", height)
    keep = np.abs(d[..., 2] + 1) > 0.05  # the sphere map's rim is a singularity
    np.testing.assert_allclose(back[keep], image[keep], atol=0.03)
    assert envmaps.horizontal_illuminance(other, layout) == pytest.approx(
        envmaps.horizontal_illuminance(image, "latlong"), rel=0.01)


def test_horizontal_illuminance_of_a_uniform_map():
    """A uniform map of luminance Y gives K_m integral V * pi * Y lux on a horizontal plane."""
    image = np.ones((64, 128, 3))
    assert envmaps.horizontal_illuminance(image, "latlong") == pytest.approx(
        envmaps.LUX_PER_Y * np.pi, rel=1e-3)


@pytest.mark.parametrize("shape, hint, words", [
    ((100, 150), None, "no environment map layout"),
    ((300, 300), "cube", "cube cross must be 4:3"),
    ((100, 300), "latlong", "aspect ratio"),
])
def test_detect_layout_refuses(shape, hint, words):
    """An image that is none of the layouts, or a cross of the wrong aspect, is refused
    with one line naming the image."""
    with pytest.raises(FileFormatError, match=words):
        envmaps.detect_layout(shape, hint, "in.exr")


def test_detect_layout():
    assert envmaps.detect_layout((64, 128)) == "latlong"
    assert envmaps.detect_layout((96, 128)) == "cross_horizontal"
    assert envmaps.detect_layout((128, 96)) == "cross_vertical"
    assert envmaps.detect_layout((64, 64)) == "sphere"
    assert envmaps.detect_layout((64, 64), "angular") == "angular"


def test_six_faces_round_trip(rng):
    """A cross split into its six faces and assembled again is the same cross, in both
    cross layouts."""
    for layout in ("cross_horizontal", "cross_vertical"):
        height, width = envmaps.output_shape(layout, 48)
        cross = rng.random((height, width, 3)) * envmaps.PROJECTORS[layout][2](
            envmaps.pixel_centres(height, width))[..., None]
        faces = envmaps.split_cross(cross, layout)
        face = height // (3 if layout == "cross_horizontal" else 4)
        assert set(faces) == set(envmaps.FACES) and faces["+y"].shape == (face, face, 3)
        np.testing.assert_array_equal(envmaps.assemble_cross(faces, layout), cross)


def test_six_faces_must_be_equal_squares():
    faces = {face: np.ones((8, 8, 3)) for face in envmaps.FACES}
    faces["-z"] = np.ones((8, 9, 3))
    with pytest.raises(FileFormatError, match="squares of one size"):
        envmaps.assemble_cross(faces)


#: Monte Carlo (2^16 meter samples of a smooth sky) and resampling tolerance.
RTOL_RENDER = 0.01


@pytest.mark.parametrize("layout", ["latlong", "cross_horizontal", "sphere", "angular"])
def test_layouts_render_the_same(variant_rgb, layout):
    """One sky stored in each layout and fed to Mitsuba's ``envmap`` as latlong (through
    ``convert``) gives the same illuminance on Mitsuba's irradiancemeter, and it is the
    illuminance ``horizontal_illuminance`` computes from the map."""
    import mitsuba as mi

    sys_path = str(Path(__file__).resolve().parent / "plugins")
    if sys_path not in sys.path:
        sys.path.insert(0, sys_path)
    import daylight_checks as day

    uv = envmaps.pixel_centres(128, 256)
    d = envmaps.latlong_to_direction(uv)
    sky = np.stack([0.2 + 0.8 * np.clip(d[..., 1], 0, 1) + 0.3 * np.clip(d[..., 0], 0, 1),
                    0.3 + 0.5 * np.clip(d[..., 1], 0, 1), 0.5 + 0.0 * d[..., 1]], axis=-1)
    stored = envmaps.convert(sky, "latlong", layout, 192) if layout != "latlong" else sky
    latlong = envmaps.convert(stored, layout, "latlong", 128) if layout != "latlong" else sky
    light = {"type": "envmap", "bitmap": mi.Bitmap(latlong.astype(np.float32))}
    measured = day.meter_lux(light, spp=2**16)
    expected = envmaps.horizontal_illuminance(sky, "latlong")
    assert measured == pytest.approx(expected, rel=RTOL_RENDER)
    assert envmaps.horizontal_illuminance(stored, layout) == pytest.approx(expected,
                                                                           rel=RTOL_RENDER)


def brute_force_irradiance(image, normals):
    """E(n) = sum over the latlong texels of L max(n . omega, 0) d omega."""
    height, width = image.shape[:2]
    uv = envmaps.pixel_centres(height, width)
    d = envmaps.latlong_to_direction(uv).reshape(-1, 3)
    solid_angle = ((np.pi / height) * (2 * np.pi / width) * np.sin(np.pi * uv[..., 1])).ravel()
    cos = np.clip(np.asarray(normals) @ d.T, 0.0, None)
    return cos @ (image.reshape(-1, image.shape[-1]) * solid_angle[:, None])


def test_sh_basis_is_orthonormal():
    """The 9 harmonics are orthonormal on the sphere (integrated on a fine latlong grid)."""
    height = 256
    uv = envmaps.pixel_centres(height, 2 * height)
    d = envmaps.latlong_to_direction(uv)
    w = (np.pi / height) * (np.pi / height) * np.sin(np.pi * uv[..., 1])
    Y = envmaps.sh_basis(d)
    gram = np.einsum("hwk,hwl,hw->kl", Y, Y, w)
    np.testing.assert_allclose(gram, np.eye(9), atol=1e-4)


def test_sh_irradiance_is_exact_for_band_limited_maps(rng):
    """For a map with no band above 2 (L = 1 + 0.5 y + 0.3 x z + 0.2 (x^2 - y^2)), the order-2
    irradiance equals the brute-force integral of L cos at random normals."""
    uv = envmaps.pixel_centres(256, 512)
    d = envmaps.latlong_to_direction(uv)
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    image = (1 + 0.5 * y + 0.3 * x * z + 0.2 * (x * x - y * y))[..., None]
    normals = rng.normal(size=(20, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    sh = envmaps.sh_irradiance(envmaps.sh_project(image), normals)
    np.testing.assert_allclose(sh, brute_force_irradiance(image, normals), rtol=2e-4)
    assert envmaps.sh_irradiance(envmaps.sh_project(np.ones((64, 128, 1))),
                                 [[0, 1, 0]])[0, 0] == pytest.approx(np.pi, rel=1e-3)


def test_sh_irradiance_of_the_shipped_sky(rng):
    """The project's clear-sky map: the order-2 irradiance is within 10 % of the brute-force
    integral for normals over the sphere (Ramamoorthi and Hanrahan report about 1-3 % on
    average for natural light probes; a clear sky with its bright circumsolar region is
    harder)."""
    from spectrace import scenes

    image = envmaps.read_map(scenes.FOLDER / "textures" / "daylight_sky.exr")
    normals = rng.normal(size=(50, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    sh = envmaps.sh_irradiance(envmaps.sh_project(image), normals)
    exact = brute_force_irradiance(image, normals)
    np.testing.assert_allclose(sh, exact, rtol=0.10)
    assert np.mean(np.abs(sh / exact - 1)) < 0.03
