"""``opening``: the emitting geometry of the sized lights (helper page, not a plugin).

A light with a size (``pointlight`` or ``spotlight`` with ``source_radius`` > 0; later the
luminous openings of ``ieslight``) emits from a surface, a sphere or a disk, instead of a
point. Each point of the surface emits the radiance L(omega) = I(omega) / A_proj(omega),
where I is the light's radiant intensity and A_proj the surface's area projected on a plane
normal to omega, so that far away the surface lights like the point light of intensity I:

* sphere of radius r: A_proj = pi r^2 in every direction, so L = I / (pi r^2) is uniform
  (a Lambertian sphere) and its flux is 4 pi I, the point light's;
* disk of radius r facing +Z: A_proj = pi r^2 cos(gamma), gamma the angle from +Z, so
  L = I(gamma) / (pi r^2 cos gamma).

This module samples points of these surfaces for a shaded point (``sample_direction``) and
gives the densities in solid angle that go with them (``pdf_direction``), for the
integrators' next-event estimation and multiple importance sampling; it also has the
rectangle (sampled by area, or uniformly in the solid angle it subtends, the spherical
rectangle of Urena et al.) and the projected areas of the rectangle, box and cylinder that
the luminous openings of IES LM-63 files need. Executed before the
lights (see ``spectrace.plugins.PLUGIN_MODULES``).

Parameters
----------

===================  ======  ===========  ====  ===============================================
parameter            type    default      unit  description
===================  ======  ===========  ====  ===============================================
``source_sampling``  string  (below)      --    how a sphere or disk is sampled from a
                                                shaded point: ``solid_angle`` (uniform in
                                                the cone a sphere subtends; a disk: uniform
                                                in the solid angle of its circumscribed
                                                square, samples off the disk discarded),
                                                ``area`` (uniform over the surface, the
                                                reference for comparisons) or, for disks,
                                                ``auto``: solid angle closer than 1.5 radii
                                                to the centre, area farther. Default:
                                                ``solid_angle`` for spheres, ``auto`` for
                                                disks
===================  ======  ===========  ====  ===============================================

Formula
-------

::

    sphere, solid_angle:  pdf(omega) = 1 / (2 pi (1 - cos theta_max)),  sin theta_max = r / d
    sphere, area:         pdf(omega) = t^2 / (4 pi r^2 |cos theta_l|)
    disk, solid_angle:    pdf(omega) = 1 / Omega_square     (on the disk; pi/4 of the square)
    disk, auto:           solid_angle where |x - centre| < 1.5 r, area elsewhere
    disk, area:           pdf(omega) = t^2 / (pi r^2 cos theta_l)

with d the distance from the shaded point to the sphere's centre, t the distance to the
sampled point and theta_l the angle between the surface normal there and the direction back
to the shaded point. ``solid_angle`` draws cos theta uniformly in [cos theta_max, 1] about the
direction to the centre and finds the point of the sphere seen in that direction from the
angle alpha at the centre, cos alpha = sin^2 theta / sin theta_max + cos theta sqrt(1 -
sin^2 theta / sin^2 theta_max), so no ray is intersected; 1 - cos theta_max is computed as
sin^2 theta_max / (1 + cos theta_max), exact for far spheres too. The disk's square (side
2 r, the disk's frame) is sampled as a spherical rectangle, whose solid angle Omega_square
has a closed form (the sum of its four angles less 2 pi); where it falls under
:data:`MIN_SPHERICAL_RECTANGLE` (far away) the square is sampled by area. Shaded points
inside a sphere or behind a disk see no emission: density 0.

Sources
-------

Pharr, Jakob, Humphreys (2023), *Physically Based Rendering* 4th ed., sec. 6.2.4 (sampling a
sphere by the cone it subtends) and A.5 (area sampling, the area-to-solid-angle Jacobian
t^2 / cos theta_l); Shirley, Chiu (1997), "A low distortion map between disk and square",
*Journal of Graphics Tools* 2(3) (``mi.warp.square_to_uniform_disk_concentric``); Urena,
Fajardo, King (2013), "An area-preserving parametrization for spherical rectangles",
*Computer Graphics Forum* 32(4) (rectangles by solid angle).

Example
-------

A 10 cm sphere sampled by area, to compare its noise with the default::

    <emitter type="pointlight">
        <point name="position" x="0" y="2" z="0"/>
        <float name="source_radius" value="0.1"/>
        <string name="source_sampling" value="area"/>
    </emitter>
"""

