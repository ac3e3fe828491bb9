"""Tests of the ``spotlight`` emitter (``plugins/emitters/spotlight.py``): closed-form
radiometry of the three cone falloffs, equivalence with Mitsuba's built-in ``spot``, power,
``sample_ray`` (chi-square), light tracing, parameters and the scene
``scenes/spotlight_stage.xml``."""

from __future__ import annotations

from pathlib import Path

import emitter_checks as checks
import numpy as np
import pytest

SCENE = Path(__file__).resolve().parents[2] / "scenes" / "spotlight_stage.xml"
GOBO = Path(__file__).resolve().parents[2] / "scenes" / "textures" / "gobo_window.png"
P_LIGHT = (0.4, 1.5, -0.3)
TARGET = (0.1, 0.0, 0.2)
UMBRA, PENUMBRA = 40.0, 20.0
INTENSITY = 3.0
#: Relative tolerance of two renders that must agree up to float rounding.
RTOL_SAME = 1e-5
#: Relative tolerance of float32 evaluations against float64 formulas (acos near the axis).
RTOL_EVAL = 1e-4
#: Relative tolerance of the power against the quadrature of the emitted intensity.
RTOL_POWER = 1e-4
#: Block means (channel sums) of ptracer against direct lighting: about 1% noise.
RTOL_PTRACER = 0.04
#: Significance level of the chi-square test.
CHI2_SIGNIFICANCE = 0.01


def cone_profile(cos_alpha, umbra: float, penumbra: float, law: str):
    """cone(alpha) of each ``cone_falloff`` value, written out in numpy (the oracle)."""
    cos_alpha = np.asarray(cos_alpha, dtype=np.float64)
    cos_u, cos_p = np.cos(np.radians(umbra)), np.cos(np.radians(penumbra))
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.clip((cos_alpha - cos_u) / (cos_p - cos_u), 0.0, 1.0)
        if law == "quadratic":
            return t**2
        if law == "smoothstep":
            return 3 * t**2 - 2 * t**3
        alpha = np.arccos(np.clip(cos_alpha, -1.0, 1.0))
        ramp = np.clip((np.radians(umbra) - alpha) / np.radians(umbra - penumbra), 0.0, 1.0)
        return np.where(cos_alpha > cos_u, ramp, 0.0)


CONE_LAWS = ["quadratic", "smoothstep", "linear_angle"]


def spot(law: str = "quadratic", umbra: float = UMBRA, penumbra: float = PENUMBRA,
         **extra) -> dict:
    T = checks.transform()
    return {"type": "spotlight", "to_world": T.look_at(list(P_LIGHT), list(TARGET), [0, 0, 1]),
            "intensity": INTENSITY, "umbra_angle": umbra, "penumbra_angle": penumbra,
            "cone_falloff": law, **extra}


def builtin_spot(**extra) -> dict:
    T = checks.transform()
    return {"type": "spot", "to_world": T.look_at(list(P_LIGHT), list(TARGET), [0, 0, 1]),
            "intensity": INTENSITY, "cutoff_angle": UMBRA, "beam_width": PENUMBRA, **extra}


def cos_alpha_at(points: np.ndarray) -> np.ndarray:
    axis = np.subtract(TARGET, P_LIGHT)
    axis /= np.linalg.norm(axis)
    v = points - np.asarray(P_LIGHT)
    return (v @ axis) / np.linalg.norm(v, axis=-1)


@pytest.fixture(scope="module")
def plane_positions():
    import spectrace

    spectrace.set_variant("llvm_ad_rgb")
    return checks.positions()


