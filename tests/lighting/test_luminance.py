"""Tests of ``spectrace.lighting.luminance``: the luminance of a uniform sky and of a
diffuse floor under a point light against closed forms in every variant, the exact solid
angles of a perspective camera's pixels, and the EXR it writes.

Oracles: L_v = K_m integral V L (flat spectra: K_m integral(V) L, the integral from
colour-science); a Lambertian floor of albedo rho under I at height h: L = rho / pi *
I h / r^3; the solid angle of a rectangular pyramid of half-angles a, b:
4 arcsin(sin a sin b).
"""

from __future__ import annotations

import numpy as np
import pytest

#: Exact cases (a single light, flat spectra: no random part) against float64.
RTOL_EXACT = 1e-5
#: Pixel solid angles (float32 ray directions) against the closed form.
RTOL_SOLID_ANGLE = 1e-4
KM = 683.0


def v_integral() -> float:
    import colour

    V = colour.colorimetry.SDS_LEFS_PHOTOPIC["CIE 1924 Photopic Standard Observer"]
    return float(np.sum(V[np.arange(360.0, 831.0)]))


def test_sky_and_lit_floor(any_variant):
    """Rays into a uniform sky of radiance L see K_m integral(V) L cd/m^2; rays looking
    down at a diffuse floor (albedo 0.5) under a 100 cd light 1 m above see
    rho / pi * 100 h / r^3 (direct light only, max_depth 1)."""
    import mitsuba as mi

    from spectrace.lighting.luminance import luminance_along

    flat = {"type": "uniform", "value": 0.25}
    sky = mi.load_dict({"type": "scene", "sky": {"type": "constant", "radiance": flat}})
    L, err = luminance_along(sky, [[0, 0, 0], [1, 2, 3]], [[0, 1, 0], [1, 0, 0]], spp=4)
    np.testing.assert_allclose(L, KM * v_integral() * 0.25, rtol=RTOL_EXACT)
    assert np.all(err < RTOL_EXACT * L)
    T = mi.ScalarTransform4f
    floor = mi.load_dict({
        "type": "scene",
        "floor": {"type": "rectangle", "to_world": T().rotate([1, 0, 0], -90).scale(10),
                  "bsdf": {"type": "diffuse", "reflectance": {"type": "uniform", "value": 0.5}}},
        "light": {"type": "pointlight", "position": [0, 1, 0], "luminous_intensity": 100.0,
                  "spectrum": {"type": "uniform", "value": 1.0}},
    })
    x = np.array([0.0, 0.5, 1.5])
    origins = np.column_stack([x, np.full(3, 0.5), np.zeros(3)])
    L, _ = luminance_along(floor, origins, np.tile([0.0, -1.0, 0.0], (3, 1)), spp=4)
    r = np.sqrt(x**2 + 1.0)
    np.testing.assert_allclose(L, 0.5 / np.pi * 100.0 / r**3, rtol=RTOL_EXACT)


def test_pixel_solid_angles(variant_rgb):
    """The pixels of a 60 x 40 degree perspective camera subtend in all the pyramid's
    4 arcsin(sin a sin b), and the centre pixel about its (pixel angle)^2."""
    import mitsuba as mi

    from spectrace.lighting.luminance import pixel_geometry

    width, height = 60, 40
    a = np.radians(30.0)
    b = np.arctan(np.tan(a) * height / width)
    sensor = mi.load_dict({"type": "perspective", "fov": 60.0, "fov_axis": "x",
                           "film": {"type": "hdrfilm", "width": width, "height": height}})
    _, forward, d, omega = pixel_geometry(sensor)
    np.testing.assert_allclose(omega.sum(), 4 * np.arcsin(np.sin(a) * np.sin(b)),
                               rtol=RTOL_SOLID_ANGLE)
    np.testing.assert_allclose(np.linalg.norm(d, axis=-1), 1.0, rtol=1e-6)
    np.testing.assert_allclose(forward, [0, 0, 1], atol=1e-6)
    pixel = 2 * np.tan(a) / width
    assert omega[height // 2, width // 2] == pytest.approx(pixel**2, rel=1e-3)


def test_luminance_image_and_exr(variant_rgb, tmp_path):
    """A camera inside a uniform sky sees K_m integral(V) L in every pixel, and the EXR
    holds it as channel Y with units cd/m^2."""
    import mitsuba as mi
    import OpenEXR

    from spectrace.lighting.luminance import luminance_image, write_luminance_exr

    scene = mi.load_dict({"type": "scene",
                          "sky": {"type": "constant", "radiance": 0.5},
                          "sensor": {"type": "perspective", "film": {
                              "type": "hdrfilm", "width": 8, "height": 6}}})
    image = luminance_image(scene, spp=2)
    np.testing.assert_allclose(image.Y, KM * v_integral() * 0.5, rtol=RTOL_EXACT)
    path = tmp_path / "L.exr"
    write_luminance_exr(path, image)
    with OpenEXR.File(str(path)) as f:
        assert f.header()["units"] == "cd/m^2"
        np.testing.assert_allclose(f.channels()["Y"].pixels, image.Y, rtol=1e-6)
