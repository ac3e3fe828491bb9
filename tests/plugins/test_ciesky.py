"""Tests of the ``ciesky`` emitter: the 15 CIE standard general skies, the CIE overcast
and the uniform sky (ISO 15469:2004 / CIE S 011/E:2003), against closed forms and an
independent implementation of the standard's formula written here."""

from __future__ import annotations

import daylight_checks as day
import emitter_checks as checks
import numpy as np
import pytest

#: The standard's table 1 (a, b, c, d, e), typed again from ISO 15469:2004 / CIE S 011/E:2003
#: for an implementation independent of the plugin's.
STANDARD = {
    1: (4.0, -0.7, 0, -1.0, 0.0), 2: (4.0, -0.7, 2, -1.5, 0.15), 3: (1.1, -0.8, 0, -1.0, 0.0),
    4: (1.1, -0.8, 2, -1.5, 0.15), 5: (0.0, -1.0, 0, -1.0, 0.0), 6: (0.0, -1.0, 2, -1.5, 0.15),
    7: (0.0, -1.0, 5, -2.5, 0.3), 8: (0.0, -1.0, 10, -3.0, 0.45),
    9: (-1.0, -0.55, 2, -1.5, 0.15), 10: (-1.0, -0.55, 5, -2.5, 0.3),
    11: (-1.0, -0.55, 10, -3.0, 0.45), 12: (-1.0, -0.32, 10, -3.0, 0.45),
    13: (-1.0, -0.32, 16, -3.0, 0.3), 14: (-1.0, -0.15, 16, -3.0, 0.3),
    15: (-1.0, -0.15, 24, -2.8, 0.15),
}
#: float32 evaluation against the float64 formula.
RTOL_EVAL = 2e-5
#: Monte Carlo estimates (4096 samples of the meter or the plane) against closed forms.
RTOL_MC = 0.01
#: The sky component through an opening: the meter's cosine-distributed rays reach the
#: opening with probability F ~ 0.2, so 2^18 samples leave a binomial noise of
#: sqrt((1 - F) / (F N)) = 0.4 %; four of those.
RTOL_OPENING = 0.016
SPP_OPENING = 2**18
#: The window's share of the meter's cosine-distributed rays is smaller (~0.1): 0.6 %
#: binomial noise, four of those.
RTOL_WINDOW = 0.025
#: Direction samples on a cell boundary may be looked up in the neighbouring cell by the
#: pdf (float32 rounding): the share of samples allowed to differ.
BOUNDARY_SHARE = 0.01
#: The numerical E_h / L_z of the plugin against this file's own integral.
RTOL_INTEGRAL = 1e-4
CHI2_SIGNIFICANCE = 0.01
LZ = 1000.0
SUN = {"sun_azimuth": 200.0, "sun_elevation": 35.0}


def relative_luminance(sky_type, zenith, chi, zenith_sun):
    """L / L_z of the standard (eq. 1-3), angles in radians; numpy."""
    a, b, c, d, e = STANDARD[sky_type]

    def phi(z):
        return 1 + a * np.exp(b / np.cos(z))

    def f(x):
        return 1 + c * (np.exp(d * x) - np.exp(d * np.pi / 2)) + e * np.cos(x) ** 2

    return f(chi) * phi(zenith) / (f(zenith_sun) * (1 + a * np.exp(b)))


def sun_vector(azimuth, elevation):
    """The sun's direction in the scene frame of DESIGN.md: +Y up, north -Z, east +X."""
    A, h = np.radians(azimuth), np.radians(elevation)
    return np.array([np.cos(h) * np.sin(A), np.sin(h), -np.cos(h) * np.cos(A)])


def eval_sky(emitter, directions):
    """Luminance (cd/m^2) of ``emitter.eval`` towards the unit ``directions`` (N, 3): RGB
    variant, white spectrum, L_v = K_m CIE_Y_INTEGRAL Y."""
    import drjit as dr
    import mitsuba as mi

    n = directions.shape[0]
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = mi.Vector3f(*(-directions[:, i].astype(np.float32) for i in range(3)))
    value = np.array(emitter.eval(si), dtype=np.float64).T.reshape(n, -1)
    Y = value @ np.array([0.2126, 0.7152, 0.0722])
    return checks.KM * checks.CIE_Y_INTEGRAL * Y


