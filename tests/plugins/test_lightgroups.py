"""Tests of the ``lightgroups`` integrator (``plugins/integrators/lightgroups.py``): the
layers sum to the beauty image, the beauty is Mitsuba's ``path`` (MIS, Russian roulette,
``max_depth``, ``hide_emitters``, area lights, environment maps, delta lights, smooth
BSDFs, spectrace's own emitters; every path-traced scene of ``scenes/``), a light's layer
is that light's image, relighting equals rendering the changed scene, and bad groups.

Oracles: Mitsuba's C++ ``path`` integrator, and the linearity of light transport.
"""

from __future__ import annotations

from pathlib import Path

import drjit as dr
import mitsuba as mi
import numpy as np
import pytest

import spectrace
from spectrace import lightgroups

ROOT = Path(__file__).resolve().parents[2]
#: The layers against the beauty of the same render: float32 sums of the same terms in
#: another order (relative to the image's largest value).
SUM_RTOL = 1e-5
#: The beauty against ``path``: the mean over pixels (and over a block) and SEEDS may differ
#: by this many standard errors of the seed-to-seed spread of the difference...
NOISE_SIGMAS = 5.0
#: ... or this fraction of the mean (float rounding where both estimates share samples).
MEAN_RTOL = 2e-3
#: The image is also compared block by block, blocks of BLOCK x BLOCK pixels.
BLOCK = 8
SEEDS = tuple(range(8))
RES = 16
SPP = 8
#: The path-traced scenes of scenes/ and their small-size parameters.
SCENE_FILES = {
    "showcase.xml": {"res": "16", "spp": "16"},
    "closed_box.xml": {"res": "16", "spp": "16"},
    "phong_vs_energy.xml": {"res": "16", "spp": "16"},
}


def _look_at(origin, target, up=(0, 1, 0)):
    return mi.ScalarTransform4f().look_at(origin=origin, target=target, up=up)


def _envmap():
    """A 16 x 8 latitude-longitude map, bright towards +x and the zenith."""
    v, u = np.meshgrid(np.linspace(0, 1, 8), np.linspace(0, 1, 16), indexing="ij")
    rgb = np.stack([0.2 + u, 0.3 + 0.5 * (1 - v), 0.4 + 0.2 * u * v], axis=-1)
    return mi.Bitmap(rgb.astype(np.float32))


def make_scene(case: str, spot_scale: float = 1.0, lamp_intensity=8.0, rfilter="box",
               **integrator) -> mi.Scene:
    """A floor, a rough-plastic sphere and a glass sphere under the lights of ``case``
    (the spot light's intensity times ``spot_scale``; the point light 'lamp' of 'delta'
    with ``lamp_intensity``), on a film with the reconstruction filter ``rfilter``."""
    lights = {
        "delta": {
            "lamp": {"type": "point", "position": [-1.5, 3.0, 1.5],
                     "intensity": lamp_intensity},
            "spot": {"type": "spotlight", "to_world": _look_at([2, 3, 2], [0, 0, 0]),
                     "intensity": {"type": "rgb",
                                   "value": [20 * spot_scale, 14 * spot_scale, 8 * spot_scale]}},
            "bulb": {"type": "pointlight", "position": [0.5, 2.0, -1.5], "intensity": 3.0},
        },
        "area": {
            "panel_shape": {"type": "rectangle",
                            "to_world": _look_at([0, 3, 0], [0, 0, 0], [0, 0, 1])
                            @ mi.ScalarTransform4f().scale(0.8),
                            "emitter": {"type": "area", "id": "panel",
                                        "radiance": {"type": "rgb", "value": [6, 5, 4]}}},
            "sky": {"type": "constant", "radiance": {"type": "rgb", "value": [0.2, 0.3, 0.5]}},
        },
        "envmap": {
            "env": {"type": "envmap", "bitmap": _envmap()},
            "lamp": {"type": "point", "position": [1.0, 3.0, 1.0], "intensity": 5.0},
        },
    }[case]
    glass = {"type": "sphere", "center": [0.9, 0.5, 0.3], "radius": 0.5,
             "bsdf": {"type": "dielectric"}}
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "path", **integrator},
        "sensor": {"type": "perspective", "fov": 45,
                   "to_world": _look_at([0, 2.5, 5], [0, 0.4, 0]),
                   "film": {"type": "hdrfilm", "width": RES, "height": RES,
                            "rfilter": {"type": rfilter}},
                   "sampler": {"type": "independent", "sample_count": SPP}},
        "floor": {"type": "rectangle", "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90)
                  @ mi.ScalarTransform4f().scale(4),
                  "bsdf": {"type": "diffuse",
                           "reflectance": {"type": "rgb", "value": [0.6, 0.5, 0.4]}}},
        "ball": {"type": "sphere", "center": [-0.7, 0.6, 0], "radius": 0.6,
                 "bsdf": {"type": "roughplastic", "alpha": 0.2,
                          "diffuse_reflectance": {"type": "rgb", "value": [0.2, 0.4, 0.7]}}},
        "glass": glass,
        **lights,
    })


