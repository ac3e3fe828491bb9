"""The closed-form references of the validation cases, each against an independent
computation (another closed form or a numerical integral in numpy), so that an error in a
reference cannot pass for an error of the renderer."""

from __future__ import annotations

import numpy as np
import pytest

from spectrace.validation import cases as C
from spectrace.validation import reference as ref

#: Relative agreement of a closed form with a dense numerical integral of the same quantity.
QUADRATURE_RTOL = 1e-4
RNG_SEED = 171


def _quadrature_factor(p, n, integrand_points, area_weights):
    """F = integral cos_p cos_s / (pi r^2) dA over a source facing -y (numpy)."""
    r = integrand_points - p
    d2 = np.sum(r * r, axis=-1)
    cos_p = np.clip(r @ n, 0.0, None) / np.sqrt(d2)
    cos_s = np.clip(r[:, 1], 0.0, None) / np.sqrt(d2)  # the source faces down (-y)
    return np.sum(area_weights * cos_p * cos_s / (np.pi * d2))


def _rectangle_nodes(x0, x1, z0, z1, y, n=200):
    x, z, w = ref.gauss_legendre_grid(x0, x1, z0, z1, n)
    return np.stack([x, np.full_like(x, y), z], axis=-1), w


def test_polygon_factor_matches_howell_corner_formula():
    """Lambert's contour formula and Howell's B-3 (element under a corner of a parallel
    rectangle) are two closed forms of one configuration factor."""
    a, b, c = 2.0, 1.0, 1.5
    vertices = np.array([[0, c, 0], [a, c, 0], [a, c, b], [0, c, b]], float)
    F = ref.polygon_irradiance_factor([[0, 0, 0]], [[0, 1, 0]], vertices)[0]
    assert F == pytest.approx(ref.rectangle_corner_factor(a, b, c), rel=1e-12)


@pytest.mark.parametrize("normal", [(0, 1, 0), (-1, 0, 0), (0.3, 0.8, -0.52)])
def test_polygon_factor_matches_numerical_integral(normal):
    """The contour formula, horizon clipping included (the perpendicular and tilted normals
    see part of the rectangle below their horizon), against a dense Gauss-Legendre
    integral of cos cos / (pi r^2) over the rectangle."""
    normal = np.asarray(normal, float) / np.linalg.norm(normal)
    p = np.array([0.7, 0.4, 0.2])
    nodes, w = _rectangle_nodes(-1.0, 1.0, -0.5, 0.5, 2.0)
    expected = _quadrature_factor(p, normal, nodes, w)
    vertices = C._rectangle_vertices()
    F = ref.polygon_irradiance_factor([p], [normal], vertices)[0]
    assert F == pytest.approx(expected, rel=QUADRATURE_RTOL)


def test_disk_factor_matches_numerical_integral():
    """Howell's B-13 (parallel disk, off axis) against a polar quadrature over the disk."""
    R, h = C.DISK_RADIUS, C.DISK_HEIGHT
    t, wt = np.polynomial.legendre.leggauss(400)
    r = 0.5 * R * (t + 1.0)
    phi = np.pi * (t + 1.0)
    Rr, Pp = np.meshgrid(r, phi, indexing="ij")
    W = np.outer(wt * 0.5 * R, wt * np.pi) * Rr
    nodes = np.stack([Rr * np.cos(Pp), np.full_like(Rr, h), Rr * np.sin(Pp)], -1).reshape(-1, 3)
    for offset in (0.0, 0.3, 1.2):
        expected = _quadrature_factor(np.array([offset, 0.0, 0.0]), np.array([0, 1.0, 0]),
                                      nodes, W.ravel())
        assert ref.disk_parallel_factor(R, h, offset) == pytest.approx(expected,
                                                                       rel=QUADRATURE_RTOL)


def test_pane_transmittance_sums_the_internal_reflections():
    """(1 - R) / (1 + R) per polarization is the sum of the series (1 - R)^2 sum R^2k of
    the light that crosses both faces after 2k internal reflections; at normal incidence
    the pane transmits 2n / (n^2 + 1)."""
    angles = np.array([0.0, 35.0, 70.0, 85.0])
    Rs, Rp = ref.fresnel_reflectance(np.cos(np.radians(angles)), 1.5)
    k = np.arange(200)[:, None]
    series = 0.5 * sum(((1 - R) ** 2 * R ** (2 * k)).sum(axis=0) for R in (Rs, Rp))
    assert ref.thin_pane_transmittance(angles, 1.5) == pytest.approx(series, rel=1e-12)
    assert ref.thin_pane_transmittance(0.0, 1.5) == pytest.approx(2 * 1.5 / (1.5**2 + 1))


