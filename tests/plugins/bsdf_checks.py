"""Checks shared by the tests of the ``phong`` and ``blinnphong`` BSDFs (a plain module).

Each check takes the plugin name and, where needed, the lobe written in numpy (the
oracle: the closed-form formula, independent of the plugin's Dr.Jit code).
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi  # one module whatever the variant: mi.Float etc. follow set_variant
import numpy as np

#: Relative tolerance of float32 evaluations against float64 formulas.
RTOL_EVAL = 2e-4
#: Absolute tolerance for values that must vanish or agree exactly up to rounding.
ATOL = 1e-6
#: Significance level of the chi-square tests (mitsuba.chi2 applies Sidak's correction).
CHI2_SIGNIFICANCE = 0.01
#: Chi-square settings (samples, histogram resolution, integration points per cell side)
#: for ordinary lobes and for sharp ones (m >= 100), whose pdf varies within a coarse
#: cell too much for the trapezoid rule near the horizon.
CHI2_SETTINGS = {"ordinary": (400_000, 101, 12), "sharp": (1_000_000, 201, 16)}
#: Wavelengths (nm) set on surface interactions in spectral variants.
WAVELENGTHS = (450.0, 520.0, 580.0, 640.0)


def load(plugin: str, **params):
    return mi.load_dict({"type": plugin, **params})


def hemisphere(rng, n, lower=False):
    """n uniformly distributed unit vectors with z > 0 (z < 0 when ``lower``), shape (n, 3)."""
    v = rng.normal(size=(n, 3))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    v[:, 2] = np.abs(v[:, 2]) * (-1.0 if lower else 1.0)
    return v


def direction(theta_deg, phi_deg=0.0):
    t, p = np.radians(theta_deg), np.radians(phi_deg)
    return np.array([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)])


def surface_interaction(wi, n=None):
    """A SurfaceInteraction3f at uv (0.5, 0.5) with local incident directions ``wi``."""
    wi = np.atleast_2d(np.asarray(wi, dtype=float))
    if n is None:
        n = wi.shape[0]
    if wi.shape[0] == 1 and n > 1:
        wi = np.repeat(wi, n, axis=0)
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = mi.Vector3f(wi[:, 0], wi[:, 1], wi[:, 2])
    si.uv = mi.Point2f(0.5, 0.5)
    si.n = mi.Normal3f(0, 0, 1)
    si.sh_frame = mi.Frame3f(si.n)
    if mi.is_spectral:
        si.wavelengths = mi.UnpolarizedSpectrum(*WAVELENGTHS)
    return si


def vec(a):
    a = np.asarray(a, dtype=float)
    return mi.Vector3f(a[:, 0], a[:, 1], a[:, 2])


def spectrum_np(x):
    """A Mitsuba spectrum as a numpy array of shape (n, channels)."""
    return np.array(mi.unpolarized_spectrum(x), dtype=np.float64).T


def eval_np(bsdf, wi, wo):
    """bsdf.eval and bsdf.pdf at local directions (n, 3) as numpy arrays."""
    si = surface_interaction(wi)
    ctx = mi.BSDFContext()
    value = spectrum_np(bsdf.eval(ctx, si, vec(wo)))
    pdf = np.array(bsdf.pdf(ctx, si, vec(wo)), dtype=np.float64)
    return value, pdf


def model_np(lobe, normalization, wi, wo, rho, rho_s, m, normalized):
    """Closed-form f * cos(theta_o) (front side only) for a lobe given in numpy."""
    k = normalization(m) if normalized else 1.0
    front = (wi[:, 2] > 0) & (wo[:, 2] > 0)
    f = rho / np.pi + rho_s * k * lobe(wi, wo, m)
    return np.where(front, f * wo[:, 2], 0.0)


def sample(bsdf, wi, n, seed=0):
    """(bs, weight) for n samples at incident direction wi, from a seeded PCG32."""
    si = surface_interaction(wi, n)
    rng = mi.PCG32(size=n, initstate=mi.UInt64(seed) + 12345)
    bs, weight = bsdf.sample(
        mi.BSDFContext(), si, rng.next_float32(), mi.Point2f(rng.next_float32(), rng.next_float32())
    )
    return si, bs, weight


def chi2_adapter(params: dict, wi):
    """(sample_func, pdf_func) for mitsuba.chi2.ChiSquareTest that, unlike the stock
    BSDFAdapter, sets the wavelengths of the surface interaction in spectral variants."""

    bsdf = mi.load_dict(params)
    ctx = mi.BSDFContext()

    def sample_func(u):
        si = surface_interaction(wi, dr.width(u))
        bs, weight = bsdf.sample(ctx, si, u.x, mi.Point2f(u.y, u.z))
        valid = dr.any(mi.unpolarized_spectrum(weight) > 0)
        return bs.wo, dr.select(valid, 1.0, 0.0)

    def pdf_func(wo):
        si = surface_interaction(wi, dr.width(wo))
        return bsdf.pdf(ctx, si, wo)

    return sample_func, pdf_func


def chi2_test(params: dict, theta_deg: float, test_count: int = 1):
    """Run Pearson's chi-square test of sample() against pdf(); returns the test object."""
    from mitsuba import chi2

    sample_func, pdf_func = chi2_adapter(params, direction(theta_deg, 30.0))
    samples, res, ires = CHI2_SETTINGS["sharp" if params["exponent"] >= 100 else "ordinary"]
    test = chi2.ChiSquareTest(
        domain=chi2.SphericalDomain(),
        sample_func=sample_func,
        pdf_func=pdf_func,
        sample_dim=3,
        sample_count=samples,
        res=res,
        ires=ires,
    )
    test.passed = test.run(CHI2_SIGNIFICANCE, test_count=test_count, quiet=True)
    return test


