"""Closed-form reference values of the validation cases (radiative transfer, no renderer).

Every function is numpy only, vectorized over points (leading axes), SI units (m, cd,
cd/m^2, lux). The tests check each against an independent numerical integral
(``tests/validation/test_reference.py``), so that a wrong reference cannot hide a wrong
renderer.

Sources
-------
* Point source, inverse-square cosine law: CIE S 017:2020 *ILV* 17-21-060; Moon (1936),
  *The Scientific Basis of Illuminating Engineering*, ch. 9.
* Irradiance from a Lambertian polygon (the contour integral of Lambert 1760, as written by
  Hottel and Sarofim 1967 and Baum, Rushmeier and Winget 1989): for a differential area at
  ``p`` with normal ``n`` and a uniform Lambertian polygon of luminance ``L`` wholly above
  its horizon, E = (L / 2) sum_i gamma_i n . (R_i x R_i+1) / |R_i x R_i+1|, with R_i the
  vectors from p to the vertices and gamma_i the angle between R_i and R_i+1. Parts of the
  polygon below the horizon are clipped away first (they send nothing).
* Configuration factors (Howell, *A Catalog of Radiation Heat Transfer Configuration
  Factors*, 3rd ed., 2010): B-3 (differential element to a parallel rectangle, normal
  through a corner) and B-13 (differential element to a parallel disk, off axis).
* Integrating sphere: Goebel (1967), "Generalized integrating-sphere theory", Applied
  Optics 6(1): E_indirect = Phi rho / (S (1 - rho)) at every point of the wall.
* Skies: the traditional CIE overcast sky of Moon and Spencer (1942), L(h) = L_z (1 + 2 sin
  h) / 3 with h the elevation (CIE S 011/E:2003, ISO 15469:2004), and the uniform sky
  L = L_z; the sky component through an opening is the integral of L(h) cos(theta_p)
  cos(theta_s) / r^2 over the opening's area (Hopkinson, Petherbridge and Longmore 1966,
  *Daylighting*, ch. 4), here by Gauss-Legendre quadrature.
* Thin pane: Fresnel's equations for the s and p polarizations, with the incoherent sum of
  the internal reflections of a non-absorbing plane-parallel slab, T = (1 - R) / (1 + R)
  for each polarization (Born and Wolf, *Principles of Optics*, 7th ed., sec. 1.5 and
  7.6; CIE 171:2006 sec. 5.5 uses this transmittance for clear glass), averaged over the
  two polarizations for unpolarized light.
"""

from __future__ import annotations

import numpy as np


def point_illuminance(points, normals, source, intensity):
    """E = I cos(theta) / d^2 (lux) at ``points`` (..., 3) with unit ``normals`` from a
    point source at ``source`` (3,); ``intensity`` is a number (cd) or a function of the
    unit direction from the source towards each point, (..., 3) -> (...) cd. Points facing
    away from the source get 0."""
    points, normals = np.asarray(points, float), np.asarray(normals, float)
    to_source = np.asarray(source, float) - points
    d2 = np.sum(to_source**2, axis=-1)
    d = np.sqrt(d2)
    cos = np.sum(normals * to_source, axis=-1) / d
    I = intensity(-to_source / d[..., None]) if callable(intensity) else intensity
    return np.where(cos > 0.0, I * cos / d2, 0.0)


def _clip_polygon(vertices, p, n):
    """The part of the polygon ``vertices`` (k, 3) above the plane through ``p`` with normal
    ``n`` (Sutherland-Hodgman against one plane)."""
    out = []
    k = len(vertices)
    side = (vertices - p) @ n
    for i in range(k):
        a, b = vertices[i], vertices[(i + 1) % k]
        sa, sb = side[i], side[(i + 1) % k]
        if sa > 0.0:
            out.append(a)
        if (sa > 0.0) != (sb > 0.0) and sa != sb:
            out.append(a + (b - a) * (sa / (sa - sb)))
    return np.array(out)