def random_upper_directions(rng, n):
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    d[:, 1] = np.abs(d[:, 1]) + 1e-3
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def test_reference_page(variant_rgb):
    """The docstring is a reference page in the one format of spectrace's plugins."""
    from spectrace.plugins.emitters import ciesky

    table = checks.parse_reference_page(ciesky.__doc__, "ciesky")
    assert {"sky_type", "zenith_luminance", "horizontal_illuminance", "ground_reflectance",
            "sun_azimuth", "sun_elevation", "latitude", "longitude", "datetime", "up",
            "spectrum", "cct"} == set(table)


def test_coefficient_table_is_the_standards(variant_rgb):
    """The plugin's table of (a, b, c, d, e) is the standard's table 1, type by type."""
    from spectrace.plugins.emitters import ciesky

    assert ciesky.CIE_STANDARD_SKIES == {k: tuple(map(float, v)) for k, v in STANDARD.items()}


@pytest.mark.parametrize("sky_type", range(1, 16))
def test_relative_luminance_of_each_type(variant_rgb, rng, sky_type):
    """At random sky directions, L / L_z of each of the 15 types is the standard's
    f(chi) phi(Z) / (f(Z_s) phi(0)), and the zenith has the luminance asked for."""
    import mitsuba as mi

    sky = mi.load_dict({"type": "ciesky", "sky_type": sky_type, "zenith_luminance": LZ, **SUN})
    d = random_upper_directions(rng, 200)
    s = sun_vector(SUN["sun_azimuth"], SUN["sun_elevation"])
    zenith = np.arccos(np.clip(d[:, 1], -1, 1))
    chi = np.arccos(np.clip(d @ s, -1, 1))
    expected = LZ * relative_luminance(sky_type, zenith, chi, np.radians(90 - 35.0))
    np.testing.assert_allclose(eval_sky(sky, d), expected, rtol=RTOL_EVAL)
    assert eval_sky(sky, np.array([[0.0, 1.0, 0.0]]))[0] == pytest.approx(LZ, rel=RTOL_EVAL)


def test_cie_overcast_and_uniform_formulas(variant_rgb, rng):
    """CIE overcast: L = L_z (1 + 2 sin h) / 3, h the elevation; uniform: L = L_z; both
    independent of the sun; black below the horizon without a ground."""
    import mitsuba as mi

    d = random_upper_directions(rng, 100)
    overcast = mi.load_dict({"type": "ciesky", "sky_type": "cie_overcast",
                             "zenith_luminance": LZ, **SUN})
    np.testing.assert_allclose(eval_sky(overcast, d), LZ * (1 + 2 * d[:, 1]) / 3,
                               rtol=RTOL_EVAL)
    uniform = mi.load_dict({"type": "ciesky", "sky_type": "uniform", "zenith_luminance": LZ})
    np.testing.assert_allclose(eval_sky(uniform, d), LZ, rtol=RTOL_EVAL)
    below = d * np.array([1, -1, 1])
    assert np.all(eval_sky(overcast, below) == 0.0)


@pytest.mark.parametrize("sky_type", [1, 5, 8, 12, 15])
def test_horizontal_factor_against_own_integral(variant_rgb, sky_type):
    """E_h / L_z of the plugin (midpoint rule) equals this file's Gauss-Legendre integral of
    the standard's formula over the hemisphere; type 5 (no gradation, no indicatrix) is the
    uniform sky: pi."""
    import mitsuba as mi

    sky = mi.load_dict({"type": "ciesky", "sky_type": sky_type, "zenith_luminance": LZ, **SUN})
    x, w = np.polynomial.legendre.leggauss(400)
    mu, w_mu = 0.5 * (x + 1), 0.5 * w
    phi = (np.arange(1440) + 0.5) * (2 * np.pi / 1440)
    mu_g, phi_g = np.meshgrid(mu, phi, indexing="ij")
    sin_t = np.sqrt(1 - mu_g**2)
    d = np.stack([sin_t * np.cos(phi_g), mu_g, sin_t * np.sin(phi_g)], axis=-1)
    s = sun_vector(SUN["sun_azimuth"], SUN["sun_elevation"])
    rel = relative_luminance(sky_type, np.arccos(mu_g), np.arccos(np.clip(d @ s, -1, 1)),
                             np.radians(55.0))
    factor = np.sum(rel * mu_g * w_mu[:, None]) * (2 * np.pi / 1440)
    assert sky.horizontal_illuminance / LZ == pytest.approx(factor, rel=RTOL_INTEGRAL)
    if sky_type == 5:
        assert factor == pytest.approx(np.pi, rel=1e-9)


@pytest.mark.parametrize("sky_type, factor", [("cie_overcast", 7 * np.pi / 9),
                                              ("uniform", np.pi)])
