"""Tests of the near-field study (``spectrace/studies/near_field.py``): the point
approximation's error against closed forms, the penumbra of a straight edge against
similar triangles, and the shadow-sample noise of ``local``."""

from __future__ import annotations

import numpy as np
import pytest

from spectrace.studies import near_field as study

#: Measured (2^14 light samples) against closed-form ratios E_point / E.
RTOL_RATIO = 1e-2
#: Edge profiles: shadow and light fractions outside the penumbra, allowed noise.
FRACTION_TOL = 0.03


def test_lambertian_disk_reaches_one_percent_at_five_diameters():
    """(r / h)^2 = 1 % at h = 10 r = 5 D: the photometric five-times rule is exact for a
    Lambertian disk on its axis; the sphere has no near-field error."""
    assert study.under_one_percent("lambertian_disk") == pytest.approx(5.0, rel=1e-6)
    assert study.point_error_closed_form("lambertian_disk", 1.0) == pytest.approx(0.25)
    assert study.under_one_percent("spot_disk") > 5.0
    np.testing.assert_array_equal(study.point_error_closed_form("sphere", [1, 2]), 0.0)


def test_measured_error_matches_the_closed_form(variant_rgb):
    """The lights' next-event samples give the closed-form near-field errors: the spot
    disk's and the sphere's (zero)."""
    x = np.array([0.75, 2.0, 5.0])
    np.testing.assert_allclose(1 + study.point_error_measured("spot_disk", x, samples=2**14),
                               1 + study.point_error_closed_form("spot_disk", x),
                               rtol=RTOL_RATIO)
    np.testing.assert_allclose(1 + study.point_error_measured("sphere", x, samples=2**14), 1.0,
                               rtol=RTOL_RATIO)


@pytest.mark.parametrize("radius", [0.0, 0.2])
def test_edge_profile_follows_similar_triangles(variant_rgb, radius):
    """Dark before the umbra's end, fully lit (E = I h / d^3) after the penumbra's, by
    similar triangles 2 r h_e / (h_l - h_e) wide; a step for a point."""
    profile = study.edge_profile(radius, res=32, spp=32)
    f, half = profile.fraction(), study.penumbra_width(radius) / 2
    pixel = profile.x[1] - profile.x[0]
    assert np.all(f[profile.x < -half - pixel] < FRACTION_TOL)
    np.testing.assert_allclose(f[profile.x > half + pixel], 1.0, atol=FRACTION_TOL)
    inside = np.abs(profile.x) < half - pixel
    assert radius == 0 or np.all(np.diff(f[inside]) > -FRACTION_TOL)


def test_shadow_noise_falls_as_one_over_sqrt_n(variant_rgb):
    """The RMS error of a penumbra in ``local`` falls as 1 / sqrt(shadow_samples)."""
    noise = study.shadow_noise(counts=(1, 16), res=24)
    assert noise[16] / noise[1] == pytest.approx(0.25, rel=0.3)


def test_rectangle_corner_factor_against_quadrature():
    """Howell's corner factor equals the integral of cos^2 / (pi t^2) over the rectangle
    (midpoint rule), and the point error under a square at five sides is 1.3 %, under a
    long linear luminaire (aspect 10) 0.7 %."""
    X, Y, n = 0.7, 1.9, 800
    x = (np.arange(n) + 0.5) / n * X
    y = (np.arange(n) + 0.5) / n * Y
    xx, yy = np.meshgrid(x, y)
    quadrature = np.sum(1.0 / (np.pi * (1 + xx**2 + yy**2) ** 2)) * (X / n) * (Y / n)
    assert study.rectangle_corner_factor(X, Y) == pytest.approx(quadrature, rel=1e-5)
    assert study.point_error_rectangle(5.0, 1.0) == pytest.approx(0.0133, abs=1e-4)
    assert study.point_error_rectangle(5.0, 10.0) == pytest.approx(0.0067, abs=1e-4)
    assert study.under_one_percent("lambertian_rectangle", aspect=10.0) < 5.0
