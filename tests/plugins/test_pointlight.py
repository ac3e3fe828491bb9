"""Tests of the ``pointlight`` emitter (``plugins/emitters/pointlight.py``): equivalence with
Mitsuba's built-in ``point`` under every integrator, power, light tracing against direct
lighting, the emitter interface and its parameters."""

from __future__ import annotations

import emitter_checks as checks
import numpy as np
import pytest

P_LIGHT = (0.4, 1.5, -0.3)
#: Relative tolerance of two renders that must agree up to float rounding.
RTOL_SAME = 1e-5
#: Tolerance of a light-tracing estimate against direct lighting: relative error of the
#: mean over 8x8-pixel blocks of the channel sum (ptracer's noise there is about 1%).
RTOL_PTRACER = 0.04

INTEGRATORS = ["path", "direct", "ptracer", "prb"]


def intensities(variant: str) -> dict:
    """The kinds of spectra the light takes: value, RGB, d65, tabulated SPD, blackbody
    (all of them in the RGB and spectral variants; value and SPD in the mono and polarized
    ones, to keep the suite fast)."""
    kinds = {
        "value": 4.0,
        "rgb": {"type": "rgb", "value": [3.0, 2.0, 0.5]},
        "d65": {"type": "d65", "scale": 2.0},
        "spd": {"type": "spectrum", "value": [(400.0, 1.0), (550.0, 3.0), (700.0, 2.0)]},
    }
    if variant == "llvm_ad_spectral":
        kinds["blackbody"] = {"type": "blackbody", "temperature": 3000.0}
    if variant not in ("llvm_ad_rgb", "llvm_ad_spectral"):
        kinds = {name: kinds[name] for name in ("value", "spd")}
    return kinds


def scene_with_sphere(light: dict, integrator: str) -> dict:
    """The plane with a sphere on it (shadows and interreflection), perspective view."""
    scene = checks.plane_scene(light, integrator, spp=4, sensor="perspective", res=16)
    scene["sphere"] = {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5}
    return scene


@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_matches_builtin_point(any_variant, integrator):
    """With the default 1/r^2 law the plugin renders exactly like Mitsuba's ``point``
    (same seed, same image up to float rounding), for every kind of spectrum, in every
    variant (RGB, mono, spectral, and the polarized ones, where the light emits a
    depolarizing Mueller matrix)."""
    import mitsuba as mi

    for name, intensity in intensities(any_variant).items():
        if name == "blackbody" and integrator == "ptracer":
            continue  # Mitsuba's blackbody cannot be sampled in ptracer's symbolic loop
        images = []
        for plugin in ("point", "pointlight"):
            light = {"type": plugin, "position": list(P_LIGHT), "intensity": intensity}
            scene = mi.load_dict(scene_with_sphere(light, integrator))
            images.append(np.array(mi.render(scene, seed=7)))
        reference, image = images
        assert reference.max() > 0.0, name
        np.testing.assert_allclose(image, reference, rtol=RTOL_SAME,
                                   atol=RTOL_SAME * reference.max(), err_msg=name)


