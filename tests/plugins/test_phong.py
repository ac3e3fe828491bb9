"""Tests of the ``phong`` BSDF (plugins/bsdfs/phong.py) against closed-form formulas,
Mitsuba's ``diffuse`` and Mitsuba's chi-square test."""

from __future__ import annotations

import bsdf_checks as checks
import numpy as np
import pytest

PLUGIN = "phong"
#: Tolerance of the quadrature albedo against the closed form (grid 400 x 200).
RTOL_QUADRATURE = 2e-3
#: Largest coefficient of variation accepted for the sample weights of a sharp lobe, per
#: incident angle: the weight is (m+2)/(m+1) cos(theta_o), which varies across the lobe
#: more and more as the lobe tilts (about 0.16 at 60 degrees for m = 120).
MAX_WEIGHT_CV = {0.0: 0.02, 30.0: 0.1}
#: Relative tolerance between prb's gradient and the central difference.
RTOL_GRADIENT = 1e-4


def lobe(wi, wo, m):
    """Phong's lobe (r . wo)^m, r the mirror image of wi about the normal (+Z)."""
    r = wi * np.array([-1.0, -1.0, 1.0])
    return np.maximum(np.sum(r * wo, axis=1), 0.0) ** m


def normalization(m):
    """(m + 2) / (2 pi): the lobe's albedo at normal incidence is 2 pi / (m + 2)."""
    return (m + 2.0) / (2.0 * np.pi)


def test_eval_matches_formula(any_variant, rng):
    """eval = (rho/pi + rho_s k (r.wo)^m) cos(theta_o) at random directions, classic and
    normalized."""
    checks.check_eval_matches_formula(PLUGIN, lobe, normalization, rng)


def test_rgb_reflectances(variant_rgb, rng):
    """Coloured reflectances act channel by channel."""
    checks.check_rgb_reflectances(PLUGIN, lobe, normalization, rng)


def test_diffuse_part_is_mitsuba_diffuse(any_variant, rng):
    """With rho_s = 0, phong is Mitsuba's Lambertian `diffuse` (eval, pdf, weights, reflectance)."""
    checks.check_diffuse_part_matches_mitsuba(PLUGIN, rng)


def test_textured_reflectance(variant, rng):
    """Reflectances given as textures are evaluated at the hit's uv."""
    checks.check_textured_reflectance(PLUGIN, lobe, normalization, rng)


def test_reciprocity(variant_rgb, rng):
    """Helmholtz reciprocity f(wi, wo) = f(wo, wi)."""
    checks.check_reciprocity(PLUGIN, rng)


def test_zero_below_horizon(variant, rng):
    """Front side only: nothing is reflected to or from below the surface."""
    checks.check_below_horizon(PLUGIN, rng)


@pytest.mark.parametrize(
    "m, normalized, theta, reflectances",
    [
        (1.0, False, 0.0, (0.5, 0.2)),
        (4.0, True, 45.0, (0.3, 0.6)),
        (20.0, False, 70.0, (0.5, 0.2)),
        (60.0, True, 30.0, (0.0, 1.0)),
        (50.0, True, 80.0, (0.0, 1.0)),
        (300.0, True, 80.0, (0.2, 0.8)),
        (300.0, False, 45.0, (0.0, 0.5)),
    ],
)
def test_chi2_sampling_matches_pdf(variant, m, normalized, theta, reflectances):
    """pdf() is the density of sample(): Pearson's chi-square test (mitsuba.chi2) does not
    reject it, for several exponents, incident angles and mixtures, RGB and spectral."""
    rho, rho_s = reflectances
    params = {"type": PLUGIN, "exponent": m, "normalized": normalized,
              "diffuse_reflectance": rho, "specular_reflectance": rho_s}
    test = checks.chi2_test(params, theta)
    assert test.passed, test.messages


def test_weight_is_eval_over_pdf(variant):
    """sample() returns weight = eval / pdf and the pdf of the sampled direction."""
    checks.check_weight_is_eval_over_pdf(PLUGIN)


@pytest.mark.parametrize("theta", sorted(MAX_WEIGHT_CV))
def test_sharp_lobe_weights_nearly_constant(variant_rgb, theta):
    """Sampling the lobe itself makes the weights of a sharp normalized lobe (m = 120,
    rho = 0) nearly constant: weight = (m+2)/(m+1) cos(theta_o), whose mean is the albedo
    (1 at normal incidence) and whose coefficient of variation is small (printed with -s)."""
    cv, w = checks.weight_cv(PLUGIN, theta)
    print(f"{PLUGIN} m=120 theta={theta}: weight mean {w.mean():.4f}, CV {cv:.4f}")
    assert cv < MAX_WEIGHT_CV[theta]


@pytest.mark.parametrize("m", [2.0, 10.0, 100.0])
def test_albedo_at_normal_incidence_by_quadrature(variant_rgb, m):
    """Integrating eval over the hemisphere at normal incidence gives rho_s 2 pi/(m+2)
    for the classic lobe and rho_s for the normalized one."""
    for normalized, expected in ((False, 2 * np.pi / (m + 2)), (True, 1.0)):
        bsdf = checks.load(PLUGIN, exponent=m, normalized=normalized,
                           diffuse_reflectance=0.0, specular_reflectance=1.0)
        albedo = checks.albedo_quadrature(bsdf, 0.0)
        np.testing.assert_allclose(albedo, expected, rtol=RTOL_QUADRATURE)


def test_components(variant_rgb, rng):
    """Component selection through BSDFContext and the flags of both components."""
    checks.check_components(PLUGIN, lobe, normalization, rng)


def test_traverse_updates(variant, rng):
    """Reflectances and exponent are exposed by traverse (differentiable) and take effect."""
    checks.check_traverse(PLUGIN, lobe, normalization, rng)


def test_exponent_gradient(variant_rgb, rng):
    """The exponent is differentiable: d eval/d m matches the closed form's derivative."""
    checks.check_exponent_gradient(PLUGIN, lobe, normalization, rng)


@pytest.mark.parametrize("key", ["diffuse_reflectance", "specular_reflectance"])
def test_prb_gradient_matches_finite_differences(variant, key):
    """The gradient of a rendered image (prb) w.r.t. a reflectance is non-zero and equals
    the central finite difference (the image is linear in it under a point light; both
    use the same samples)."""
    grad, fd = checks.prb_gradient_and_fd(PLUGIN, f"ball.bsdf.{key}.value", 0.4, 0.1)
    assert abs(grad) > 1e-4
    assert grad == pytest.approx(fd, rel=RTOL_GRADIENT)


@pytest.mark.parametrize("params, name", checks.BAD_PARAMETERS)
def test_bad_parameters_fail_at_load(variant_rgb, params, name):
    """Invalid parameters fail at load with a message naming the parameter."""
    checks.check_bad_parameter(PLUGIN, params, name)
