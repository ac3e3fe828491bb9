"""Tests of the emitting geometry of the sized lights (``plugins/emitters/opening.py``):
each sampling routine's density is what it reports (chi-square through the lights'
``sample_direction`` and ``pdf_direction``), and the densities integrate to 1."""

from __future__ import annotations

import emitter_checks as checks
import numpy as np
import pytest

#: Significance level of the chi-square tests.
CHI2_SIGNIFICANCE = 0.01
#: The mean of 1/pdf over the samples is the solid angle the samples cover.
RTOL_SOLID_ANGLE = 5e-3
REF = (0.1, -0.2, 0.3)


def assert_chi2(sample, pdf, ires: int = 64) -> None:
    """mitsuba.chi2 on the sphere of directions: ``sample`` (2D samples -> directions)
    follows ``pdf`` (directions -> density)."""
    from mitsuba import chi2

    test = chi2.ChiSquareTest(domain=chi2.SphericalDomain(), sample_func=sample,
                              pdf_func=pdf, sample_dim=2, sample_count=400_000, res=101,
                              ires=ires)
    assert test.run(CHI2_SIGNIFICANCE), test.messages


def uniform_sphere_pdf(d):
    import drjit as dr
    import mitsuba as mi

    return dr.full(mi.Float, 1.0 / (4.0 * np.pi), dr.width(d))


def carried(light: dict):
    """(scene, emitter): ``light`` on its shape (``sized.expand_dict``), alone in a scene."""
    import mitsuba as mi
    from spectrace.plugins.emitters import sized

    scene = mi.load_dict(sized.expand_dict({"type": "scene", "light": light}))
    return scene, scene.emitters()[0]


def direction_pdf(scene, emitter, it, d):
    """The density pdf_direction reports for the direction ``d`` from ``it``: the ray is
    traced to the light's shape and the direction sample built as the integrators build
    it for multiple importance sampling (0 where it misses)."""
    import drjit as dr
    import mitsuba as mi

    it = dr.zeros(mi.Interaction3f, dr.width(d)) if it is None else it
    it.p = mi.Point3f(*REF)
    si = scene.ray_intersect(mi.Ray3f(it.p, d))
    ds = mi.DirectionSample3f(scene, si, it)
    return dr.select(si.is_valid(), emitter.pdf_direction(it, ds, si.is_valid()), 0.0)


def lights():
    T = checks.transform()
    return {
        "sphere_far": {"type": "pointlight", "position": [0.4, 2.0, 0.3], "source_radius": 0.5},
        "sphere_near": {"type": "pointlight", "position": [0.1, 0.1, 0.3],
                        "source_radius": 0.25},
        "disk": {"type": "spotlight", "source_radius": 0.6, "umbra_angle": 80,
                 "penumbra_angle": 60,
                 "to_world": T.look_at([0.5, 0.7, 0.2], list(REF), [0, 0, 1])},
        "disk_near": {"type": "spotlight", "source_radius": 0.6, "umbra_angle": 80,
                      "penumbra_angle": 60,
                      "to_world": T.look_at([0.3, 0.2, 0.2], list(REF), [0, 0, 1])},
        "disk_oblique": {"type": "spotlight", "source_radius": 0.6, "umbra_angle": 85,
                         "penumbra_angle": 60,
                         "to_world": T.look_at([0.5, 0.4, 0.2], [1.094, -0.404, 0.247],
                                               [0, 0, 1])},  # 70 degrees to REF
    }


SAMPLED = [("sphere_far", "solid_angle"), ("sphere_near", "solid_angle"),
           ("disk", "solid_angle"), ("disk_oblique", "solid_angle"), ("disk", "area"),
           ("disk_oblique", "area"), ("disk_near", "auto"), ("disk", "auto")]