from __future__ import annotations

import math

import drjit as dr
import mitsuba as mi


def _sphere_solid_angle(center, radius, ref_p, sample):
    """A point of the sphere seen from ``ref_p``, uniform in the cone it subtends.

    Returns ``(p, n, pdf)``: the point, its outward normal and the density in solid angle
    (0 when ``ref_p`` is inside)."""
    to_ref = mi.Vector3f(ref_p - center)
    dc2 = dr.squared_norm(to_ref)
    outside = dc2 > dr.square(radius)
    inv_dc = dr.rsqrt(dc2)
    sin2_max = dr.minimum(dr.square(radius) * dr.rcp(dc2), 1.0)
    cos_max = dr.safe_sqrt(1.0 - sin2_max)
    one_minus_cos_max = sin2_max * dr.rcp(1.0 + cos_max)
    u_omc = sample.x * one_minus_cos_max  # 1 - cos(theta), theta uniform in cos
    cos_theta = 1.0 - u_omc
    sin2_theta = u_omc * (2.0 - u_omc)
    ratio = sin2_theta * dr.rcp(dr.maximum(sin2_max, 1e-30))
    cos_alpha = sin2_theta * dr.rsqrt(dr.maximum(sin2_max, 1e-30)) + cos_theta * dr.safe_sqrt(
        1.0 - ratio)
    cos_alpha = dr.clip(cos_alpha, -1.0, 1.0)
    sin_alpha = dr.safe_sqrt(1.0 - dr.square(cos_alpha))
    sin_phi, cos_phi = dr.sincos(dr.two_pi * sample.y)
    frame = mi.Frame3f(to_ref * inv_dc)
    n = frame.to_world(mi.Vector3f(sin_alpha * cos_phi, sin_alpha * sin_phi, cos_alpha))
    p = center + radius * n
    pdf = dr.select(outside, dr.rcp(dr.two_pi * one_minus_cos_max), 0.0)
    return mi.Point3f(p), mi.Normal3f(n), pdf


def _sphere_solid_angle_pdf(center, radius, ref_p, p, n):
    """Density in solid angle of :func:`_sphere_solid_angle` (the point is not needed)."""
    dc2 = dr.squared_norm(ref_p - center)
    sin2_max = dr.minimum(dr.square(radius) * dr.rcp(dc2), 1.0)
    one_minus_cos_max = sin2_max * dr.rcp(1.0 + dr.safe_sqrt(1.0 - sin2_max))
    return dr.select(dc2 > dr.square(radius), dr.rcp(dr.two_pi * one_minus_cos_max), 0.0)


def _solid_angle_from_area(ref_p, p, n, area):
    """The density t^2 / (area cos theta_l) of a uniform area sample seen from ``ref_p``
    (0 where the surface faces away from it)."""
    d = mi.Vector3f(ref_p - p)
    dist2 = dr.squared_norm(d)
    cos_l = dr.dot(n, d) * dr.rsqrt(dist2)
    return dr.select(cos_l > 0.0, dist2 * dr.rcp(area * cos_l), 0.0)


def _sphere_area(center, radius, ref_p, sample):
    """A point uniform over the whole sphere; the density in solid angle from ``ref_p``."""
    n = mi.warp.square_to_uniform_sphere(sample)
    p = mi.Point3f(center + radius * n)
    return p, mi.Normal3f(n), _sphere_area_pdf(center, radius, ref_p, p, n)


def _sphere_area_pdf(center, radius, ref_p, p, n):
    outside = dr.squared_norm(ref_p - center) > dr.square(radius)
    area = 2.0 * dr.two_pi * dr.square(radius)
    return dr.select(outside, _solid_angle_from_area(ref_p, p, n, area), 0.0)


#: ``source_sampling`` -> ``(sample(center, radius, ref_p, sample) -> (p, n, pdf),
#: pdf(center, radius, ref_p, p, n) -> pdf)`` for spheres.
SPHERE_SAMPLING_METHODS = {
    "solid_angle": (_sphere_solid_angle, _sphere_solid_angle_pdf),
    "area": (_sphere_area, _sphere_area_pdf),
}
DEFAULT_SAMPLING = "solid_angle"


