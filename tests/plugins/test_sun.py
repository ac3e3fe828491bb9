"""Tests of the ``sun`` emitter: illuminance in lux normal to the sun, the cone of
directions of its 0.533 degree disk and the penumbra it casts (width h x 0.0093)."""

from __future__ import annotations

import emitter_checks as checks
import numpy as np
import pytest

#: Monte Carlo and float32 tolerances.
RTOL_LUX = 2e-3
RTOL_SPECTRAL = 0.01
#: Visible share of the disk against the circular-segment formula (absolute, 2^16 samples).
ATOL_SHARE = 0.01
E_N = 80000.0


def test_reference_page(variant_rgb):
    """The docstring is a reference page in the one format of spectrace's plugins."""
    from spectrace.plugins.emitters import sun

    table = checks.parse_reference_page(sun.__doc__, "sun")
    assert {"illuminance", "angular_diameter", "sun_azimuth", "sun_elevation"} <= set(table)


@pytest.mark.parametrize("elevation", [90.0, 30.0])
def test_horizontal_illuminance(variant, elevation):
    """A horizontal diffuse plane under the sun at elevation h receives E_n sin h lux."""
    light = {"type": "sun", "illuminance": E_N, "sun_elevation": elevation,
             "sun_azimuth": 140.0}
    tol = RTOL_LUX if variant.endswith("rgb") else RTOL_SPECTRAL
    assert checks.lux_at(light, (0.2, -0.1), spp=256) == pytest.approx(
        E_N * np.sin(np.radians(elevation)), rel=tol)


def test_directions_fill_the_disk(variant_rgb, rng):
    """Sampled directions lie within the cone of half-angle delta / 2 about the sun's
    direction (azimuth clockwise from north, north -Z, east +X) and fill it uniformly in
    solid angle: the mean of 1 - cos(angle) is half its maximum."""
    import drjit as dr
    import mitsuba as mi

    sun = mi.load_dict({"type": "sun", "sun_azimuth": 90.0, "sun_elevation": 0.0,
                        "angular_diameter": 2.0})
    n = 100_000
    it = dr.zeros(mi.Interaction3f, n)
    u = rng.random((n, 2)).astype(np.float32)
    ds, weight = sun.sample_direction(it, mi.Point2f(u[:, 0], u[:, 1]))
    d = np.array(ds.d, dtype=np.float64).T
    one_minus_cos = 1.0 - d @ np.array([1.0, 0.0, 0.0])  # east = +X
    limit = 1.0 - np.cos(np.radians(1.0))
    assert one_minus_cos.max() <= limit * (1 + 1e-3)
    assert one_minus_cos.mean() == pytest.approx(limit / 2, rel=0.02)
    assert np.all(np.array(ds.delta))
    w = np.array(weight)
    assert np.allclose(w, w[:, :1])


def visible_share(t):
    """Share of a uniform disk of radius 1 on the far side of a chord at signed distance t
    from its centre (t > 0: the centre is uncovered)."""
    t = np.clip(t, -1.0, 1.0)
    covered = (np.arccos(t) - t * np.sqrt(1 - t * t)) / np.pi
    return 1.0 - covered


def test_penumbra_width(variant_rgb):
    """A straight roof edge at height h over the floor, the sun at the zenith: the floor's
    illuminance rises from 0 to E_n across x in [-h alpha, h alpha] (alpha the disk's
    radius, 0.2665 degrees: a penumbra h x 0.0093 wide) as the uncovered share of the disk,
    sampled through Mitsuba's scene (emitter sampling and shadow rays)."""
    import drjit as dr
    import mitsuba as mi

    h = 10.0
    T = mi.ScalarTransform4f()
    scene = mi.load_dict({
        "type": "scene",
        "sun": {"type": "sun", "illuminance": E_N, "sun_elevation": 90.0},
        # a half-plane x < 0 at height h
        "roof": {"type": "rectangle",
                 "to_world": T.translate([-500.0, h, 0]).rotate([1, 0, 0], 90).scale(500.0),
                 "bsdf": {"type": "diffuse"}},
    })
    alpha = np.radians(0.533) / 2
    assert 2 * h * np.tan(alpha) == pytest.approx(h * 0.0093, rel=0.01)
    xs = np.linspace(-1.5, 1.5, 13) * h * alpha
    per_point = 2**16
    n = xs.size * per_point
    rng = np.random.default_rng(7)
    it = dr.zeros(mi.Interaction3f, n)
    it.p = mi.Point3f(mi.Float(np.repeat(xs, per_point).astype(np.float32)), 0.0, 0.0)
    it.n = mi.Normal3f(0, 1, 0)
    u = rng.random((n, 2)).astype(np.float32)
    ds, weight = scene.sample_emitter_direction(it, mi.Point2f(u[:, 0], u[:, 1]), True)
    cos = np.array(ds.d.y, dtype=np.float64)
    Y = np.array(weight, dtype=np.float64).T @ np.array([0.2126, 0.7152, 0.0722])
    lux = (checks.KM * checks.CIE_Y_INTEGRAL * Y * cos).reshape(xs.size, per_point).mean(1)
    np.testing.assert_allclose(lux / E_N, visible_share(xs / (h * alpha)), atol=ATOL_SHARE)