@pytest.mark.parametrize(("name", "method"), SAMPLED)
def test_sample_direction_chi2(variant_rgb, name, method):
    """The directions ``sample_direction`` draws from a point follow the density that
    ``pdf_direction`` reports for the hit the integrators build (mitsuba.chi2 on the sphere
    of directions): the sphere's cone sampling seen from afar and from close by, the disk's
    methods facing the point and seen obliquely (``auto``: near and far). The disk's
    ``solid_angle`` samples
    are uniform over its circumscribed square, those off the disk discarded: their
    density there is the square's, 1 / Omega_square (``rectangle_solid_angle_pdf``)."""
    import drjit as dr
    import mitsuba as mi
    from spectrace.plugins.emitters import opening

    light = lights()[name]
    if name.startswith("disk"):
        light["source_sampling"] = method
    scene, emitter = carried(light)
    square = None
    near = name == "disk_near"  # within 1.5 radii: auto samples by solid angle there
    if name.startswith("disk") and (method == "solid_angle" or (method == "auto" and near)):
        r = light["source_radius"]
        square = mi.load_dict({"type": "scene", "square": {
            "type": "rectangle", "to_world": light["to_world"] @ mi.ScalarTransform4f().scale(
                [r, r, 1])}})
        to_world = mi.Transform4f(light["to_world"])

    def sample(s):
        it = dr.zeros(mi.Interaction3f, dr.width(s))
        it.p = mi.Point3f(*REF)
        ds, _ = emitter.sample_direction(it, s)
        return ds.d

    def pdf(d):
        value = direction_pdf(scene, emitter, None, d)
        if square is not None:
            si = square.ray_intersect(mi.Ray3f(mi.Point3f(*REF), d))
            off_disk = opening.rectangle_solid_angle_pdf(
                to_world, light["source_radius"], light["source_radius"], mi.Point3f(*REF),
                si.p)
            value = dr.select(si.is_valid() & (value == 0.0), off_disk, value)
        return value

    assert_chi2(sample, pdf, ires=64)


@pytest.mark.parametrize("method", ["solid_angle", "area"])
def test_sphere_densities_cover_the_cone(variant_rgb, rng, method):
    """Sum of 1 / pdf over the valid samples / number of samples estimates the solid angle
    they cover, the cone 2 pi (1 - cos theta_max), for both methods; every solid-angle
    sample is valid, and of the area samples those on the cap seen from the point,
    (1 - r / d) / 2 of the sphere (the rest faces away: density 0)."""
    import drjit as dr
    import mitsuba as mi

    center, radius = np.array([0.4, 2.0, 0.3]), 0.5
    emitter = mi.load_dict({"type": "pointlight", "position": list(center),
                            "source_radius": radius, "source_sampling": method})
    n = 200_000
    u = rng.random((2, n)).astype(np.float32)
    it = dr.zeros(mi.Interaction3f, n)
    it.p = mi.Point3f(*REF)
    ds, _ = emitter.sample_direction(it, mi.Point2f(u[0], u[1]))
    pdf = np.broadcast_to(np.array(ds.pdf, dtype=np.float64), (n,))
    valid = pdf > 0
    d = np.linalg.norm(center - np.array(REF))
    cone = 2 * np.pi * (1 - np.sqrt(1 - (radius / d) ** 2))
    covered = 1.0 if method == "solid_angle" else (1 - radius / d) / 2
    assert valid.mean() == pytest.approx(covered, abs=5e-3)
    assert np.sum(1.0 / pdf[valid]) / n == pytest.approx(cone, rel=RTOL_SOLID_ANGLE)