def sphere_sample_direction(center, radius, ref_p, sample, method: str = DEFAULT_SAMPLING):
    """``(p, n, pdf)``: a point of the sphere, its outward normal and the density in solid
    angle seen from ``ref_p`` (0 when invalid), by ``method`` of
    :data:`SPHERE_SAMPLING_METHODS`."""
    return SPHERE_SAMPLING_METHODS[method][0](center, radius, ref_p, sample)


def sphere_pdf_direction(center, radius, ref_p, p, n, method: str = DEFAULT_SAMPLING):
    """The density in solid angle with which :func:`sphere_sample_direction` picks the
    point ``p`` (normal ``n``) of the sphere from ``ref_p``."""
    return SPHERE_SAMPLING_METHODS[method][1](center, radius, ref_p, p, n)


def disk_point(to_world, radius, sample):
    """A point uniform on the disk of ``radius`` in the plane z = 0 of ``to_world`` (a
    rigid transform), and the disk's normal (world +Z of the frame)."""
    local = mi.warp.square_to_uniform_disk_concentric(sample) * radius
    p = to_world @ mi.Point3f(local.x, local.y, 0.0)
    n = dr.normalize(to_world @ mi.Normal3f(0.0, 0.0, 1.0))
    return mi.Point3f(p), mi.Normal3f(n)


def _disk_area(to_world, to_local, radius, ref_p, sample):
    p, n = disk_point(to_world, radius, sample)
    return p, n, _disk_area_pdf(to_world, to_local, radius, ref_p, p, n)


def _disk_area_pdf(to_world, to_local, radius, ref_p, p, n):
    return _solid_angle_from_area(ref_p, p, n, dr.pi * dr.square(radius))


def _disk_solid_angle(to_world, to_local, radius, ref_p, sample):
    p, n, pdf = rectangle_solid_angle_sample(to_world, radius, radius, ref_p, sample)
    local = to_local @ p
    inside = dr.square(local.x) + dr.square(local.y) <= dr.square(radius)
    return p, n, dr.select(inside, pdf, 0.0)


def _disk_solid_angle_pdf(to_world, to_local, radius, ref_p, p, n):
    return rectangle_solid_angle_pdf(to_world, radius, radius, ref_p, p)


#: ``auto`` samples a disk by solid angle from points closer than this many radii to its
#: centre and by area farther away, where the discarded samples of the solid-angle method
#: cost more noise than area sampling's 1 / t^2 (measured: ``benchmarks/bench_emitters.py``).
NEAR_DISK_RADII = 1.5


def _disk_near(to_world, radius, ref_p):
    return dr.squared_norm(ref_p - to_world.translation()) < dr.square(NEAR_DISK_RADII * radius)


def _disk_auto(to_world, to_local, radius, ref_p, sample):
    near = _disk_near(to_world, radius, ref_p)
    p_s, n_s, pdf_s = _disk_solid_angle(to_world, to_local, radius, ref_p, sample)
    p_a, n_a, pdf_a = _disk_area(to_world, to_local, radius, ref_p, sample)
    return (dr.select(near, p_s, p_a), dr.select(near, n_s, n_a),
            dr.select(near, pdf_s, pdf_a))


def _disk_auto_pdf(to_world, to_local, radius, ref_p, p, n):
    return dr.select(_disk_near(to_world, radius, ref_p),
                     _disk_solid_angle_pdf(to_world, to_local, radius, ref_p, p, n),
                     _disk_area_pdf(to_world, to_local, radius, ref_p, p, n))


#: ``source_sampling`` -> ``(sample(to_world, to_local, radius, ref_p, sample) -> (p, n,
#: pdf), pdf(to_world, to_local, radius, ref_p, p, n) -> pdf)`` for disks. ``solid_angle``:
#: uniform in the solid angle of the disk's circumscribed square (the spherical
#: rectangle), the samples outside the disk discarded (density 0, about 21 %), so the
#: density on the disk is 1 / Omega_square; ``area``: uniform over the disk; ``auto``:
#: ``solid_angle`` within :data:`NEAR_DISK_RADII` of the centre, ``area`` beyond.
DISK_SAMPLING_METHODS = {
    "auto": (_disk_auto, _disk_auto_pdf),
    "solid_angle": (_disk_solid_angle, _disk_solid_angle_pdf),
    "area": (_disk_area, _disk_area_pdf),
}
DEFAULT_DISK_SAMPLING = "auto"