@pytest.mark.parametrize("props, words", [
    ({"sun_elevation": -3.0}, "below the horizon"),
    ({"angular_diameter": 0.0}, "angular_diameter"),
    ({"illuminance": -1.0}, "illuminance"),
    ({"latitude": 10.0, "longitude": 200.0, "datetime": "2026-01-01T12:00:00Z"}, "longitude"),
])
def test_bad_parameters(variant_rgb, props, words):
    """Bad parameters fail at load with one line naming the parameter."""
    import mitsuba as mi

    with pytest.raises(Exception) as error:
        mi.load_dict({"type": "sun", **props})
    assert words in str(error.value) and "sun" in str(error.value)


def test_sample_direction_chi2(variant_rgb):
    """The sun's directions are uniform in solid angle over its disk: Pearson's chi-square
    test (mitsuba.chi2) against 1 / Omega inside the cone, for a disk of 20 degrees that
    the test's histogram resolves (its pdf is integrated on 64 x 64 points per cell: the
    cells that the disk's edge, a discontinuity, crosses need them)."""
    import drjit as dr
    import mitsuba as mi
    from mitsuba import chi2

    sun = mi.load_dict({"type": "sun", "angular_diameter": 20.0, "sun_azimuth": 30.0,
                        "sun_elevation": 50.0})
    it = dr.zeros(mi.Interaction3f)
    axis = np.array(dr.slice(sun.direction), dtype=np.float64)
    cos_alpha = np.cos(np.radians(10.0))

    def sample(s):
        ds, _ = sun.sample_direction(it, s)
        return ds.d

    def pdf(v):
        inside = v.x * axis[0] + v.y * axis[1] + v.z * axis[2] >= cos_alpha
        return dr.select(inside, 1.0 / (2 * np.pi * (1 - cos_alpha)), 0.0)

    test = chi2.ChiSquareTest(domain=chi2.SphericalDomain(), sample_func=sample, pdf_func=pdf,
                              sample_dim=2, sample_count=400_000, res=101, ires=64)
    assert test.run(0.01), test.messages


@pytest.mark.parametrize("variant_name", ["llvm_ad_rgb", "llvm_ad_mono", "llvm_ad_spectral"])
def test_cct_keeps_the_illuminance(variant_name):
    """A sun of a CIE daylight spectrum (``cct``) gives the same lux in every variant: the
    spectrum sets the colour, ``illuminance`` the scale; in RGB its colour is bluish at
    10000 K."""
    import mitsuba as mi

    import spectrace

    spectrace.set_variant(variant_name)
    light = {"type": "sun", "cct": 10000.0, "illuminance": E_N, "sun_elevation": 90.0}
    tol = RTOL_LUX if variant_name != "llvm_ad_spectral" else RTOL_SPECTRAL
    assert checks.lux_at(light, (0.0, 0.0), spp=256) == pytest.approx(E_N, rel=tol)
    if variant_name == "llvm_ad_rgb":
        rgb = np.array(mi.load_dict(light).texture.eval(mi.SurfaceInteraction3f())).ravel()
        assert rgb[2] > rgb[1] > rgb[0]


def test_sun_and_sky_together(variant_rgb):
    """A ``sun`` and a ``ciesky`` in one scene (the sun is a delta light, so Mitsuba's rule
    of one environment emitter holds), placed by one datetime: a horizontal plane receives
    the sky's E_h plus E_n sin(h), h the SPA elevation both share."""
    import mitsuba as mi
    from spectrace.plugins.emitters import solar

    place = {"latitude": 52.52, "longitude": 13.405, "datetime": "2026-06-20T15:00:00+02:00"}
    _, elevation = solar.solar_position(52.52, 13.405,
                                        solar.parse_datetime(place["datetime"], "test"))
    scene = checks.plane_scene({"type": "sun", "illuminance": E_N, **place})
    scene["sky"] = {"type": "ciesky", "sky_type": 12, "horizontal_illuminance": 15000.0,
                    **place}
    loaded = mi.load_dict(scene)
    sun, sky = sorted(loaded.emitters(), key=lambda e: type(e).__name__, reverse=True)
    assert (sun.azimuth, sun.elevation) == (sky.azimuth, sky.elevation)
    scene["sensor"] = {
        "type": "radiancemeter", "origin": [0.1, 0.5, 0.2], "direction": [0, -1, 0],
        "film": {"type": "hdrfilm", "width": 1, "height": 1, "pixel_format": "luminance",
                 "rfilter": {"type": "box"}},
        "sampler": {"type": "independent", "sample_count": 4096},
    }
    Y = np.array(mi.render(mi.load_dict(scene), seed=0), dtype=np.float64).ravel()[0]
    assert checks.lux_from_film_y(Y) == pytest.approx(
        15000.0 + E_N * np.sin(np.radians(elevation)), rel=0.01)
