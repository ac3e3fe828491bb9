"""Tests of spectrace.studies.phong_vs_energy, the energy-conservation study.

Oracles: closed-form lobe integrals (scipy quadrature), the Lambertian BSDF's exact
albedo, the geometric series of bounces in a closed box, and projected sphere areas.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from spectrace.studies import phong_vs_energy as study

#: Ratio of successive bounce increments in a closed diffuse box against its albedo.
BOUNCE_RATIO_ATOL = 0.04
#: Sphere pixel count against its projected disc area (relative).
AREA_RTOL = 0.05


def test_beckmann_alpha_of_blinn_phong_exponent():
    """Walter et al. 2007: alpha = sqrt(2 / (m + 2)), so m = 2 gives sqrt(1/2)."""
    assert study.beckmann_alpha(2.0) == pytest.approx(math.sqrt(0.5))
    assert study.beckmann_alpha(0.0) == pytest.approx(1.0)


def test_classic_phong_normal_albedo_is_the_lobe_integral():
    """integral of cos^m(theta) cos(theta) over the hemisphere = 2 pi / (m + 2)."""
    from scipy.integrate import quad

    def lobe(t, m):
        return np.cos(t) ** (m + 1) * np.sin(t)

    for m in (1.0, 2.0, 32.0):
        integral = 2 * np.pi * quad(lobe, 0, np.pi / 2, args=(m,))[0]
        assert study.classic_phong_albedo_normal(m) == pytest.approx(integral, rel=1e-9)


def test_albedo_curves_of_a_lambertian_family_are_its_reflectance(variant_rgb):
    """A diffuse BSDF reflects exactly its reflectance from every direction."""
    family = {"diffuse": lambda m: {"type": "diffuse", "reflectance": 0.3}}
    curves = study.albedo_curves([1, 8], [0.0, 45.0, 80.0], families=family, samples=1 << 10)
    np.testing.assert_allclose(curves["diffuse"], 0.3, rtol=1e-5)


def test_closed_box_bounces_multiply_by_the_albedo(variant_rgb):
    """In a closed diffuse box each bounce adds the previous one's light times the albedo."""
    albedo = 0.5
    series = study.bounce_series({"type": "diffuse", "reflectance": albedo},
                                   [1, 2, 3, 4, 5, 6, 7], res=16, spp=32)
    assert series[0] == 0.0  # a point light is invisible to the camera
    increments = np.diff(series)
    assert np.all(increments > 0)
    ratios = increments[2:] / increments[1:-1]
    assert np.mean(ratios) == pytest.approx(albedo, abs=BOUNCE_RATIO_ATOL)


def test_shape_labels_cover_each_sphere_disc(variant_rgb):
    """Each sphere's labelled pixels cover its projected disc, pi r^2, in grid order."""
    import mitsuba as mi

    res, cols = 60, 3
    family = {"grey": lambda m: {"type": "diffuse"}}
    scene = mi.load_dict(study.sphere_grid_scene(family, [1, 2, 3], res=res, spp=1))
    labels, centres = study.shape_labels(scene)
    pixels_per_unit = res / cols
    disc = np.pi * (0.42 * pixels_per_unit) ** 2
    np.testing.assert_allclose(np.bincount(labels[labels >= 0]), disc, rtol=AREA_RTOL)
    rows, columns = study.grid_position(centres)
    np.testing.assert_array_equal(rows, [0, 0, 0])
    np.testing.assert_array_equal(columns, [0, 1, 2])
