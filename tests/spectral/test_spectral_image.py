"""spectral_image_to_xyz: the per-pixel spd_to_xyz conversion as one weight matrix."""

from __future__ import annotations

import colour
import numpy as np
import pytest

from spectrace import spectral as S

# colour-science warns when it resamples the oracle data; expected here.
pytestmark = pytest.mark.filterwarnings("ignore::colour.utilities.ColourRuntimeWarning")

FLOAT32_RTOL = 1e-5  # float32 products of 31 terms vs float64
FLOAT64_RTOL = 1e-12
COLOUR_RTOL = 2e-4  # colour-science's msds_to_XYZ_integration (1 nm Riemann sum after resampling)


@pytest.fixture
def image(rng):
    return rng.uniform(0, 1, (6, 5, 31)).astype(np.float32)


WAVELENGTHS = np.arange(400.0, 701.0, 10.0)


@pytest.mark.parametrize("illuminant", [None, "D65"])
def test_every_pixel_equals_spd_to_xyz(image, illuminant):
    """Each pixel's XYZ is spd_to_xyz of its spectrum (float32 in, float32 out)."""
    xyz = S.spectral_image_to_xyz(image, WAVELENGTHS, illuminant)
    assert xyz.shape == (6, 5, 3) and xyz.dtype == np.float32
    expected = S.spd_to_xyz(WAVELENGTHS, image.astype(np.float64), illuminant)
    np.testing.assert_allclose(xyz, expected, rtol=FLOAT32_RTOL, atol=1e-7)
    xyz64 = S.spectral_image_to_xyz(image.astype(np.float64), WAVELENGTHS, illuminant)
    np.testing.assert_allclose(xyz64, expected, rtol=FLOAT64_RTOL)


def test_matches_colour_msds_to_xyz_integration(image):
    """Reflective XYZ under D65 equals colour-science's msds_to_XYZ_integration / 100 on the same
    image (after resampling our linear interpolation onto its 1 nm grid)."""
    cmfs = colour.MSDS_CMFS[S.CIE_1931_2]
    fine = np.stack([np.interp(cmfs.wavelengths, WAVELENGTHS, px) for px in image.reshape(-1, 31)])
    theirs = (
        colour.colorimetry.msds_to_XYZ_integration(
            fine.reshape(6, 5, -1), cmfs, colour.SDS_ILLUMINANTS["D65"], shape=cmfs.shape
        )
        / 100
    )
    np.testing.assert_allclose(
        S.spectral_image_to_xyz(image, WAVELENGTHS, "D65"), theirs, rtol=COLOUR_RTOL
    )


def test_linear_srgb_is_xyz_then_matrix(image):
    """spectral_image_to_linear_srgb = xyz_to_linear_srgb(spectral_image_to_xyz(...))."""
    np.testing.assert_allclose(
        S.spectral_image_to_linear_srgb(image, WAVELENGTHS),
        S.xyz_to_linear_srgb(S.spectral_image_to_xyz(image, WAVELENGTHS)),
        rtol=FLOAT32_RTOL,
        atol=1e-6,
    )


def test_weights_are_cached_per_grid():
    """The weight matrix is computed once per grid/observer/illuminant and is read-only."""
    a = S.xyz_weights(WAVELENGTHS, "D65")
    assert S.xyz_weights(WAVELENGTHS.copy(), "D65") is a
    assert S.xyz_weights(WAVELENGTHS, None) is not a
    assert not a.flags.writeable


def test_non_contiguous_and_integer_images(image):
    """A strided view and an integer image convert like their contiguous float copies."""
    view = image[:, ::2]
    np.testing.assert_allclose(
        S.spectral_image_to_xyz(view, WAVELENGTHS),
        S.spectral_image_to_xyz(view.copy(), WAVELENGTHS),
    )
    ints = np.ones((2, 2, 31), dtype=np.int32)
    np.testing.assert_allclose(S.spectral_image_to_xyz(ints, WAVELENGTHS)[..., 1], 1.0, rtol=1e-9)


def test_nan_pixel_and_wrong_channel_count_raise(image):
    """A NaN pixel or a channel count different from the wavelengths raises ValueError."""
    bad = image.copy()
    bad[2, 3, 7] = np.nan
    with pytest.raises(ValueError, match=r"NaN.*\(2, 3\)"):
        S.spectral_image_to_xyz(bad, WAVELENGTHS)
    with pytest.raises(ValueError, match="mismatched"):
        S.spectral_image_to_xyz(image[..., :30], WAVELENGTHS)
    with pytest.raises(ValueError, match="empty"):
        S.spectral_image_to_xyz(np.zeros((0, 31)), WAVELENGTHS)
