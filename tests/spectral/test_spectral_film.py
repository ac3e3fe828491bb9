"""The spectral film (specfilm with hat bands) and its conversion to linear sRGB.

Oracle: colour-science's sRGB of ColorChecker reflectances under D65, and Mitsuba's own
hdrfilm rendering of the same scene in llvm_ad_spectral.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import colour
import numpy as np
import pytest

from spectrace import spectral as S
from spectrace.errors import ParameterError
from spectrace.spectral_film import (
    band_centres,
    band_gram_matrix,
    band_responses,
    bands_to_linear_srgb,
    film_to_bands,
    replace_film,
)

# colour-science warns when it resamples the oracle data; expected here.
pytestmark = pytest.mark.filterwarnings("ignore::colour.utilities.ColourRuntimeWarning")

#: CIEDE2000 between a rendered patch and colour-science's colour of its reflectance.
DE_RENDER_MAX = 0.5
#: band quantisation alone (exact band averages, no noise) at 16 bands over 400-700 nm.
DE_QUANTISATION_MAX = 0.3
#: rendered band values vs their exact band averages (Monte Carlo noise at SPP, and Mitsuba's
#: `d65` being 0.1% below colour-science's D65 at Y = 1).
BAND_RTOL = 0.03
BAND_RTOL_ENV = 3e-3  # directly seen environment: wavelength noise only, low-discrepancy
GRID = 5  # 5 x 5 patches, the last cell empty (the D65 environment itself)
PIXELS_PER_PATCH = 2
SPP = 4096  # low-discrepancy sampler: colour noise well below the CIEDE2000 tolerance
BANDS = 16

FINE = np.arange(360.0, 830.01, 0.25)


def scene_xml(film="hdrfilm"):
    """Flat diffuse ColorChecker patches facing an orthographic camera, in a constant
    Mitsuba `d65` environment (normalised so a white surface has Y = 1)."""
    wl, refl, _ = S.colorchecker()
    shapes = []
    for p in range(24):
        r, c = divmod(p, GRID)
        x, y = -1 + (2 * c + 1) / GRID, 1 - (2 * r + 1) / GRID
        shapes.append(
            f'<shape type="rectangle"><transform name="to_world"><scale value="{1 / GRID}"/>'
            f'<translate x="{x}" y="{y}"/></transform><bsdf type="diffuse">'
            f"{S.to_mitsuba_spectrum_xml('reflectance', wl, refl[p])}</bsdf></shape>"
        )
    res = GRID * PIXELS_PER_PATCH
    return f"""<scene version="3.0.0">
  <integrator type="path"><integer name="max_depth" value="2"/></integrator>
  <sensor type="orthographic">
    <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <sampler type="ldsampler"><integer name="sample_count" value="{SPP}"/></sampler>
    <film type="{film}" id="myfilm">
      <integer name="width" value="{res}"/><integer name="height" value="{res}"/>
      <string name="pixel_format" value="rgb"/><rfilter type="box"/></film>
  </sensor>
  <emitter type="constant"><spectrum name="radiance" type="d65"/></emitter>
  {"".join(shapes)}
</scene>"""


def patch_means(image):
    """(25, C) mean of each patch's pixels (row-major patches, last = environment)."""
    h, w, c = image.shape
    k = PIXELS_PER_PATCH
    return image.reshape(GRID, k, GRID, k, c).mean(axis=(1, 3)).reshape(GRID * GRID, c)


def oracle_srgb():
    """colour-science: sRGB of each reflectance under D65 (white Y = 1), + the white itself.

    Linear sRGB from colour-science, encoded with encode_srgb (odd extension) because
    colour-science encodes the negative components of out-of-gamut colours (cyan) differently.
    """
    sds = colour.SDS_COLOURCHECKERS["ColorChecker N Ohta"]
    xyz = [
        colour.sd_to_XYZ(sd, illuminant=colour.SDS_ILLUMINANTS["D65"]) / 100 for sd in sds.values()
    ]
    white = colour.xy_to_XYZ(colour.CCS_ILLUMINANTS[S.CIE_1931_2]["D65"])
    return S.encode_srgb(
        colour.XYZ_to_RGB(np.vstack([xyz, white]), "sRGB", apply_cctf_encoding=False)
    )


def radiance_on_fine_grid():
    """Exact reflected radiance R(l) D65(l) / Y(D65) of the 24 patches + the environment."""
    wl, refl, _ = S.colorchecker()
    d65_wl, d65 = S.illuminant("D65")
    rows = np.vstack([[np.interp(FINE, wl, r) for r in refl], np.ones((1, FINE.size))])
    return rows * np.interp(FINE, d65_wl, d65) / S.spd_to_xyz(d65_wl, d65)[1]