def test_sphere_sample_ray_chi2(variant_rgb):
    """``sample_ray`` of a sized point light leaves a uniform point of the sphere in a
    cosine-distributed direction about its normal: the directions are then uniform over
    the sphere of directions (integral over the sphere of cos+/pi dA / A = 1 / (4 pi)),
    mitsuba.chi2 against that density, each ray of weight 4 pi I."""
    import drjit as dr
    import mitsuba as mi

    light = mi.load_dict({"type": "pointlight", "position": [0.2, 0.1, 0.3],
                          "source_radius": 0.3, "intensity": 2.0})
    rng = np.random.default_rng(5)

    def sample(s):
        u = rng.random((2, dr.width(s))).astype(np.float32)
        ray, weight = light.sample_ray(0.0, 0.5, mi.Point2f(u[0], u[1]), s)
        return ray.d

    assert_chi2(sample, uniform_sphere_pdf, ires=16)
    _, weight = light.sample_ray(0.0, 0.5, mi.Point2f(0.3, 0.7), mi.Point2f(0.1, 0.2))
    np.testing.assert_allclose(np.array(weight).ravel(), 4 * np.pi * 2.0, rtol=1e-6)


def test_reference_page(variant_rgb):
    """The helper page of ``opening`` follows the one reference-page format."""
    from spectrace.plugins.emitters import opening

    assert set(checks.parse_reference_page(opening.__doc__, "opening")) == {"source_sampling"}


#: Cauchy's formula: the projected area of a convex body averaged over directions.
RTOL_CAUCHY = 2e-3


def test_projected_areas_follow_cauchy(variant_rgb):
    """The mean over all directions of a convex body's projected area is a quarter of its
    surface (Cauchy): a sphere (pi r^2 = 4 pi r^2 / 4), a disk and a rectangle seen from
    both sides, a box and a closed cylinder (midpoint rule over the sphere)."""
    import mitsuba as mi
    from spectrace.plugins.emitters import opening

    d, w = checks.sphere_quadrature(400, 200)
    cos = mi.Float(d[:, 2].astype(np.float32))
    direction = mi.Vector3f(*(d[:, i].astype(np.float32) for i in range(3)))

    def mean(area):
        return float(np.sum(np.broadcast_to(np.array(area, dtype=np.float64), w.shape) * w)
                     / (4 * np.pi))

    r, h, size = 0.3, 1.1, (0.4, 0.7, 1.3)

    def two_sided(area):
        return area(cos) + area(-cos)

    cases = {
        "sphere": (mean(opening.sphere_projected_area(mi.Float(r)) + 0 * cos),
                   4 * np.pi * r**2),
        "disk": (mean(two_sided(lambda c: opening.disk_projected_area(r, c))), 2 * np.pi * r**2),
        "rectangle": (mean(two_sided(lambda c: opening.rectangle_projected_area(0.2, 0.5, c))),
                      2 * 0.4 * 1.0),
        "box": (mean(opening.box_projected_area(size, direction)),
                2 * (size[0] * size[1] + size[1] * size[2] + size[0] * size[2])),
        "cylinder": (mean(opening.cylinder_projected_area(r, h, cos)),
                     2 * np.pi * r * h + 2 * np.pi * r**2),
    }
    for name, (got, surface) in cases.items():
        assert got == pytest.approx(surface / 4, rel=RTOL_CAUCHY), name
    one_cap = mean(opening.cylinder_projected_area(r, h, cos, caps=1))
    assert one_cap == pytest.approx((2 * np.pi * r * h + np.pi * r**2) / 4, rel=RTOL_CAUCHY)


def test_rectangle_sample_direction_chi2(variant_rgb):
    """Points uniform on a rectangle seen from a point: the directions follow the density
    ``rectangle_pdf_direction`` gives for the point where the direction meets Mitsuba's own
    ``rectangle`` of the same size (mitsuba.chi2)."""
    import drjit as dr
    import mitsuba as mi
    from spectrace.plugins.emitters import opening

    T = checks.transform()
    frame = T.look_at([0.5, 0.6, 0.2], list(REF), [0, 0, 1]).rotate([0, 0, 1], 30)
    hx, hy = 0.7, 0.3
    scene = mi.load_dict({"type": "scene", "r": {"type": "rectangle",
                                                 "to_world": frame.scale([hx, hy, 1])}})
    to_world = mi.Transform4f(frame)

    def sample(s):
        p, _, _ = opening.rectangle_sample_direction(to_world, hx, hy, mi.Point3f(*REF), s)
        return dr.normalize(p - mi.Point3f(*REF))

    def pdf(d):
        si = scene.ray_intersect(mi.Ray3f(mi.Point3f(*REF), d))
        value = opening.rectangle_pdf_direction(hx, hy, mi.Point3f(*REF), si.p, si.n)
        return dr.select(si.is_valid(), value, 0.0)

    assert_chi2(sample, pdf, ires=64)