@pytest.mark.parametrize("law", CONE_LAWS)
def test_cone_falloff_on_lit_plane(variant, plane_positions, law):
    """A diffuse plane under the spot has the radiance rho/pi * I0 * cone(alpha) / r^2 *
    cos(theta) at every pixel: full inside the penumbra, dark outside the umbra, each law
    in between (RGB: absolute; both variants: relative to the built-in ``point``)."""
    image = checks.render(spot(law))
    cone = cone_profile(cos_alpha_at(plane_positions), UMBRA, PENUMBRA, law)
    assert np.any(cone == 0.0) and np.any(cone == 1.0) and np.any((cone > 0.05) & (cone < 0.95))
    reference = checks.builtin_point(P_LIGHT, INTENSITY)
    checks.assert_image_close(image, reference * cone[..., None], rtol=RTOL_EVAL)
    if variant == "llvm_ad_rgb":
        expected = checks.closed_form(plane_positions, P_LIGHT,
                                      lambda d, r: INTENSITY * cone / r**2)
        checks.assert_image_close(image, expected, rtol=RTOL_EVAL)


def test_cone_and_distance_laws_combine(variant, plane_positions):
    """With a distance law the radiance is rho/pi * I0 * cone(alpha) * falloff(r) * cos."""
    image = checks.render(spot("smoothstep", falloff="polynomial", kc=1.0, kl=0.5, kq=0.25))
    r = np.linalg.norm(plane_positions - np.asarray(P_LIGHT), axis=-1)
    factor = cone_profile(cos_alpha_at(plane_positions), UMBRA, PENUMBRA, "smoothstep") * (
        r**2 / (1.0 + 0.5 * r + 0.25 * r**2))
    reference = checks.builtin_point(P_LIGHT, INTENSITY)
    checks.assert_image_close(image, reference * factor[..., None], rtol=RTOL_EVAL)


def test_hard_edge_when_penumbra_equals_umbra(variant_rgb, plane_positions):
    """penumbra = umbra is a hard-edged cone: full intensity inside, none outside."""
    image = checks.render(spot("quadratic", umbra=30.0, penumbra=30.0))
    inside = cos_alpha_at(plane_positions) > np.cos(np.radians(30.0))
    expected = checks.closed_form(plane_positions, P_LIGHT,
                                  lambda d, r: INTENSITY * inside / r**2)
    ambiguous = np.abs(np.degrees(np.arccos(cos_alpha_at(plane_positions))) - 30.0) < 1e-3
    checks.assert_image_close(image[~ambiguous], expected[~ambiguous], rtol=RTOL_EVAL)


@pytest.mark.parametrize("integrator", ["path", "direct", "ptracer", "prb"])
def test_linear_angle_matches_builtin_spot(any_variant, integrator):
    """``cone_falloff=linear_angle`` renders like Mitsuba's ``spot`` (cutoff_angle = umbra,
    beam_width = penumbra), with and without a gobo texture, same seed, same image, in
    every variant (RGB intensity: RGB and spectral variants only, to keep it fast)."""
    import mitsuba as mi

    texture = {"type": "bitmap", "filename": str(GOBO)}
    cases = {"plain": {}, "gobo": {"texture": texture},
             "rgb": {"intensity": {"type": "rgb", "value": [3.0, 1.0, 0.5]}}}
    if any_variant not in ("llvm_ad_rgb", "llvm_ad_spectral"):
        del cases["rgb"]
    for name, extra in cases.items():
        images = []
        for light in (builtin_spot(**extra), spot("linear_angle", **extra)):
            scene = checks.plane_scene(light, integrator, spp=4, sensor="perspective", res=16)
            scene["sphere"] = {"type": "sphere", "center": [0.1, 0.3, 0.2], "radius": 0.3}
            images.append(np.array(mi.render(mi.load_dict(scene), seed=5)))
        reference, image = images
        assert reference.max() > 0.0
        np.testing.assert_allclose(image, reference, rtol=RTOL_SAME,
                                   atol=RTOL_SAME * reference.max(), err_msg=name)


ANGLES = [(30.0, 20.0), (45.0, 45.0), (60.0, 5.0), (90.0, 30.0), (10.0, 9.99)]


