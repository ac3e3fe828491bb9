"""Render until clean (spectrace.passes): the between-pass error estimate worked by hand, and
the stopping rules of the local loop."""

from __future__ import annotations

import math

import numpy as np
import pytest

from spectrace.errors import ParameterError
from spectrace.passes import check_until_clean, relative_error


def test_relative_error_by_hand():
    """Two pixels, three passes of 4, 4 and 8 samples with values (1, 3), (3, 3), (2, 3):
    M = (2, 3); s^2 = sum n_i (I_i - M)^2 / (P - 1) = (4 + 4 + 0) / 2 = 4 for pixel 1, 0 for
    pixel 2; var M = s^2 / N = 4 / 16; e = sqrt(mean(0.25, 0) / mean(4, 9)) = sqrt(0.125 /
    6.5)."""
    n = np.array([4.0, 4.0, 8.0])
    images = np.array([[1.0, 3.0], [3.0, 3.0], [2.0, 3.0]])
    sum_w = (n[:, None] * images).sum(axis=0)
    sum_w2 = (n[:, None] * images**2).sum(axis=0)
    assert relative_error(sum_w, sum_w2, 16, 3) == pytest.approx(math.sqrt(0.125 / 6.5))


def test_relative_error_dr_jit_equals_numpy(variant_rgb):
    """The Dr.Jit sums of the local loop give the numpy figure."""
    import mitsuba as mi

    rng = np.random.default_rng(4)
    sum_w, sum_w2 = rng.uniform(1, 2, 50), rng.uniform(5, 6, 50)
    expected = relative_error(sum_w, sum_w2, 10, 5)
    assert relative_error(mi.Float64(sum_w), mi.Float64(sum_w2), 10, 5) == \
        pytest.approx(expected, rel=1e-12)


def test_relative_error_of_independent_passes_is_the_true_error():
    """Passes of Gaussian noise around a known image: the estimate after 400 passes is the
    true relative RMS error of their mean to within 5 % (its own relative spread is about
    1 / sqrt(2 * 399 * pixels))."""
    rng = np.random.default_rng(5)
    truth = rng.uniform(0.5, 1.5, 256)
    passes = truth + rng.normal(0.0, 0.3, (400, truth.size))
    sum_w, sum_w2 = passes.sum(axis=0), (passes**2).sum(axis=0)
    mean = sum_w / 400
    true = math.sqrt(np.mean((mean - truth) ** 2) / np.mean(truth**2))
    assert relative_error(sum_w, sum_w2, 400, 400) == pytest.approx(true, rel=0.05)
    assert relative_error(sum_w, sum_w2, 400, 1) == math.inf


@pytest.mark.parametrize("noise, time_limit", [(0, None), (1.0, None), (math.nan, None),
                                               (None, 0), (None, math.inf), (None, -1)])
def test_bad_stopping_rules(noise, time_limit):
    """noise must lie in (0, 1), time_limit be positive and finite."""
    with pytest.raises(ParameterError, match="render_passes"):
        check_until_clean(noise, time_limit)


def test_render_stops_by_noise(variant_rgb):
    """spectrace.render(scene, noise=0.05) stops at the first pass (from the 8th) whose
    estimate is below 0.05, and says so."""
    from pathlib import Path

    import spectrace
    from spectrace.scene import load_scene

    scene = load_scene(Path(__file__).resolve().parents[1] / "scenes" / "showcase.xml",
                       {"res": "16"})
    result = spectrace.render(scene, seed=1, spp_per_pass=1, noise=0.05)
    assert result.stopped_by == "noise" and result.noise < 0.05
    assert result.passes >= 8 and result.spp % result.passes == 0  # ldsampler: 4 per pass