def test_unobstructed_horizontal_illuminance(variant, sky_type, factor):
    """Mitsuba's irradiancemeter under the unobstructed sky reads E_h = 7 pi L_z / 9 (CIE
    overcast) and pi L_z (uniform), in lux, in RGB and spectral variants."""
    light = {"type": "ciesky", "sky_type": sky_type, "zenith_luminance": LZ}
    assert day.meter_lux(light) == pytest.approx(factor * LZ, rel=RTOL_MC)


def test_horizontal_illuminance_sets_the_scale(variant_rgb):
    """Given ``horizontal_illuminance``, the zenith luminance is E_h / (7 pi / 9) for the
    CIE overcast sky, and a diffuse plane lit through emitter sampling reads E_h."""
    import mitsuba as mi

    light = {"type": "ciesky", "horizontal_illuminance": 12000.0}
    sky = mi.load_dict(light)
    assert sky.zenith_luminance == pytest.approx(12000.0 / (7 * np.pi / 9), rel=1e-12)
    assert checks.lux_at(light, (0.3, 0.2), spp=4096) == pytest.approx(12000.0, rel=RTOL_MC)


@pytest.mark.parametrize("sky_type", ["uniform", "cie_overcast"])
def test_sky_component_under_roof_opening(variant_rgb, sky_type):
    """Under a horizontal a x b opening at height c, the sky component at the point below
    its centre is pi L F (uniform sky, F the configuration factor of the rectangle) and,
    for the CIE overcast sky, this file's numerical integral of L cos(theta) d omega over
    the opening (dA c^2 / r^4)."""
    a, b, c = 2.0, 1.0, 1.5
    light = {"type": "ciesky", "sky_type": sky_type, "zenith_luminance": LZ}
    if sky_type == "uniform":
        expected = np.pi * LZ * day.rectangle_configuration_factor(a, b, c)
    else:
        n = 800
        x = (np.arange(n) + 0.5) / n * a - a / 2
        z = (np.arange(n) + 0.5) / n * b - b / 2
        X, Z = np.meshgrid(x, z, indexing="ij")
        r = np.sqrt(X**2 + Z**2 + c * c)
        L = LZ * (1 + 2 * c / r) / 3
        expected = float(np.sum(L * c * c / r**4) * (a / n) * (b / n))
    measured = day.meter_lux(light, day.roof_with_opening(c, a, b), spp=SPP_OPENING)
    assert measured == pytest.approx(expected, rel=RTOL_OPENING)


@pytest.mark.parametrize("sky", [
    {"sky_type": 12, "sun_azimuth": 120.0, "sun_elevation": 25.0},
    {"sky_type": "cie_overcast", "ground_reflectance": 0.3},
    {"sky_type": 15, "sun_azimuth": 300.0, "sun_elevation": 60.0, "ground_reflectance": 0.2},
])
def test_sample_direction_chi2(variant_rgb, sky):
    """``sample_direction`` draws directions with the density ``pdf_direction`` reports
    (Pearson's chi-square test, mitsuba.chi2)."""
    import drjit as dr
    import mitsuba as mi
    from mitsuba import chi2

    emitter = mi.load_dict({"type": "ciesky", **sky})
    it = dr.zeros(mi.Interaction3f)

    def sample(s):
        ds, _ = emitter.sample_direction(it, s)
        return ds.d

    def pdf(v):
        ds = dr.zeros(mi.DirectionSample3f)
        ds.d = v
        return emitter.pdf_direction(it, ds)

    test = chi2.ChiSquareTest(domain=chi2.SphericalDomain(), sample_func=sample, pdf_func=pdf,
                              sample_dim=2, sample_count=400_000, res=101, ires=16)
    assert test.run(CHI2_SIGNIFICANCE), test.messages


def test_sample_weight_is_radiance_over_pdf(variant_rgb, rng):
    """Each direction sample's weight is L(d) / pdf(d), and it names the emitter."""
    import drjit as dr
    import mitsuba as mi

    emitter = mi.load_dict({"type": "ciesky", "sky_type": 9, **SUN, "ground_reflectance": 0.2})
    n = 1000
    it = dr.zeros(mi.Interaction3f, n)
    u = rng.random((n, 2)).astype(np.float32)
    ds, weight = emitter.sample_direction(it, mi.Point2f(u[:, 0], u[:, 1]))
    radiance = emitter.eval_direction(it, ds)
    pdf = np.array(emitter.pdf_direction(it, ds))
    ratio = np.array(weight)[0] / (np.array(radiance)[0] / pdf)
    assert np.mean(np.abs(ratio - 1) > 1e-5) < BOUNDARY_SHARE
    assert np.mean(np.abs(np.array(ds.pdf) / pdf - 1) > 1e-6) < BOUNDARY_SHARE
    assert np.median(ratio) == pytest.approx(1.0, rel=1e-6)
    assert np.all(np.array(dr.reinterpret_array(mi.UInt32, ds.emitter)) != 0)


