"""Tests of spectrace.studies.light_compositing, the light compositing study.

Oracles: the linearity of light transport (the layers of a render sum to it; separate
renders of each light sum to the all-on render within noise) and relighting arithmetic.
"""

from __future__ import annotations

import numpy as np

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
