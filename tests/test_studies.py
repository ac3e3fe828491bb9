"""Tests of spectrace.studies, the library code of the study notebooks.

Oracles: colour-science (colorimetry), closed-form laws written out in the tests,
Mitsuba's built-in `point`/`spot` lights and `diffuse` BSDF with exact radiometry, and
geometry (areas, distances).
"""

from __future__ import annotations

import math

import colour
import numpy as np
import pytest

from spectrace import spectral, studies

#: Colorimetric agreement of two independent integrations (relative, XYZ).
XYZ_RTOL = 2e-3
#: Agreement with colour-science's sRGB of a reflectance under D65 (linear sRGB).
RGB_ATOL = 2e-3
#: CIEDE2000 taken as "the same colour" (well under one just-noticeable difference).
SAME_COLOUR_DE = 0.05
#: CIEDE2000 a metameric pair must split by under illuminant A (clearly visible).
METAMER_SPLIT_DE = 5.0
#: Exactness of an RGB render of a diffuse patch under a directional light (float32).
RENDER_RTOL = 1e-4
#: Mean / max CIEDE2000 of the spectral chart render against the reference at test size.
SPECTRAL_MEAN_DE, SPECTRAL_MAX_DE = 0.6, 2.5
#: Floor irradiance: max |render - formula| relative to the peak at test size.
FLOOR_TOL = 0.02
#: Ratio of successive bounce increments in a closed diffuse box against its albedo.
BOUNCE_RATIO_ATOL = 0.04
#: Sphere pixel count against its projected disc area (relative).
AREA_RTOL = 0.05
CMFS = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]


def _sd(values):
    return colour.SpectralDistribution(values, colour.SpectralShape(360, 830, 1))


def _colour_science_xyz(reflectance, illuminant_name):
    """colour-science's XYZ (perfect white Y = 1) of a reflectance on GRID."""
    illuminant = colour.SDS_ILLUMINANTS[illuminant_name].copy().align(
        colour.SpectralShape(360, 830, 1),
        interpolator=colour.LinearInterpolator,
        extrapolator_kwargs={"method": "Constant", "left": None, "right": None},
    )
    return colour.sd_to_XYZ(_sd(reflectance), CMFS, illuminant, method="Integration") / 100.0


# --------------------------------------------------------------------------- sizes


def test_budget_follows_the_quick_environment_variable(monkeypatch):
    """SPECTRACE_QUICK=1 selects the small size, anything else the normal one."""
    monkeypatch.setenv(studies.QUICK_ENV, "1")
    assert studies.budget(128, 16) == 16
    monkeypatch.setenv(studies.QUICK_ENV, "0")
    assert studies.budget(128, 16) == 128
    monkeypatch.delenv(studies.QUICK_ENV)
    assert studies.budget(128, 16) == 128


def test_scene_path_finds_the_study_scenes():
    """The scenes the notebooks render exist; an unknown name raises FileNotFoundError."""
    for name in ("phong_vs_energy", "falloff_laws", "spotlight_stage", "shading_models",
                 "shadow_acne", "fog", "fog_volpath"):
        assert studies.scene_path(name).is_file()
    with pytest.raises(FileNotFoundError):
        studies.scene_path("no_such_scene")


# --------------------------------------------------------------------------- colorimetry


def test_resample_matches_colour_science_linear_constant_alignment():
    """Resampling to 1 nm is colour-science's linear interpolation with constant ends."""
    sd = colour.SDS_ILLUMINANTS["FL11"]
    expected = sd.copy().align(
        colour.SpectralShape(360, 830, 1),
        interpolator=colour.LinearInterpolator,
        extrapolator_kwargs={"method": "Constant", "left": None, "right": None},
    ).values
    np.testing.assert_allclose(studies.resample(sd.wavelengths, sd.values), expected, rtol=1e-12)


def test_reference_xyz_matches_spectrace_emissive_integration():
    """Two integrations of rho * S (colour-science, spectrace.spectral) agree."""
    _, reflectances = studies.colorchecker()
    spd = studies.light_spd("FL2")
    ours = spectral.spd_to_xyz(studies.GRID, reflectances * spd)
    np.testing.assert_allclose(studies.reference_xyz(reflectances, spd), ours, rtol=XYZ_RTOL,
                               atol=1e-6)


