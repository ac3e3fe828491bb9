"""The pass loop: passes are seeded apart and averaged with weights equal to their spp."""

from __future__ import annotations

import numpy as np
import pytest

import spectrace
from spectrace.errors import UserError
from spectrace.passes import pass_seed, pass_sizes, render_passes


def small_scene():
    import mitsuba as mi

    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 3},
        "sphere": {"type": "sphere", "bsdf": {"type": "diffuse"}},
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": [0.9, 0.7, 0.5]}},
        "camera": {"type": "perspective", "fov": 45,
                   "to_world": mi.ScalarTransform4f().look_at([0, 0, 4], [0, 0, 0], [0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": 16, "height": 12}},
    })


def test_pass_sizes_cover_spp_exactly():
    """The passes add up to the requested spp, the remainder in the last pass."""
    assert pass_sizes(10, 4) == [4, 4, 2]
    assert pass_sizes(8, 4) == [4, 4]
    assert pass_sizes(3, 16) == [3]
    with pytest.raises(UserError, match="spp"):
        pass_sizes(0, 4)
    with pytest.raises(UserError, match="spp-per-pass"):
        pass_sizes(4, 0)


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