def disk_sample_direction(to_world, to_local, radius, ref_p, sample,
                          method: str = DEFAULT_DISK_SAMPLING):
    """``(p, n, pdf)``: a point of the disk (front side +Z only) by ``method`` of
    :data:`DISK_SAMPLING_METHODS` and its density in solid angle from ``ref_p`` (0 behind
    the disk or when discarded)."""
    return DISK_SAMPLING_METHODS[method][0](to_world, to_local, radius, ref_p, sample)


def disk_pdf_direction(to_world, to_local, radius, ref_p, p, n,
                       method: str = DEFAULT_DISK_SAMPLING):
    """The density in solid angle of :func:`disk_sample_direction` at the point ``p``."""
    pdf = DISK_SAMPLING_METHODS[method][1](to_world, to_local, radius, ref_p, p, n)
    return dr.select(dr.dot(n, ref_p - p) > 0.0, pdf, 0.0)


def sphere_projected_area(radius):
    """A_proj of a sphere: pi r^2 in every direction."""
    return dr.pi * dr.square(radius)


def disk_projected_area(radius, cos_gamma):
    """A_proj of a disk seen at the angle gamma from its normal: pi r^2 cos(gamma) (0 from
    behind)."""
    return dr.pi * dr.square(radius) * dr.maximum(cos_gamma, 0.0)


def rectangle_point(to_world, half_x, half_y, sample):
    """A point uniform on the rectangle [-half_x, half_x] x [-half_y, half_y] in the plane
    z = 0 of ``to_world`` (rigid), and its normal (the frame's +Z): the luminous opening
    of a rectangular luminaire (LM-63 length along local x, width along y)."""
    local = mi.Point3f(dr.fma(sample.x, 2.0, -1.0) * half_x,
                       dr.fma(sample.y, 2.0, -1.0) * half_y, 0.0)
    return mi.Point3f(to_world @ local), mi.Normal3f(dr.normalize(
        to_world @ mi.Normal3f(0.0, 0.0, 1.0)))


def rectangle_sample_direction(to_world, half_x, half_y, ref_p, sample):
    """``(p, n, pdf)``: a point uniform by area on the rectangle (front side +Z) and its
    density in solid angle from ``ref_p`` (0 behind it)."""
    p, n = rectangle_point(to_world, half_x, half_y, sample)
    return p, n, rectangle_pdf_direction(half_x, half_y, ref_p, p, n)


def rectangle_pdf_direction(half_x, half_y, ref_p, p, n):
    """The density in solid angle of :func:`rectangle_sample_direction` at ``p``."""
    return _solid_angle_from_area(ref_p, p, n, 4.0 * half_x * half_y)


#: Smallest solid angle (sr) that the spherical-rectangle sampler handles; smaller (a far
#: rectangle, or one seen edge-on) is sampled by area.
MIN_SPHERICAL_RECTANGLE = 1e-5


def _angle_between(a, b):
    """The angle between unit vectors, accurate near 0 and pi."""
    return dr.select(dr.dot(a, b) < 0.0, dr.pi - 2.0 * dr.safe_asin(0.5 * dr.norm(a + b)),
                     2.0 * dr.safe_asin(0.5 * dr.norm(b - a)))