def test_exposure_brings_a_white_diffuser_to_one():
    """An exposed light makes a perfect white diffuser's brightest sRGB channel exactly 1."""
    for light in studies.LIGHTS:
        white = spectral.xyz_to_linear_srgb(
            studies.reference_xyz(np.ones_like(studies.GRID), studies.light_spd(light)))
        assert white.max() == pytest.approx(1.0, rel=XYZ_RTOL)


def test_albedo_rgb_is_the_colour_under_d65():
    """A patch's RGB albedo is colour-science's linear sRGB of it under D65 (in gamut)."""
    names, reflectances = studies.colorchecker()
    for name, rho in zip(names, reflectances, strict=True):
        expected = colour.XYZ_to_RGB(_colour_science_xyz(rho, "D65"), "sRGB",
                                     chromatic_adaptation_transform=None)
        if np.all((expected >= 0) & (expected <= 1)):
            np.testing.assert_allclose(studies.albedo_rgb(rho), expected, atol=RGB_ATOL,
                                       err_msg=name)


def test_delta_e_equals_spectrace_ciede2000_inside_the_gamut(rng):
    """For in-gamut colours, CIEDE2000 from XYZ equals delta_e_2000 on encoded sRGB."""
    a, b = rng.uniform(0.02, 0.98, (2, 50, 3))
    expected = spectral.delta_e_2000(spectral.encode_srgb(a), spectral.encode_srgb(b))
    got = studies.delta_e(spectral.linear_srgb_to_xyz(a), spectral.linear_srgb_to_xyz(b))
    np.testing.assert_allclose(got, expected, rtol=1e-6, atol=1e-6)


def test_metameric_pair_matches_under_d65_and_splits_under_a():
    """The pair has one colour under D65 (colour-science) and two under illuminant A."""
    names, reflectances = studies.colorchecker()
    pair = studies.metameric_pair(reflectances[names.index("neutral 6.5 (.44 D)")])
    assert pair.min() >= 0.0 and pair.max() <= 1.0
    assert not np.allclose(pair[0], pair[1], atol=0.05)
    d65 = [_colour_science_xyz(p, "D65") for p in pair]
    a = [_colour_science_xyz(p, "A") for p in pair]
    assert studies.delta_e(*d65) < SAME_COLOUR_DE
    assert studies.delta_e(*a) > METAMER_SPLIT_DE


def test_metameric_black_is_invisible_under_its_light():
    """A metameric black has XYZ = 0 under its light (colour-science, unnormalised)."""
    b = studies.metameric_black("D65", "FL11")
    xyz = _colour_science_xyz(b, "D65")
    np.testing.assert_allclose(xyz, 0.0, atol=1e-6)
    assert np.max(np.abs(b)) == pytest.approx(1.0)


# --------------------------------------------------------------------------- chart scene


def test_layout_means_recover_painted_colours(rng):
    """Averaging the patches of a painted chart returns the colours painted."""
    layout = studies.ChartLayout(7, cols=3, cell=10)
    colours = rng.uniform(0, 1, (7, 3))
    np.testing.assert_allclose(layout.means(layout.paint(colours)), colours)
    assert layout.size == (30, 30)


def test_rgb_chart_render_is_the_product_of_albedo_and_light(variant_rgb):
    """Lambert under a directional light of irradiance pi * E: radiance = albedo * E."""
    import mitsuba as mi

    import spectrace

    _, reflectances = studies.colorchecker()
    spd = studies.light_spd("A")
    layout = studies.ChartLayout(24, cell=8)
    scene = mi.load_dict(studies.chart_scene(reflectances, spd, rgb=True, layout=layout, spp=1))
    image = spectrace.render(scene, spp=1).image
    np.testing.assert_allclose(layout.means(image),
                               studies.albedo_rgb(reflectances) * studies.emitted_rgb(spd),
                               rtol=RENDER_RTOL, atol=1e-7)
    assert np.all(image[:, 0] == 0) and np.all(image[0] == 0)  # black gaps (1 px at cell 8)


def test_spectral_chart_render_matches_colour_science(variant_spectral):
    """The spectral render of the chart has colour-science's colours under illuminant A."""
    names, reflectances = studies.colorchecker()
    chart = studies.render_chart(reflectances, "A", spp=32,
                                 layout=studies.ChartLayout(24, cell=8))
    assert chart.delta_e_spectral.mean() < SPECTRAL_MEAN_DE
    assert chart.delta_e_spectral.max() < SPECTRAL_MAX_DE
    assert chart.delta_e_rgb.mean() > 2 * chart.delta_e_spectral.mean()  # RGB misses under A
    assert chart.cri == pytest.approx(spectral.cri(studies.GRID, chart.spd))


