"""Tests of spectrace.studies.light_falloff, the light falloff study.

Oracles: the distance, cone and fog laws at hand-computed points, and Mitsuba's built-in
`point` and `spot` lights over a Lambertian floor (exact radiometry).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from spectrace.studies import light_falloff as study

#: Floor irradiance: max |render - formula| relative to the peak at test size.
FLOOR_TOL = 0.02


def test_distance_laws_closed_form():
    """The distance laws of DESIGN.md at hand-computed points."""
    laws = study.DISTANCE_LAWS
    assert laws["inverse_square"](2.0) == pytest.approx(0.25)
    assert laws["inverse_square_epsilon"](1.5, epsilon=0.5) == pytest.approx(0.25)
    assert laws["polynomial"](2.0, kc=1, kl=0.5, kq=0.25) == pytest.approx(1 / 3)
    assert laws["windowed"](1.0, radius=2.0) == pytest.approx((1 - 1 / 16) ** 2)
    assert laws["windowed"](2.5, radius=2.0) == 0.0
    assert laws["windowed"](0.0, radius=2.0, epsilon=0.1) == pytest.approx(100.0)
    assert laws["none"](7.0) == 1.0


def test_cone_falloffs_closed_form():
    """Full inside the penumbra, zero outside the umbra, the ramps at their midpoints."""
    umbra, penumbra = 30.0, 20.0
    for law in study.CONE_FALLOFFS.values():
        assert law(np.radians(10.0), umbra, penumbra) == pytest.approx(1.0)
        assert law(np.radians(31.0), umbra, penumbra) == 0.0
    mid_cos = np.arccos(0.5 * (np.cos(np.radians(umbra)) + np.cos(np.radians(penumbra))))
    assert study.CONE_FALLOFFS["quadratic"](mid_cos, umbra, penumbra) == pytest.approx(0.25)
    assert study.CONE_FALLOFFS["smoothstep"](mid_cos, umbra, penumbra) == pytest.approx(0.5)
    assert study.CONE_FALLOFFS["linear_angle"](np.radians(25.0), umbra, penumbra) == \
        pytest.approx(0.5)


def test_fog_laws_closed_form():
    """OpenGL fog: linear is 1 at start and 0 at end; exponential laws at d = 1/density."""
    laws = study.FOG_LAWS
    assert laws["linear"](2.0, 2.0, 10.0) == 1.0
    assert laws["linear"](6.0, 2.0, 10.0) == pytest.approx(0.5)
    assert laws["linear"](12.0, 2.0, 10.0) == 0.0
    assert laws["exponential"](4.0, density=0.25) == pytest.approx(math.exp(-1))
    assert laws["exponential_squared"](4.0, density=0.25) == pytest.approx(math.exp(-1))
    assert laws["none"](100.0) == 1.0


def test_fog_fraction_recovers_the_blend():
    """f is recovered from L = f L_surface + (1 - f) L_fog; background pixels are NaN."""
    clear = np.zeros((2, 3, 3))
    clear[:, :2] = [[0.8, 0.5, 0.2]]
    fog = np.array([0.3, 0.3, 0.35])
    f = np.array([[0.9, 0.25, 0.0], [0.5, 0.0, 0.0]])
    fogged = f[..., None] * clear + (1 - f[..., None]) * fog
    depth = np.array([[1.0, 5.0, 0.0], [3.0, 20.0, 0.0]])
    fogged[:, 2] = fog  # background: the fog colour
    got = study.fog_fraction(fogged, clear, depth)
    np.testing.assert_allclose(got[:, :2], f[:, :2], atol=1e-12)
    assert np.all(np.isnan(got[:, 2]))


def test_floor_irradiance_of_mitsuba_point_light_is_the_cosine_inverse_square(variant_rgb):
    """Mitsuba's point light over a Lambertian floor: E = I cos(theta) / r^2 = I h / r^3."""
    profile = study.floor_irradiance({"type": "point", "intensity": 2.0}, height=1.0,
                                       half_width=3.0, res=48, spp=16)
    x = profile.x
    peak = 2.0  # I / h^2 at the foot point
    assert np.max(np.abs(profile.measured - profile.expected)) < FLOOR_TOL * peak
    far = np.abs(x) > 1.0  # where pixel averaging no longer matters: the plain formula
    plain = 2.0 * 1.0 / (x[far] ** 2 + 1.0) ** 1.5
    np.testing.assert_allclose(profile.expected[far], plain, rtol=0.02)


def test_floor_irradiance_of_mitsuba_spot_follows_its_linear_cone(variant_rgb):
    """Mitsuba's spot (linear in the angle) over the floor matches I cone(alpha) h / r^3."""
    profile = study.floor_irradiance(
        {"type": "spot", "intensity": 1.0, "cutoff_angle": 40.0, "beam_width": 25.0},
        height=2.0, half_width=2.5, res=48, spp=16)
    peak = 1.0 / 4.0
    assert np.max(np.abs(profile.measured - profile.expected)) < FLOOR_TOL * peak
    assert profile.measured[0] == 0.0 and profile.measured[-1] == 0.0  # beyond the cutoff
