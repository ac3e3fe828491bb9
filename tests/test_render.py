"""The pass loop: passes are seeded apart and averaged with weights equal to their spp."""

from __future__ import annotations

import os

import numpy as np
import pytest

import spectrace
from spectrace.errors import ParameterError
from spectrace.passes import (
    MAX_SPP_PER_PASS,
    PASS_SAMPLES,
    default_spp_per_pass,
    pass_seed,
    pass_sizes,
    render_passes,
)


def small_scene(sampler: str = "independent"):
    import mitsuba as mi

    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 3},
        "sphere": {"type": "sphere", "bsdf": {"type": "diffuse"}},
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": [0.9, 0.7, 0.5]}},
        "camera": {"type": "perspective", "fov": 45,
                   "to_world": mi.ScalarTransform4f().look_at([0, 0, 4], [0, 0, 0], [0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": 16, "height": 12},
                   "sampler": {"type": sampler}},
    })


def test_pass_sizes_cover_spp_exactly():
    """The passes add up to the requested spp, the remainder in the last pass."""
    assert pass_sizes(10, 4) == [4, 4, 2]
    assert pass_sizes(8, 4) == [4, 4]
    assert pass_sizes(3, 16) == [3]
    with pytest.raises(ParameterError, match="spp"):
        pass_sizes(0, 4)
    with pytest.raises(ParameterError, match="spp_per_pass"):
        pass_sizes(4, 0)


@pytest.mark.parametrize("pixels, spp, expected", [
    (256 * 256, 1024, 64),   # 4 M samples: the cap and the budget meet
    (512 * 512, 1024, 16),   # the budget: 4 M samples
    (1920 * 1080, 1024, 1),  # 2 M pixels: one spp per pass (the budget allows 2)
    (4096 * 4096, 64, 1),    # more pixels than the budget: still 1 spp
    (32 * 32, 4, 4),         # no more than the render's spp
    (64 * 64, 1024, 64),     # the cap
])
def test_default_pass_size(pixels, spp, expected):
    """The default pass size: the largest power of 4 up to MAX_SPP_PER_PASS within
    PASS_SAMPLES samples, at least 1 and at most the render's spp."""
    k = default_spp_per_pass(pixels, spp)
    assert k == expected
    assert k == spp or (k & (k - 1) == 0 and k.bit_length() % 2 == 1)  # a power of 4
    assert k <= MAX_SPP_PER_PASS and (k == 1 or k * pixels <= PASS_SAMPLES)


def test_default_passes_follow_the_film(variant_rgb):
    """Without spp_per_pass the loop uses the default for the sensor's film (16 x 12 pixels:
    passes of MAX_SPP_PER_PASS spp)."""
    result = render_passes(small_scene(), spp=2 * MAX_SPP_PER_PASS + 3, seed=0)
    assert result.passes == 3 and result.spp == 2 * MAX_SPP_PER_PASS + 3


def test_pass_seeds_are_distinct_across_nearby_seeds():
    """Passes of seed 0 and seed 1 never reuse a seed (no correlated passes)."""
    seeds = {pass_seed(s, i) for s in range(8) for i in range(1000)}
    assert len(seeds) == 8 * 1000


def test_passes_are_the_spp_weighted_mean_of_mi_render(variant_rgb):
    """The result equals the spp-weighted mean of mi.render calls with the passes' seeds."""
    import mitsuba as mi

    scene = small_scene()
    result = render_passes(scene, spp=10, seed=3, spp_per_pass=4)
    sizes = [4, 4, 2]
    expected = sum(np.asarray(mi.render(scene, spp=n, seed=pass_seed(3, i))) * n
                   for i, n in enumerate(sizes)) / 10
    assert result.spp == 10 and result.passes == 3 and not result.interrupted
    assert result.image.shape == (12, 16, 3) and result.image.dtype == np.float32
    np.testing.assert_allclose(result.image, expected, rtol=1e-5, atol=1e-6)


def test_passes_are_weighted_by_the_samples_the_sampler_took(variant_rgb):
    """ldsampler makes a pass of 8 spp one of 16 (a power of 4): each pass weighs what was
    rendered, and the render reports the 32 spp it holds, not the 24 asked."""
    import mitsuba as mi

    scene = small_scene("ldsampler")
    result = render_passes(scene, spp=24, seed=5, spp_per_pass=8)
    expected = sum(np.asarray(mi.render(scene, spp=8, seed=pass_seed(5, i))) * 16
                   for i in range(3)) / 48
    assert result.spp == 48 and result.passes == 3
    np.testing.assert_allclose(result.image, expected, rtol=1e-5, atol=1e-6)
    exact = render_passes(small_scene(), spp=24, seed=5, spp_per_pass=8)  # independent
    assert exact.spp == 24


