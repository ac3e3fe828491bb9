"""Tests of :mod:`spectrace.lightgroups`: group parsing and naming, the layered EXR (read
back by OpenEXR and colour-science), relighting arithmetic, and the one-line errors.

Oracles: OpenEXR's and colour-science's readers; the linearity of a weighted sum.
"""

from __future__ import annotations

import numpy as np
import pytest

from spectrace import lightgroups
from spectrace.errors import FileAccessError, FileFormatError, ParameterError

#: A float32 weighted sum of layers against the float64 one.
RELIGHT_RTOL = 1e-6


@pytest.fixture
def layers(rng):
    return {g: rng.random((6, 5, 3), dtype=np.float32) for g in ("key", "fill", "sky")}


def test_parse_groups_and_their_errors():
    """``name=id1,id2;name2=id3``: names kept in order; each mistake one error naming it."""
    assert lightgroups.parse_groups("key=a,b; fill=c") == {"key": ["a", "b"], "fill": ["c"]}
    assert lightgroups.make_groups({"k": ("a",)}) == {"k": ["a"]}
    for text, words in [("key", "expected NAME=id1"), ("k=a;k=b", "given twice"),
                        ("k=", "no emitters"), ("k.x=a", "letters, digits"),
                        ("k=a;l=a", "'a' is in two light groups"), ("", "no light groups")]:
        with pytest.raises(ParameterError, match=words):
            lightgroups.parse_groups(text)


def test_scale_parsing_refuses_negative_and_nan():
    """``group=scale[,spectrum]``; a scale < 0, NaN or infinite is refused naming the group."""
    assert lightgroups.parse_scale("key=0.3") == ("key", 0.3, None)
    assert lightgroups.parse_scale("key=1,FL2") == ("key", 1.0, "FL2")
    for text, words in [("key=-1", "'key' must be a finite number >= 0"),
                        ("key=nan", "'key' must be"), ("key=inf", "'key' must be"),
                        ("key=x", "not a number"), ("=1", "expected GROUP=SCALE")]:
        with pytest.raises(ParameterError, match=words):
            lightgroups.parse_scale(text)


def test_layers_round_trip_through_openexr_and_colour(tmp_path, layers):
    """The beauty as R, G, B and each group as <group>.R/G/B float32 channels: read back
    exactly by the reader here, by OpenEXR channel by channel and by colour-science."""
    import colour
    import OpenEXR

    beauty = sum(layers.values())
    path = lightgroups.write_layers_exr(tmp_path / "l.exr", beauty, layers, {"spp": 4})
    b, back, header = lightgroups.read_layers_exr(path)
    assert list(back) == ["key", "fill", "sky"] and header["spp"] == 4
    np.testing.assert_array_equal(b, beauty)
    for g in layers:
        np.testing.assert_array_equal(back[g], layers[g])
    with OpenEXR.File(str(path), separate_channels=True) as f:
        channels = f.channels()
        assert set(channels) == {"R", "G", "B"} | {f"{g}.{c}" for g in layers for c in "RGB"}
        np.testing.assert_array_equal(channels["fill.G"].pixels, layers["fill"][..., 1])
        assert channels["sky.B"].pixels.dtype == np.float32
    image = colour.read_image(str(path))  # every channel, as an array
    assert image.shape == (6, 5, 12)
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temp file


def test_reading_a_file_without_layers_or_missing(tmp_path):
    """A plain RGB EXR has no layers, a missing file is named: one error each."""
    from spectrace.images import write_exr

    plain = tmp_path / "plain.exr"
    write_exr(plain, np.ones((2, 2, 3), np.float32))
    with pytest.raises(FileFormatError, match="no light-group layers"):
        lightgroups.read_layers_exr(plain)
    with pytest.raises(FileAccessError, match="no such file"):
        lightgroups.read_layers_exr(tmp_path / "none.exr")


def test_relight_is_the_weighted_sum_of_layers(layers):
    """sum_g s_g L_g, with scale 1 for the groups not named; the scaled layers returned."""
    image, scaled = lightgroups.relight(layers, {"key": 0.3, "sky": 0.0})
    expected = 0.3 * layers["key"].astype(np.float64) + layers["fill"]
    np.testing.assert_allclose(image, expected, rtol=RELIGHT_RTOL)
    assert image.dtype == np.float32 and not scaled["sky"].any()
    np.testing.assert_allclose(sum(scaled.values()), image, rtol=RELIGHT_RTOL)


def test_relight_refuses_unknown_groups_bad_scales_and_rgb_spectra(layers):
    """A group not in the layers, a negative or NaN scale, a new spectrum for an RGB layer:
    each a ParameterError naming the group."""
    for scales, spectra, words in [({"nope": 1.0}, None, "no light group 'nope'"),
                                   ({"key": -0.5}, None, "'key' must be"),
                                   ({"key": float("nan")}, None, "'key' must be"),
                                   ({}, {"fill": "FL2"}, "'fill': a new spectrum needs")]:
        with pytest.raises(ParameterError, match=words):
            lightgroups.relight(layers, scales, spectra)


def test_split_takes_the_layers_after_the_film_channels():
    """A render's channels: the film's (RGB, or RGBA), then three per group."""
    pixels = np.arange(2 * 2 * 10, dtype=np.float32).reshape(2, 2, 10)
    beauty, layers = lightgroups.split(pixels, ["a", "b"])
    np.testing.assert_array_equal(beauty, pixels[..., :3])
    np.testing.assert_array_equal(layers["b"], pixels[..., 7:10])
    with pytest.raises(ParameterError, match="cannot hold"):
        lightgroups.split(pixels, ["a", "b", "c", "d"])