def _spherical_rectangle(to_world, half_x, half_y, ref_p):
    """The spherical rectangle seen from ``ref_p``: its local frame and corner
    coordinates, the normals of its great-circle edges, its solid angle Omega and whether
    ``ref_p`` is in front of the rectangle."""
    corner = mi.Point3f(to_world @ mi.Point3f(-half_x, -half_y, 0.0))
    ex = mi.Vector3f(to_world @ mi.Vector3f(2.0 * half_x, 0.0, 0.0))
    ey = mi.Vector3f(to_world @ mi.Vector3f(0.0, 2.0 * half_y, 0.0))
    n = mi.Normal3f(dr.normalize(to_world @ mi.Normal3f(0.0, 0.0, 1.0)))
    exl, eyl = dr.norm(ex), dr.norm(ey)
    x_axis, y_axis = ex / exl, ey / eyl
    z_axis = dr.cross(x_axis, y_axis)
    d = mi.Vector3f(corner - ref_p)
    z0 = dr.dot(d, z_axis)
    z_axis = dr.select(z0 > 0.0, -z_axis, z_axis)  # the local frame has the rectangle at z < 0
    z0 = -dr.abs(z0)
    x0, y0 = dr.dot(d, x_axis), dr.dot(d, y_axis)
    x1, y1 = x0 + exl, y0 + eyl
    v00, v01 = mi.Vector3f(x0, y0, z0), mi.Vector3f(x0, y1, z0)
    v10, v11 = mi.Vector3f(x1, y0, z0), mi.Vector3f(x1, y1, z0)
    n0 = dr.normalize(dr.cross(v00, v10))
    n1 = dr.normalize(dr.cross(v10, v11))
    n2 = dr.normalize(dr.cross(v11, v01))
    n3 = dr.normalize(dr.cross(v01, v00))
    g0, g1 = _angle_between(-n0, n1), _angle_between(-n1, n2)
    g2, g3 = _angle_between(-n2, n3), _angle_between(-n3, n0)
    omega = g0 + g1 + g2 + g3 - dr.two_pi
    front = dr.dot(n, ref_p - corner) > 0.0
    frame = (x_axis, y_axis, z_axis, x0, x1, y0, y1, z0, n0.z, n2.z, g2 + g3)
    return frame, n, omega, front


def rectangle_solid_angle_sample(to_world, half_x, half_y, ref_p, sample):
    """``(p, n, pdf)``: a point of the rectangle uniform in the solid angle it subtends at
    ``ref_p`` (Urena, Fajardo, King 2013, "An area-preserving parametrization for
    spherical rectangles"), its normal and the density 1 / Omega (0 behind the rectangle;
    by area where Omega < :data:`MIN_SPHERICAL_RECTANGLE`)."""
    frame, n, omega, front = _spherical_rectangle(to_world, half_x, half_y, ref_p)
    x_axis, y_axis, z_axis, x0, x1, y0, y1, z0, b0, b1, g23 = frame
    au = sample.x * omega - g23  # the spherical area up to x_u is sample.x * omega
    fu = (dr.cos(au) * b0 - b1) / dr.sin(au)
    cu = dr.clip(dr.mulsign(dr.rsqrt(dr.square(fu) + dr.square(b0)), fu), -1.0, 1.0)
    xu = dr.clip(-(cu * z0) * dr.rcp(dr.safe_sqrt(1.0 - dr.square(cu))), x0, x1)
    dist = dr.sqrt(dr.square(xu) + dr.square(z0))
    h0 = y0 * dr.rsqrt(dr.square(dist) + dr.square(y0))
    h1 = y1 * dr.rsqrt(dr.square(dist) + dr.square(y1))
    hv = h0 + sample.y * (h1 - h0)
    yv = dr.select(dr.square(hv) < 1.0 - 1e-6, hv * dist * dr.rsqrt(1.0 - dr.square(hv)), y1)
    p = mi.Point3f(ref_p + xu * x_axis + yv * y_axis + z0 * z_axis)
    small = omega < MIN_SPHERICAL_RECTANGLE
    p_area, _ = rectangle_point(to_world, half_x, half_y, sample)
    p = dr.select(small, p_area, p)
    pdf = dr.select(small, rectangle_pdf_direction(half_x, half_y, ref_p, p, n),
                    dr.rcp(omega))
    return p, n, dr.select(front, pdf, 0.0)


def rectangle_solid_angle_pdf(to_world, half_x, half_y, ref_p, p):
    """The density in solid angle of :func:`rectangle_solid_angle_sample` at the point
    ``p`` of the rectangle."""
    _, n, omega, front = _spherical_rectangle(to_world, half_x, half_y, ref_p)
    pdf = dr.select(omega < MIN_SPHERICAL_RECTANGLE,
                    rectangle_pdf_direction(half_x, half_y, ref_p, p, n), dr.rcp(omega))
    return dr.select(front, pdf, 0.0)


