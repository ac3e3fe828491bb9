"""Tests of the photometric units of ``pointlight`` and ``spotlight``
(``plugins/emitters/luminous.py`` and the emission parameters of ``delta.py``): luminous
efficacy against colour-science, candela and lux (100 cd at 1 m give 100 lux), lumens
integrated over a floor, RGB against spectral, traversal and the one-line errors.

Lux is read with Mitsuba's own integrator (``direct``) and films (the luminance Y of a
white diffuse plane), never with spectrace's ``illuminance`` integrator; see
``emitter_checks.lux_from_film_y`` for the derivation.
"""

from __future__ import annotations

import emitter_checks as checks
import numpy as np
import pytest

#: Relative tolerance of luminous efficacies and integrals against colour-science (1 nm
#: sum against colour-science's trapezoidal rule and its own interpolation of V).
RTOL_COLOUR = 2e-3
#: Lux in RGB and mono variants, where every sample gives the exact value: the film's
#: Y weights (0.212671, 0.715160, 0.072169) against the Rec. 709 ones (0.2126, ...).
RTOL_LUX_RGB = 2e-4
#: Lux in spectral variants from LUX_SPP wavelength samples (measured spread 0.05%).
RTOL_LUX_SPECTRAL = 5e-3
LUX_SPP = 4096
#: Luminous flux summed over the floor: pixel means of FLUX_SPP position samples
#: (measured error 0.1-0.3%).
RTOL_FLUX = 1e-2
FLUX_SPP = 64
FLUX_RES = 32
#: Two renders that must agree up to float rounding.
RTOL_SAME = 1e-5
#: Our radiant spectrum against the one computed with colour-science (float32 sums).
RTOL_SPECTRUM = 2e-3

SPD = [(400.0, 1.0), (550.0, 3.0), (700.0, 2.0)]
HEIGHT = 1.0
#: Floor points (x, z) around the foot of a light at (0, HEIGHT, 0).
POINTS = [(0.0, 0.0), (0.5, 0.3), (-1.0, 0.8)]


def tabulated() -> dict:
    return {"type": "spectrum", "value": SPD}


def tabulated_sd(scale: float = 1.0):
    """The same SPD as a colour-science distribution on the 1 nm grid 360-830 nm, linear
    between the samples and 0 outside (as Mitsuba's irregular spectrum)."""
    import colour

    w = np.arange(360.0, 831.0)
    values = np.interp(w, [p[0] for p in SPD], [p[1] for p in SPD], left=0.0, right=0.0)
    return colour.SpectralDistribution(dict(zip(w, scale * values, strict=True)))


def lux_rtol() -> float:
    import mitsuba as mi

    return RTOL_LUX_SPECTRAL if mi.is_spectral else RTOL_LUX_RGB


# -- the conversion against colour-science ------------------------------------------------

def test_luminous_efficacy_matches_colour_science(variant_spectral):
    """K = 683 integral V s / integral s (lm/W) of a tabulated SPD and a 2700 K blackbody
    equals colour-science's ``luminous_efficacy``, and 683 integral V s of the SPD and of
    D65 its ``luminous_flux`` (so W per lumen = 1 / luminous_flux)."""
    import colour
    import drjit as dr
    import mitsuba as mi
    from spectrace.plugins.emitters import luminous

    shape = colour.SpectralShape(360, 830, 1)
    cases = {
        "spd": (tabulated(), tabulated_sd()),
        "blackbody": ({"type": "blackbody", "temperature": 2700.0},
                      colour.sd_blackbody(2700.0, shape)),
    }
    for name, (spectrum, sd) in cases.items():
        texture = mi.load_dict(spectrum)
        expected = colour.luminous_efficacy(sd)
        np.testing.assert_allclose(luminous.luminous_efficacy(texture), expected,
                                   rtol=RTOL_COLOUR, err_msg=name)
    # Mitsuba's D65 is the CIE table times a constant up to 780 nm (its values above,
    # where V < 1e-4, differ from colour-science's): compare integral V s, scaled by the
    # ratio of the two tables at 560 nm.
    d65 = mi.load_dict({"type": "d65"})
    si = dr.zeros(mi.SurfaceInteraction3f)
    si.wavelengths = mi.UnpolarizedSpectrum(560.0)
    ratio = float(dr.slice(d65.eval(si)[0])) / colour.SDS_ILLUMINANTS["D65"][560.0]
    np.testing.assert_allclose(
        luminous.photometric_integral(d65),
        ratio * colour.luminous_flux(colour.SDS_ILLUMINANTS["D65"].copy().align(shape)) / 683.0,
        rtol=RTOL_COLOUR)
    # absolute scale on the tabulated SPD, whose values Mitsuba keeps as given
    texture = mi.load_dict(tabulated())
    np.testing.assert_allclose(luminous.watts_per_lumen(texture, "test"),
                               1.0 / colour.luminous_flux(tabulated_sd()), rtol=RTOL_COLOUR)


