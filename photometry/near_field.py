"""The near-field error of the point law for a luminaire's luminous opening.

A luminaire whose opening (``Photometry.opening``) emits from each of its points the
luminance L(x, omega) = I(omega) / A_proj(omega) (as ``ieslight``'s ``opening`` renders it:
A_proj the area the opening shows along omega; flat openings show both faces) has the file's
intensity far away, but near it the illuminance differs from the point law I / d^2.
:func:`axial_near_field_error` measures that difference on the photometric axis (gamma = 0)
by a midpoint quadrature over the opening's surface::

    E_opening = sum over surface elements dA of L(x, w) cos(theta_x) cos(theta_r) dA / t^2
    error = E_opening / E_point - 1,        E_point = I(gamma = 0) / d^2

at the distance d from the photometric centre, the receiving plane facing the luminaire.
"""

from __future__ import annotations

import numpy as np

#: Midpoint nodes per axis of the surface quadrature (its error is far under 0.1% at the
#: photometric distance).
NODES = 96
#: Openings whose surface the quadrature knows (those ``ieslight`` renders).
SHAPES = ("rectangle", "disk", "sphere", "box")


def _grid(n: int):
    return (np.arange(n) + 0.5) / n


def _face(axis: int, offset: float, half_a: float, half_b: float, sign: float, n: int):
    """Points, outward normals and element areas of a face normal to ``axis``."""
    others = [k for k in range(3) if k != axis]
    a, b = np.meshgrid((2 * _grid(n) - 1) * half_a, (2 * _grid(n) - 1) * half_b,
                       indexing="ij")
    p = np.zeros(a.shape + (3,))
    p[..., axis], p[..., others[0]], p[..., others[1]] = offset, a, b
    normal = np.zeros(3)
    normal[axis] = sign
    return p.reshape(-1, 3), np.broadcast_to(normal, (a.size, 3)), \
        np.full(a.size, 4.0 * half_a * half_b / a.size)


def opening_surface(shape: str, width: float, length: float, height: float,
                    n: int = NODES):
    """(points (N, 3), outward normals (N, 3), areas (N,)) of the emitting surface of an
    opening in the luminaire's frame (x along C0-C180: the length; y along C90-C270: the
    width; z towards gamma = 0), and A_proj as a function of unit directions (N, 3)."""
    hx, hy, hz = 0.5 * length, 0.5 * width, 0.5 * height
    if shape == "rectangle":
        faces = [_face(2, 0.0, hx, hy, s, n) for s in (1.0, -1.0)]
        def proj(w):
            return 4 * hx * hy * np.abs(w[:, 2])
    elif shape == "box":
        faces = [_face(axis, s * h, *[x for k, x in enumerate((hx, hy, hz)) if k != axis],
                       s, n) for axis, h in enumerate((hx, hy, hz)) for s in (1.0, -1.0)]
        def proj(w):
            return (4 * hy * hz * np.abs(w[:, 0]) + 4 * hx * hz * np.abs(w[:, 1])
                    + 4 * hx * hy * np.abs(w[:, 2]))
    elif shape == "disk":
        r = hy
        rr, phi = np.meshgrid(_grid(n) * r, _grid(n) * 2 * np.pi, indexing="ij")
        p = np.stack([rr * np.cos(phi), rr * np.sin(phi), 0 * rr], -1).reshape(-1, 3)
        area = (rr * (r / n) * (2 * np.pi / n)).ravel()
        faces = [(p, np.broadcast_to([0.0, 0.0, s], p.shape), area) for s in (1.0, -1.0)]
        def proj(w):
            return np.pi * r * r * np.abs(w[:, 2])
    elif shape == "sphere":
        r = hy
        mu, phi = np.meshgrid(2 * _grid(n) - 1, _grid(2 * n) * 2 * np.pi, indexing="ij")
        s = np.sqrt(1 - mu * mu)
        normal = np.stack([s * np.cos(phi), s * np.sin(phi), mu], -1).reshape(-1, 3)
        faces = [(r * normal, normal, np.full(len(normal), 4 * np.pi * r * r / mu.size))]
        def proj(w):
            return np.full(len(w), np.pi * r * r)
    else:
        raise ValueError(f"no surface quadrature for a {shape} opening (only {SHAPES})")
    points, normals, areas = (np.concatenate(part) for part in zip(*faces, strict=True))
    return points, normals, areas, proj


def axial_near_field_error(photometry, distance: float | None = None) -> float:
    """E_opening / E_point - 1 on the photometric axis (gamma = 0) at ``distance`` m from
    the centre (default: the photometric distance, 5 times the largest dimension); NaN
    when the file has no intensity at gamma = 0, 0 for a point opening. Raises
    ``ValueError`` for an opening outside :data:`SHAPES`."""
    o = photometry.opening
    if o.shape == "point":
        return 0.0
    d = o.photometric_distance if distance is None else float(distance)
    points, normals, areas, proj = opening_surface(o.shape, o.width, o.length, o.height)
    v = np.array([0.0, 0.0, d]) - points
    t2 = np.sum(v * v, axis=1)
    w = v / np.sqrt(t2)[:, None]
    cos_x = np.sum(w * normals, axis=1)
    cos_r = w[:, 2]
    gamma = np.degrees(np.arctan2(np.hypot(w[:, 0], w[:, 1]), w[:, 2]))
    c = np.degrees(np.arctan2(-w[:, 1], w[:, 0])) % 360.0
    seen = (cos_x > 0) & (cos_r > 0)
    L = np.asarray(photometry.intensity(gamma, c), float) / proj(w)
    E = float(np.sum(np.where(seen, L * cos_x * cos_r / t2 * areas, 0.0)))
    E_point = float(np.asarray(photometry.intensity(0.0, 0.0), float)) / d**2
    return E / E_point - 1.0 if E_point > 0 else float("nan")
