"""Flux, peak, beam and field angles of analytic distributions written as IES and LDT files.

The expected values are closed forms of the analytic profiles (not produced by the reader):
an isotropic source of I cd emits 4 pi I lm, I0 cos(gamma) below the horizon pi I0,
I0 cos^n(gamma) 2 pi I0 / (n + 1), with beam (50%) and field (10%) full angles
2 arccos(0.5^(1/n)) and 2 arccos(0.1^(1/n)).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from spectrace.photometry import generate as G
from spectrace.photometry import read_photometry

FLUX_RTOL = 1e-3  # the brief: analytic profiles within 0.1%
ANGLE_ATOL_DEG = 0.1  # 50% / 10% crossings of cos^n between 0.5-degree samples
ZONAL_RTOL = 5e-3  # our exact integral of the interpolated table vs the zonal-lumen sum
GAMMA_FINE = np.arange(0.0, 90.001, 0.5)  # downward hemisphere, 0.5 degree steps
GAMMA_SPHERE = np.arange(0.0, 180.001, 2.5)


@pytest.mark.parametrize("symmetry", ["rotational", "quadrant", "none"])
def test_isotropic_flux_is_4_pi_I(tmp_path, symmetry):
    """A uniform 50 cd over the whole sphere is 4 pi 50 lm, whatever the symmetry."""
    path = G.write_ies_function(tmp_path / "iso.ies", G.isotropic(50.0), symmetry=symmetry,
                                vertical_angles=GAMMA_SPHERE)
    assert read_photometry(path).flux == pytest.approx(4 * np.pi * 50.0, rel=FLUX_RTOL)


@pytest.mark.parametrize("n", [1, 2, 10, 29])
def test_cos_power_flux_beam_and_field(tmp_path, n):
    """I0 cos^n(gamma): flux 2 pi I0 / (n + 1) (pi I0 for Lambertian n = 1), beam and field
    angles 2 arccos(0.5^(1/n)), 2 arccos(0.1^(1/n)), peak I0 at nadir."""
    I0 = 1200.0
    path = G.write_ies_function(tmp_path / "cos.ies", G.cos_power(I0, n),
                                vertical_angles=GAMMA_FINE)
    ph = read_photometry(path)
    assert ph.flux == pytest.approx(2 * np.pi * I0 / (n + 1), rel=FLUX_RTOL)
    if n == 1:
        assert ph.flux == pytest.approx(np.pi * I0, rel=FLUX_RTOL)
    assert ph.beam_angle == pytest.approx(2 * np.degrees(np.arccos(0.5 ** (1 / n))),
                                          abs=ANGLE_ATOL_DEG)
    assert ph.field_angle == pytest.approx(2 * np.degrees(np.arccos(0.1 ** (1 / n))),
                                           abs=ANGLE_ATOL_DEG)
    assert ph.max_candela == pytest.approx(I0)
    assert ph.peak_direction[0] == 0.0


def test_zonal_flux_of_an_isotropic_source(tmp_path):
    """An isotropic I sends 2 pi I (cos a - cos b) into the zone a <= gamma <= b: 2 pi I
    downward; the same from a Type B file covering the sphere."""
    I = 20.0
    ph = read_photometry(G.write_ies_function(tmp_path / "iso.ies", G.isotropic(I),
                                              vertical_angles=GAMMA_SPHERE))
    assert ph.flux_between(0.0, 90.0) == pytest.approx(2 * np.pi * I, rel=1e-12)
    a, b = np.radians(31.0), np.radians(58.0)
    assert ph.flux_between(31.0, 58.0) == pytest.approx(2 * np.pi * I * (np.cos(a) - np.cos(b)),
                                                        rel=1e-12)
    H, V = np.arange(-90.0, 90.001, 5.0), np.arange(-180.0, 180.001, 5.0)
    b_file = G.write_ies(tmp_path / "b.ies", V, H, np.full((H.size, V.size), I),
                         photometric_type="B")
    ph_b = read_photometry(b_file)
    assert ph_b.flux == pytest.approx(4 * np.pi * I, rel=FLUX_RTOL)
    assert ph_b.flux_between(0.0, 90.0) == pytest.approx(2 * np.pi * I, rel=FLUX_RTOL)


def test_ldt_cos_power_flux(tmp_path):
    """A EULUMDAT cos^3 file in cd/klm of a 2000 lm lamp: flux 2 pi I0 / 4 in lm."""
    I0 = 800.0
    path = G.write_ldt(tmp_path / "cos.ldt", G.cos_power(I0, 3), isym=1,
                       gamma_angles=np.arange(0.0, 180.001, 1.0), lamp_flux=2000.0)
    ph = read_photometry(path)
    assert ph.format == "EULUMDAT"
    assert ph.flux == pytest.approx(2 * np.pi * I0 / 4, rel=FLUX_RTOL)


def test_type_b_flux_of_a_spot_about_the_aiming_axis(tmp_path):
    """Type B: I0 cos^n of the angle to the aiming axis (H = V = 0), tabulated over
    H -90..90 and V -90..90 (the front hemisphere), emits 2 pi I0 / (n + 1); laterally
    symmetric (H 0..90) the same."""
    I0, n = 500.0, 4
    H = np.arange(-90.0, 90.001, 1.0)
    V = np.arange(-90.0, 90.001, 1.0)
    func = G.cos_power(I0, n)
    for h in (H, H[H >= 0]):
        path = G.write_ies(tmp_path / "b.ies", V, h, G.tabulate(func, V, h, "B"),
                           photometric_type="B")
        ph = read_photometry(path)
        assert ph.flux == pytest.approx(2 * np.pi * I0 / (n + 1), rel=FLUX_RTOL)


def test_wall_washer_peak_is_toward_c0(tmp_path):
    """The wall-washer lobe (no downlight term) has its axis 40 degrees towards C = 0: its
    peak is there, and it sends far more light towards C = 0 than C = 180 at one gamma."""
    lobe = G.wall_washer(1000.0, tilt_deg=40.0, downlight=0.0)
    path = G.write_ies_function(tmp_path / "ww.ies", lobe,
                                symmetry="bilateral_0_180", c_step=5.0,
                                vertical_angles=np.arange(0.0, 90.001, 1.0))
    ph = read_photometry(path)
    assert ph.symmetry == "bilateral_0_180"
    assert ph.peak_direction == pytest.approx((40.0, 0.0))
    assert ph.intensity(40.0, 0.0) > 10 * ph.intensity(40.0, 180.0)


def zonal_lumens(ph) -> float:
    """The IES zonal-lumen method of photometric reports (an independent oracle): each
    tabulated gamma_i stands for the zone halfway to its neighbours, lumens = the C-mean
    intensity at gamma_i times the zone's solid angle 2 pi (cos a - cos b)."""
    g = ph.vertical_angles
    edges = np.concatenate([[g[0]], (g[1:] + g[:-1]) / 2, [g[-1]]])
    c = np.linspace(0.0, 360.0, 721)
    mean_I = ph.intensity(g[None, :], c[:, None]).mean(axis=0)
    return float(np.sum(mean_I * 2 * np.pi * -np.diff(np.cos(np.radians(edges)))))