def test_rgb_watts_per_lumen_uses_luminance(variant_rgb):
    """RGB variants: 1 lm of colour c is c / (683 Y(c) integral V) W, Y the sRGB luminance
    row of colour-science's sRGB RGB-to-XYZ matrix and integral V dlambda colour-science's
    (a colour stands for the spectra whose film Y is its Y)."""
    import colour
    import mitsuba as mi
    from spectrace.plugins.emitters import luminous

    rgb = np.array([0.9, 0.4, 0.1])
    Y = colour.models.RGB_COLOURSPACE_sRGB.matrix_RGB_to_XYZ[1] @ rgb
    texture = mi.load_dict({"type": "rgb", "value": rgb.tolist()})
    np.testing.assert_allclose(luminous.watts_per_lumen(texture, "test"),
                               1.0 / (683.0 * Y * checks.CIE_Y_INTEGRAL), rtol=RTOL_LUX_RGB)


def test_candela_renders_like_colour_science_radiant_intensity(variant_spectral):
    """A 100 cd pointlight of a tabulated spectrum s renders exactly like Mitsuba's own
    ``point`` given the radiant intensity 100 s / (683 integral V s) computed with
    colour-science (same samples, same wavelengths: every pixel)."""
    import colour
    import mitsuba as mi

    intensity = 100.0
    factor = intensity / colour.luminous_flux(tabulated_sd())
    reference_light = {"type": "point", "position": [0.0, HEIGHT, 0.0],
                       "intensity": {"type": "spectrum",
                                     "value": [(w, v * factor) for w, v in SPD]}}
    light = {"type": "pointlight", "position": [0.0, HEIGHT, 0.0],
             "luminous_intensity": intensity, "spectrum": tabulated()}
    images = [np.array(mi.render(mi.load_dict(checks.plane_scene(l, spp=4)), seed=3))
              for l in (reference_light, light)]
    assert images[0].max() > 0.0
    np.testing.assert_allclose(images[1], images[0], rtol=RTOL_SPECTRUM,
                               atol=RTOL_SPECTRUM * images[0].max())


# -- candela and lux ------------------------------------------------------------------------

@pytest.mark.parametrize("spectrum", ["default", "tabulated"])
def test_100_candela_give_100_lux_under_the_light(any_variant, spectrum):
    """Scene units are metres: a 100 cd pointlight at height h = 1 m gives E = 100 lux on
    the floor under it and E = I h / r^3 around it (inverse square law times the cosine
    h / r), with the default D65 spectrum and a tabulated one, in every variant."""
    light = {"type": "pointlight", "position": [0.0, HEIGHT, 0.0], "luminous_intensity": 100.0}
    if spectrum == "tabulated":
        light["spectrum"] = tabulated()
    for i, (x, z) in enumerate(POINTS):
        r = np.sqrt(x**2 + z**2 + HEIGHT**2)
        lux = checks.lux_at(light, (x, z), LUX_SPP, seed=i)
        np.testing.assert_allclose(lux, 100.0 * HEIGHT / r**3, rtol=lux_rtol(),
                                   err_msg=f"at {(x, z)}")