def polygon_irradiance_factor(points, normals, vertices):
    """The configuration factor F from differential areas at ``points`` (N, 3) with unit
    ``normals`` (N, 3) to the planar polygon ``vertices`` (k, 3), the part below each
    point's horizon clipped away (Lambert's contour formula, see the module docstring).
    The irradiance from a uniform Lambertian polygon of luminance L is pi L F."""
    points = np.atleast_2d(np.asarray(points, float))
    normals = np.atleast_2d(np.asarray(normals, float))
    vertices = np.asarray(vertices, float)
    factor = np.zeros(len(points))
    for j, (p, n) in enumerate(zip(points, normals, strict=True)):
        poly = _clip_polygon(vertices, p, n)
        if len(poly) < 3:
            continue
        R = poly - p
        total = 0.0
        for i in range(len(R)):
            a, b = R[i], R[(i + 1) % len(R)]
            c = np.cross(a, b)
            norm = np.linalg.norm(c)
            if norm == 0.0:
                continue
            gamma = np.arctan2(norm, a @ b)
            total += gamma * (n @ c) / norm
        factor[j] = abs(total) / (2.0 * np.pi)
    return factor


def rectangle_corner_factor(a, b, c):
    """Howell B-3: differential element to a parallel rectangle a x b at distance c, the
    element's normal through one corner of the rectangle."""
    A, B = np.asarray(a, float) / c, np.asarray(b, float) / c
    sa, sb = np.sqrt(1.0 + A**2), np.sqrt(1.0 + B**2)
    return (A / sa * np.arctan(B / sa) + B / sb * np.arctan(A / sb)) / (2.0 * np.pi)


def disk_parallel_factor(radius, height, offset):
    """Howell B-13: differential element to a parallel disk of ``radius`` at ``height``,
    the element ``offset`` from the disk's axis (0 on the axis: r^2 / (r^2 + h^2))."""
    r2, h2, a2 = radius**2, np.asarray(height, float) ** 2, np.asarray(offset, float) ** 2
    return 0.5 * (1.0 - (h2 + a2 - r2) / np.sqrt((h2 + a2 + r2) ** 2 - 4.0 * a2 * r2))


def fresnel_reflectance(cos_i, eta):
    """Fresnel reflectances (R_s, R_p) of a smooth interface from a medium of index 1 to
    one of index ``eta`` at incidence cosines ``cos_i``."""
    cos_i = np.asarray(cos_i, float)
    sin_t2 = (1.0 - cos_i**2) / eta**2
    cos_t = np.sqrt(np.maximum(0.0, 1.0 - sin_t2))
    rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    return rs**2, rp**2


def thin_pane_transmittance(theta_deg, eta=1.5):
    """Directional transmittance of a clear, non-absorbing plane-parallel pane of index
    ``eta`` in air for unpolarized light at incidence angles ``theta_deg`` (degrees), the
    internal reflections summed incoherently for each polarization: T = (1 - R) / (1 + R)."""
    Rs, Rp = fresnel_reflectance(np.cos(np.radians(theta_deg)), eta)
    return 0.5 * ((1.0 - Rs) / (1.0 + Rs) + (1.0 - Rp) / (1.0 + Rp))


def sphere_indirect_illuminance(flux, radius, reflectance):
    """Goebel (1967): the illuminance that light reflected any number of times adds at
    every point of the inner wall of a sphere of ``radius`` with a uniform Lambertian
    ``reflectance`` lit by ``flux`` (lm) from inside: Phi rho / (S (1 - rho))."""
    S = 4.0 * np.pi * radius**2
    return flux * reflectance / (S * (1.0 - reflectance))