# --------------------------------------------------------------------------- energy


def test_beckmann_alpha_of_blinn_phong_exponent():
    """Walter et al. 2007: alpha = sqrt(2 / (m + 2)), so m = 2 gives sqrt(1/2)."""
    assert studies.beckmann_alpha(2.0) == pytest.approx(math.sqrt(0.5))
    assert studies.beckmann_alpha(0.0) == pytest.approx(1.0)


def test_classic_phong_normal_albedo_is_the_lobe_integral():
    """integral of cos^m(theta) cos(theta) over the hemisphere = 2 pi / (m + 2)."""
    from scipy.integrate import quad

    def lobe(t, m):
        return np.cos(t) ** (m + 1) * np.sin(t)

    for m in (1.0, 2.0, 32.0):
        integral = 2 * np.pi * quad(lobe, 0, np.pi / 2, args=(m,))[0]
        assert studies.classic_phong_albedo_normal(m) == pytest.approx(integral, rel=1e-9)


def test_albedo_curves_of_a_lambertian_family_are_its_reflectance(variant_rgb):
    """A diffuse BSDF reflects exactly its reflectance from every direction."""
    family = {"diffuse": lambda m: {"type": "diffuse", "reflectance": 0.3}}
    curves = studies.albedo_curves([1, 8], [0.0, 45.0, 80.0], families=family, samples=1 << 10)
    np.testing.assert_allclose(curves["diffuse"], 0.3, rtol=1e-5)


def test_closed_box_bounces_multiply_by_the_albedo(variant_rgb):
    """In a closed diffuse box each bounce adds the previous one's light times the albedo."""
    albedo = 0.5
    series = studies.bounce_series({"type": "diffuse", "reflectance": albedo},
                                   [1, 2, 3, 4, 5, 6, 7], res=16, spp=32)
    assert series[0] == 0.0  # a point light is invisible to the camera
    increments = np.diff(series)
    assert np.all(increments > 0)
    ratios = increments[2:] / increments[1:-1]
    assert np.mean(ratios) == pytest.approx(albedo, abs=BOUNCE_RATIO_ATOL)


def test_shape_labels_cover_each_sphere_disc(variant_rgb):
    """Each sphere's labelled pixels cover its projected disc, pi r^2, in grid order."""
    import mitsuba as mi

    res, cols = 60, 3
    family = {"grey": lambda m: {"type": "diffuse"}}
    scene = mi.load_dict(studies.sphere_grid_scene(family, [1, 2, 3], res=res, spp=1))
    labels, centres = studies.shape_labels(scene)
    pixels_per_unit = res / cols
    disc = np.pi * (0.42 * pixels_per_unit) ** 2
    np.testing.assert_allclose(np.bincount(labels[labels >= 0]), disc, rtol=AREA_RTOL)
    rows, columns = studies.grid_position(centres)
    np.testing.assert_array_equal(rows, [0, 0, 0])
    np.testing.assert_array_equal(columns, [0, 1, 2])


def test_depth_aov_is_the_camera_distance(variant_rgb):
    """The depth AOV of the chart is the camera's height (2 m) minus the near clip distance
    (orthographic rays start on the near plane) on the patches, 0 in the gaps."""
    import mitsuba as mi

    layout = studies.ChartLayout(2, cols=2, cell=8)
    scene = mi.load_dict(studies.chart_scene(np.full((2, studies.GRID.size), 0.5),
                                             studies.light_spd("D65"), rgb=True, layout=layout))
    depth = studies.aov(scene, "depth")[..., 0]
    near_clip = float(mi.traverse(scene.sensors()[0])["near_clip"])
    assert depth[4, 4] == pytest.approx(2.0 - near_clip, rel=1e-6)
    assert depth[0, 0] == 0.0


# --------------------------------------------------------------------------- falloff


def test_distance_laws_closed_form():
    """The distance laws of DESIGN.md at hand-computed points."""
    laws = studies.DISTANCE_LAWS
    assert laws["inverse_square"](2.0) == pytest.approx(0.25)
    assert laws["inverse_square_epsilon"](1.5, epsilon=0.5) == pytest.approx(0.25)
    assert laws["polynomial"](2.0, kc=1, kl=0.5, kq=0.25) == pytest.approx(1 / 3)
    assert laws["windowed"](1.0, radius=2.0) == pytest.approx((1 - 1 / 16) ** 2)
    assert laws["windowed"](2.5, radius=2.0) == 0.0
    assert laws["windowed"](0.0, radius=2.0, epsilon=0.1) == pytest.approx(100.0)
    assert laws["none"](7.0) == 1.0