def test_sphere_indirect_illuminance_is_the_series_of_reflections():
    """Goebel's Phi rho / (S (1 - rho)): each reflection spreads rho times the flux it
    receives uniformly over the wall (the sphere's exchange factor is 1)."""
    flux, radius, rho = 1000.0, 1.0, 0.5
    S = 4 * np.pi * radius**2
    series = sum(flux * rho**k / S for k in range(1, 200))
    assert ref.sphere_indirect_illuminance(flux, radius, rho) == pytest.approx(series)


def test_asymmetric_distribution_has_the_stated_flux():
    """800 pi lm: the distribution of asymmetric.ies integrated over the sphere
    numerically."""
    t, w = np.polynomial.legendre.leggauss(200)
    gamma = 0.25 * np.pi * (t + 1.0)  # each hemisphere on its own: the kink at 90 degrees
    c = np.pi * (t + 1.0)
    flux = 0.0
    for g in (gamma, gamma + 0.5 * np.pi):
        G, Cc = np.meshgrid(g, c, indexing="ij")
        I = C.asymmetric_intensity(np.degrees(G), np.degrees(Cc))
        flux += np.sum(np.outer(w * 0.25 * np.pi, w * np.pi) * I * np.sin(G))
    assert flux == pytest.approx(C.ASYMMETRIC_FLUX, rel=1e-6)


def test_room_quadrature_integrates_the_flux():
    """The walls' Gauss-Legendre nodes of flux_closed_room integrate the reference
    illuminance of the luminaire to its flux within the flux family's quadrature claim
    (0.05 %)."""
    points, normals, weights = C.room_quadrature(24)
    E = ref.point_illuminance(points, normals, C.ROOM_LIGHT, C._ies_direction_intensity)
    assert np.sum(weights * E) == pytest.approx(C.ASYMMETRIC_FLUX, rel=5e-4)
    assert np.sum(weights) == pytest.approx(2 * (4 * 3 + 4 * 5 + 3 * 5))


def test_obstructed_reflection_matches_a_visibility_integral():
    """The configuration-factor algebra of the obstructed reflector against a direct
    numerical integral over the reflector with explicit tests of what the obstruction
    hides from the light and from the point."""
    rng = np.random.default_rng(RNG_SEED)
    nodes, w = _rectangle_nodes(-1.0, 1.0, -1.0, 1.0, 0.0, n=600)
    h_o, half = C.OBSTRUCTION_HEIGHT, C.OBSTRUCTION_HALF
    lit = ~((np.abs(nodes[:, 0]) < half * C.LIGHT_HEIGHT / (C.LIGHT_HEIGHT - h_o))
            & (np.abs(nodes[:, 2]) < half * C.LIGHT_HEIGHT / (C.LIGHT_HEIGHT - h_o)))
    E1 = C.LIGHT_INTENSITY / C.LIGHT_HEIGHT**2
    for p in rng.uniform([-1.5, C.PLANE_HEIGHT, -1.5], [1.5, C.PLANE_HEIGHT, 1.5], (4, 3)):
        s = (h_o - 0.0) / (p[1] - 0.0)  # where the segment node -> p crosses y = h_o
        cross = nodes + s * (p - nodes)
        seen = ~((np.abs(cross[:, 0]) < half) & (np.abs(cross[:, 2]) < half))
        r = p - nodes
        d2 = np.sum(r * r, axis=-1)
        integrand = C.RHO * E1 / np.pi * (r[:, 1] ** 2) / d2**2 * (lit & seen)
        expected = np.sum(w * integrand)
        got = C.reflected_illuminance(p[None, :], obstructed=True)[0]
        assert got == pytest.approx(expected, rel=2e-3)  # the mask's edges at 600 nodes


def test_committed_ies_file_is_the_generated_one(tmp_path):
    """scenes/validation/asymmetric.ies is what write_asymmetric_ies writes."""
    written = C.write_asymmetric_ies(tmp_path / "asymmetric.ies")
    assert written.read_bytes() == (C.folder() / "asymmetric.ies").read_bytes()
