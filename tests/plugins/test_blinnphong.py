"""Tests of the ``blinnphong`` BSDF (plugins/bsdfs/blinnphong.py) against closed-form formulas,
Mitsuba's ``diffuse`` and Mitsuba's chi-square test."""

from __future__ import annotations

import bsdf_checks as checks
import numpy as np
import pytest
from scipy.integrate import quad

PLUGIN = "blinnphong"
#: Tolerance of the quadrature albedo against the closed form (grid 400 x 200).
RTOL_QUADRATURE = 2e-3
#: Largest coefficient of variation accepted for the sample weights of a sharp lobe, per
#: incident angle: the weight is 8 pi k/(m+1) (wo.h) cos(theta_o), which varies across
#: the lobe more and more as it tilts. At normal incidence theta_o = 2 theta_h and the
#: weight is about 1 - 2.5 theta_h^2 with theta_h^2 roughly exponential of mean 2/m,
#: so CV ~ 5/m (0.042 for m = 120); 0.16 measured at 30 degrees.
MAX_WEIGHT_CV = {0.0: 0.06, 30.0: 0.25}
#: Relative tolerance between prb's gradient and the central difference.
RTOL_GRADIENT = 1e-4


def lobe(wi, wo, m):
    """Blinn's lobe (n . h)^m, h the normalized half vector of wi and wo, n = +Z."""
    h = wi + wo
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    return np.maximum(h[:, 2], 0.0) ** m


def normalization(m):
    """(m+2)(m+4) / (8 pi (2^(-m/2) + m)), the inverse of the lobe's albedo at normal incidence."""
    return (m + 2.0) * (m + 4.0) / (8.0 * np.pi * (2.0 ** (-m / 2) + m))


def albedo_at_normal_incidence(m):
    """Integral of cos^m(theta_o / 2) cos(theta_o) over the hemisphere, by scipy's quad."""
    value, _ = quad(lambda t: np.cos(t / 2) ** m * np.cos(t) * np.sin(t), 0.0, np.pi / 2)
    return 2 * np.pi * value


def test_eval_matches_formula(any_variant, rng):
    """eval = (rho/pi + rho_s k (n.h)^m) cos(theta_o) at random directions, classic and
    normalized."""
    checks.check_eval_matches_formula(PLUGIN, lobe, normalization, rng)


def test_rgb_reflectances(variant_rgb, rng):
    """Coloured reflectances act channel by channel."""
    checks.check_rgb_reflectances(PLUGIN, lobe, normalization, rng)


def test_diffuse_part_is_mitsuba_diffuse(any_variant, rng):
    """With rho_s = 0, blinnphong is Mitsuba's Lambertian `diffuse` (eval, pdf, weights,
    reflectance)."""
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
    """Sampling half vectors from the lobe makes the weights of a sharp normalized lobe
    (m = 120, rho = 0) nearly constant: weight = 8 pi k/(m+1) (wo.h) cos(theta_o), whose
    mean is the albedo (1 at normal incidence) and whose coefficient of variation is
    small (printed with -s)."""
    cv, w = checks.weight_cv(PLUGIN, theta)
    print(f"{PLUGIN} m=120 theta={theta}: weight mean {w.mean():.4f}, CV {cv:.4f}")
    assert cv < MAX_WEIGHT_CV[theta]


@pytest.mark.parametrize("m", [0.5, 2.0, 8.8, 100.0])
def test_normalization_is_exact(m):
    """The closed-form normalization is the inverse of the lobe's albedo at normal
    incidence (scipy quadrature), and the popular (m+8)/(8 pi) overshoots it (m > 4)."""
    albedo = albedo_at_normal_incidence(m)
    assert normalization(m) * albedo == pytest.approx(1.0, rel=1e-10)
    if m > 4:
        assert (m + 8) / (8 * np.pi) * albedo > 1.0


def test_classic_lobe_gains_energy_below_m_18_7():
    """The classic lobe (rho_s = 1) reflects more than it receives at normal incidence
    for m below about 18.7 (the docstring's figure) and less above."""
    assert albedo_at_normal_incidence(18.6) > 1.0 > albedo_at_normal_incidence(18.8)


@pytest.mark.parametrize("m", [2.0, 10.0, 100.0])
def test_albedo_at_normal_incidence_by_quadrature(variant_rgb, m):
    """Integrating eval over the hemisphere at normal incidence gives the closed-form
    albedo rho_s 8 pi (2^(-m/2) + m)/((m+2)(m+4)) for the classic lobe, rho_s normalized."""
    for normalized, expected in ((False, albedo_at_normal_incidence(m)), (True, 1.0)):
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