def test_cone_falloffs_closed_form():
    """Full inside the penumbra, zero outside the umbra, the ramps at their midpoints."""
    umbra, penumbra = 30.0, 20.0
    for law in studies.CONE_FALLOFFS.values():
        assert law(np.radians(10.0), umbra, penumbra) == pytest.approx(1.0)
        assert law(np.radians(31.0), umbra, penumbra) == 0.0
    mid_cos = np.arccos(0.5 * (np.cos(np.radians(umbra)) + np.cos(np.radians(penumbra))))
    assert studies.CONE_FALLOFFS["quadratic"](mid_cos, umbra, penumbra) == pytest.approx(0.25)
    assert studies.CONE_FALLOFFS["smoothstep"](mid_cos, umbra, penumbra) == pytest.approx(0.5)
    assert studies.CONE_FALLOFFS["linear_angle"](np.radians(25.0), umbra, penumbra) == \
        pytest.approx(0.5)


def test_fog_laws_closed_form():
    """OpenGL fog: linear is 1 at start and 0 at end; exponential laws at d = 1/density."""
    laws = studies.FOG_LAWS
    assert laws["linear"](2.0, 2.0, 10.0) == 1.0
    assert laws["linear"](6.0, 2.0, 10.0) == pytest.approx(0.5)
    assert laws["linear"](12.0, 2.0, 10.0) == 0.0
    assert laws["exponential"](4.0, density=0.25) == pytest.approx(math.exp(-1))
    assert laws["exponential_squared"](4.0, density=0.25) == pytest.approx(math.exp(-1))
    assert laws["none"](100.0) == 1.0


def test_fog_fraction_recovers_the_blend():
    """f is recovered from L = f L_surface + (1 - f) L_fog; background pixels are NaN."""
    clear = np.zeros((2, 3, 3))
    clear[:, :2] = [[0.8, 0.5, 0.2]]
    fog = np.array([0.3, 0.3, 0.35])
    f = np.array([[0.9, 0.25, 0.0], [0.5, 0.0, 0.0]])
    fogged = f[..., None] * clear + (1 - f[..., None]) * fog
    depth = np.array([[1.0, 5.0, 0.0], [3.0, 20.0, 0.0]])
    fogged[:, 2] = fog  # background: the fog colour
    got = studies.fog_fraction(fogged, clear, depth)
    np.testing.assert_allclose(got[:, :2], f[:, :2], atol=1e-12)
    assert np.all(np.isnan(got[:, 2]))


def test_floor_irradiance_of_mitsuba_point_light_is_the_cosine_inverse_square(variant_rgb):
    """Mitsuba's point light over a Lambertian floor: E = I cos(theta) / r^2 = I h / r^3."""
    profile = studies.floor_irradiance({"type": "point", "intensity": 2.0}, height=1.0,
                                       half_width=3.0, res=48, spp=16)
    x = profile.x
    peak = 2.0  # I / h^2 at the foot point
    assert np.max(np.abs(profile.measured - profile.expected)) < FLOOR_TOL * peak
    far = np.abs(x) > 1.0  # where pixel averaging no longer matters: the plain formula
    plain = 2.0 * 1.0 / (x[far] ** 2 + 1.0) ** 1.5
    np.testing.assert_allclose(profile.expected[far], plain, rtol=0.02)


def test_floor_irradiance_of_mitsuba_spot_follows_its_linear_cone(variant_rgb):
    """Mitsuba's spot (linear in the angle) over the floor matches I cone(alpha) h / r^3."""
    profile = studies.floor_irradiance(
        {"type": "spot", "intensity": 1.0, "cutoff_angle": 40.0, "beam_width": 25.0},
        height=2.0, half_width=2.5, res=48, spp=16)
    peak = 1.0 / 4.0
    assert np.max(np.abs(profile.measured - profile.expected)) < FLOOR_TOL * peak
    assert profile.measured[0] == 0.0 and profile.measured[-1] == 0.0  # beyond the cutoff


def test_text_table_aligns_columns():
    """Columns are right-aligned under a rule as wide as each column."""
    text = studies.text_table(["a", "bb"], [("1", "2"), ("333", "4")])
    assert text.splitlines() == ["  a  bb", "---  --", "  1   2", "333   4"]
