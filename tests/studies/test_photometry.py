"""Tests of spectrace.studies.photometry, the photometry study of scenes/luminaires.xml.

Oracles: the Type C angles of hand-placed directions (LM-63), the inverse-square cosine
law, the luminaires' fluxes as the scene file states them, and the point-by-point hand
calculation, which is written from the photometric definitions, not from the renderer.
"""

from __future__ import annotations

import numpy as np
import pytest

from spectrace.studies import photometry as study

#: A float32 render at the pixel centres against the float64 hand calculation (RGB).
RTOL_HAND = 1e-3
#: Pixels this close (m) to the ball on the left table (its shadow) are left out.
BALL = (np.array([-1.0, -0.1]), 0.3)
#: Mean lux on the work plane, spectral against RGB, both VARIANTS_SPP independent samples
#: (spectral: four wavelengths each drawn from V; measured spread over seeds 0.4 %).
RTOL_VARIANTS = 2e-2
VARIANTS_SPP = 16
RES = 30


class _Stub:
    """A photometry whose intensity is a chosen function of the Type C angles."""

    def __init__(self, function, flux=1.0):
        self.function = function
        self.flux = flux

    def intensity(self, gamma, c):
        return self.function(np.asarray(gamma, np.float64), np.asarray(c, np.float64))


def downward(stub, origin=(0.0, 2.0, 0.0)):
    """A luminaire aimed straight down with up = world +X, as in the scene."""
    origin = np.asarray(origin, np.float64)
    frame = study.luminaire_frame(origin, origin - [0.0, 1.0, 0.0], [1.0, 0.0, 0.0])
    return study.Luminaire("stub", stub, origin, frame, 1.0)


def test_type_c_angles_of_the_scene_frame():
    """Aimed straight down with up = +X (the scene's lookat): gamma = 0 at the nadir;
    C = 0 towards local +X = up x aim = world -Z, C = 90 towards local -Y = world -X,
    C = 270 towards +X (LM-63: C counterclockwise seen from above the luminaire)."""
    lum = downward(_Stub(lambda gamma, c: c))
    height = 2.0
    for direction, c in (((0, 0, -1), 0.0), ((-1, 0, 0), 90.0), ((0, 0, 1), 180.0),
                         ((1, 0, 0), 270.0)):
        point = np.array([direction[0], 0.0, direction[2]], np.float64) * 0.5
        # E = I cos(theta) / d^2 with I = C: undo the geometry to read C back
        d2 = 0.25 + height**2
        E = study.hand_calculation([lum], point[None, :])[0]
        assert E * d2 / (height / np.sqrt(d2)) == pytest.approx(c, abs=1e-6), direction
    lum = downward(_Stub(lambda gamma, c: gamma))
    E = study.hand_calculation([lum], np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]]))
    assert E[0] == pytest.approx(0.0, abs=1e-9)
    assert E[1] * 8.0 / (2.0 / np.sqrt(8.0)) == pytest.approx(45.0)


def test_hand_calculation_is_the_cosine_cubed_law():
    """An isotropic 100 cd source h = 2 m above the plane: E = I cos^3(gamma) / h^2."""
    lum = downward(_Stub(lambda gamma, c: np.full(np.shape(gamma), 100.0)))
    x = np.linspace(-3.0, 3.0, 7)
    points = np.stack([x, np.zeros_like(x), 0.5 * x], axis=-1)
    cos_gamma = 2.0 / np.sqrt(x**2 + 0.25 * x**2 + 4.0)
    np.testing.assert_allclose(study.hand_calculation([lum], points),
                               100.0 * cos_gamma**3 / 4.0, rtol=1e-12)


def test_room_luminaires_as_the_scene_states():
    """Four ieslights, all aimed straight down from 2.68 m; the EULUMDAT downlight is
    rescaled to its luminous_flux of 800 lm; every flux is positive."""
    luminaires = study.room_luminaires()
    assert [l.filename.split("/")[-1] for l in luminaires] == [
        "downlight.ies", "downlight.ldt", "wallwasher.ies", "wallwasher.ies"]
    for lum in luminaires:
        np.testing.assert_allclose(lum.frame[2], [0.0, -1.0, 0.0], atol=1e-12)
        assert lum.origin[1] == pytest.approx(2.68) and lum.flux > 0
    assert luminaires[1].flux == pytest.approx(800.0)


def test_work_plane_matches_the_hand_calculation(variant_rgb):
    """The rendered direct illuminance on the work plane at the pixel centres equals the
    point-by-point hand calculation (away from the ball on the left table, which shadows
    and hides the plane), along the line z = 0.3 and over the room; so does the direct
    utilisation factor; interreflections raise it, and it stays below 1."""
    luminaires = study.room_luminaires()
    plane = study.work_plane("llvm_ad_rgb", RES, 1)
    hand = study.hand_calculation(luminaires, plane.points)
    row = plane.row(0.3)
    np.testing.assert_allclose(plane.luxmap.lux[row], hand[row], rtol=RTOL_HAND)
    xx, zz = np.meshgrid(plane.x, plane.z)
    away = np.hypot(xx - BALL[0][0], zz - BALL[0][1]) > BALL[1]
    assert plane.luxmap.valid[away].all()
    np.testing.assert_allclose(plane.luxmap.lux[away], hand[away], rtol=RTOL_HAND)
    direct = study.utilisation_factor(plane, luminaires)
    hand_flux = hand[plane.luxmap.valid].sum() * plane.pixel_area
    total = sum(l.flux for l in luminaires)
    assert direct == pytest.approx(hand_flux / total, rel=5e-3)
    bounced = study.utilisation_factor(study.work_plane("llvm_ad_rgb", RES, 4, max_depth=4),
                                       luminaires)
    assert direct < bounced < 1.0


def test_spectral_and_rgb_work_plane_agree():
    """Under the 3000 K LED, the mean illuminance on the work plane is the same in
    llvm_ad_spectral (K_m integral V E) and llvm_ad_rgb (K_m Y(E))."""
    rgb = study.work_plane("llvm_ad_rgb", RES, VARIANTS_SPP).luxmap
    spectral = study.work_plane("llvm_ad_spectral", RES, VARIANTS_SPP, seed=1).luxmap
    np.testing.assert_allclose(spectral.mean, rgb.mean, rtol=RTOL_VARIANTS)