def test_rgb_and_spectral_variants_give_the_same_lux():
    """The photometric scale is the same in every variant: the lux of a 100 cd light of a
    non-flat tabulated spectrum measured in llvm_ad_rgb and llvm_ad_spectral agree (K_m Y
    of the RGB irradiance against K_m integral V E of the spectral one)."""
    import spectrace

    light = {"type": "pointlight", "position": [0.0, HEIGHT, 0.0], "luminous_intensity": 100.0,
             "spectrum": tabulated()}
    lux = {}
    for variant in ("llvm_ad_rgb", "llvm_ad_spectral"):
        spectrace.set_variant(variant)
        lux[variant] = checks.lux_at(light, POINTS[1], LUX_SPP)
    np.testing.assert_allclose(lux["llvm_ad_spectral"], lux["llvm_ad_rgb"],
                               rtol=RTOL_LUX_SPECTRAL)


def test_radiant_lights_give_the_same_image_in_rgb_and_spectral_variants():
    """A colour stands for the spectra of the same film Y: a light of radiant intensity 1
    (the flat spectrum 1 W/sr/nm in spectral variants, white 1 in RGB) gives the same
    image, hence the same lux, in llvm_ad_rgb and llvm_ad_spectral."""
    import spectrace

    light = {"type": "pointlight", "position": [0.0, HEIGHT, 0.0], "intensity": 1.0}
    lux = {}
    for variant in ("llvm_ad_rgb", "llvm_ad_spectral"):
        spectrace.set_variant(variant)
        lux[variant] = checks.lux_at(light, POINTS[1], LUX_SPP)
    np.testing.assert_allclose(lux["llvm_ad_spectral"], lux["llvm_ad_rgb"],
                               rtol=RTOL_LUX_SPECTRAL)


def test_pointlight_lumens_are_candela_times_four_pi(variant):
    """``luminous_flux`` Phi_v of a pointlight is I_v = Phi_v / (4 pi) in every direction:
    it renders exactly like ``luminous_intensity`` Phi_v / (4 pi)."""
    flux = 1200.0
    base = {"type": "pointlight", "position": [0.3, HEIGHT, 0.1], "spectrum": tabulated()}
    a = checks.render({**base, "luminous_flux": flux}, spp=4)
    b = checks.render({**base, "luminous_intensity": flux / (4 * np.pi)}, spp=4)
    assert b.max() > 0.0
    checks.assert_image_close(a, b, rtol=RTOL_SAME)


@pytest.mark.parametrize("law", ["quadratic", "smoothstep", "linear_angle"])
def test_spotlight_lumens_all_reach_the_floor(variant, law):
    """A spotlight of luminous_flux Phi_v aimed straight down 1 m above a floor that
    catches its whole cone (umbra 45 degrees: radius 1 m, the floor seen is 4 m wide):
    the lux integrated over the floor (sum of pixel means times pixel area) is Phi_v,
    for every cone falloff (the flux is that of the cone with its falloff)."""
    import mitsuba as mi

    flux = 1000.0
    T = mi.ScalarTransform4f()
    light = {"type": "spotlight", "luminous_flux": flux, "cone_falloff": law,
             "to_world": T.look_at([0.1, HEIGHT, -0.2], [0.1, 0.0, -0.2], [0, 0, 1]),
             "umbra_angle": 45.0, "penumbra_angle": 25.0}
    lux = checks.plane_lux(light, FLUX_SPP, res=FLUX_RES)
    assert lux[0, 0] == 0.0 and lux[-1, -1] == 0.0  # the cone ends inside the view
    np.testing.assert_allclose(lux.sum() * checks.pixel_area(FLUX_RES), flux, rtol=RTOL_FLUX)