def gauss_legendre_grid(x0, x1, y0, y1, n):
    """Gauss-Legendre nodes (n x n) and weights on the rectangle [x0, x1] x [y0, y1]:
    sum(w * f(x, y)) integrates polynomials of degree 2n - 1 in each axis exactly."""
    t, w = np.polynomial.legendre.leggauss(n)
    x = 0.5 * (x1 - x0) * t + 0.5 * (x1 + x0)
    y = 0.5 * (y1 - y0) * t + 0.5 * (y1 + y0)
    X, Y = np.meshgrid(x, y, indexing="ij")
    W = np.outer(w, w) * 0.25 * (x1 - x0) * (y1 - y0)
    return X.ravel(), Y.ravel(), W.ravel()


def cie_overcast_luminance(sin_elevation, zenith_luminance):
    """L = L_z (1 + 2 sin h) / 3 (Moon and Spencer 1942; CIE S 011 / ISO 15469 overcast)."""
    return zenith_luminance * (1.0 + 2.0 * np.asarray(sin_elevation, float)) / 3.0


def sky_opening_illuminance(points, normals, corner, edge_a, edge_b, luminance, n=64,
                            masks=()):
    """The illuminance (lux) at ``points`` (N, 3) with unit ``normals`` (N, 3) from a sky of
    luminance ``luminance(sin_elevation)`` (cd/m^2, +y up) seen through the planar
    parallelogram opening ``corner + s edge_a + t edge_b`` (s, t in [0, 1]):
    E = integral L(h) cos(theta_p) cos(theta_s) / r^2 dA, with n x n Gauss-Legendre nodes.
    Directions below a point's horizon or the sky's (h < 0) send nothing, nor those that
    meet one of the opaque ``masks``, parallelograms (corner, edge_a, edge_b) outside the
    opening (overhangs, fins)."""
    points = np.atleast_2d(np.asarray(points, float))
    normals = np.atleast_2d(np.asarray(normals, float))
    corner, edge_a, edge_b = (np.asarray(v, float) for v in (corner, edge_a, edge_b))
    s, t, w = gauss_legendre_grid(0.0, 1.0, 0.0, 1.0, n)
    nodes = corner + s[:, None] * edge_a + t[:, None] * edge_b
    normal_s = np.cross(edge_a, edge_b)
    area = np.linalg.norm(normal_s)
    normal_s /= area
    out = np.zeros(len(points))
    for j, (p, normal) in enumerate(zip(points, normals, strict=True)):
        r = nodes - p
        d = np.sqrt(np.sum(r * r, axis=-1))
        u = r / d[:, None]
        cos_p = np.clip(u @ normal, 0.0, None)
        cos_s = np.abs(u @ normal_s)
        sin_h = u[:, 1]
        L = np.where(sin_h > 0.0, luminance(sin_h), 0.0)
        for mask in masks:
            L = np.where(_meets(p, u, *mask), 0.0, L)
        out[j] = np.sum(w * area * L * cos_p * cos_s / d**2)
    return out


def _meets(origin, directions, corner, edge_a, edge_b):
    """Whether rays from ``origin`` along unit ``directions`` (M, 3) meet the parallelogram
    corner + s edge_a + t edge_b (s, t in [0, 1]) in front of the origin."""
    corner, edge_a, edge_b = (np.asarray(v, float) for v in (corner, edge_a, edge_b))
    normal = np.cross(edge_a, edge_b)
    denom = directions @ normal
    with np.errstate(divide="ignore", invalid="ignore"):
        t = ((corner - origin) @ normal) / denom
    hit = origin + t[:, None] * directions - corner
    # coordinates in the (edge_a, edge_b) basis through the dual basis
    gram = np.array([[edge_a @ edge_a, edge_a @ edge_b], [edge_a @ edge_b, edge_b @ edge_b]])
    st = np.linalg.solve(gram, np.stack([hit @ edge_a, hit @ edge_b]))
    inside = (st[0] >= 0) & (st[0] <= 1) & (st[1] >= 0) & (st[1] <= 1)
    return np.isfinite(t) & (t > 0) & inside