def test_ground_luminance(variant_rgb):
    """Below the horizon the ground is uniform with L = rho E_h / pi."""
    import mitsuba as mi

    sky = mi.load_dict({"type": "ciesky", "zenith_luminance": LZ, "ground_reflectance": 0.25})
    L = eval_sky(sky, np.array([[0.3, -0.5, 0.1], [0.0, -1.0, 0.0]]) /
                 np.array([[np.sqrt(0.35)], [1.0]]))
    np.testing.assert_allclose(L, 0.25 * 7 * np.pi / 9 * LZ / np.pi, rtol=RTOL_EVAL)


def test_up_axis(variant_rgb):
    """With ``up`` = +Z the zenith is +Z and the sun at azimuth 90 (east) lies towards +X."""
    import mitsuba as mi

    sky = mi.load_dict({"type": "ciesky", "sky_type": 13, "zenith_luminance": LZ,
                        "sun_azimuth": 90.0, "sun_elevation": 20.0,
                        "up": mi.ScalarVector3f(0, 0, 1)})
    assert eval_sky(sky, np.array([[0.0, 0.0, 1.0]]))[0] == pytest.approx(LZ, rel=RTOL_EVAL)
    h = np.radians(20.0)
    towards_sun = np.array([[np.cos(h), 0.0, np.sin(h)], [-np.cos(h), 0.0, np.sin(h)]])
    east, west = eval_sky(sky, towards_sun)
    assert east > 5 * west


def test_position_from_place_and_time(variant_rgb):
    """``latitude``/``longitude``/``datetime`` put the sun where NREL's SPA (pvlib) says."""
    import mitsuba as mi
    from spectrace.plugins.emitters import solar

    when = "2026-06-21T15:00:00+02:00"
    sky = mi.load_dict({"type": "ciesky", "sky_type": 12, "latitude": 48.85,
                        "longitude": 2.35, "datetime": when})
    azimuth, elevation = solar.solar_position(48.85, 2.35, solar.parse_datetime(when, "t"))
    assert (sky.azimuth, sky.elevation) == pytest.approx((azimuth, elevation), abs=1e-9)
    assert 200 < azimuth < 260 and 50 < elevation < 65


@pytest.mark.parametrize("props, words", [
    ({"sky_type": 16}, "sky_type"),
    ({"sky_type": "clear"}, "sky_type"),
    ({"sky_type": 12, "sun_elevation": -5.0}, "below the horizon"),
    ({"zenith_luminance": 1.0, "horizontal_illuminance": 1.0}, "not both"),
    ({"zenith_luminance": -1.0}, "zenith_luminance"),
    ({"ground_reflectance": 1.5}, "ground_reflectance"),
    ({"latitude": 95.0, "longitude": 0.0, "datetime": "2026-01-01T12:00:00+00:00"},
     "latitude"),
    ({"latitude": 45.0, "longitude": 0.0, "datetime": "2026-01-01T12:00:00"}, "UTC offset"),
    ({"latitude": 45.0, "longitude": 0.0}, "datetime"),
    ({"sun_elevation": 30.0, "latitude": 45.0}, "not both"),
    ({"cct": 2000.0}, "cct"),
])
def test_bad_parameters(variant_rgb, props, words):
    """Bad parameters fail at load with one line naming the parameter."""
    import mitsuba as mi

    with pytest.raises(Exception) as error:
        mi.load_dict({"type": "ciesky", **props})
    message = str(error.value)
    assert words in message and "ciesky" in message


def test_sunless_sky_accepts_a_sun_below_the_horizon(variant_rgb):
    """Types 1, 3 and 5 and the CIE overcast sky do not depend on the sun: a night sun
    is no error."""
    import mitsuba as mi

    for sky_type in (1, 3, 5, "cie_overcast"):
        mi.load_dict({"type": "ciesky", "sky_type": sky_type, "sun_elevation": -10.0})