def exact_band_averages(bands=BANDS, wavelength_range=(400.0, 700.0)):
    L = radiance_on_fine_grid()
    responses = [
        np.interp(FINE, w, v, left=0, right=0) for w, v in band_responses(bands, wavelength_range)
    ]
    # divided by the response's own quadrature: the discrete ramp at a half hat's edge cancels
    return np.stack(
        [np.trapezoid(L * r, FINE, axis=-1) / np.trapezoid(r, FINE) for r in responses], axis=-1
    )


@pytest.fixture(scope="module")
def renders():
    """The same scene rendered with hdrfilm and with replace_film (16 bands), llvm_ad_spectral."""
    import spectrace

    spectrace.set_variant("llvm_ad_spectral")
    import mitsuba as mi

    xml = scene_xml()
    rgb_ref = np.array(mi.render(mi.load_string(xml), seed=1))
    root = ET.fromstring(xml)
    centres = replace_film(root, BANDS)
    raw = mi.render(mi.load_string(ET.tostring(root, encoding="unicode")), seed=2)
    return rgb_ref, film_to_bands(raw, centres), centres


def test_replace_film_structure():
    """Every sensor gets a specfilm with N hat bands (unit integral), keeping id, size and
    rfilter and dropping hdrfilm-only parameters; centres are linspace(400, 700, N)."""
    root = ET.fromstring(scene_xml())
    second = ET.fromstring('<sensor type="perspective"/>')
    root.append(second)
    centres = replace_film(root, 8)
    np.testing.assert_allclose(centres, np.linspace(400, 700, 8))
    films = [s.find("film") for s in root.iter("sensor")]
    assert [f.get("type") for f in films] == ["specfilm", "specfilm"]
    first = films[0]
    assert first.get("id") == "myfilm"
    assert first.find("integer[@name='width']").get("value") == "10"
    assert first.find("rfilter").get("type") == "box"
    assert first.find("string[@name='pixel_format']") is None
    assert len(first.findall("spectrum")) == 8
    np.testing.assert_allclose(band_centres(1), [550.0])


@pytest.mark.parametrize("bands", [1, 2, 16, 18])
def test_responses_sum_to_a_constant(bands):
    """The band responses sum to one constant over [400, 700] nm (1; 1/300 nm for one band):
    flat wavelength sampling; each is a hat (or box) with its peak at its centre."""
    inside = FINE[(FINE >= 400) & (FINE <= 700)]
    responses = band_responses(bands)
    total = sum(np.interp(inside, w, v, left=0, right=0) for w, v in responses)
    np.testing.assert_allclose(total, total[0], rtol=1e-12)
    assert total[0] == pytest.approx(1.0 if bands > 1 else 1 / 300)
    for c, (w, v) in zip(band_centres(bands), responses, strict=True):
        assert w[np.argmax(v)] == pytest.approx(c) or bands == 1


def test_replace_film_bad_input():
    """bands < 1 and a scene without a sensor are user errors."""
    with pytest.raises(ParameterError, match="bands"):
        replace_film(ET.fromstring(scene_xml()), 0)
    with pytest.raises(ParameterError, match="no <sensor>"):
        replace_film(ET.fromstring('<scene version="3.0.0"/>'), 4)
    with pytest.raises(ParameterError, match="range"):
        replace_film(ET.fromstring(scene_xml()), 4, (700.0, 400.0))


def test_gram_matrix_is_the_band_average_of_the_hats(rng):
    """G from its closed form equals band averages of each hat, by numerical quadrature,
    also on an uneven set of centres."""
    for centres in (band_centres(7), np.sort(rng.uniform(400, 700, 6))):
        grid = np.linspace(centres[0], centres[-1], 200001)
        hats = np.stack(
            [np.interp(grid, centres, np.eye(centres.size)[j]) for j in range(centres.size)]
        )
        expected = (hats @ hats.T) / hats.sum(axis=1)[:, None]  # uniform grid: sums ~ integrals
        np.testing.assert_allclose(band_gram_matrix(centres), expected, atol=1e-4)


def test_bands_to_linear_srgb_is_deconvolved_xyz(rng):
    """bands_to_linear_srgb = xyz_to_linear_srgb(spectral_image_to_xyz(G^-1 B, centres))."""
    c = band_centres(BANDS)
    b = rng.uniform(0, 1, (3, 4, BANDS)).astype(np.float32)
    samples = np.linalg.solve(band_gram_matrix(c), b.reshape(-1, BANDS).T).T.reshape(b.shape)
    expected = S.xyz_to_linear_srgb(S.spectral_image_to_xyz(samples, c))
    out = bands_to_linear_srgb(b, c)
    assert out.shape == (3, 4, 3) and out.dtype == np.float32
    np.testing.assert_allclose(out, expected, rtol=1e-5, atol=1e-6)