def albedo_quadrature(bsdf, theta_deg: float, n_theta=400, n_phi=200):
    """Directional albedo by midpoint quadrature of eval over the hemisphere (no sampling).

    Per channel; the lobe must be resolved by the grid (exponents up to a few hundred).
    """
    t = (np.arange(n_theta) + 0.5) * (np.pi / 2) / n_theta
    p = (np.arange(n_phi) + 0.5) * 2 * np.pi / n_phi
    T, P = np.meshgrid(t, p, indexing="ij")
    wo = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1).reshape(-1, 3)
    value, _ = eval_np(bsdf, direction(theta_deg)[None, :].repeat(len(wo), 0), wo)
    d_omega = (np.sin(T).ravel() * (np.pi / 2 / n_theta) * (2 * np.pi / n_phi))[:, None]
    return (value * d_omega).sum(axis=0)


#: Seed of prb's differential phase, reused by the finite-difference renders.
SEED_GRAD = 7


def prb_gradient_and_fd(plugin: str, key: str, value: float, h: float, res=16, spp=4):
    """d mean(image) / d parameter by prb's reverse mode, and by central differences.

    A sphere lit by Mitsuba's point light only, max_depth 2: the image is linear in the
    reflectances, so the finite difference is exact up to rounding.
    """

    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "prb", "max_depth": 2},
        "sensor": {
            "type": "perspective",
            "fov": 30,
            "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 5], target=[0, 0, 0],
                                                        up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": res, "height": res, "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": spp},
        },
        "light": {"type": "point", "position": [2.0, 2.0, 3.0],
                  "intensity": {"type": "uniform", "value": 20.0}},
        "ball": {
            "type": "sphere",
            "bsdf": {"type": plugin, "exponent": 8.0, "diffuse_reflectance": 0.5,
                     "specular_reflectance": 0.3},
        },
    })
    params = mi.traverse(scene)

    def render(v, grad=False):
        params[key] = mi.Float(v)
        if grad:
            dr.enable_grad(params[key])
        params.update()
        # prb's differential phase draws its samples with seed_grad; the finite
        # differences use those same samples (primal renders with seed=SEED_GRAD).
        seeds = (1, SEED_GRAD) if grad else (SEED_GRAD, SEED_GRAD + 1)
        image = mi.render(scene, params, seed=seeds[0], seed_grad=seeds[1], spp=spp)
        return dr.mean(image.array), params[key]

    loss, p = render(value, grad=True)
    dr.backward(loss)
    grad = float(dr.grad(p)[0])
    plus = float(dr.detach(render(value + h)[0])[0])
    minus = float(dr.detach(render(value - h)[0])[0])
    return grad, (plus - minus) / (2 * h)


# -- checks called by the tests of both plugins -----------------------------------------

EXPONENTS = (0.5, 2.0, 8.0, 37.0, 250.0)