def test_cct_spectrum(variant_spectral):
    """``cct`` gives the CIE daylight of that CCT; the luminance stays the one asked for."""
    import mitsuba as mi
    from spectrace.plugins.emitters import luminous

    sky = mi.load_dict({"type": "ciesky", "sky_type": "uniform", "zenith_luminance": LZ,
                        "cct": 6500.0})
    assert luminous.KM * luminous.photometric_integral(sky.texture) * sky.scale == \
        pytest.approx(LZ, rel=1e-6)


@pytest.mark.parametrize("light", [
    {"type": "ciesky", "sky_type": "uniform", "zenith_luminance": LZ},
    {"type": "sun", "sun_elevation": 60.0},
])
@pytest.mark.parametrize("integrator", ["direct", "path"])
def test_no_light_inside_a_closed_box(variant_rgb, light, integrator):
    """Inside a closed box of six identical grey rectangles, which Mitsuba 3.9 merges into
    one mesh of invalid bounds (its own ``constant`` sky then leaks through the walls), the
    daylight emitters give exactly 0: their shadow rays do not depend on the scene's
    bounds."""
    image, shapes = day.render_inside_box(light, integrator)
    assert shapes == 1  # the trap is there: every wall merged into one mesh
    assert np.all(image == 0.0)


@pytest.mark.parametrize("sky_type", ["uniform", "cie_overcast"])
def test_sky_component_of_a_vertical_window(variant_rgb, sky_type):
    """At a floor point of a closed room with one window in its north wall (a vertical
    opening x in [-1, 1], y in [0.5, 2] at distance Z = 1.5), the horizontal illuminance is
    this file's numerical integral of L cos(theta) d omega over the window (dA y Z / r^4),
    for the uniform and the CIE overcast sky (L = L_z (1 + 2 y / r) / 3)."""
    Z, (x0, x1), (y0, y1) = 1.5, (-1.0, 1.0), (0.5, 2.0)
    n = 1000
    x = x0 + (np.arange(n) + 0.5) / n * (x1 - x0)
    y = y0 + (np.arange(n) + 0.5) / n * (y1 - y0)
    X, Y = np.meshgrid(x, y, indexing="ij")
    r = np.sqrt(X**2 + Y**2 + Z * Z)
    L = LZ * ((1 + 2 * Y / r) / 3 if sky_type == "cie_overcast" else 1.0)
    expected = float(np.sum(L * Y * Z / r**4) * ((x1 - x0) / n) * ((y1 - y0) / n))
    room = day.room_with_window((-3.0, 3.0), (-Z, 3.0), 3.0, (x0, x1), (y0, y1))
    light = {"type": "ciesky", "sky_type": sky_type, "zenith_luminance": LZ}
    measured = day.meter_lux(light, room, spp=SPP_OPENING)
    assert measured == pytest.approx(expected, rel=RTOL_WINDOW)


@pytest.mark.parametrize("position, words", [
    ('<float name="latitude" value="45"/><float name="longitude" value="5"/>'
     '<string name="datetime" value="2026-06-21T12:00:00"/>', "no UTC offset"),
    ('<float name="latitude" value="95"/><float name="longitude" value="5"/>'
     '<string name="datetime" value="2026-06-21T12:00:00+02:00"/>', "latitude"),
    ('<float name="sun_elevation" value="-4"/>', "below the horizon"),
])
def test_bad_sky_on_the_command_line(tmp_path, capsys, position, words):
    """A naive datetime, a latitude out of range, a sun below the horizon under a
    sun-dependent sky: ``spectrace render`` says so in one line, exit 2, writes nothing."""
    from spectrace.cli import main

    scene = tmp_path / "sky.xml"
    scene.write_text(f"""<scene version="3.0.0">
        <integrator type="direct"/>
        <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/>
            <integer name="height" value="4"/></film></sensor>
        <emitter type="ciesky"><integer name="sky_type" value="12"/>{position}</emitter>
    </scene>""")
    out = tmp_path / "out.exr"
    assert main(["render", str(scene), "-o", str(out), "--spp", "1", "-q"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error:") and words in err and len(err.splitlines()) == 1
    assert not out.exists() and not out.with_suffix(".png").exists()


def test_every_variant(any_variant):
    """The uniform sky gives pi L_z lux on Mitsuba's irradiancemeter in every LLVM variant
    (mono and polarized included: emitted light is unpolarized)."""
    light = {"type": "ciesky", "sky_type": "uniform", "zenith_luminance": LZ}
    assert day.meter_lux(light, spp=1024) == pytest.approx(np.pi * LZ, rel=RTOL_MC)