def rectangle_projected_area(half_x, half_y, cos_gamma):
    """A_proj of a one-sided rectangle seen at gamma from its normal: 4 hx hy cos(gamma)."""
    return 4.0 * half_x * half_y * dr.maximum(cos_gamma, 0.0)


def box_projected_area(size, direction):
    """A_proj of a box of edge lengths ``size`` = (x, y, z) seen along the unit local
    ``direction``: y z |d_x| + x z |d_y| + x y |d_z| (a convex body shows half of its
    faces' projections)."""
    x, y, z = size
    return (y * z * dr.abs(direction[0]) + x * z * dr.abs(direction[1])
            + x * y * dr.abs(direction[2]))


def cylinder_projected_area(radius, height, cos_gamma, caps: int = 2):
    """A_proj of a cylinder along local z (``radius``, ``height``) seen at gamma from its
    axis: its side 2 r h sin(gamma), plus pi r^2 |cos gamma| when it has a cap on the side
    seen (``caps`` 2: both ends closed; 1: only the end at -z, which faces down; 0: open)."""
    side = 2.0 * radius * height * dr.safe_sqrt(1.0 - dr.square(cos_gamma))
    if caps == 0:
        return side
    cap = dr.pi * dr.square(radius) * dr.abs(cos_gamma)
    if caps == 1:
        cap = dr.select(cos_gamma < 0.0, cap, 0.0)
    return side + cap


def _box_face_areas(half):
    """The areas of one face normal to local x, y and z of the box of half-extents
    ``half`` = (hx, hy, hz)."""
    hx, hy, hz = half
    return 4.0 * hy * hz, 4.0 * hx * hz, 4.0 * hx * hy


def _box_face_point(half, axis_sample, sign, sample):
    """The local point and normal on the face of the box normal to the chosen axis (0, 1,
    2 in the Dr.Jit array ``axis_sample``) on the side ``sign`` (+-1), uniform from the 2D
    ``sample``."""
    hx, hy, hz = half
    a = dr.fma(sample.x, 2.0, -1.0)
    b = dr.fma(sample.y, 2.0, -1.0)
    on_x, on_y = axis_sample == 0, axis_sample == 1
    local = mi.Point3f(dr.select(on_x, sign * hx, a * hx),
                       dr.select(on_x, a * hy, dr.select(on_y, sign * hy, b * hy)),
                       dr.select(on_x | on_y, b * hz, sign * hz))
    n = mi.Normal3f(dr.select(on_x, sign, 0.0), dr.select(on_y, sign, 0.0),
                    dr.select(on_x | on_y, 0.0, sign))
    return local, n


def _pick_axis(areas, u):
    """An axis 0, 1, 2 drawn in proportion to ``areas`` from the uniform ``u``, and ``u``
    made uniform again within the chosen axis."""
    ax, ay, az = areas
    total = ax + ay + az
    t = u * total
    axis = dr.select(t < ax, 0, dr.select(t < ax + ay, 1, 2))
    start = dr.select(axis == 0, 0.0, dr.select(axis == 1, ax, ax + ay))
    width = dr.select(axis == 0, ax, dr.select(axis == 1, ay, az))
    u = dr.clip((t - start) * dr.rcp(dr.maximum(width, 1e-30)), 0.0,
                dr.one_minus_epsilon(mi.Float))
    return mi.UInt32(axis), u, total


def _box_visible(to_local, half, ref_p):
    """The weights of the faces of the box that ``ref_p`` sees (at most one per axis, on
    the side of the point; 0 for the others): each face's area times |u_k|, u the unit
    local direction from the point to the centre (the face's projected area seen from
    afar), and the signs of those faces."""
    r = to_local @ ref_p
    u = dr.normalize(mi.Vector3f(r))
    ax, ay, az = _box_face_areas(half)
    hx, hy, hz = half
    weights = (dr.select(dr.abs(r.x) > hx, ax * dr.abs(u.x), 0.0),
               dr.select(dr.abs(r.y) > hy, ay * dr.abs(u.y), 0.0),
               dr.select(dr.abs(r.z) > hz, az * dr.abs(u.z), 0.0))
    signs = (dr.sign(r.x), dr.sign(r.y), dr.sign(r.z))
    return weights, signs