def test_same_seed_same_image_other_seed_other_noise(variant_rgb):
    """A render is a function of its seed: equal for equal seeds, different otherwise."""
    scene = small_scene()
    a = render_passes(scene, spp=4, seed=7, spp_per_pass=2).image
    b = render_passes(scene, spp=4, seed=7, spp_per_pass=2).image
    c = render_passes(scene, spp=4, seed=8, spp_per_pass=2).image
    np.testing.assert_allclose(a, b, rtol=1e-5, atol=1e-6)  # parallel adds: rounding only
    assert not np.allclose(a, c, rtol=0.01, atol=0.01)


def test_public_entry_point(variant_spectral):
    """spectrace.render is the pass loop, usable from notebooks."""
    result = spectrace.render(small_scene(), spp=2, seed=1)
    assert np.isfinite(result.image).all() and result.spp == 2
    assert result.samples_per_second > 0


def test_nan_never_reaches_the_image(variant_rgb):
    """A BSDF that returns NaN (a scaled texture of NaN) leaves zeros, counted, not NaN."""
    import mitsuba as mi

    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "direct"},
        "sphere": {"type": "sphere", "bsdf": {"type": "diffuse",
                                              "reflectance": {"type": "rgb",
                                                              "value": [float("nan")] * 3}}},
        "light": {"type": "point", "position": [0, 0, 4]},
        "camera": {"type": "perspective", "fov": 45,
                   "to_world": mi.ScalarTransform4f().look_at([0, 0, 4], [0, 0, 0], [0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": 8, "height": 8}},
    })
    result = render_passes(scene, spp=2)
    assert np.isfinite(result.image).all()
    assert result.nonfinite > 0


def test_result_stays_a_tensor_until_the_image_is_asked_for(variant_rgb):
    """The local loop's pixels are a Dr.Jit tensor (no numpy needed to render and write);
    ``image`` is the same values as a float32 numpy array, converted once."""
    result = render_passes(small_scene(), spp=2, seed=1)
    assert type(result.pixels).__module__.startswith("drjit")
    assert result.shape == (12, 16, 3)
    image = result.image
    assert isinstance(image, np.ndarray) and image.dtype == np.float32
    np.testing.assert_array_equal(image, np.asarray(result.pixels))
    assert result.image is image


# ------------------------------------------- the writers given a tensor (mi.Bitmap)

#: Linear values at the edges of the PNG's encoding: below 0, the linear segment and its
#: end (0.0031308), 1, above 1, infinities and NaN.
EDGE_VALUES = [-0.5, 0.0, 1e-4, 0.0031308, 0.0031309, 0.2, 0.5, 1.0, 3.0,
               np.inf, -np.inf, np.nan]


@pytest.mark.parametrize("channels", [1, 2, 3, 4])
def test_tensor_writers_write_what_the_numpy_writers_write(variant_rgb, tmp_path, rng,
                                                           channels):
    """An image given as ``mi.TensorXf`` (written by Mitsuba's Bitmap) and as a numpy array
    (written by OpenEXR and Pillow): the same float32 EXR pixels and header attributes, the
    same 8-bit sRGB codes in the PNG (edge values included), the umask's file mode and no
    temporary file left; a one- or two-channel (mono) film as grey."""
    import mitsuba as mi
    from PIL import Image

    from spectrace.images import read_exr, write_exr, write_png

    pixels = rng.random((6, 50, channels), dtype=np.float32) ** 3
    pixels.reshape(-1)[:len(EDGE_VALUES)] = EDGE_VALUES
    header = {"spp": 12, "seed": 3, "variant": "llvm_ad_rgb", "scene": "/a/b.xml"}
    for name, image in (("tensor", mi.TensorXf(pixels)), ("numpy", pixels)):
        write_exr(tmp_path / f"{name}.exr", image, header)
        write_png(tmp_path / f"{name}.png", image)
    rgb, got = read_exr(tmp_path / "tensor.exr")
    expected, _ = read_exr(tmp_path / "numpy.exr")
    assert rgb.shape == (6, 50, 3)
    np.testing.assert_array_equal(rgb, expected)
    assert {key: got[key] for key in header} == header
    with Image.open(tmp_path / "tensor.png") as a, Image.open(tmp_path / "numpy.png") as b:
        assert a.mode == "RGB"
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    umask = os.umask(0)
    os.umask(umask)
    for path in tmp_path.iterdir():
        assert not path.name.startswith("."), path  # no temporary file left
        assert (path.stat().st_mode & 0o777) == 0o666 & ~umask, path