def test_sample_direction_matches_builtin_in_every_variant(any_variant):
    """``sample_direction``, ``eval_direction`` and ``sample_ray`` return what Mitsuba's
    ``point`` returns, value for value: in polarized variants the same depolarizing Mueller
    matrix (only its (0, 0) entry is non-zero), elsewhere the same spectrum."""
    import drjit as dr
    import mitsuba as mi

    spd = {"type": "spectrum", "value": [(400.0, 1.0), (550.0, 3.0), (700.0, 2.0)]}
    ours, builtin = (mi.load_dict({"type": plugin, "position": list(P_LIGHT), "intensity": spd})
                     for plugin in ("pointlight", "point"))
    it = dr.zeros(mi.Interaction3f, 3)
    it.p = mi.Point3f([0.0, 1.0, -1.0], [0.0, 0.0, 0.5], [0.0, 2.0, 0.0])
    it.wavelengths = checks.wavelength_grid(3).wavelengths
    ds, value = ours.sample_direction(it, mi.Point2f(0.3, 0.7))
    ds_ref, value_ref = builtin.sample_direction(it, mi.Point2f(0.3, 0.7))
    assert type(value) is type(value_ref) is mi.Spectrum
    np.testing.assert_allclose(np.array(value), np.array(value_ref), rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(np.array(ours.eval_direction(it, ds)), np.array(value_ref),
                               rtol=1e-6, atol=1e-12)
    _, weight = ours.sample_ray(0.0, 0.4, mi.Point2f(0.5), mi.Point2f(0.2, 0.9))
    _, weight_ref = builtin.sample_ray(0.0, 0.4, mi.Point2f(0.5), mi.Point2f(0.2, 0.9))
    np.testing.assert_allclose(np.array(weight), np.array(weight_ref), rtol=1e-5, atol=1e-12)


def test_power_is_intensity_integrated_over_sphere(variant):
    """``power`` Phi gives I = Phi / (4 pi): the intensity integrated over the sphere of
    directions (midpoint quadrature of eval_direction at unit distance) is Phi."""
    import mitsuba as mi

    power = 10.0
    light = mi.load_dict({"type": "pointlight", "position": list(P_LIGHT),
                          "power": checks.uniform(power)})
    directions, weights = checks.sphere_quadrature(16, 32)
    intensity = checks.eval_intensity(light, directions)
    np.testing.assert_allclose(intensity, power / (4 * np.pi), rtol=1e-5)
    np.testing.assert_allclose(weights @ intensity, power, rtol=1e-5)


def test_power_renders_like_intensity(variant):
    """A light of power Phi renders like Mitsuba's ``point`` of intensity Phi / (4 pi)."""
    power = 20.0
    image = checks.render({"type": "pointlight", "position": list(P_LIGHT), "power": power})
    reference = checks.builtin_point(P_LIGHT, power / (4 * np.pi))
    checks.assert_image_close(image, reference, rtol=RTOL_SAME)


def block_means(image: np.ndarray, block: int = 8) -> np.ndarray:
    h, w, c = image.shape
    return image.reshape(h // block, block, w // block, block, c).mean(axis=(1, 3))


def test_ptracer_agrees_with_direct(variant):
    """Light tracing (``ptracer``: sample_ray, splatting to the camera) converges to the
    direct-lighting image of the same lit plane (block means within ptracer's noise)."""
    light = {"type": "pointlight", "position": list(P_LIGHT), "intensity": 3.0}
    direct = checks.render(light, "direct", spp=16, sensor="perspective")
    traced = checks.render(light, {"type": "ptracer", "max_depth": 2}, spp=256,
                           sensor="perspective", seed=3)
    # Channel sums: spectral variants add colour noise that cancels in the sum.
    np.testing.assert_allclose(block_means(traced).sum(-1), block_means(direct).sum(-1),
                               rtol=RTOL_PTRACER)


def test_position_and_to_world_place_the_light_alike(variant_rgb):
    """``to_world``'s translation places the light like ``position``; both at once fail."""
    import mitsuba as mi

    T = checks.transform()
    a = checks.render({"type": "pointlight", "position": list(P_LIGHT)})
    b = checks.render({"type": "pointlight", "to_world": T.translate(list(P_LIGHT))})
    checks.assert_image_close(b, a, rtol=RTOL_SAME)
    with pytest.raises(Exception, match="'position'"):
        mi.load_dict({"type": "pointlight", "position": [0, 1, 0],
                      "to_world": T.translate([0, 1, 0])})


def test_emitter_interface(variant):
    """The delta-position interface: flags, sample_direction (sets ds.emitter, pdf 1,
    delta), pdf_direction 0, eval 0, sample_position at the light, bbox the point,
    sample_ray a uniform direction of weight 4 pi I (as the built-in ``point``)."""
    import drjit as dr
    import mitsuba as mi

    light = mi.load_dict({"type": "pointlight", "position": list(P_LIGHT),
                          "intensity": checks.uniform(2.0)})
    assert light.flags() == int(mi.EmitterFlags.DeltaPosition)
    it = dr.zeros(mi.Interaction3f, 3)
    it.p = mi.Point3f([0.0, 1.0, -1.0], [0.0, 0.0, 0.5], [0.0, 2.0, 0.0])
    it.wavelengths = checks.wavelength_grid(3).wavelengths
    ds, value = light.sample_direction(it, mi.Point2f(0.3, 0.7))
    v = np.array(P_LIGHT)[:, None] - np.array(it.p)
    r2 = (v**2).sum(axis=0)
    np.testing.assert_allclose(np.array(ds.d), v / np.sqrt(r2), rtol=1e-6, atol=1e-7)
    np.testing.assert_allclose(np.array(ds.dist), np.sqrt(r2), rtol=1e-6)
    np.testing.assert_allclose(np.array(value), np.broadcast_to(2.0 / r2, np.array(value).shape),
                               rtol=1e-6)
    assert np.all(np.array(ds.pdf) == 1.0) and np.all(np.array(ds.delta))
    assert dr.all(ds.emitter == mi.EmitterPtr(light), axis=None)
    assert dr.all(light.pdf_direction(it, ds) == 0.0)
    np.testing.assert_allclose(np.array(light.eval_direction(it, ds)), np.array(value), rtol=1e-6)
    si = dr.zeros(mi.SurfaceInteraction3f)
    assert dr.all(light.eval(si) == 0.0, axis=None)
    ps, weight = light.sample_position(0.0, mi.Point2f(0.5))
    np.testing.assert_allclose(np.array(ps.p).ravel(), P_LIGHT, rtol=1e-7)
    assert bool(ps.delta[0]) and float(weight[0]) == 1.0
    box = light.bbox()
    np.testing.assert_allclose(list(box.min), P_LIGHT, rtol=1e-7)
    np.testing.assert_allclose(list(box.max), P_LIGHT, rtol=1e-7)
    ray, ray_weight = light.sample_ray(0.0, 0.5, mi.Point2f(0.5), mi.Point2f(0.2, 0.9))
    np.testing.assert_allclose(np.array(ray.o).ravel(), P_LIGHT, rtol=1e-7)
    np.testing.assert_allclose(float(dr.norm(ray.d)[0]), 1.0, rtol=1e-6)
    builtin = mi.load_dict({"type": "point", "position": list(P_LIGHT),
                            "intensity": checks.uniform(2.0)})
    ray_ref, weight_ref = builtin.sample_ray(0.0, 0.5, mi.Point2f(0.5), mi.Point2f(0.2, 0.9))
    np.testing.assert_allclose(np.array(ray.d), np.array(ray_ref.d), rtol=1e-6)
    np.testing.assert_allclose(np.array(ray_weight), np.array(weight_ref), rtol=1e-6)
    if variant == "llvm_ad_rgb":  # spectral weights also divide by the wavelength pdf
        np.testing.assert_allclose(np.array(ray_weight).ravel(), 4 * np.pi * 2.0, rtol=1e-6)


def test_sample_wavelengths_are_shifted_like_builtin(variant_spectral):
    """In spectral variants the light draws its wavelengths as the built-in ``point`` does:
    one sample shifted over the four channels (stratified, all different)."""
    import drjit as dr
    import mitsuba as mi

    spd = {"type": "spectrum", "value": [(400.0, 1.0), (550.0, 3.0), (700.0, 2.0)]}
    ours = mi.load_dict({"type": "pointlight", "intensity": spd})
    builtin = mi.load_dict({"type": "point", "intensity": spd})
    si = dr.zeros(mi.SurfaceInteraction3f, 5)
    sample = mi.Float(0.05, 0.3, 0.5, 0.77, 0.99)
    wl, weight = ours.sample_wavelengths(si, sample)
    wl_ref, weight_ref = builtin.sample_wavelengths(si, sample)
    np.testing.assert_allclose(np.array(wl), np.array(wl_ref), rtol=1e-6)
    np.testing.assert_allclose(np.array(weight), np.array(weight_ref), rtol=1e-6)
    wl = np.array(wl)
    assert np.all(np.abs(np.diff(np.sort(wl, axis=0), axis=0)) > 1.0)


def test_traverse_intensity_differentiable_and_position_updatable(variant_rgb):
    """``intensity`` is a differentiable parameter (d value / d I = value / I) and
    ``position`` can be changed (the light and its bbox move)."""
    import drjit as dr
    import mitsuba as mi

    light = mi.load_dict({"type": "pointlight", "position": [0, 2, 0], "intensity": 3.0})
    params = mi.traverse(light)
    assert "intensity.value" in params and "position" in params
    assert params.flags("intensity.value") & int(mi.ParamFlags.NonDifferentiable) == 0
    dr.enable_grad(params["intensity.value"])
    params.update()
    it = dr.zeros(mi.Interaction3f)
    ds, value = light.sample_direction(it, mi.Point2f(0.5))
    dr.backward(value[0])
    np.testing.assert_allclose(dr.grad(params["intensity.value"])[0], 1.0 / 4.0,
                               rtol=1e-6)
    params["position"] = mi.Point3f(0, 1, 0)
    params.update()
    ds, value = light.sample_direction(it, mi.Point2f(0.5))
    np.testing.assert_allclose(float(dr.detach(value)[0][0]), 3.0, rtol=1e-6)
    assert list(light.bbox().min) == [0.0, 1.0, 0.0]


def test_reference_page(variant_rgb):
    """The module docstrings of ``pointlight`` and of its helper ``delta`` follow the one
    reference-page format (table columns, sections, marks), and the |exposed| /
    |differentiable| marks agree with what mi.traverse reports for each way of giving the
    emission."""
    import mitsuba as mi
    from spectrace.plugins.emitters import delta, pointlight

    checks.parse_reference_page(delta.__doc__, "delta")
    table = checks.parse_reference_page(pointlight.__doc__, "pointlight")
    assert {"intensity", "power", "luminous_intensity", "luminous_flux", "spectrum",
            "position", "falloff"} <= set(table)
    assert table["luminous_intensity"]["unit"] == "cd"
    assert table["luminous_flux"]["unit"] == "lm"
    for emission in ({"intensity": 2.0}, {"power": 2.0}, {"luminous_intensity": 2.0},
                     {"luminous_flux": 2.0}):
        light = mi.load_dict({"type": "pointlight", **emission})
        checks.check_marks_against_traverse(table, light)