def test_sphere_area_sampling_chi2(variant_rgb):
    """Area sampling of a sphere draws its points uniformly over the whole surface: their
    outward normals ds.n are uniform over the sphere of directions (mitsuba.chi2 against
    1 / (4 pi)); the conversion to solid angle is checked by the cone's coverage above
    and by Howell's irradiance (test_sized)."""
    import drjit as dr
    import mitsuba as mi

    emitter = mi.load_dict({"type": "pointlight", "position": [0.4, 1.2, 0.3],
                            "source_radius": 0.6, "source_sampling": "area"})

    def sample(s):
        it = dr.zeros(mi.Interaction3f, dr.width(s))
        it.p = mi.Point3f(*REF)
        ds, _ = emitter.sample_direction(it, s)
        return mi.Vector3f(ds.n)

    assert_chi2(sample, uniform_sphere_pdf, ires=16)


@pytest.mark.parametrize("origin", [(0.5, 0.6, 0.2), (0.3, 0.0, 0.4)])
def test_rectangle_solid_angle_sampling_chi2(variant_rgb, origin):
    """Points of a rectangle uniform in the solid angle it subtends (the spherical
    rectangle of Urena et al. 2013): the directions are uniform over the rectangle as seen
    (mitsuba.chi2 against 1 / Omega where the direction meets Mitsuba's ``rectangle``),
    and Omega equals the area estimate of the same solid angle; close by and farther; 0
    from behind."""
    import drjit as dr
    import mitsuba as mi
    from spectrace.plugins.emitters import opening

    T = checks.transform()
    frame = T.look_at(list(origin), list(REF), [0, 0, 1]).rotate([0, 0, 1], 30)
    hx, hy = 0.7, 0.3
    scene = mi.load_dict({"type": "scene", "r": {"type": "rectangle",
                                                 "to_world": frame.scale([hx, hy, 1])}})
    to_world, ref = mi.Transform4f(frame), mi.Point3f(*REF)

    def sample(s):
        p, _, _ = opening.rectangle_solid_angle_sample(to_world, hx, hy, ref, s)
        return dr.normalize(p - ref)

    _, _, pdf0 = opening.rectangle_solid_angle_sample(to_world, hx, hy, ref, mi.Point2f(0.5))
    omega = 1.0 / float(np.array(pdf0).ravel()[0])

    def pdf(d):
        si = scene.ray_intersect(mi.Ray3f(ref, d))
        return dr.select(si.is_valid(), 1.0 / omega, 0.0)

    assert_chi2(sample, pdf, ires=64)
    rng = np.random.default_rng(3)
    u = rng.random((2, 200_000)).astype(np.float32)
    _, _, area_pdf = opening.rectangle_sample_direction(to_world, hx, hy, ref,
                                                        mi.Point2f(u[0], u[1]))
    assert np.mean(1.0 / np.array(area_pdf)) == pytest.approx(omega, rel=RTOL_SOLID_ANGLE)
    behind = mi.Point3f(*(float(c) for c in 2 * np.array(origin) - np.array(REF)))
    _, _, pdf_behind = opening.rectangle_solid_angle_sample(to_world, hx, hy, behind,
                                                            mi.Point2f(0.5))
    assert float(np.array(pdf_behind).ravel()[0]) == 0.0
