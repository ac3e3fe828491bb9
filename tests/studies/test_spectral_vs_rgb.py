"""Tests of spectrace.studies.spectral_vs_rgb, the ColorChecker study.

Oracles: colour-science (colorimetry) and the exact radiometry of a diffuse patch under
a directional light.
"""

from __future__ import annotations

import colour
import numpy as np
import pytest

from spectrace import spectral
from spectrace.studies import spectral_vs_rgb as study

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


def test_resample_matches_colour_science_linear_constant_alignment():
    """Resampling to 1 nm is colour-science's linear interpolation with constant ends."""
    sd = colour.SDS_ILLUMINANTS["FL11"]
    expected = sd.copy().align(
        colour.SpectralShape(360, 830, 1),
        interpolator=colour.LinearInterpolator,
        extrapolator_kwargs={"method": "Constant", "left": None, "right": None},
    ).values
    np.testing.assert_allclose(study.resample(sd.wavelengths, sd.values), expected, rtol=1e-12)


def test_reference_xyz_matches_spectrace_emissive_integration():
    """Two integrations of rho * S (colour-science, spectrace.spectral) agree."""
    _, reflectances = study.colorchecker()
    spd = study.light_spd("FL2")
    ours = spectral.spd_to_xyz(study.GRID, reflectances * spd)
    np.testing.assert_allclose(study.reference_xyz(reflectances, spd), ours, rtol=XYZ_RTOL,
                               atol=1e-6)


def test_exposure_brings_a_white_diffuser_to_one():
    """An exposed light makes a perfect white diffuser's brightest sRGB channel exactly 1."""
    for light in study.LIGHTS:
        white = spectral.xyz_to_linear_srgb(
            study.reference_xyz(np.ones_like(study.GRID), study.light_spd(light)))
        assert white.max() == pytest.approx(1.0, rel=XYZ_RTOL)


def test_albedo_rgb_is_the_colour_under_d65():
    """A patch's RGB albedo is colour-science's linear sRGB of it under D65 (in gamut)."""
    names, reflectances = study.colorchecker()
    for name, rho in zip(names, reflectances, strict=True):
        expected = colour.XYZ_to_RGB(_colour_science_xyz(rho, "D65"), "sRGB",
                                     chromatic_adaptation_transform=None)
        if np.all((expected >= 0) & (expected <= 1)):
            np.testing.assert_allclose(study.albedo_rgb(rho), expected, atol=RGB_ATOL,
                                       err_msg=name)


def test_delta_e_equals_spectrace_ciede2000_inside_the_gamut(rng):
    """For in-gamut colours, CIEDE2000 from XYZ equals delta_e_2000 on encoded sRGB."""
    a, b = rng.uniform(0.02, 0.98, (2, 50, 3))
    expected = spectral.delta_e_2000(spectral.encode_srgb(a), spectral.encode_srgb(b))
    got = study.delta_e(spectral.linear_srgb_to_xyz(a), spectral.linear_srgb_to_xyz(b))
    np.testing.assert_allclose(got, expected, rtol=1e-6, atol=1e-6)


def test_metameric_pair_matches_under_d65_and_splits_under_a():
    """The pair has one colour under D65 (colour-science) and two under illuminant A."""
    names, reflectances = study.colorchecker()
    pair = study.metameric_pair(reflectances[names.index("neutral 6.5 (.44 D)")])
    assert pair.min() >= 0.0 and pair.max() <= 1.0
    assert not np.allclose(pair[0], pair[1], atol=0.05)
    d65 = [_colour_science_xyz(p, "D65") for p in pair]
    a = [_colour_science_xyz(p, "A") for p in pair]
    assert study.delta_e(*d65) < SAME_COLOUR_DE
    assert study.delta_e(*a) > METAMER_SPLIT_DE


def test_metameric_black_is_invisible_under_its_light():
    """A metameric black has XYZ = 0 under its light (colour-science, unnormalised)."""
    b = study.metameric_black("D65", "FL11")
    xyz = _colour_science_xyz(b, "D65")
    np.testing.assert_allclose(xyz, 0.0, atol=1e-6)
    assert np.max(np.abs(b)) == pytest.approx(1.0)


def test_layout_means_recover_painted_colours(rng):
    """Averaging the patches of a painted chart returns the colours painted."""
    layout = study.ChartLayout(7, cols=3, cell=10)
    colours = rng.uniform(0, 1, (7, 3))
    np.testing.assert_allclose(layout.means(layout.paint(colours)), colours)
    assert layout.size == (30, 30)


def test_rgb_chart_render_is_the_product_of_albedo_and_light(variant_rgb):
    """Lambert under a directional light of irradiance pi * E: radiance = albedo * E."""
    import mitsuba as mi

    import spectrace

    _, reflectances = study.colorchecker()
    spd = study.light_spd("A")
    layout = study.ChartLayout(24, cell=8)
    scene = mi.load_dict(study.chart_scene(reflectances, spd, rgb=True, layout=layout, spp=1))
    image = spectrace.render(scene, spp=1).image
    np.testing.assert_allclose(layout.means(image),
                               study.albedo_rgb(reflectances) * study.emitted_rgb(spd),
                               rtol=RENDER_RTOL, atol=1e-7)
    assert np.all(image[:, 0] == 0) and np.all(image[0] == 0)  # black gaps (1 px at cell 8)


def test_spectral_chart_render_matches_colour_science(variant_spectral):
    """The spectral render of the chart has colour-science's colours under illuminant A."""
    names, reflectances = study.colorchecker()
    chart = study.render_chart(reflectances, "A", spp=32,
                                 layout=study.ChartLayout(24, cell=8))
    assert chart.delta_e_spectral.mean() < SPECTRAL_MEAN_DE
    assert chart.delta_e_spectral.max() < SPECTRAL_MAX_DE
    assert chart.delta_e_rgb.mean() > 2 * chart.delta_e_spectral.mean()  # RGB misses under A
    assert chart.cri == pytest.approx(spectral.cri(study.GRID, chart.spd))
