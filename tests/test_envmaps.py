"""Tests of the environment-map projectors (``spectrace.envmaps``): every layout maps a
direction to the image and back within half a texel, and latlong is Mitsuba's own (rows
from pole to pole)."""

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
    """Every texel of a layout, mapped to its direction and back, lands within half a
    texel of where it started (inside the image area the layout uses; latlong rows are
    1 / (H - 1) apart, and at the two poles every u is the same direction)."""
    height, width = envmaps.output_shape(layout, SIZE)
    uv = envmaps.texel_uv(height, width, layout)
    valid = envmaps.PROJECTORS[layout][2](uv)
    d = envmaps.uv_to_direction(uv[valid], layout)
    np.testing.assert_allclose(np.linalg.norm(d, axis=-1), 1.0, atol=1e-12)
    back = envmaps.direction_to_uv(d, layout)
    error = np.abs(back - uv[valid])
    rows = height
    if layout == "latlong":
        rows = height - 1
        error[:, 0] = np.minimum(error[:, 0], 1 - error[:, 0])  # u wraps around
        error[(uv[valid][:, 1] == 0) | (uv[valid][:, 1] == 1), 0] = 0.0  # the poles
    assert np.all(error[:, 0] * width <= 0.5) and np.all(error[:, 1] * rows <= 0.5)


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


def mitsuba_envmap_eval(image, d):
    """The radiance Mitsuba's ``envmap`` of the latlong ``image`` gives from directions
    ``d`` (N, 3): (N, 3)."""
    import drjit as dr
    import mitsuba as mi

    emitter = mi.load_dict({"type": "envmap",
                            "bitmap": mi.Bitmap(np.asarray(image, dtype=np.float32))})
    si = dr.zeros(mi.SurfaceInteraction3f, len(d))
    si.wi = mi.Vector3f(*(-np.ascontiguousarray(d[:, i], dtype=np.float32) for i in range(3)))
    return np.array(emitter.eval(si), dtype=np.float64).T


#: float32 radiance and directions in Mitsuba's lookup.
RTOL_FLOAT32 = 1e-4


@pytest.mark.parametrize("height", [8, 33])
def test_latlong_lookup_is_mitsubas_envmap(variant_rgb, rng, height):
    """Mitsuba's ``envmap`` of a random latlong map gives, from random directions (and
    from the texels' own directions but the poles', where u is arbitrary), exactly the
    bilinear ``lookup`` of the map at ``direction_to_uv``: the rows sit at v = i / (H - 1)
    from pole to pole, the columns at (j + 1/2) / W. (A pixel-centre row convention
    v = (i + 1/2) / H is off by up to half a row and fails this by far more than float32
    rounding.)"""
    image = rng.random((height, 2 * height, 3))
    d = rng.normal(size=(4000, 3))
    inner = envmaps.texel_uv(height, 2 * height, "latlong")[1:-1]
    d = np.vstack([d / np.linalg.norm(d, axis=1, keepdims=True),
                   envmaps.latlong_to_direction(inner).reshape(-1, 3)])
    mitsuba = mitsuba_envmap_eval(image, d)
    ours = envmaps.lookup(image, envmaps.direction_to_uv(d, "latlong"), "latlong")
    np.testing.assert_allclose(ours, mitsuba, rtol=RTOL_FLOAT32, atol=RTOL_FLOAT32)
    texels = ours[len(d) - inner[..., 0].size:].reshape(image[1:-1].shape)
    np.testing.assert_allclose(texels, image[1:-1], rtol=RTOL_FLOAT32)


def test_latlong_row_is_where_mitsuba_puts_it(variant_rgb):
    """A latlong map with one bright row i = 2 of H = 8: Mitsuba's ``envmap`` is brightest
    at theta = pi i / (H - 1), the direction ``texel_uv`` and ``uv_to_direction`` give that
    row (not at the pixel centre pi (i + 1/2) / H, 0.027 pi away).

    The earlier check (one bright texel of a 32 x 64 map, brightest of its 3 x 3
    neighbourhood at the pixel centres, above half its value) could not fail: a
    sub-texel offset of the rows keeps the texel the brightest of its neighbours and above
    half its value for any offset below half a texel, which the pixel-centre convention
    never exceeds."""
    height, width, row = 8, 16, 2
    image = np.zeros((height, width, 3))
    image[row] = 1.0
    theta = np.linspace(0, np.pi, 2801)
    d = np.stack([np.sin(theta), np.cos(theta), np.zeros_like(theta)], axis=-1)
    peak = theta[np.argmax(mitsuba_envmap_eval(image, d)[:, 0])]
    expected = envmaps.uv_to_direction(envmaps.texel_uv(height, width, "latlong")[row, 0],
                                       "latlong")
    assert peak == pytest.approx(np.arccos(expected[1]), abs=2e-3)
    assert abs(peak - np.pi * (row + 0.5) / height) > 0.05