@pytest.mark.parametrize("name", ["downlight.ies", "downlight.ldt", "wallwasher.ies"])
def test_flux_agrees_with_the_zonal_lumen_method(name):
    """The example luminaires' flux agrees with the zonal-lumen method that photometric
    tools report, to 0.5% (the brief's bound for commercial tools on real files)."""
    path = Path(__file__).parents[2] / "scenes" / "luminaires" / name
    ph = read_photometry(path)
    assert ph.flux == pytest.approx(zonal_lumens(ph), rel=ZONAL_RTOL)


def test_uplight_beam_angle_through_the_zenith(tmp_path):
    """An uplight I0 cos^4 of the angle from the zenith (vertical angles 90-180): flux
    2 pi I0 / 5 and beam angle 2 arccos(0.5^(1/4)), measured across gamma = 180."""
    I0, n = 300.0, 4
    v = np.arange(90.0, 180.001, 0.5)
    table = (I0 * np.cos(np.radians(180.0 - v)) ** n)[None]
    ph = read_photometry(G.write_ies(tmp_path / "up.ies", v, [0.0], table))
    assert ph.flux == pytest.approx(2 * np.pi * I0 / (n + 1), rel=FLUX_RTOL)
    assert ph.flux_between(0.0, 90.0) == 0.0
    assert ph.beam_angle == pytest.approx(2 * np.degrees(np.arccos(0.5 ** (1 / n))),
                                          abs=ANGLE_ATOL_DEG)