@pytest.mark.parametrize("law", CONE_LAWS)
def test_power_is_intensity_integrated_over_sphere(variant, law):
    """``power`` Phi sets I0 so that the emitted intensity integrated over the sphere
    (quadrature of eval_direction) is Phi, for every cone law and pair of angles."""
    import mitsuba as mi

    power = 5.0
    for umbra, penumbra in ANGLES:
        light = mi.load_dict({"type": "spotlight", "power": checks.uniform(power),
                              "umbra_angle": umbra, "penumbra_angle": penumbra,
                              "cone_falloff": law})
        alpha, weights = angle_quadrature(penumbra, umbra)
        # the spot is symmetric about its axis (local +Z): directions in the xz-plane
        directions = np.stack([np.sin(alpha), np.zeros_like(alpha), np.cos(alpha)], axis=-1)
        intensity = checks.eval_intensity(light, directions)[:, 0]
        total = weights @ intensity
        np.testing.assert_allclose(total, power, rtol=RTOL_POWER, err_msg=f"{umbra}/{penumbra}")
        # and I0 (on the axis) is Phi over the integral of the closed-form profile
        omega = weights @ cone_profile(np.cos(alpha), umbra, penumbra, law)
        np.testing.assert_allclose(intensity[0], power / omega, rtol=RTOL_POWER)


def angle_quadrature(penumbra: float, umbra: float, order: int = 48):
    """Gauss-Legendre nodes alpha and weights for integrals over the sphere of functions
    of the angle alpha from the axis (weight 2 pi sin alpha), exact up to rounding for the
    profiles, which are smooth on [0, penumbra], [penumbra, umbra] and [umbra, pi]."""
    x, w = np.polynomial.legendre.leggauss(order)
    edges = [0.0, np.radians(penumbra), np.radians(umbra), np.pi]
    alphas, weights = [], []
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        if b > a:
            alpha = 0.5 * (b - a) * x + 0.5 * (b + a)
            alphas.append(alpha)
            weights.append(0.5 * (b - a) * w * 2 * np.pi * np.sin(alpha))
    return np.concatenate(alphas), np.concatenate(weights)


@pytest.mark.parametrize("source_radius", [0.0, 0.2])
def test_sample_ray_chi2(variant_rgb, source_radius):
    """``sample_ray`` draws directions uniformly in the umbra cone around the light's
    world +Z axis (mitsuba.chi2 against the closed-form uniform-cone density), from the
    point or from points of the disk of ``source_radius``."""
    import drjit as dr
    import mitsuba as mi
    from mitsuba import chi2

    umbra = 35.0
    T = checks.transform()
    to_world = T.look_at([0, 0, 0], [0.3, -1.0, 0.4], [0, 0, 1])
    light = mi.load_dict({"type": "spotlight", "to_world": to_world, "umbra_angle": umbra,
                          "penumbra_angle": 10.0, "source_radius": source_radius})
    axis = np.array([0.3, -1.0, 0.4]) / np.linalg.norm([0.3, -1.0, 0.4])
    cos_u = np.cos(np.radians(umbra))

    def sample(s):
        if source_radius == 0:
            ray, _ = light.sample_ray(0.0, 0.5, s, mi.Point2f(0.5))
        else:  # the direction comes from sample3, the point of the disk from sample2
            ray, _ = light.sample_ray(0.0, 0.5, mi.Point2f(0.3, 0.8), s)
        return ray.d

    def pdf(v):
        cos_a = v.x * axis[0] + v.y * axis[1] + v.z * axis[2]
        return dr.select(cos_a >= cos_u, 1.0 / (2 * np.pi * (1 - cos_u)), 0.0)

    test = chi2.ChiSquareTest(domain=chi2.SphericalDomain(), sample_func=sample,
                              pdf_func=pdf, sample_dim=2, sample_count=400_000, res=101,
                              ires=16)
    assert test.run(CHI2_SIGNIFICANCE), test.messages


