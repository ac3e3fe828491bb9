"""Tests of ``spectrace.lighting.glare``: Guth's position index, the UGR of CIE 117 on a
synthetic luminance image with a closed-form answer and on a render of a Mitsuba area
light under a uniform sky, and the edge cases.

Oracles: UGR = 8 log10(0.25 / L_b * L^2 omega / P^2) for one small uniform source of
known luminance L, solid angle omega (2 pi (1 - cos alpha) for a cone; a quadrature of
cos / r^2 over a rectangle) and position (sigma, tau), with the closed-form fit of Guth's
index written here.
"""

from __future__ import annotations

import numpy as np
import pytest

#: The issue's tolerance on UGR (one glare rating step is 3).
ATOL_UGR = 0.5
KM = 683.0


def guth(sigma, tau):
    """Guth's position index, closed-form fit (sigma, tau in degrees)."""
    return np.exp((35.2 - 0.31889 * tau - 1.22 * np.exp(-2 * tau / 9)) * 1e-3 * sigma
                  + (21 + 0.26667 * tau - 0.002963 * tau**2) * 1e-5 * sigma**2)


def ugr_one_source(L_b, L, omega, sigma, tau):
    return 8 * np.log10(0.25 / L_b * L**2 * omega / guth(sigma, tau) ** 2)


def direction(sigma, tau):
    """The unit direction sigma degrees from the line of sight -Z, tau degrees from the
    vertical plane through it (towards +X)."""
    s, t = np.radians(sigma), np.radians(tau)
    return np.array([np.sin(s) * np.sin(t), np.sin(s) * np.cos(t), -np.cos(s)])


def camera(width, height, fov=100.0, eye=(0.0, 1.2, 0.0)):
    import mitsuba as mi

    T = mi.ScalarTransform4f
    eye = list(eye)
    return mi.load_dict({"type": "perspective", "fov": fov, "fov_axis": "x",
                         "to_world": T().look_at(eye, [eye[0], eye[1], eye[2] - 1], [0, 1, 0]),
                         "film": {"type": "hdrfilm", "width": width, "height": height}})


def test_position_index():
    """P = 1 on the line of sight and grows away from it; tau = 0 (above) grows fastest."""
    from spectrace.lighting.glare import guth_position_index

    assert guth_position_index(0.0, 37.0) == pytest.approx(1.0)
    sigma = np.linspace(0, 80, 9)
    for tau in (0.0, 45.0, 90.0):
        assert np.all(np.diff(guth_position_index(sigma, tau)) > 0)
    np.testing.assert_allclose(guth_position_index(sigma, 20.0), guth(sigma, 20.0))


@pytest.mark.parametrize(("sigma", "tau"), [(30.0, 20.0), (15.0, 60.0), (40.0, 0.0)])
def test_synthetic_source_matches_closed_form(variant_rgb, sigma, tau):
    """A uniform background L_b and one cone of half-angle 2 degrees at (sigma, tau) of
    luminance L in a 320 x 240 perspective image: UGR within ATOL_UGR of the formula."""
    from spectrace.lighting.glare import ugr
    from spectrace.lighting.luminance import pixel_geometry

    _, forward, d, omega = pixel_geometry(camera(320, 240))
    L_b, L, alpha = 20.0, 2e4, 2.0
    Y = np.full(omega.shape, L_b)
    Y[d @ direction(sigma, tau) > np.cos(np.radians(alpha))] = L
    result = ugr(Y, d, omega, forward)
    expected = ugr_one_source(L_b, L, 2 * np.pi * (1 - np.cos(np.radians(alpha))), sigma, tau)
    assert result.UGR == pytest.approx(expected, abs=ATOL_UGR)
    assert result.L_b == pytest.approx(L_b)


def test_rendered_area_light_under_a_uniform_sky(variant):
    """A 0.3 m square Mitsuba ``area`` light of radiance L_e facing down at 2.2 m, ahead
    of and above an eye at 1.2 m, under a uniform sky of radiance L_s: its luminance
    image (one jittered sample per pixel, so the source's edge pixels are its area on
    average) gives the UGR of the closed form with L = K_m integral(V) L_e,
    L_b = K_m integral(V) L_s and omega the square's solid angle (quadrature)."""
    import mitsuba as mi
    from spectrace.plugins.emitters import luminous

    from spectrace.lighting.glare import ugr
    from spectrace.lighting.luminance import luminance_image

    T = mi.ScalarTransform4f
    centre, half, L_e, L_s = np.array([0.4, 2.2, -2.0]), 0.15, 20.0, 0.02
    scene = mi.load_dict({
        "type": "scene", "sensor": camera(256, 192, fov=90.0),
        "sky": {"type": "constant", "radiance": {"type": "uniform", "value": L_s}},
        "lamp": {"type": "rectangle", "bsdf": {"type": "diffuse", "reflectance": 0.0},
                 "to_world": T().translate(centre.tolist()).rotate([1, 0, 0], 90).scale(half),
                 "emitter": {"type": "area", "radiance": {"type": "uniform", "value": L_e}}},
    })
    image = luminance_image(scene, spp=1, seed=5)
    result = ugr(image.Y, image.directions, image.solid_angle, image.forward)
    eye = np.array([0.0, 1.2, 0.0])
    n = 200
    u = (np.arange(n) + 0.5) / n * 2 * half - half
    x, z = np.meshgrid(centre[0] + u, centre[2] + u)
    v = np.stack([x, np.full_like(x, centre[1]), z], axis=-1) - eye
    r = np.linalg.norm(v, axis=-1)
    omega = np.sum(v[..., 1] / r**3) * (2 * half / n) ** 2
    d = (centre - eye) / np.linalg.norm(centre - eye)
    sigma = np.degrees(np.arccos(-d[2]))
    tau = np.degrees(np.arctan2(abs(d[0]), d[1]))
    scale = KM * luminous.v_integral()
    expected = ugr_one_source(scale * L_s, scale * L_e, omega, sigma, tau)
    assert result.UGR == pytest.approx(expected, abs=ATOL_UGR)
    assert result.L_b == pytest.approx(scale * L_s, rel=1e-3)


def test_no_source_and_vertical_line_of_sight(variant_rgb):
    """A uniform image has no glare source (UGR None); a vertical line of sight has no
    vertical plane for tau and is refused."""
    from spectrace.errors import ParameterError
    from spectrace.lighting.glare import position_angles, ugr
    from spectrace.lighting.luminance import pixel_geometry

    _, forward, d, omega = pixel_geometry(camera(32, 24))
    assert ugr(np.full(omega.shape, 50.0), d, omega, forward).UGR is None
    with pytest.raises(ParameterError, match="vertical"):
        position_angles(d, [0.0, -1.0, 0.0])
