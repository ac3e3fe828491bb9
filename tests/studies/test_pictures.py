"""spectrace.studies.pictures: chromaticities against colour-science, pictures per setting."""

from __future__ import annotations

import numpy as np
import pytest

from spectrace.studies import pictures as study


def test_chromaticities_match_colour_science():
    """xy of linear sRGB pixels are colour-science's (sRGB -> XYZ -> xy); a pixel with a
    negative component is out of gamut, a black one left out."""
    colour = pytest.importorskip("colour")
    rgb = np.array([[[0.2, 0.5, 0.1], [0.3, 0.3, 0.3], [-0.05, 0.4, 0.2], [0.0, 0.0, 0.0]]])
    xy, outside = study.chromaticities(rgb)
    expected = colour.XYZ_to_xy(colour.sRGB_to_XYZ(rgb[0, :3], apply_cctf_decoding=False))
    np.testing.assert_allclose(xy, expected, atol=1e-12)
    assert outside.tolist() == [False, False, True]


def test_develop_all_gives_one_picture_per_setting():
    """One uint8 picture per title, the image's size."""
    rgb = np.random.default_rng(0).uniform(0, 3, (4, 5, 3)).astype(np.float32)
    pictures = study.develop_all(rgb, study.VIEWS)
    assert list(pictures) == list(study.VIEWS)
    assert all(p.shape == (4, 5, 3) and p.dtype == np.uint8 for p in pictures.values())