def test_band_quantisation_error_is_small():
    """Without noise (exact band averages), 16 bands over 400-700 nm reproduce colour-science's
    sRGB of every ColorChecker patch under D65, and the white, to CIEDE2000 < 0.3."""
    rgb = bands_to_linear_srgb(exact_band_averages()[None], band_centres(BANDS))[0]
    de = S.delta_e_2000(S.encode_srgb(rgb), oracle_srgb())
    assert de.max() < DE_QUANTISATION_MAX, de


@pytest.mark.slow
def test_rendered_bands_are_band_averaged_radiance(renders):
    """specfilm channel i holds integral L hat_i / integral hat_i, in wavelength order."""
    _, bands, _ = renders
    np.testing.assert_allclose(patch_means(bands), exact_band_averages(), rtol=BAND_RTOL)


@pytest.mark.slow
def test_rendered_colorchecker_matches_colour_science(renders):
    """Each rendered patch's sRGB from the band image is colour-science's sRGB of that
    reflectance under D65 (CIEDE2000 < 0.5), like the hdrfilm render; the environment is white."""
    rgb_ref, bands, centres = renders
    ours = S.encode_srgb(patch_means(bands_to_linear_srgb(bands, centres)))
    hdr = S.encode_srgb(patch_means(rgb_ref))
    oracle = oracle_srgb()
    assert S.delta_e_2000(ours, oracle).max() < DE_RENDER_MAX
    assert S.delta_e_2000(hdr, oracle).max() < DE_RENDER_MAX
    assert S.delta_e_2000(ours, hdr).max() < DE_RENDER_MAX


@pytest.mark.slow
def test_spectral_exr_of_a_render_round_trips(renders, tmp_path):
    """The render path of `--film spectral`: the band image written as a Fichet 2021 EXR
    (preview = bands_to_linear_srgb) reads back with the same bands and wavelengths."""
    _, bands, centres = renders
    rgb = bands_to_linear_srgb(bands, centres)
    path = S.write_spectral_exr(tmp_path / "out.spectral.exr", bands, centres, preview=rgb)
    back, wl = S.read_spectral_exr(path)
    np.testing.assert_array_equal(wl, centres)
    np.testing.assert_array_equal(back, bands.astype(np.float32))


@pytest.mark.parametrize("bands", [1, 5, 18, 19])
def test_band_averages_for_any_band_count(variant_spectral, bands):
    """In a constant D65 environment every band of film_to_bands(render) is the band average
    of Mitsuba's d65 radiance, also for band counts whose spacing is not a float32-exact
    divisor of the range (18, 19: regression for specfilm's sampling grid)."""
    import mitsuba as mi

    xml = """<scene version="3.0.0"><integrator type="path"/>
      <sensor type="orthographic"><sampler type="ldsampler"/>
        <film type="hdrfilm"><integer name="width" value="2"/><integer name="height" value="2"/>
          <rfilter type="box"/></film></sensor>
      <emitter type="constant"><spectrum name="radiance" type="d65"/></emitter></scene>"""
    root = ET.fromstring(xml)
    centres = replace_film(root, bands)
    raw = mi.render(mi.load_string(ET.tostring(root, encoding="unicode")), spp=1024, seed=3)
    got = film_to_bands(raw, centres).reshape(-1, bands).mean(axis=0)
    d65 = mi.load_dict({"type": "d65"})  # Mitsuba's own D65 scale (Y = 1 up to 0.1%)
    import drjit as dr

    si = dr.zeros(mi.SurfaceInteraction3f, FINE.size)
    si.wavelengths = mi.Spectrum(*[mi.Float(FINE)] * 4)
    radiance = np.array(d65.eval(si)[0])
    responses = [np.interp(FINE, w, v, left=0, right=0) for w, v in band_responses(bands)]
    expected = [np.trapezoid(radiance * r, FINE) / np.trapezoid(r, FINE) for r in responses]
    np.testing.assert_allclose(got, expected, rtol=BAND_RTOL_ENV)


def test_film_to_bands_divides_by_hat_areas():
    """A raw channel integral L hat_i becomes a band average: for constant L = 1 the raw
    values are the hat areas (d, d/2 at the ends), film_to_bands gives 1 in every band."""
    c = band_centres(7)
    areas = np.array([np.trapezoid(v, w) for w, v in band_responses(7)])
    np.testing.assert_allclose(areas, [25, 50, 50, 50, 50, 50, 25])
    raw = np.broadcast_to(areas, (2, 3, 7))
    np.testing.assert_allclose(film_to_bands(raw, c), 1.0, rtol=1e-7)
    one = np.full((2, 2, 1), 0.7)
    np.testing.assert_allclose(film_to_bands(one, band_centres(1)), 0.7, rtol=1e-7)
    with pytest.raises(ValueError, match="mismatched"):
        film_to_bands(raw[..., :6], c)
    with pytest.raises(ValueError, match="evenly"):
        film_to_bands(raw, np.r_[c[:-1], 720.0])
