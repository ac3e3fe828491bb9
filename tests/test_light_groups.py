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


WL = np.linspace(400.0, 700.0, 7)  # band centres, 50 nm apart


def test_band_averages_of_constant_and_linear_spectra():
    """A constant spectrum averages to itself in every band, a linear one to its value at
    the centre of the inner (symmetric) bands; a line inside one band only lights the
    bands whose hats cover it."""
    np.testing.assert_allclose(lightgroups.band_averages([380, 780], [2.0, 2.0], WL), 2.0)
    linear = lightgroups.band_averages([380, 780], [380, 780], WL)
    np.testing.assert_allclose(linear[1:-1], WL[1:-1], rtol=1e-9)
    line = lightgroups.band_averages([519, 520, 521], [0, 1, 0], WL)
    assert np.count_nonzero(line) == 2 and line[2] > line[3] > 0  # 520 nm: bands 500, 550


def test_spectral_layers_round_trip(tmp_path, rng):
    """Beauty S0.* (read by the Fichet reader), <group>.S0.* layers, R, G, B preview and
    the recorded lamp spectra come back as written; a group without a spectrum has None."""
    from spectrace.spectral import read_spectral_exr

    layers = {g: rng.random((3, 4, WL.size), dtype=np.float32) for g in ("a", "b")}
    total = sum(layers.values())
    spectra = {"a": np.linspace(0.5, 1.0, WL.size), "b": None}
    path = lightgroups.write_spectral_layers_exr(tmp_path / "s.exr", total, layers, WL,
                                                 np.zeros((3, 4, 3)), spectra, {"spp": 2})
    bands, back, wl, got, header = lightgroups.read_spectral_layers_exr(path)
    np.testing.assert_array_equal(bands, total)
    np.testing.assert_array_equal(back["b"], layers["b"])
    np.testing.assert_allclose(wl, WL)
    np.testing.assert_allclose(got["a"], spectra["a"], rtol=1e-8)
    assert got["b"] is None and header["spp"] == 2
    np.testing.assert_array_equal(read_spectral_exr(path)[0], total)
    assert lightgroups.is_spectral_layers_file(path)


def test_relight_spectral_swaps_a_lamp_spectrum(rng):
    """A group lit by a flat lamp relit with a spectrum rising across the bands: its layer
    times new / old band by band, at the same luminous output (sum of V S over the bands);
    the others only scaled."""
    layers = {g: rng.random((2, 2, WL.size), dtype=np.float32) for g in ("lamp", "sky")}
    old = {"lamp": np.ones(WL.size), "sky": None}
    new = (WL, np.linspace(1.0, 3.0, WL.size))
    image, scaled = lightgroups.relight_spectral(layers, WL, {"sky": 0.5}, {"lamp": new}, old)
    V = lightgroups.band_averages(*lightgroups._photopic(), WL)
    S = lightgroups.band_averages(*new, WL)
    factor = S * np.sum(V) / np.sum(V * S)
    np.testing.assert_allclose(scaled["lamp"], layers["lamp"] * factor, rtol=1e-5)
    np.testing.assert_allclose(image, scaled["lamp"] + 0.5 * layers["sky"], rtol=1e-5)


def test_relight_spectral_errors(rng):
    """No recorded old spectrum, a negative new one, an old one that is 0 where the new
    one is not, a group not in the layers: each one ParameterError naming the group."""
    layers = {"lamp": rng.random((2, 2, WL.size), dtype=np.float32)}
    flat = (WL, np.ones(WL.size))
    dark = np.where(WL < 500, 0.0, 1.0)
    for old, new, group, words in [
        ({"lamp": None}, flat, "lamp", "not recorded"),
        ({"lamp": np.ones(WL.size)}, (WL, -np.ones(WL.size)), "lamp", "negative"),
        ({"lamp": dark}, flat, "lamp", "is 0 where"),
        ({"lamp": np.ones(WL.size)}, flat, "nope", "no light group 'nope'"),
    ]:
        with pytest.raises(ParameterError, match=words):
            lightgroups.relight_spectral(layers, WL, {}, {group: new}, old)