def _box_face_pdf(half, weights, axis, ref_p, p, n):
    """The density in solid angle of a point ``p`` of the face normal to ``axis`` drawn
    with probability weights[axis] / sum(weights), uniform on it."""
    areas = _box_face_areas(half)
    total = weights[0] + weights[1] + weights[2]
    w = dr.select(axis == 0, weights[0], dr.select(axis == 1, weights[1], weights[2]))
    a = dr.select(axis == 0, areas[0], dr.select(axis == 1, areas[1], areas[2]))
    pdf_area_inv = a * total * dr.rcp(dr.maximum(w, 1e-30))  # 1 / density by area
    pdf = _solid_angle_from_area(ref_p, p, n, pdf_area_inv)
    return dr.select((total > 0.0) & (w > 0.0), pdf, 0.0)


def box_sample_direction(to_world, to_local, half, ref_p, sample):
    """``(p, n, pdf)``: a point of the box of half-extents ``half`` (local axes of
    ``to_world``, rigid) on one of the (at most three) faces that ``ref_p`` sees, picked
    in proportion to its area times the cosine towards the point, uniform on it; its
    outward normal and the density in solid angle (0 from inside)."""
    weights, signs = _box_visible(to_local, half, ref_p)
    axis, u, _ = _pick_axis(weights, sample.x)
    sign = dr.select(axis == 0, signs[0], dr.select(axis == 1, signs[1], signs[2]))
    local, n_local = _box_face_point(half, axis, sign, mi.Point2f(u, sample.y))
    p = mi.Point3f(to_world @ local)
    n = mi.Normal3f(dr.normalize(to_world @ n_local))
    return p, n, _box_face_pdf(half, weights, axis, ref_p, p, n)


def box_pdf_direction(to_local, half, ref_p, p, n):
    """The density in solid angle of :func:`box_sample_direction` at the point ``p``
    (outward normal ``n``) of the box."""
    weights, _ = _box_visible(to_local, half, ref_p)
    n_local = to_local @ mi.Vector3f(n)
    ax, ay = dr.abs(n_local.x), dr.abs(n_local.y)
    axis = dr.select(ax > 0.5, 0, dr.select(ay > 0.5, 1, 2))
    return _box_face_pdf(half, weights, mi.UInt32(axis), ref_p, p, n)


def box_point(to_world, half, sample):
    """A point uniform by area over the whole surface of the box (``sample``: 2D), its
    outward normal, and the box's area."""
    areas = _box_face_areas(half)
    axis, u, total = _pick_axis(areas, sample.x)
    sign = dr.select(u < 0.5, 1.0, -1.0)
    u = dr.select(u < 0.5, 2.0 * u, 2.0 * u - 1.0)
    local, n_local = _box_face_point(half, axis, sign, mi.Point2f(u, sample.y))
    return (mi.Point3f(to_world @ local), mi.Normal3f(dr.normalize(to_world @ n_local)),
            2.0 * total)


def _cylinder_visible(to_local, radius, half_height, ref_p):
    """What ``ref_p`` sees of the closed cylinder (local z axis, ``radius``, from -hz to
    hz): the half-angle alpha of the lit arc of its side (acos(r / rho), 0 when rho <= r),
    the azimuth of the point, the sign of the cap it sees (0 for none) and the areas seen
    of the side (2 alpha r 2 hz) and of that cap."""
    r = to_local @ ref_p
    rho = dr.sqrt(dr.square(r.x) + dr.square(r.y))
    alpha = dr.select(rho > radius, dr.acos(dr.minimum(radius * dr.rcp(rho), 1.0)), 0.0)
    cap_sign = dr.select(r.z > half_height, 1.0, dr.select(r.z < -half_height, -1.0, 0.0))
    side = 4.0 * alpha * radius * half_height
    cap = dr.abs(cap_sign) * dr.pi * radius * radius
    return alpha, dr.atan2(r.y, r.x), cap_sign, side, cap


