"""Tests of spectrace.studies.light_compositing, the light compositing study.

Oracles: the linearity of light transport (the layers of a render sum to it; separate
renders of each light sum to the all-on render within noise) and relighting arithmetic.
"""

from __future__ import annotations

import numpy as np

import spectrace
from spectrace.studies import light_compositing as study

RES, SPP = 16, 16
#: Layers against the beauty of the same render (float32, relative to the peak).
SUM_RTOL = 1e-5
#: Mean luminance of the summed separate renders against the all-on render at RES, SPP
#: (the noise of a mean over RES^2 pixels; measured 0.1 % at 48 px).
MEAN_RTOL = 0.05


def test_room_has_the_path_tracer_and_named_lights():
    """The room's local integrator is replaced by path; the luminaires get their ids;
    keeping one light removes the three others."""
    root = study.room_tree(max_depth=4)
    assert root.find("integrator").get("type") == "path"
    assert [e.get("id") for e in root.findall("emitter")] == list(study.LIGHTS)
    assert [e.get("id") for e in study.room_tree(lights=["washer_left"]).findall("emitter")] \
        == ["washer_left"]


def test_layers_and_separate_renders_sum_to_all_on(variant_rgb):
    """Superposition: the four layers sum to the beauty (float precision) and the four
    separate renders of one light each sum to it within noise; the light scene 'all on'
    is the beauty and 'work' is the tables' layers."""
    beauty, layers = study.render_layers(study.load_room(RES, SPP), SPP)
    assert list(layers) == list(study.LIGHTS)
    np.testing.assert_allclose(sum(layers.values()), beauty, rtol=0,
                               atol=SUM_RTOL * beauty.max())
    alone = study.render_alone(RES, SPP)
    Y, Y_alone = study.luminance(beauty).mean(), study.luminance(sum(alone.values())).mean()
    assert abs(Y_alone / Y - 1.0) < MEAN_RTOL
    scenes = study.light_scenes(layers)
    np.testing.assert_allclose(scenes["all on"], beauty, rtol=0, atol=SUM_RTOL * beauty.max())
    np.testing.assert_allclose(scenes["work (tables only)"],
                               layers["table_left"] + layers["table_right"], rtol=1e-6)
    rows = study.linearity_rows(beauty, layers, alone)
    assert len(rows) == 2 and abs(float(rows[0][1])) < SUM_RTOL


def test_lamp_change_methods(variant_spectral):
    """The spectral relight to the lamps' own spectrum gives back the layers' image (the
    probed spectrum is the LED's), the RGB shortcut is the identity for the same lamp and
    D65's RGB is white; a 4000 K LED relit from spectral layers is closer to the fresh
    render in CIEDE2000 than the RGB shortcut."""
    from spectrace.spectral_film import bands_to_linear_srgb

    np.testing.assert_allclose(study.lamp_rgb("D65"), 1.0, atol=2e-3)
    led = study.LAMPS["3000 K LED"]
    scene = study.load_room(RES, SPP)
    wl, layers, spectra = study.render_spectral_layers(scene, SPP)
    same = study.spectral_relight(layers, wl, spectra, led)
    np.testing.assert_allclose(same, bands_to_linear_srgb(sum(layers.values()), wl),
                               rtol=2e-3, atol=1e-5)
    beauty, _ = study.render_layers(scene, SPP)
    np.testing.assert_allclose(study.rgb_relight(beauty, led, led), beauty, rtol=1e-6)
    lamp = study.LAMPS["4000 K LED"]
    fresh = {"4000 K LED": spectrace.render(study.load_room(RES, SPP, lamp=lamp),
                                            spp=SPP).image[..., :3]}
    rows = study.lamp_change_rows({"4000 K LED": {
        "spectral": study.spectral_relight(layers, wl, spectra, lamp),
        "rgb": study.rgb_relight(beauty, led, lamp)}}, fresh)
    assert float(rows[0][2]) < float(rows[1][2])
