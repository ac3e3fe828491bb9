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
#: Albedo of the diffuse closed box, and the path length limits of the bounce series.
BOX_ALBEDO = 0.5
BOX_DEPTHS = [1, 2, 3, 4, 5, 6, 7]
#: BSDF of scenes/closed_box.xml against the study's dict (float32 evaluations).
BSDF_RTOL = 1e-5
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


@pytest.fixture(scope="module")
def box_series():
    """One sweep of scenes/closed_box.xml: a diffuse box (albedo BOX_ALBEDO) and a classic
    Phong box (m = 2) over max_depth 1..7, on a LocalCluster started for the call."""
    import spectrace

    spectrace.set_variant("llvm_ad_rgb")
    return study.bounce_series(["diffuse", "classic_phong"], BOX_DEPTHS, exponent=2.0,
                               res=16, spp=32, reflectance=BOX_ALBEDO)


def test_closed_box_bounces_multiply_by_the_albedo(box_series):
    """In a closed diffuse box each bounce adds the previous one's light times the albedo."""
    assert box_series.dims == ("bsdf", "max_depth")
    assert list(box_series.max_depth.values) == BOX_DEPTHS
    series = box_series.sel(bsdf="diffuse").values
    assert series[0] == 0.0  # a point light is invisible to the camera
    increments = np.diff(series)
    assert np.all(increments > 0)
    ratios = increments[2:] / increments[1:-1]
    assert np.mean(ratios) == pytest.approx(BOX_ALBEDO, abs=BOUNCE_RATIO_ATOL)


def test_closed_box_of_classic_phong_diverges(box_series):
    """Classic Phong at m = 2 reflects up to 2 pi / (m + 2) = 1.57: bounces grow, not fade."""
    increments = np.diff(box_series.sel(bsdf="classic_phong").values)
    ratios = increments[2:] / increments[1:-1]
    assert np.mean(ratios) > 1.0 + BOUNCE_RATIO_ATOL


def test_closed_box_bsdfs_are_the_energy_families(variant_rgb, rng):
    """scenes/closed_box.xml lines the box with each family's very BSDF: equal f(wi, wo)."""
    import drjit as dr
    import mitsuba as mi

    n = 64
    wi = rng.normal(size=(3, n))
    wo = rng.normal(size=(3, n))
    wi[2], wo[2] = np.abs(wi[2]) + 0.1, np.abs(wo[2]) + 0.1  # upper hemisphere
    wi, wo = (mi.Vector3f(w / np.linalg.norm(w, axis=0)) for w in (wi, wo))
    si = dr.zeros(mi.SurfaceInteraction3f)
    si.wi = wi
    si.n = si.sh_frame.n = mi.Vector3f(0, 0, 1)
    ctx = mi.BSDFContext()
    assert set(study.CLOSED_BOX_BSDFS) == set(study.ENERGY_FAMILIES)
    for m in (2.0, 32.0):
        for label, bsdf_id in study.CLOSED_BOX_BSDFS.items():
            expected = mi.load_dict(study.ENERGY_FAMILIES[label](m)).eval(ctx, si, wo)
            got = study.closed_box_bsdf(bsdf_id, exponent=m).eval(ctx, si, wo)
            np.testing.assert_allclose(np.asarray(got), np.asarray(expected),
                                       rtol=BSDF_RTOL, err_msg=f"{label}, m = {m}")


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