def _cylinder_surface(radius, half_height, on_side, phi, cap_sign, sample):
    """The local point and outward normal of the closed cylinder: on its side at the
    azimuth ``phi`` and the height from ``sample.y`` where ``on_side``, else uniform on the
    cap ``cap_sign`` (+-1) from the 2D ``sample``."""
    disk = mi.warp.square_to_uniform_disk_concentric(sample)
    local = mi.Point3f(dr.select(on_side, radius * dr.cos(phi), radius * disk.x),
                       dr.select(on_side, radius * dr.sin(phi), radius * disk.y),
                       dr.select(on_side, half_height * dr.fma(sample.y, 2.0, -1.0),
                                 cap_sign * half_height))
    n_local = mi.Normal3f(dr.select(on_side, dr.cos(phi), 0.0),
                          dr.select(on_side, dr.sin(phi), 0.0),
                          dr.select(on_side, 0.0, cap_sign))
    return local, n_local


def cylinder_sample_direction(to_world, to_local, radius, half_height, ref_p, sample):
    """``(p, n, pdf)``: a point uniform by area on the part of the closed cylinder that
    ``ref_p`` sees (the lit arc of its side and the cap on its side; the cylinder is
    convex, so the rest is hidden), its outward normal and the density in solid angle (0
    from inside)."""
    alpha, phi_ref, cap_sign, side, cap = _cylinder_visible(to_local, radius, half_height,
                                                            ref_p)
    total = side + cap
    t = sample.x * total
    on_side = t < side
    u = dr.select(on_side, t * dr.rcp(dr.maximum(side, 1e-30)),
                  (t - side) * dr.rcp(dr.maximum(cap, 1e-30)))
    u = dr.clip(u, 0.0, dr.one_minus_epsilon(mi.Float))
    phi = phi_ref + alpha * dr.fma(u, 2.0, -1.0)
    local, n_local = _cylinder_surface(radius, half_height, on_side, phi, cap_sign,
                                       mi.Point2f(u, sample.y))
    p = mi.Point3f(to_world @ local)
    n = mi.Normal3f(dr.normalize(to_world @ n_local))
    pdf = _solid_angle_from_area(ref_p, p, n, total)
    return p, n, dr.select(total > 0.0, pdf, 0.0)


def cylinder_pdf_direction(to_local, radius, half_height, ref_p, p, n):
    """The density in solid angle of :func:`cylinder_sample_direction` at the point ``p``
    (outward normal ``n``) of the cylinder."""
    _, _, _, side, cap = _cylinder_visible(to_local, radius, half_height, ref_p)
    total = side + cap
    return dr.select(total > 0.0, _solid_angle_from_area(ref_p, p, n, total), 0.0)


def cylinder_point(to_world, radius, half_height, sample):
    """A point uniform by area over the whole closed cylinder (``sample``: 2D), its
    outward normal, and the cylinder's area 2 pi r (2 hz) + 2 pi r^2."""
    side = 4.0 * math.pi * radius * half_height
    cap = math.pi * radius * radius
    total = side + 2.0 * cap
    t = sample.x * total
    on_side = t < side
    u = dr.select(on_side, t / side, (t - side) / cap)
    cap_sign = dr.select(u < 1.0, 1.0, -1.0)
    u = dr.clip(dr.select(on_side | (u < 1.0), u, u - 1.0), 0.0,
                dr.one_minus_epsilon(mi.Float))
    local, n_local = _cylinder_surface(radius, half_height, on_side, 2.0 * math.pi * u,
                                       cap_sign, mi.Point2f(u, sample.y))
    return (mi.Point3f(to_world @ local), mi.Normal3f(dr.normalize(to_world @ n_local)),
            mi.Float(total))


def cylinder_mesh(segments: int = 256):
    """Vertices (V, 3) and triangles (F, 3) of the closed unit cylinder (radius 1, z from
    -1 to 1; outward winding) with ``segments`` sides, for the shape that carries a
    cylinder opening."""
    import numpy as np

    phi = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    ring = np.stack([np.cos(phi), np.sin(phi)], axis=1)
    vertices = np.concatenate([np.c_[ring, -np.ones(segments)], np.c_[ring, np.ones(segments)],
                               [[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]]])
    i = np.arange(segments)
    j = (i + 1) % segments
    n = segments
    faces = np.concatenate([np.stack([i, j, n + j], 1), np.stack([i, n + j, n + i], 1),
                            np.stack([np.full(n, 2 * n), j, i], 1),
                            np.stack([np.full(n, 2 * n + 1), n + i, n + j], 1)])
    return vertices.astype(np.float32), faces.astype(np.uint32)