def cardioid(I0: float, k: float):
    """I0 ((1 + cos gamma) / 2)^k: falls to the fraction f of its peak at
    cos gamma = 2 f^(1/k) - 1, so its full spread is 2 arccos(2 f^(1/k) - 1)."""

    def intensity(gamma, c):
        g = np.radians(np.asarray(gamma, np.float64))
        return I0 * ((1.0 + np.cos(g)) / 2.0) ** k + 0.0 * np.asarray(c)

    return intensity


def test_beam_and_field_per_plane_of_cos_powers(tmp_path):
    """cos^m beams in each main plane: beam 2 arccos(0.5^(1/m)), field 2 arccos(0.1^(1/m));
    a distribution cos^m in C0-C180 and cos^n in C90-C270 (I = I0 (cos gamma)^(m cos^2 C +
    n sin^2 C)) has the two planes' own angles."""
    m, n = 2.0, 20.0
    g = np.arange(0.0, 180.001, 0.25)

    def elliptic(gamma, c):
        e = m * np.cos(np.radians(c)) ** 2 + n * np.sin(np.radians(c)) ** 2
        cg = np.cos(np.radians(gamma))
        return np.where(cg > 0, 1000.0 * np.abs(cg) ** e, 0.0)

    ph = read_photometry(G.write_ies_function(tmp_path / "e.ies", elliptic, symmetry="quadrant",
                                              vertical_angles=g, c_step=5.0))
    for fraction, angles in ((0.5, ph.beam_angles), (0.1, ph.field_angles)):
        for plane, power in (("C0-C180", m), ("C90-C270", n)):
            expected = 2 * np.degrees(np.arccos(fraction ** (1 / power)))
            assert angles[plane] == pytest.approx(expected, abs=ANGLE_ATOL_DEG), plane


def test_wide_distributions_have_no_beam_beyond_a_half_plane(tmp_path):
    """A cardioid ((1 + cos gamma) / 2)^4 has beam 2 arccos(2 0.5^(1/4) - 1) = 94.0 deg and
    field 2 arccos(2 0.1^(1/4) - 1) = 159.6 deg; ((1 + cos gamma) / 2)^0.5 would have
    beam 240 deg and field 337 deg, arcs wider than 180 deg: not defined (NaN); an
    isotropic source never falls: not defined; a Lambertian troffer (cos gamma, nothing
    upwards) has beam 120 deg and field 2 arccos(0.1) = 168.5 deg."""
    g = np.arange(0.0, 180.001, 0.25)
    narrow = read_photometry(G.write_ies_function(tmp_path / "c4.ies", cardioid(500.0, 4.0),
                                                  vertical_angles=g))
    for angles, fraction in ((narrow.beam_angles, 0.5), (narrow.field_angles, 0.1)):
        expected = 2 * np.degrees(np.arccos(2 * fraction ** 0.25 - 1))
        assert list(angles.values()) == pytest.approx([expected] * 2, abs=ANGLE_ATOL_DEG)
    assert 2 * np.degrees(np.arccos(2 * 0.5 ** 0.25 - 1)) == pytest.approx(94.0, abs=0.05)
    wide = read_photometry(G.write_ies_function(tmp_path / "c05.ies", cardioid(500.0, 0.5),
                                                vertical_angles=g))
    assert np.isnan(list(wide.beam_angles.values())).all() and np.isnan(wide.beam_angle)
    assert np.isnan(wide.field_angle)
    iso = read_photometry(G.write_ies_function(tmp_path / "iso.ies", G.isotropic(10.0)))
    assert np.isnan(iso.beam_angle) and np.isnan(iso.field_angle)
    troffer = read_photometry(G.write_ies_function(tmp_path / "t.ies", G.cos_power(800.0, 1),
                                                   vertical_angles=g))
    assert troffer.beam_angle == pytest.approx(120.0, abs=ANGLE_ATOL_DEG)
    assert troffer.field_angle == pytest.approx(2 * np.degrees(np.arccos(0.1)),
                                                abs=ANGLE_ATOL_DEG)