def test_spotlight_candela_on_its_axis(variant_rgb):
    """``luminous_intensity`` of a spotlight is its on-axis intensity: 100 cd straight
    down from 1 m give 100 lux at the foot of the axis."""
    import mitsuba as mi

    T = mi.ScalarTransform4f()
    light = {"type": "spotlight", "luminous_intensity": 100.0,
             "to_world": T.look_at([0.0, HEIGHT, 0.0], [0.0, 0.0, 0.0], [0, 0, 1])}
    np.testing.assert_allclose(checks.lux_at(light, (0.0, 0.0), 1), 100.0, rtol=RTOL_LUX_RGB)


# -- parameters -----------------------------------------------------------------------------

def test_traverse_luminous_parameters(variant):
    """``luminous_intensity`` and ``spectrum`` are exposed and differentiable: the emitted
    value is proportional to the candela (d I_e / d I_v = I_e / I_v), and scaling the
    spectrum leaves it unchanged (the luminous intensity is fixed), also in the gradient."""
    import drjit as dr
    import mitsuba as mi

    light = mi.load_dict({"type": "pointlight", "position": [0.0, 2.0, 0.0],
                          "luminous_intensity": 100.0,
                          "spectrum": {"type": "uniform", "value": 1.0}})
    params = mi.traverse(light)
    assert params.flags("luminous_intensity") & int(mi.ParamFlags.NonDifferentiable) == 0
    assert params.flags("spectrum.value") & int(mi.ParamFlags.NonDifferentiable) == 0
    it = dr.zeros(mi.Interaction3f)
    it.wavelengths = checks.wavelength_grid(1).wavelengths

    def emitted():
        _, value = light.sample_direction(it, mi.Point2f(0.5))
        return mi.unpolarized_spectrum(value)[0]

    before = float(dr.slice(dr.detach(emitted())))
    params["spectrum.value"] = 3.0
    params.update()
    np.testing.assert_allclose(float(dr.slice(dr.detach(emitted()))), before, rtol=1e-6)
    params["luminous_intensity"] = 250.0
    params.update()
    np.testing.assert_allclose(float(dr.slice(dr.detach(emitted()))), 2.5 * before, rtol=1e-6)
    dr.enable_grad(params["luminous_intensity"], params["spectrum.value"])
    params.update()
    value = emitted()
    dr.backward(value)
    np.testing.assert_allclose(dr.grad(params["luminous_intensity"])[0], 2.5 * before / 250.0,
                               rtol=1e-5)
    np.testing.assert_allclose(dr.grad(params["spectrum.value"])[0], 0.0, atol=1e-9)


def test_to_string_names_the_unit(variant_rgb):
    import mitsuba as mi

    light = mi.load_dict({"type": "spotlight", "luminous_flux": 800.0})
    assert "luminous_flux=800 lm" in str(light)


INVALID = [
    ({"intensity": 1.0, "luminous_intensity": 2.0}, "'intensity' and 'luminous_intensity'"),
    ({"power": 1.0, "luminous_flux": 2.0}, "'power' and 'luminous_flux'"),
    ({"luminous_intensity": 1.0, "luminous_flux": 2.0},
     "'luminous_intensity' and 'luminous_flux'"),
    ({"intensity": 1.0, "power": 1.0, "luminous_flux": 2.0},
     "'intensity' and 'power' and 'luminous_flux'"),
    ({"luminous_intensity": -5.0}, "'luminous_intensity' must be >= 0"),
    ({"luminous_flux": -1.0}, "'luminous_flux' must be >= 0"),
    ({"luminous_intensity": "100"}, "'luminous_intensity' must be a float"),
    ({"intensity": 2.0, "spectrum": {"type": "d65"}},
     "'spectrum' only applies to 'luminous_intensity' and 'luminous_flux'"),
    ({"spectrum": {"type": "d65"}}, "'spectrum' only applies to"),
    ({"luminous_flux": 100.0, "spectrum": {"type": "uniform", "value": 0.0}},
     "'spectrum' has no luminous content"),
    ({"luminous_flux": 100.0, "spectrum": {"type": "uniform", "value": -1.0}},
     "'spectrum' must be >= 0"),
]