def check_eval_matches_formula(plugin, lobe, normalization, rng, n=2000):
    """eval at random directions (both hemispheres) equals the closed-form model."""
    for m in EXPONENTS:
        for normalized in (False, True):
            rho, rho_s = rng.uniform(0, 1, size=2)
            bsdf = load(plugin, exponent=m, normalized=normalized,
                        diffuse_reflectance=rho, specular_reflectance=rho_s)
            wi = hemisphere(rng, n)
            wo = hemisphere(rng, n)
            wo[: n // 4, 2] *= -1  # a quarter below the surface
            wi[n // 4 : n // 2, 2] *= -1
            value, _ = eval_np(bsdf, wi, wo)
            expected = model_np(lobe, normalization, wi, wo, rho, rho_s, m, normalized)
            np.testing.assert_allclose(value, np.repeat(expected[:, None], value.shape[1], 1),
                                       rtol=RTOL_EVAL, atol=ATOL,
                                       err_msg=f"{plugin} m={m} normalized={normalized}")


def check_rgb_reflectances(plugin, lobe, normalization, rng, n=500):
    """RGB reflectances act per channel: eval = rho_c/pi + rho_s,c k lobe per channel."""
    rho, rho_s = np.array([0.7, 0.3, 0.1]), np.array([0.1, 0.5, 0.9])
    bsdf = load(plugin, exponent=12.0, diffuse_reflectance={"type": "rgb", "value": list(rho)},
                specular_reflectance={"type": "rgb", "value": list(rho_s)})
    wi, wo = hemisphere(rng, n), hemisphere(rng, n)
    value, _ = eval_np(bsdf, wi, wo)
    for c in range(3):
        expected = model_np(lobe, normalization, wi, wo, rho[c], rho_s[c], 12.0, False)
        np.testing.assert_allclose(value[:, c], expected, rtol=RTOL_EVAL, atol=ATOL)


def check_diffuse_part_matches_mitsuba(plugin, rng, n=500):
    """With rho_s = 0 the BSDF is Mitsuba's `diffuse` (eval, pdf, sample weights), for an
    RGB reflectance in RGB and spectral variants (Mitsuba's own upsampling)."""
    rgb = {"type": "rgb", "value": [0.8, 0.4, 0.1]}
    ours = load(plugin, diffuse_reflectance=rgb, specular_reflectance=0.0)
    ref = load("diffuse", reflectance=rgb)
    wi, wo = hemisphere(rng, n), hemisphere(rng, n)
    v1, p1 = eval_np(ours, wi, wo)
    v2, p2 = eval_np(ref, wi, wo)
    np.testing.assert_allclose(v1, v2, rtol=RTOL_EVAL, atol=ATOL)
    np.testing.assert_allclose(p1, p2, rtol=RTOL_EVAL, atol=ATOL)
    _, _, w1 = sample(ours, direction(40.0), 1000)
    _, _, w2 = sample(ref, direction(40.0), 1000)
    np.testing.assert_allclose(spectrum_np(w1), spectrum_np(w2), rtol=RTOL_EVAL, atol=ATOL)
    si = surface_interaction(direction(10.0))
    np.testing.assert_allclose(spectrum_np(ours.eval_diffuse_reflectance(si)),
                               spectrum_np(ref.eval_diffuse_reflectance(si)), rtol=RTOL_EVAL)


def check_reciprocity(plugin, rng, n=2000):
    """Helmholtz reciprocity: f(wi, wo) = f(wo, wi), i.e. eval(wi,wo)/cos_o = eval(wo,wi)/cos_i."""
    for m in (1.0, 20.0, 300.0):
        for normalized in (False, True):
            bsdf = load(plugin, exponent=m, normalized=normalized)
            wi, wo = hemisphere(rng, n), hemisphere(rng, n)
            a, _ = eval_np(bsdf, wi, wo)
            b, _ = eval_np(bsdf, wo, wi)
            np.testing.assert_allclose(a / wo[:, 2:3], b / wi[:, 2:3], rtol=1e-3, atol=ATOL)


def check_below_horizon(plugin, rng, n=1000):
    """Front side only: eval and pdf vanish when wi or wo is below the surface, and
    sampling from below the surface returns weight 0."""
    bsdf = load(plugin, exponent=5.0, normalized=True)
    up, down = hemisphere(rng, n), hemisphere(rng, n, lower=True)
    for wi, wo in ((up, down), (down, up), (down, hemisphere(rng, n, lower=True))):
        value, pdf = eval_np(bsdf, wi, wo)
        assert np.all(value == 0) and np.all(pdf == 0)
    _, _, weight = sample(bsdf, direction(120.0), 1000)
    assert np.all(spectrum_np(weight) == 0)
    _, bs, weight = sample(bsdf, direction(70.0), 20000)
    wo_z = np.array(bs.wo.z)
    assert np.all(spectrum_np(weight)[wo_z <= 0] == 0)


def check_weight_is_eval_over_pdf(plugin, n=20000):
    """sample() returns weight = eval/pdf and bs.pdf = pdf at the sampled direction."""
    for m, normalized, theta in ((3.0, False, 20.0), (80.0, True, 60.0)):
        bsdf = load(plugin, exponent=m, normalized=normalized,
                    diffuse_reflectance={"type": "rgb", "value": [0.3, 0.5, 0.2]},
                    specular_reflectance=0.4)
        si, bs, weight = sample(bsdf, direction(theta), n)
        ctx = mi.BSDFContext()
        value, pdf = bsdf.eval_pdf(ctx, si, bs.wo)
        w, v, p = spectrum_np(weight), spectrum_np(value), np.array(pdf)
        valid = p > 0
        assert valid.mean() > 0.5
        np.testing.assert_allclose(np.array(bs.pdf)[valid], p[valid], rtol=RTOL_EVAL)
        np.testing.assert_allclose(w[valid], v[valid] / p[valid, None], rtol=1e-3, atol=ATOL)
        assert np.all(w[~valid] == 0)
        np.testing.assert_allclose(spectrum_np(bsdf.eval(ctx, si, bs.wo)), v, rtol=RTOL_EVAL)
        np.testing.assert_allclose(np.array(bsdf.pdf(ctx, si, bs.wo)), p, rtol=RTOL_EVAL)


def weight_cv(plugin, theta, m=120.0, n=100_000):
    """Coefficient of variation of the sample weights of a pure normalized lobe (rho = 0)."""
    bsdf = load(plugin, exponent=m, normalized=True, diffuse_reflectance=0.0,
                specular_reflectance=1.0)
    _, _, weight = sample(bsdf, direction(theta), n)
    w = spectrum_np(weight)[:, 0]
    return w.std() / w.mean(), w


def check_components(plugin, lobe, normalization, rng, n=500):
    """A BSDFContext selecting one component gives that component alone, for eval and
    for sample (which then only draws that component)."""

    rho, rho_s, m = 0.6, 0.3, 10.0
    bsdf = load(plugin, exponent=m, diffuse_reflectance=rho, specular_reflectance=rho_s)
    wi, wo = hemisphere(rng, n), hemisphere(rng, n)
    si = surface_interaction(wi)
    for component, expected in (
        (0, model_np(lobe, normalization, wi, wo, rho, 0.0, m, False)),
        (1, model_np(lobe, normalization, wi, wo, 0.0, rho_s, m, False)),
    ):
        ctx = mi.BSDFContext()
        ctx.component = component
        value = spectrum_np(bsdf.eval(ctx, si, vec(wo)))[:, 0]
        np.testing.assert_allclose(value, expected, rtol=RTOL_EVAL, atol=ATOL)
        bs, _ = bsdf.sample(ctx, si, mi.Float(rng.uniform(size=n)),
                            mi.Point2f(rng.uniform(size=n), rng.uniform(size=n)))
        assert np.all(np.array(bs.sampled_component) == component)
    assert bsdf.flags() == (bsdf.flags(0) | bsdf.flags(1))
    assert mi.has_flag(bsdf.flags(0), mi.BSDFFlags.DiffuseReflection)
    assert mi.has_flag(bsdf.flags(1), mi.BSDFFlags.GlossyReflection)
    assert mi.has_flag(bsdf.flags(), mi.BSDFFlags.FrontSide)


def check_traverse(plugin, lobe, normalization, rng, n=200):
    """Parameters exposed by traverse update eval (reflectances and exponent)."""
    bsdf = load(plugin, exponent=4.0, diffuse_reflectance=0.2, specular_reflectance=0.2)
    params = mi.traverse(bsdf)
    for key in ("diffuse_reflectance.value", "specular_reflectance.value", "exponent"):
        assert key in params
        assert params.flags(key) & int(mi.ParamFlags.NonDifferentiable) == 0
    params["diffuse_reflectance.value"] = 0.7
    params["specular_reflectance.value"] = 0.1
    params["exponent"] = 30.0
    params.update()
    wi, wo = hemisphere(rng, n), hemisphere(rng, n)
    value, _ = eval_np(bsdf, wi, wo)
    expected = model_np(lobe, normalization, wi, wo, 0.7, 0.1, 30.0, False)
    np.testing.assert_allclose(value[:, 0], expected, rtol=RTOL_EVAL, atol=ATOL)


BAD_PARAMETERS = (
    ({"exponent": -1.0}, "exponent"),
    ({"exponent": 0.0}, "exponent"),
    ({"exponent": float("nan")}, "exponent"),
    ({"exponent": float("inf")}, "exponent"),
    ({"diffuse_reflectance": 1.5}, "diffuse_reflectance"),
    ({"specular_reflectance": -0.2}, "specular_reflectance"),
    ({"specular_reflectance": {"type": "rgb", "value": [1.2, 0.0, 0.0]}}, "specular_reflectance"),
    ({"normalized": "yes"}, "normalized"),
    ({"exponnent": 3.0}, "exponnent"),
)


def check_bad_parameter(plugin, params, name):
    """An invalid parameter fails at load with a message naming the plugin and parameter."""
    import pytest

    with pytest.raises(Exception) as info:
        mi.load_dict({"type": plugin, **params})
    assert f"{plugin}: " in str(info.value) and repr(name) in str(info.value)


def check_exponent_gradient(plugin, lobe, normalization, rng, n=1000):
    """d eval / d exponent (forward-mode AD through traverse) equals the central
    difference of the closed-form model, and stays finite where the lobe vanishes
    (random directions: r.wo <= 0 for about half of them with phong)."""

    m, h = 6.0, 1e-3
    wi, wo = hemisphere(rng, n), hemisphere(rng, n)
    for normalized in (False, True):
        bsdf = load(plugin, exponent=m, normalized=normalized, diffuse_reflectance=0.2,
                    specular_reflectance=0.5)
        params = mi.traverse(bsdf)
        dr.enable_grad(params["exponent"])
        params.update()
        value = bsdf.eval(mi.BSDFContext(), surface_interaction(wi), vec(wo))
        dr.forward(params["exponent"])
        grad = spectrum_np(dr.grad(value))[:, 0]
        expected = (model_np(lobe, normalization, wi, wo, 0.2, 0.5, m + h, normalized)
                    - model_np(lobe, normalization, wi, wo, 0.2, 0.5, m - h, normalized)) / (2 * h)
        assert np.all(np.isfinite(grad))
        np.testing.assert_allclose(grad, expected, rtol=1e-2, atol=1e-4)
        assert "exponent = 6" in str(bsdf)


def check_textured_reflectance(plugin, lobe, normalization, rng, n=1000):
    """A texture (Mitsuba's checkerboard) as diffuse_reflectance is looked up at the hit's
    uv: with rho_s = 0 the BSDF equals Mitsuba's `diffuse` with the same texture, and the
    specular texture scales the lobe."""

    checker = {"type": "checkerboard", "color0": 0.1, "color1": 0.9}
    ours = load(plugin, diffuse_reflectance=checker, specular_reflectance=0.0)
    ref = load("diffuse", reflectance=checker)
    wi, wo = hemisphere(rng, n), hemisphere(rng, n)
    si = surface_interaction(wi)
    si.uv = mi.Point2f(rng.uniform(size=n), rng.uniform(size=n))
    ctx = mi.BSDFContext()
    np.testing.assert_allclose(spectrum_np(ours.eval(ctx, si, vec(wo))),
                               spectrum_np(ref.eval(ctx, si, vec(wo))), rtol=RTOL_EVAL, atol=ATOL)
    glossy = load(plugin, diffuse_reflectance=0.0, specular_reflectance=checker, exponent=5.0)
    value = spectrum_np(glossy.eval(ctx, si, vec(wo)))[:, 0]
    u, v = np.array(si.uv.x), np.array(si.uv.y)
    rho_s = np.where((u > 0.5) == (v > 0.5), 0.1, 0.9)  # checkerboard: color0 where equal
    expected = model_np(lobe, normalization, wi, wo, 0.0, 1.0, 5.0, False) * rho_s
    np.testing.assert_allclose(value, expected, rtol=RTOL_EVAL, atol=ATOL)