#: (case, path parameters): what each exercises.
CASES = [
    ("delta", {"max_depth": 6}),  # delta lights, spectrace's pointlight/spotlight, glass
    ("area", {"max_depth": -1, "rr_depth": 1}),  # MIS on an area light, RR from the start
    ("area", {"max_depth": 2}),  # direct light only
    ("area", {"max_depth": 1}),  # emitters seen directly only
    ("area", {"max_depth": 5, "hide_emitters": True}),
    ("envmap", {"max_depth": 4}),  # an importance-sampled environment map
    ("envmap", {"max_depth": 4, "hide_emitters": True}),
]


def _beauty_and_layers(scene, seed, spp=SPP, groups=True):
    result = spectrace.render(scene, spp=spp, seed=seed, light_groups=groups)
    beauty, layers = lightgroups.split(result.image, result.light_groups)
    return beauty, layers


def _path(scene, seed, spp=SPP):
    return np.asarray(spectrace.render(scene, spp=spp, seed=seed).image)[..., :3]


def assert_matches_path(mine: list[np.ndarray], ref: list[np.ndarray]):
    """The beauty against ``path``'s: the mean over the image, and over each BLOCK x BLOCK
    block of pixels (a bias anywhere in the image fails it), averaged over the seeds."""
    diff = np.stack(mine) - np.stack(ref)  # (seeds, H, W, 3)
    scale = max(float(np.stack(ref).mean()), 1e-6)
    n, h, w, c = diff.shape
    blocks = diff.reshape(n, h // BLOCK, BLOCK, w // BLOCK, BLOCK, c).mean(axis=(2, 4))
    for values in (diff.mean(axis=(1, 2, 3)), blocks.reshape(n, -1)):
        se = values.std(axis=0, ddof=1) / np.sqrt(n)
        excess = np.abs(values.mean(axis=0)) - (NOISE_SIGMAS * se + MEAN_RTOL * scale)
        assert np.max(excess) <= 0.0, (np.max(excess), scale)


def assert_layers_sum(beauty, layers):
    total = sum(layers.values())
    np.testing.assert_allclose(total, beauty, rtol=0,
                               atol=SUM_RTOL * max(float(np.abs(beauty).max()), 1e-6))


def _check_layers_and_path(scene):
    """The beauty of each of SEEDS (its layers checked to sum to it), and ``path``'s."""
    mine, ref = [], []
    for seed in SEEDS:
        beauty, layers = _beauty_and_layers(scene, seed)
        assert_layers_sum(beauty, layers)
        mine.append(beauty)
        ref.append(_path(scene, seed))
    return mine, ref


@pytest.mark.parametrize(("case", "params"), CASES)
def test_layers_sum_to_beauty_and_beauty_is_path(variant, case, params):
    """Light is additive: the layers of one render sum to its beauty image (float
    precision); and the beauty is the radiance Mitsuba's ``path`` estimates (within Monte
    Carlo noise over eight seeds), so no contribution is lost or double-counted by MIS,
    Russian roulette, the depth limit or hidden emitters."""
    scene = make_scene(case, **params)
    mine, ref = _check_layers_and_path(scene)
    assert np.isfinite(np.stack(mine)).all() and np.stack(ref).mean() > 0
    assert_matches_path(mine, ref)


@pytest.mark.parametrize(("case", "params"), CASES)
def test_same_seed_traces_the_same_paths_as_path(variant, case, params):
    """The integrator draws its samples in the order of Mitsuba 3.9's ``path`` (light
    sample, BSDF sample, roulette), so with the same seed it traces the same paths and its
    beauty equals ``path``'s pixel by pixel up to float rounding: a stronger check than
    agreement within noise (any difference in a decision shows)."""
    scene = make_scene(case, **params)
    beauty, _ = _beauty_and_layers(scene, seed=11)
    ref = _path(scene, seed=11)
    np.testing.assert_allclose(beauty, ref, rtol=0, atol=SUM_RTOL * float(ref.max()))


#: Film filters other than box: Mitsuba's splatted default, and one with negative lobes.
FILTERS = ("gaussian", "lanczos", "tent")
#: The chi-square test's significance level (Mitsuba's ``mitsuba.chi2``).
CHI2_SIGNIFICANCE = 0.01
#: A filter sample's |weight| against (int |f|)^2: the tabulated filter's interpolation.
WEIGHT_RTOL = 0.05


@pytest.mark.parametrize("rfilter", FILTERS[:2])
def test_importance_sampled_filter_gives_paths_filtered_image(variant, rfilter):
    """With a Gaussian or Lanczos film the filter is importance sampled, not splatted: the
    beauty is still the filtered image that ``path`` (which splats) estimates, within
    noise over eight seeds, and the layers still sum to it."""
    scene = make_scene("area", rfilter=rfilter, max_depth=4)
    mine, ref = _check_layers_and_path(scene)
    assert np.isfinite(np.stack(mine)).all()
    assert_matches_path(mine, ref)


@pytest.mark.parametrize("rfilter", FILTERS)
def test_filter_offsets_follow_the_filter(variant_rgb, rfilter):
    """Filter importance sampling draws a sample's offset from the pixel centre with
    density |f(x) f(y)| / (int |f|)^2 (chi-square test against the filter evaluated by
    Mitsuba, normalised by quadrature), and its weight f(x) f(y) / pdf is the constant
    (int |f|)^2 with the sign of f(x) f(y), so the estimate is the filtered image."""
    from mitsuba import chi2
    from spectrace.plugins.integrators.lightgroups import sample_filter

    f = mi.load_dict({"type": rfilter})
    r = float(f.radius())
    x = np.linspace(-r, r, 200_001)
    fx = np.abs(np.asarray(f.eval(mi.Float(x))))
    norm = float(np.sum((fx[1:] + fx[:-1]) / 2) * (x[1] - x[0]))  # int |f|, trapezoids

    def pdf(p):
        return dr.abs(f.eval(p.x) * f.eval(p.y)) / norm**2

    test = chi2.ChiSquareTest(domain=chi2.PlanarDomain(mi.ScalarBoundingBox2f(-r, r)),
                              sample_func=lambda u: sample_filter(f, u)[0],
                              pdf_func=pdf, sample_dim=2, sample_count=400_000, res=61,
                              ires=8)
    assert test.run(CHI2_SIGNIFICANCE), test.messages
    signed = float(np.sum((fx[1:] + fx[:-1]) / 2 * np.sign(np.asarray(
        f.eval(mi.Float((x[1:] + x[:-1]) / 2))))) * (x[1] - x[0]))  # int f
    u = np.random.default_rng(3).random((2, 100_000)).astype(np.float32)
    offset, weight = sample_filter(f, mi.Point2f(u[0], u[1]))
    fxy = np.asarray(f.eval(offset.x) * f.eval(offset.y))
    sign, w = np.sign(fxy), np.asarray(weight)
    # |weight| is (int |f|)^2 up to the table's linear interpolation (float32 sampling,
    # the kinks of |f| at a negative lobe's zero crossings, the float32 cancellation in
    # the tail of Mitsuba's gaussian): bounded above (no fireflies), constant in the bulk
    keep = np.abs(fxy) > 1e-3 * np.abs(fxy).max()
    assert np.all(np.abs(w) <= (1 + WEIGHT_RTOL) * norm**2)
    assert np.all(w[keep] * sign[keep] > 0)
    np.testing.assert_allclose(np.median(np.abs(w)), norm**2, rtol=1e-4)
    # E[weight] = int int f(x) f(y) dx dy: the estimator's normalisation is unbiased
    se = w.std() / np.sqrt(w.size)
    assert abs(w.mean() - signed**2) <= 4 * se + 1e-4 * norm**2, (w.mean(), signed**2, se)


@pytest.mark.parametrize("name", sorted(SCENE_FILES))
def test_scenes_of_the_project_match_path(variant, name):
    """Every path-traced scene of scenes/ (spectrace's phong, blinnphong, pointlight,
    spotlight beside Mitsuba's BSDFs and lights): the beauty is ``path``'s within noise and
    the layers sum to it."""
    from spectrace.scene import load_scene

    scene = load_scene(ROOT / "scenes" / name, SCENE_FILES[name])
    assert_matches_path(*_check_layers_and_path(scene))


def test_a_layer_is_the_image_of_its_light_alone(variant_rgb):
    """Linearity: the layer of the area light equals a ``path`` render of the scene with
    only that light (and the sky's layer the scene with only the sky), within noise."""
    scene = make_scene("area", max_depth=4)
    layers_by_seed = [_beauty_and_layers(scene, seed)[1] for seed in SEEDS]
    for name, keep in (("panel", "panel"), ("sky", "sky")):
        alone = make_scene("area", max_depth=4)
        params = mi.traverse(alone)
        other = "sky" if keep == "panel" else "panel"
        key = "sky.radiance.value" if other == "sky" else "panel_shape.emitter.radiance.value"
        params[key] = dr.zeros(type(params[key]), dr.width(params[key]))
        params.update()
        ref = [_path(alone, seed) for seed in SEEDS]
        assert_matches_path([layers[name] for layers in layers_by_seed], ref)


def test_relit_layers_equal_a_render_of_the_dimmed_scene(variant):
    """Dimming one light to 30 % by scaling its layer gives the image of the scene whose
    light is at 30 %: with the same seed the same paths are traced (the emitter sampling
    does not depend on intensity), so to float precision; with another seed within noise."""
    scene = make_scene("delta", max_depth=5)
    _, layers = _beauty_and_layers(scene, seed=7)
    relit, _ = lightgroups.relight(layers, {"spot": 0.3})
    dimmed = make_scene("delta", spot_scale=0.3, max_depth=5)
    fresh, _ = _beauty_and_layers(dimmed, seed=7)
    np.testing.assert_allclose(relit, fresh, rtol=0,
                               atol=SUM_RTOL * float(np.abs(fresh).max()))
    assert_matches_path([lightgroups.relight(_beauty_and_layers(scene, s)[1],
                                             {"spot": 0.3})[0] for s in SEEDS],
                        [_path(dimmed, s + 100) for s in SEEDS])


def test_direct_integrator_is_replaced_by_two_vertex_paths(variant_rgb):
    """A scene rendered with ``direct`` gets the path tracer with max_depth 2: the same
    image (direct light and the emitters seen directly) within noise."""
    scene = make_scene("area", max_depth=2)
    direct = mi.load_dict({"type": "direct"})
    mine = []
    for seed in SEEDS:
        result = spectrace.render(scene, spp=SPP, seed=seed, integrator=direct,
                                  light_groups=True)
        mine.append(lightgroups.split(result.image, result.light_groups)[0])
    ref = [np.asarray(spectrace.render(scene, spp=SPP, seed=s, integrator=direct).image)
           for s in SEEDS]
    assert_matches_path(mine, ref)


def test_named_groups_and_the_rest(variant_rgb):
    """Groups of several emitters: 'key' holds two lights, the one left out forms 'rest',
    and the layers still sum to the beauty."""
    scene = make_scene("delta", max_depth=3)
    beauty, layers = _beauty_and_layers(scene, 0, groups=["key=lamp,spot"])
    assert list(layers) == ["key", "rest"]
    assert_layers_sum(beauty, layers)
    assert layers["rest"].mean() > 0 and layers["key"].mean() > layers["rest"].mean()


def test_xml_plugin_and_its_reference_page(variant_rgb):
    """``<integrator type="lightgroups">`` loads with its AOV names; bad parameters are one
    line naming the parameter; the docstring is a reference page."""
    from spectrace.plugins.integrators import lightgroups as plugin

    integ = mi.load_dict({"type": "lightgroups", "groups": "a=x;b=y,z", "max_depth": 3})
    assert integ.aov_names() == ["a.R", "a.G", "a.B", "b.R", "b.G", "b.B"]
    for props, words in [
        ({}, "'groups' is required"),
        ({"groups": "a=x;a=y"}, "given twice"),
        ({"groups": "a.b=x"}, "letters, digits"),
        ({"groups": "a=x;b=x"}, "two light groups"),
        ({"groups": "a=x", "max_depth": -2}, "max_depth"),
        ({"groups": "a=x", "rr_depth": 0}, "rr_depth"),
    ]:
        with pytest.raises(RuntimeError, match=words):
            mi.load_dict({"type": "lightgroups", **props})
    for word in ("Parameters", "Formula", "Example", "groups", "max_depth", "hide_emitters"):
        assert word in plugin.__doc__


def test_unknown_and_missing_emitters_are_refused(variant_rgb):
    """A group naming an emitter the scene lacks, or a scene emitter in no group of the
    plugin's own ``groups``: one ParameterError naming it."""
    from spectrace.errors import ParameterError

    scene = make_scene("delta")
    with pytest.raises(ParameterError, match="no emitter 'nope'"):
        lightgroups.integrator_for(scene, ["a=nope"])
    own = mi.load_dict({"type": "lightgroups", "groups": "a=lamp;b=spot"})
    with pytest.raises(ParameterError, match="'bulb' is in no group"):
        lightgroups.integrator_for(scene, True, own)
    with pytest.raises(ParameterError, match="'path', 'direct', 'local' or 'illuminance'"):
        lightgroups.integrator_for(scene, True, mi.load_dict({"type": "volpath"}))


#: Spectral layers (16 bands over 400-700 nm) against the film's RGB of the same render:
#: the band discretisation (relative RMS over pixels).
BAND_RTOL = 0.02
BANDS = 16
#: A lamp relit from illuminant A to FL2 against a fresh render with FL2 at RELIGHT_SPP:
#: the mean colour of the image within the band discretisation (measured 0.25 %) ...
RELIGHT_MEAN_RTOL = 0.01
#: ... and the pixels within the spectral noise of the fresh render (FL2's lines are hit
#: by few of its sampled wavelengths; measured relative RMS 4-5 %).
RELIGHT_PIXEL_RTOL = 0.1
RELIGHT_SPP = 64


def _lamp_scene(lamp_spectrum: dict) -> mi.Scene:
    """The 'delta' scene with its point light 'lamp' emitting ``lamp_spectrum``."""
    return make_scene("delta", lamp_intensity=lamp_spectrum, max_depth=4)


def _spectral_layers(scene, seed, spp=SPP):
    from spectrace.spectral_film import band_centres, film_to_bands

    wl = band_centres(BANDS)
    integ = lightgroups.integrator_for(scene, True, band_wavelengths=wl)
    result = spectrace.render(scene, spp=spp, seed=seed, integrator=integ, light_groups=True)
    beauty, raw = lightgroups.split(result.image, result.light_groups, per_layer=BANDS)
    return wl, beauty, {g: film_to_bands(v, wl) for g, v in raw.items()}


def test_spectral_layers_give_the_film_colour(variant_spectral):
    """The band layers (16 hat bands) of a render, summed and converted to linear sRGB,
    give the RGB film's beauty of the same render within the band discretisation."""
    from spectrace.spectral_film import bands_to_linear_srgb

    scene = make_scene("area", max_depth=4)
    wl, beauty, bands = _spectral_layers(scene, seed=5)
    rgb = bands_to_linear_srgb(sum(bands.values()), wl)
    rms = np.sqrt(np.mean((rgb - beauty) ** 2)) / beauty.mean()
    assert rms < BAND_RTOL, rms


def test_new_lamp_spectrum_by_relighting_equals_a_fresh_render(variant_spectral):
    """Relighting the spectral layer of a lamp of illuminant A's spectrum with FL2's (same
    luminous output over the bands) gives the image of a fresh render whose lamp emits
    that FL2 (same seed: same paths), within the band discretisation in the mean colour
    and the fresh render's spectral noise per pixel; the probed lamp spectrum is A's."""
    import colour
    from spectrace.spectral import to_mitsuba_spectrum

    from spectrace.spectral_film import bands_to_linear_srgb

    A = colour.SDS_ILLUMINANTS["A"]
    FL2 = colour.SDS_ILLUMINANTS["FL2"]
    scene = _lamp_scene(to_mitsuba_spectrum(A.wavelengths, A.values * 0.05))
    wl, _, bands = _spectral_layers(scene, seed=3, spp=RELIGHT_SPP)
    spectra = lightgroups.group_spectra(scene, {g: [g] for g in bands}, wl)
    A_c = lightgroups.band_averages(A.wavelengths, A.values, wl)
    np.testing.assert_allclose(spectra["lamp"], A_c / A_c.max(), rtol=1e-3)
    relit, _ = lightgroups.relight_spectral(bands, wl, {}, {"lamp": (FL2.wavelengths,
                                                                     FL2.values)}, spectra)
    V = lightgroups.band_averages(*lightgroups._photopic(), wl)
    FL2_c = lightgroups.band_averages(FL2.wavelengths, FL2.values, wl)
    k = 0.05 * np.sum(V * A_c) / np.sum(V * FL2_c)
    fresh_scene = _lamp_scene(to_mitsuba_spectrum(FL2.wavelengths, FL2.values * k))
    _, _, fresh = _spectral_layers(fresh_scene, seed=3, spp=RELIGHT_SPP)
    a = bands_to_linear_srgb(relit, wl)
    b = bands_to_linear_srgb(sum(fresh.values()), wl)
    np.testing.assert_allclose(a.mean(axis=(0, 1)), b.mean(axis=(0, 1)),
                               rtol=RELIGHT_MEAN_RTOL)
    assert np.sqrt(np.mean((a - b) ** 2)) / b.mean() < RELIGHT_PIXEL_RTOL


LOCAL_SCENE = """<scene version="3.0.0">
  <integrator type="local">{ambient}{fog}</integrator>
  <sensor type="perspective"><transform name="to_world"><lookat origin="0, 0, 3"
      target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>
    <rfilter type="box"/></film></sensor>
  <shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
  </shape>
  {lamps}
</scene>
"""
LOCAL_LAMPS = {
    "key": '<emitter type="point" id="key"><point name="position" x="0.5" y="0" z="1"/>'
           '<rgb name="intensity" value="2, 1, 0.5"/></emitter>',
    "fill": '<emitter type="point" id="fill"><point name="position" x="-1" y="0.5" z="1"/>'
            '<float name="intensity" value="0.7"/></emitter>',
}
LOCAL_AMBIENT = 0.2
LOCAL_ALBEDO = 0.5
#: Layers of the deterministic local model (point lights) against renders of one light.
LOCAL_ATOL = 1e-6
#: The fog fraction at the centre pixel against exp(-density * 3 m) (measured 0.2 %).
LOCAL_FOG_RTOL = 5e-3


def _local_scene(lamps, ambient=True, fog=False):
    return mi.load_string(LOCAL_SCENE.format(
        ambient=f'<float name="ambient" value="{LOCAL_AMBIENT}"/>' if ambient else "",
        fog='<string name="fog" value="exponential"/><float name="fog_density" value="0.2"/>'
            if fog else "",
        lamps="".join(LOCAL_LAMPS[k] for k in lamps)))


@pytest.mark.parametrize("fog", [False, True])
def test_local_layers_are_its_lights_and_ambient(variant_rgb, fog):
    """`local` scene, --light-groups: one layer per light and 'ambient'; the layers sum to
    the beauty, a light's layer is the image of the scene with that light alone and no
    ambient (point lights: the model is deterministic), and the ambient layer is
    rho / pi * E_ambient on the surface (times the fog fraction)."""
    scene = _local_scene(["key", "fill"], fog=fog)
    result = spectrace.render(scene, spp=4, light_groups=True)
    beauty, layers = lightgroups.split(result.image, result.light_groups)
    assert list(layers) == ["key", "fill", "ambient"]
    np.testing.assert_allclose(sum(layers.values()), beauty, rtol=0,
                               atol=SUM_RTOL * beauty.max())
    for name in ("key", "fill"):
        alone = spectrace.render(_local_scene([name], ambient=False, fog=fog), spp=4).image
        np.testing.assert_allclose(layers[name], alone[..., :3], rtol=0, atol=LOCAL_ATOL)
        assert layers[name].max() > 0
    centre = layers["ambient"][8, 8]
    if not fog:
        np.testing.assert_allclose(centre, LOCAL_ALBEDO / np.pi * LOCAL_AMBIENT, rtol=1e-5)
    else:  # attenuated by the fog fraction, about exp(-0.2 d) at d = 3 m; no fog colour
        np.testing.assert_allclose(centre, LOCAL_ALBEDO / np.pi * LOCAL_AMBIENT
                                   * np.exp(-0.2 * 3), rtol=LOCAL_FOG_RTOL)


ILLUMINANCE_SCENE = LOCAL_SCENE.replace('<integrator type="local">{ambient}{fog}',
                                        '<integrator type="illuminance">{integrator}')
ILLUMINANCE_LAMPS = {
    "key": '<emitter type="pointlight" id="key"><point name="position" x="0.5" y="0" z="1"/>'
           '<float name="luminous_intensity" value="100"/></emitter>',
    "fill": '<emitter type="point" id="fill"><point name="position" x="-1" y="0.5" z="1"/>'
            '<rgb name="intensity" value="0.7, 0.5, 0.2"/></emitter>',
    "panel": '<shape type="rectangle" id="panel_shape"><transform name="to_world">'
             '<scale value="0.3"/><rotate y="1" angle="180"/><translate z="1.5"/></transform>'
             '<emitter type="area" id="panel"><rgb name="radiance" value="2"/></emitter>'
             '</shape>',
    "wall": '<shape type="rectangle"><transform name="to_world"><rotate y="1" angle="-90"/>'
            '<translate x="1.2" z="1"/></transform><bsdf type="diffuse"/></shape>',
}
#: Per-light lux of delta lights at one sample (exact) against a render of that light
#: alone, and the layers' sum against the lux channel: float32 rounding of the sums.
LUX_RTOL = 1e-5


def _illuminance_render(lamps, integrator="", light_groups=None, spp=1):
    """(lux (H, W), {group: lux layer (H, W)}) of a render of the illuminance scene."""
    scene = mi.load_string(ILLUMINANCE_SCENE.format(
        integrator=integrator, lamps="".join(ILLUMINANCE_LAMPS[k] for k in lamps)))
    result = spectrace.render(scene, spp=spp, seed=3, light_groups=light_groups)
    image = np.asarray(result.image, np.float64)
    if light_groups is None:
        return image[..., -2], {}
    base = image.shape[-1] - 3 * len(result.light_groups)
    _, layers = lightgroups.split(result.image, result.light_groups)
    for layer in layers.values():  # R = G = B = the lux
        np.testing.assert_array_equal(layer[..., 0], layer[..., 2])
    return image[..., base - 2], {g: v[..., 0].astype(np.float64) for g, v in layers.items()}


def test_illuminance_layers_are_the_lux_of_each_light(variant):
    """`illuminance` scene, --light-groups: one lux layer per light and 'indirect'; delta
    lights are exact at one sample, so a light's layer equals the lux of a render with that
    light alone (to float precision), the layers sum to the lux, and direct light only
    leaves 'indirect' empty."""
    lux, layers = _illuminance_render(["key", "fill"], light_groups=True)
    assert list(layers) == ["key", "fill", "indirect"]
    np.testing.assert_allclose(sum(layers.values()), lux, rtol=LUX_RTOL, atol=0)
    for name in ("key", "fill"):
        alone, _ = _illuminance_render([name])
        np.testing.assert_allclose(layers[name], alone, rtol=LUX_RTOL, atol=0)
        assert layers[name].max() > 1.0
    assert not layers["indirect"].any()
    plain, _ = _illuminance_render(["key", "fill"])
    np.testing.assert_array_equal(lux, plain)  # the layers change nothing of the lux


def test_illuminance_layers_with_area_lights_and_interreflections(variant_rgb):
    """With an area light (its light sample and its MIS companion both go to its group)
    and interreflections (max_depth 3: the 'indirect' layer), the per-light lux still sum
    to the total lux to float precision, and the panel's and the wall's light are there."""
    lux, layers = _illuminance_render(["key", "panel", "wall"],
                                      '<integer name="max_depth" value="3"/>',
                                      light_groups=True, spp=4)
    assert list(layers) == ["key", "panel", "indirect"]
    np.testing.assert_allclose(sum(layers.values()), lux, rtol=LUX_RTOL,
                               atol=LUX_RTOL * lux.max())
    assert layers["panel"].max() > 0 and layers["indirect"].max() > 0


def test_illuminance_layers_refuse_spectral_bands(variant_spectral):
    """Per-light lux layers are lux, not spectral bands: asking for bands is refused."""
    from spectrace.errors import ParameterError

    scene = mi.load_string(ILLUMINANCE_SCENE.format(integrator="",
                                                    lamps=ILLUMINANCE_LAMPS["key"]))
    with pytest.raises(ParameterError, match="illuminance"):
        lightgroups.integrator_for(scene, True, band_wavelengths=[400.0, 500.0, 600.0])


def test_illuminance_layers_integrator_is_kept(variant_rgb):
    """`spectrace render --light-groups` builds the per-light lux integrator before the
    render: giving it back to integrator_for keeps it (not refused, not wrapped twice)."""
    scene = mi.load_string(ILLUMINANCE_SCENE.format(integrator="",
                                                    lamps=ILLUMINANCE_LAMPS["key"]))
    made = lightgroups.integrator_for(scene, True)
    assert type(made).__name__ == "IlluminanceLightGroups"
    assert lightgroups.integrator_for(scene, True, made) is made