@pytest.mark.parametrize("plugin", ["pointlight", "spotlight"])
@pytest.mark.parametrize(("params", "message"), INVALID)
def test_invalid_emission_fails_in_one_line(variant, plugin, params, message):
    """Two or more of the four quantities (all named), negative or non-float luminous
    values, ``spectrum`` with a radiometric quantity and a spectrum the eye cannot see fail
    at load with one line naming the parameters."""
    import mitsuba as mi

    with pytest.raises(Exception) as info:
        mi.load_dict({"type": plugin, **params})
    text = str(info.value)
    assert f"{plugin}: " in text and message in text, text
    line = next(l for l in text.splitlines() if f"{plugin}: " in l)
    assert message in line


def test_invisible_spectrum_fails(variant_spectral):
    """A spectrum entirely outside the visible range (V = 0 there: 840-900 nm, beyond
    Mitsuba's range) has no luminous content."""
    import mitsuba as mi

    with pytest.raises(Exception, match="'spectrum' has no luminous content"):
        mi.load_dict({"type": "pointlight", "luminous_intensity": 10.0,
                      "spectrum": {"type": "spectrum", "value": [(840.0, 1.0), (900.0, 1.0)]}})


def test_reference_page(variant_rgb):
    """The module docstring of ``luminous`` follows the one reference-page format with the
    units cd and lm."""
    from spectrace.plugins.emitters import luminous

    table = checks.parse_reference_page(luminous.__doc__, "luminous")
    assert table["luminous_intensity"]["unit"] == "cd"
    assert table["luminous_flux"]["unit"] == "lm"


def test_spectrum_unavailable_in_variant_fails_in_one_line(variant_rgb):
    """A spectrum the variant cannot evaluate (Mitsuba's blackbody in RGB) fails at load in
    one line naming the parameter and the variant."""
    import mitsuba as mi

    with pytest.raises(Exception) as info:
        mi.load_dict({"type": "pointlight", "luminous_flux": 10.0,
                      "spectrum": {"type": "blackbody", "temperature": 3000.0}})
    line = next(l for l in str(info.value).splitlines() if "pointlight: " in l)
    assert "'spectrum'" in line and "llvm_ad_rgb" in line, line


def test_negative_luminous_value_fails_at_update(variant_rgb):
    """A luminous value set negative through mi.traverse is refused when the parameters
    are updated, naming the parameter."""
    import mitsuba as mi

    light = mi.load_dict({"type": "spotlight", "luminous_flux": 500.0})
    params = mi.traverse(light)
    params["luminous_flux"] = -1.0
    with pytest.raises(ValueError, match="spotlight: parameter 'luminous_flux' must be >= 0"):
        params.update()


PHOTOPIC_SCRIPT = """
import sys
import spectrace
spectrace.set_variant("llvm_ad_spectral")
from spectrace.plugins.emitters import luminous
w, V = luminous.photopic_efficiency()
print(int(w[V.argmax()]), repr(float(V.max())), "colour" in sys.modules)
"""


def test_photopic_table_is_kept_in_the_user_cache(tmp_path):
    """V(lambda) comes from colour-science the first time and from the user's cache folder
    after: the same table (peak 1 at 555 nm), and the second process never imports
    colour-science (its import costs more than a small render)."""
    import os
    import subprocess
    import sys

    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path)}
    runs = [subprocess.run([sys.executable, "-c", PHOTOPIC_SCRIPT], env=env, text=True,
                           capture_output=True, timeout=300) for _ in range(2)]
    for run in runs:
        assert run.returncode == 0, run.stderr[-2000:]
    first, second = (run.stdout.split() for run in runs)
    assert first[:2] == second[:2] and first[0] == "555"
    assert float(first[1]) == pytest.approx(1.0, abs=1e-12)
    assert first[2] == "True" and second[2] == "False"
    assert len(list((tmp_path / "spectrace").glob("photopic-*.npy"))) == 1
