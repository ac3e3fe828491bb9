"""Tests of the near-field study (``spectrace/studies/near_field.py``): the point
approximation's error against closed forms, the penumbra of a straight edge against
similar triangles, and the shadow-sample noise of ``local``."""

from __future__ import annotations

import numpy as np
import pytest

from spectrace.errors import ParameterError
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


def _lambert_polygon(vertices, point, normal):
    """E / L of a uniform polygon wholly above the receiver's horizon by Lambert's contour
    formula, (1/2) sum_i theta_i n . (v_i x v_i+1) / |v_i x v_i+1| (v the unit vectors
    to the vertices, theta_i the angle between consecutive ones)."""
    v = np.asarray(vertices, np.float64) - point
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    total = 0.0
    for a, b in zip(v, np.roll(v, -1, axis=0), strict=True):
        cross = np.cross(a, b)
        total += np.arccos(np.clip(a @ b, -1, 1)) * (cross @ normal) / np.linalg.norm(cross)
    return abs(total) / 2


def _box_lambert(dims, point, normal):
    """The visible faces of a box centred at the origin, each by :func:`_lambert_polygon`."""
    half = np.asarray(dims, np.float64) / 2
    total = 0.0
    for axis in range(3):
        for sign in (-1, 1):
            if sign * point[axis] <= half[axis]:
                continue
            i, j = [k for k in range(3) if k != axis]
            corners = []
            for si, sj in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                q = np.zeros(3)
                q[axis], q[i], q[j] = sign * half[axis], si * half[i], sj * half[j]
                corners.append(q)
            total += _lambert_polygon(corners, point, normal)
    return total


@pytest.mark.parametrize("dims, direction", [((1, 1, 1), (0, 0, -1)), ((1, 1, 1), (1, 1, -1)),
                                             ((2, 1, 1), (1, 0.5, -0.3))])
def test_box_irradiance_against_lambert_contour_formula(dims, direction):
    """The face quadrature of a luminous box (uniform L on its faces) equals Lambert's
    contour integral over its visible faces, near (2 D) and farther (6 D)."""
    w = np.asarray(direction, np.float64) / np.linalg.norm(direction)
    for x in (2.0, 6.0):
        p = x * max(dims) * w
        assert study.box_irradiance(dims, p, -w) == pytest.approx(
            _box_lambert(dims, p, -w), rel=1e-4)


def test_box_point_error_limits_and_one_percent_distances():
    """Far away the box is its point (error -> 0); along a face's normal the face is D / 2
    nearer than the photometric centre, so the error tends to -D / d (first order) and
    1 % needs about 100 D, twenty times the five-times rule; along the diagonal the first
    order cancels and a cube reaches 1 % near 7 D."""
    assert abs(study.point_error_box(1e4, (2, 1, 1), (1, 1, -1))[0]) < 1e-6
    assert study.point_error_box(200.0, (2, 1, 1), (1, 0, 0))[0] == pytest.approx(
        -1 / 200, rel=0.01)
    assert study.point_error_box(5.0, (1, 1, 1))[0] == pytest.approx(-0.177, abs=1e-3)
    assert study.under_one_percent("box", dims=(1, 1, 1), direction=(0, 0, -1)) == \
        pytest.approx(99.4, abs=0.5)
    assert 5.0 < study.under_one_percent("box", dims=(1, 1, 1), direction=(1, 1, -1)) < 8.0
    np.testing.assert_allclose(study.box_projected_area((2, 1, 1), (0, 0, 1)), 2.0)
    with pytest.raises(ParameterError, match="distance_over_size"):
        study.point_error_box(0.7, (1, 1, 1), (1, 1, -1))  # inside the cube