@pytest.mark.parametrize("law", CONE_LAWS)
def test_sample_ray_weight(variant_rgb, rng, law):
    """The weight of a ray from ``sample_ray`` is I(alpha) / pdf(direction), with the
    uniform-cone pdf 1 / (2 pi (1 - cos umbra))."""
    import mitsuba as mi

    light = mi.load_dict({"type": "spotlight", "intensity": INTENSITY, "umbra_angle": UMBRA,
                          "penumbra_angle": PENUMBRA, "cone_falloff": law})
    u = rng.random((2, 1000)).astype(np.float32)
    ray, weight = light.sample_ray(0.0, 0.5, mi.Point2f(u[0], u[1]), mi.Point2f(0.5))
    cos_alpha = np.array(ray.d)[2]
    pdf = 1.0 / (2 * np.pi * (1 - np.cos(np.radians(UMBRA))))
    expected = INTENSITY * cone_profile(cos_alpha, UMBRA, PENUMBRA, law) / pdf
    np.testing.assert_allclose(np.array(weight)[0], expected, rtol=RTOL_EVAL,
                               atol=RTOL_EVAL * expected.max())


@pytest.mark.parametrize("law", ["quadratic", "smoothstep"])
def test_ptracer_agrees_with_direct(variant, law):
    """Light tracing from the spot (sample_ray) converges to the direct-lighting image."""
    light = spot(law)
    direct = checks.render(light, "direct", spp=16, sensor="perspective")
    traced = checks.render(light, {"type": "ptracer", "max_depth": 2}, spp=256,
                           sensor="perspective", seed=3)

    def block_sums(image, block=8):
        h, w, c = image.shape
        return image.reshape(h // block, block, w // block, block, c).mean(axis=(1, 3)).sum(-1)

    np.testing.assert_allclose(block_sums(traced), block_sums(direct), rtol=RTOL_PTRACER,
                               atol=RTOL_PTRACER * block_sums(direct).max())


def test_emitter_interface(variant):
    """Delta position; the light shines along its world +Z (eval I0 on the axis, 0 behind);
    sample_direction sets ds.emitter, pdf 1, delta; pdf_direction and eval are 0;
    sample_position at the light with its axis as normal; bbox the point."""
    import drjit as dr
    import mitsuba as mi

    light = mi.load_dict(spot("quadratic", intensity=checks.uniform(INTENSITY)))
    assert light.flags() == int(mi.EmitterFlags.DeltaPosition)
    axis = np.subtract(TARGET, P_LIGHT) / np.linalg.norm(np.subtract(TARGET, P_LIGHT))
    values = checks.eval_intensity(light, np.stack([axis, -axis]), distance=1.0)
    np.testing.assert_allclose(values[0], INTENSITY, rtol=RTOL_EVAL)
    assert np.all(values[1] == 0.0)
    it = dr.zeros(mi.Interaction3f)
    it.p = mi.Point3f(*(float(c) for c in np.add(P_LIGHT, 2 * axis)))
    it.wavelengths = checks.wavelength_grid(1).wavelengths
    ds, value = light.sample_direction(it, mi.Point2f(0.5))
    np.testing.assert_allclose(np.array(value), INTENSITY / 4.0, rtol=RTOL_EVAL)
    np.testing.assert_allclose(np.array(ds.d).ravel(), -axis, rtol=1e-5, atol=1e-6)
    assert dr.all(ds.emitter == mi.EmitterPtr(light), axis=None)
    assert bool(ds.delta[0]) and float(ds.pdf[0]) == 1.0
    assert dr.all(light.pdf_direction(it, ds) == 0.0)
    assert dr.all(light.eval(dr.zeros(mi.SurfaceInteraction3f)) == 0.0, axis=None)
    ps, weight = light.sample_position(0.0, mi.Point2f(0.5))
    np.testing.assert_allclose(np.array(ps.p).ravel(), P_LIGHT, rtol=1e-6)
    np.testing.assert_allclose(np.array(ps.n).ravel(), axis, rtol=1e-5, atol=1e-6)
    box = light.bbox()
    np.testing.assert_allclose(list(box.min), P_LIGHT, rtol=1e-6)
    assert light.flags() == int(mi.EmitterFlags.DeltaPosition)
    gobo = mi.load_dict(spot(texture={"type": "bitmap", "filename": str(GOBO)}))
    assert gobo.flags() == int(mi.EmitterFlags.DeltaPosition | mi.EmitterFlags.SpatiallyVarying)


def test_angles_are_differentiable_and_update_the_cosines(variant_rgb):
    """``umbra_angle`` and ``penumbra_angle`` are differentiable scene parameters:
    changing them recomputes the cached cosines (the value follows the closed form with
    the new angles) and the gradient matches the derivative of the closed form."""
    import drjit as dr
    import mitsuba as mi

    light = mi.load_dict({"type": "spotlight", "intensity": INTENSITY,
                          "umbra_angle": 30.0, "penumbra_angle": 10.0})
    alpha = np.radians(17.0)
    direction = np.array([[np.sin(alpha), 0.0, np.cos(alpha)]])
    params = mi.traverse(light)
    for name in ("umbra_angle", "penumbra_angle", "intensity.value"):
        assert params.flags(name) & int(mi.ParamFlags.NonDifferentiable) == 0, name
    params["umbra_angle"] = 25.0
    params["penumbra_angle"] = 12.0
    params.update()
    value = checks.eval_intensity(light, direction)[0, 0]
    np.testing.assert_allclose(
        value, INTENSITY * cone_profile(np.cos(alpha), 25.0, 12.0, "quadratic"), rtol=RTOL_EVAL)
    dr.enable_grad(params["umbra_angle"], params["penumbra_angle"])
    params.update()
    it = dr.zeros(mi.Interaction3f)
    it.p = mi.Point3f(*(float(c) for c in direction[0]))
    ds = dr.zeros(mi.DirectionSample3f)
    ds.p = mi.Point3f(0.0)
    out = light.eval_direction(it, ds)
    dr.backward(out[0])
    h = 1e-4

    def f(u, p):
        return INTENSITY * cone_profile(np.cos(alpha), u, p, "quadratic")

    du = (f(25.0 + h, 12.0) - f(25.0 - h, 12.0)) / (2 * h)
    dp = (f(25.0, 12.0 + h) - f(25.0, 12.0 - h)) / (2 * h)
    np.testing.assert_allclose(dr.grad(params["umbra_angle"])[0], du, rtol=1e-3)
    np.testing.assert_allclose(dr.grad(params["penumbra_angle"])[0], dp, rtol=1e-3)


def test_power_follows_changed_angles(variant_rgb):
    """With ``power``, changing the angles keeps the emitted power (I0 is recomputed)."""
    import mitsuba as mi

    light = mi.load_dict({"type": "spotlight", "power": 2.0, "umbra_angle": 30.0,
                          "penumbra_angle": 10.0, "cone_falloff": "smoothstep"})
    params = mi.traverse(light)
    params["umbra_angle"] = 50.0
    params.update()
    cos_u, cos_p = np.cos(np.radians(50.0)), np.cos(np.radians(10.0))
    omega = 2 * np.pi * ((1 - cos_p) + 0.5 * (cos_p - cos_u))
    value = checks.eval_intensity(light, np.array([[0.0, 0.0, 1.0]]))[0, 0]
    np.testing.assert_allclose(value, 2.0 / omega, rtol=RTOL_EVAL)


INVALID_ANGLES = [
    ({"umbra_angle": 0.0}, "umbra_angle"),
    ({"umbra_angle": 91.0}, "umbra_angle"),
    ({"umbra_angle": -10.0}, "umbra_angle"),
    ({"penumbra_angle": 0.0}, "penumbra_angle"),
    ({"penumbra_angle": 35.0}, "penumbra_angle"),
    ({"umbra_angle": 20.0, "penumbra_angle": 25.0}, "penumbra_angle"),
    ({"cone_falloff": "cosine"}, "cone_falloff"),
]


@pytest.mark.parametrize(("params", "name"), INVALID_ANGLES)
def test_invalid_angles_fail_at_load(variant_rgb, params, name):
    """Angles outside (0, 90], penumbra > umbra and unknown cone laws fail at load, naming
    the parameter."""
    import mitsuba as mi

    with pytest.raises(Exception, match=f"spotlight: .*'{name}'"):
        mi.load_dict({"type": "spotlight", **params})


def test_spotlight_stage_scene_renders(variant_spectral):
    """scenes/spotlight_stage.xml (spectral: it has a blackbody spot) loads and renders at
    tiny size; the 3200 K spot is warmer (R/B larger) than the d65 one."""
    import mitsuba as mi

    scene = mi.load_file(str(SCENE), res=24, spp=4)
    image = np.array(mi.render(scene, seed=1))
    assert image.shape == (24, 24, 3) and np.all(np.isfinite(image)) and image.max() > 0.0
    names = [str(e) for e in scene.emitters()]
    assert len(names) == 6
    assert {n.split("cone_falloff=")[1].split(",")[0] for n in names} == set(CONE_LAWS)
    blackbody, d65 = (next(e for e in scene.emitters() if key in str(e))
                      for key in ("BlackBody", "D65"))
    si = checks.wavelength_grid(301)
    warm = np.array(blackbody.intensity.eval(si))[0]
    cool = np.array(d65.intensity.eval(si))[0]
    assert warm[-1] / warm[0] > 3 * cool[-1] / cool[0]


def test_to_world_can_be_changed(variant_rgb):
    """Changing ``to_world`` through mi.traverse moves and re-aims the spot: the cached
    position and inverse transform follow (on-axis intensity I0 along the new +Z)."""
    import mitsuba as mi

    light = mi.load_dict({"type": "spotlight", "intensity": INTENSITY})
    params = mi.traverse(light)
    T = checks.transform()
    params["to_world"] = mi.Transform4f(T.look_at([1.0, 2.0, 3.0], [1.0, 0.0, 3.0], [0, 0, 1]))
    params.update()
    values = checks.eval_intensity(light, np.array([[0.0, -1.0, 0.0], [0.0, 0.0, 1.0]]))
    np.testing.assert_allclose(values[0], INTENSITY, rtol=RTOL_EVAL)
    assert np.all(values[1] == 0.0)
    np.testing.assert_allclose(list(light.bbox().min), [1.0, 2.0, 3.0], rtol=1e-6)


def test_sample_wavelengths_weight_is_spectrum_over_pdf(variant_spectral):
    """In spectral variants sample_wavelengths draws shifted wavelengths whose weight times
    pdf_wavelengths is the intensity spectrum (here a 3000 K blackbody, Planck's law in
    Mitsuba's units W/(m^2 sr nm))."""
    import drjit as dr
    import mitsuba as mi

    light = mi.load_dict({"type": "spotlight",
                          "intensity": {"type": "blackbody", "temperature": 3000.0}})
    si = dr.zeros(mi.SurfaceInteraction3f, 3)
    wavelengths, weight = light.sample_wavelengths(si, mi.Float(0.1, 0.5, 0.9))
    pdf = light.pdf_wavelengths(wavelengths)
    lam = np.array(wavelengths) * 1e-9
    h, c, k = 6.62607015e-34, 2.99792458e8, 1.380649e-23
    planck = 2 * h * c**2 / lam**5 / np.expm1(h * c / (lam * k * 3000.0)) * 1e-9
    np.testing.assert_allclose(np.array(weight) * np.array(pdf), planck, rtol=1e-3)
    assert len(np.unique(np.round(np.array(wavelengths), 3))) == 12


def test_invalid_angles_fail_at_update(variant_rgb):
    """Angles set through mi.traverse are checked when the parameters are updated."""
    import mitsuba as mi

    light = mi.load_dict({"type": "spotlight", "umbra_angle": 30.0, "penumbra_angle": 10.0})
    params = mi.traverse(light)
    params["penumbra_angle"] = 40.0
    with pytest.raises(ValueError, match="penumbra_angle"):
        params.update()


def test_gobo_pdf_wavelengths_is_the_density_sampled(variant_spectral):
    """With a gobo, sample_wavelengths draws from the texture's spectral density (as the
    built-in ``spot``), so pdf_wavelengths must be that density: weight * pdf_wavelengths
    equals the emitted spectrum gobo(uv, lambda) * I(lambda) at every wavelength drawn (a
    blackbody intensity, whose own density differs, makes a wrong pdf visible)."""
    import drjit as dr
    import mitsuba as mi

    intensity = {"type": "blackbody", "temperature": 3000.0}
    light = mi.load_dict({"type": "spotlight", "intensity": intensity,
                          "texture": {"type": "bitmap", "filename": str(GOBO)}})
    gobo = mi.load_dict({"type": "bitmap", "filename": str(GOBO)})
    planck = mi.load_dict(intensity)
    n = 64
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    u = np.linspace(0.05, 0.95, n)
    si.uv = mi.Point2f(u, u[::-1])
    wavelengths, weight = light.sample_wavelengths(si, mi.Float(np.linspace(0.01, 0.99, n)))
    pdf = light.pdf_wavelengths(wavelengths)
    si.wavelengths = wavelengths
    emitted = np.array(gobo.eval(si)) * np.array(planck.eval(si))
    lit = emitted > 0.0
    assert lit.sum() > n  # the window is open over most of the gobo
    np.testing.assert_allclose((np.array(weight) * np.array(pdf))[lit], emitted[lit], rtol=1e-4)
    own = np.array(planck.pdf_spectrum(si))
    assert not np.allclose(own, np.array(pdf), rtol=1e-2)


def test_mitsuba_spot_angles_are_accepted(variant):
    """Mitsuba's ``spot`` calls the angles ``cutoff_angle`` and ``beam_width``: given to
    ``spotlight`` with ``cone_falloff=linear_angle`` they render exactly as ``spot`` with
    the same parameters, also with ``cutoff_angle`` alone (Mitsuba's beam width, 3/4 of
    the cutoff)."""
    import mitsuba as mi

    T = checks.transform()
    frame = T.look_at(list(P_LIGHT), list(TARGET), [0, 0, 1])
    for angles in ({"cutoff_angle": UMBRA, "beam_width": PENUMBRA}, {"cutoff_angle": UMBRA}):
        images = []
        for kind, extra in (("spot", {}), ("spotlight", {"cone_falloff": "linear_angle"})):
            light = {"type": kind, "to_world": frame, "intensity": INTENSITY, **angles, **extra}
            images.append(checks.render(light, spp=4, sensor="perspective", res=16, seed=2))
        assert images[0].max() > 0.0
        np.testing.assert_allclose(images[1], images[0], rtol=RTOL_SAME,
                                   atol=RTOL_SAME * images[0].max(), err_msg=str(angles))
    light = mi.load_dict({"type": "spotlight", "cutoff_angle": 40.0})
    assert float(mi.traverse(light)["penumbra_angle"][0]) == pytest.approx(30.0)


@pytest.mark.parametrize(("name", "ours"), [("cutoff_angle", "umbra_angle"),
                                            ("beam_width", "penumbra_angle")])
def test_both_names_of_an_angle_fail(variant_rgb, name, ours):
    """An angle given under both names (ours and Mitsuba's) fails in one line naming
    both."""
    import mitsuba as mi

    with pytest.raises(Exception) as info:
        mi.load_dict({"type": "spotlight", name: 20.0, ours: 20.0})
    line = next(l for l in str(info.value).splitlines() if "spotlight: " in l)
    assert f"'{name}'" in line and f"'{ours}'" in line, line


def test_reference_page(variant_rgb):
    """The module docstring of ``spotlight`` follows the one reference-page format, and
    its |exposed| / |differentiable| marks agree with mi.traverse (with and without a
    gobo, radiometric and luminous)."""
    import mitsuba as mi
    from spectrace.plugins.emitters import spotlight

    table = checks.parse_reference_page(spotlight.__doc__, "spotlight")
    assert {"umbra_angle", "penumbra_angle", "cone_falloff", "texture", "luminous_flux",
            "luminous_intensity", "spectrum"} <= set(table)
    assert table["umbra_angle"]["unit"] == "degrees"
    for extra in ({"intensity": 2.0, "texture": {"type": "bitmap", "filename": str(GOBO)}},
                  {"power": 2.0}, {"luminous_flux": 100.0}, {"luminous_intensity": 10.0}):
        checks.check_marks_against_traverse(
            table, mi.load_dict({"type": "spotlight", **extra}))