def test_latlong_solid_angles():
    """The texels' solid angles (integrals of their bilinear hat functions times
    sin(theta)) sum to 4 pi, are equal within a row, and are 2 pi / W (1 - sin D / D)
    at the poles, 2 pi / W 2 (1 - cos D) / D sin(theta_i) between them (D = pi / (H - 1))."""
    height, width = 9, 18
    w = envmaps.latlong_solid_angles(height, width)
    delta = np.pi / (height - 1)
    assert w.sum() == pytest.approx(4 * np.pi, rel=1e-14)
    np.testing.assert_allclose(w, w[:, :1] * np.ones(width), rtol=0)
    row = w[:, 0] * width / (2 * np.pi)
    np.testing.assert_allclose(row[[0, -1]], 1 - np.sin(delta) / delta, rtol=1e-12)
    theta = np.arange(1, height - 1) * delta
    np.testing.assert_allclose(row[1:-1], 2 * (1 - np.cos(delta)) / delta * np.sin(theta),
                               rtol=1e-12)


@pytest.mark.parametrize("height", [8, 9])
def test_horizontal_illuminance_is_the_rendered_maps(rng, height):
    """``horizontal_illuminance`` of a random latlong map is the integral of Y cos(theta)
    over the upper hemisphere of the map as ``lookup`` (= Mitsuba's ``envmap``)
    interpolates it (a fine midpoint grid: 1e-4), rows at the poles and the horizon
    between rows (H = 8) or on one (H = 9)."""
    image = rng.random((height, 2 * height, 3))
    fine = 1024
    theta = (np.arange(fine // 2) + 0.5) / fine * np.pi  # the upper hemisphere
    phi = (np.arange(2 * fine) + 0.5) / (2 * fine) * 2 * np.pi
    t, p = np.meshgrid(theta, phi, indexing="ij")
    uv = np.stack([p / (2 * np.pi), t / np.pi], axis=-1)
    L = envmaps.lookup(image, uv, "latlong") @ np.array([0.2126, 0.7152, 0.0722])
    E = np.sum(L * np.cos(t) * np.sin(t)) * (np.pi / fine) ** 2
    assert envmaps.horizontal_illuminance(image, "latlong") / envmaps.LUX_PER_Y == \
        pytest.approx(E, rel=1e-4)


@pytest.mark.parametrize("layout", ["sphere", "angular", "cross_horizontal", "cross_vertical"])
def test_convert_preserves_a_smooth_map(layout):
    """A smooth latlong map converted to another layout and back is itself (bilinear
    resampling error of a smooth function), and its horizontal illuminance is kept."""
    height, width = 128, 256
    d = envmaps.latlong_to_direction(envmaps.texel_uv(height, width, "latlong"))
    image = np.repeat((1.2 + d[..., 1] + 0.3 * d[..., 0])[..., None], 3, axis=-1)
    other = envmaps.convert(image, "latlong", layout, 192)
    back = envmaps.convert(other, layout, "latlong", height)
    # the rim of a sphere map (-Z) or of an angular map (+Z) is one direction: singular
    keep = np.abs(d[..., 2] + (1 if layout == "sphere" else -1)) > 0.05
    np.testing.assert_allclose(back[keep], image[keep], atol=0.03)
    assert envmaps.horizontal_illuminance(other, layout) == pytest.approx(
        envmaps.horizontal_illuminance(image, "latlong"), rel=0.01)


def test_horizontal_illuminance_of_a_uniform_map():
    """A uniform map of luminance Y gives K_m integral V * pi * Y lux on a horizontal plane
    (exactly: the bilinear interpolation of a constant is that constant)."""
    image = np.ones((64, 128, 3))
    assert envmaps.horizontal_illuminance(image, "latlong") == pytest.approx(
        envmaps.LUX_PER_Y * np.pi, rel=1e-12)


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
            envmaps.texel_uv(height, width, layout))[..., None]
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

    d = envmaps.latlong_to_direction(envmaps.texel_uv(128, 256, "latlong"))
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
    d = envmaps.latlong_to_direction(envmaps.texel_uv(height, width, "latlong")).reshape(-1, 3)
    solid_angle = envmaps.latlong_solid_angles(height, width).ravel()
    cos = np.clip(np.asarray(normals) @ d.T, 0.0, None)
    return cos @ (image.reshape(-1, image.shape[-1]) * solid_angle[:, None])


def test_sh_basis_is_orthonormal():
    """The 9 harmonics are orthonormal on the sphere (integrated on a fine latlong grid
    with the texels' solid angles)."""
    height = 256
    d = envmaps.latlong_to_direction(envmaps.texel_uv(height, 2 * height, "latlong"))
    w = envmaps.latlong_solid_angles(height, 2 * height)
    Y = envmaps.sh_basis(d)
    gram = np.einsum("hwk,hwl,hw->kl", Y, Y, w)
    np.testing.assert_allclose(gram, np.eye(9), atol=1e-4)


def test_sh_irradiance_is_exact_for_band_limited_maps(rng):
    """For a map with no band above 2 (L = 1 + 0.5 y + 0.3 x z + 0.2 (x^2 - y^2)), the order-2
    irradiance equals the brute-force integral of L cos at random normals."""
    d = envmaps.latlong_to_direction(envmaps.texel_uv(256, 512, "latlong"))
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
