"""The study of ``notebooks/pictures.ipynb``: the display chain on one spectral render.

The luminaires room (``scenes/luminaires.xml``, 3000 K LEDs) rendered in
``llvm_ad_spectral``: its pixels' chromaticities against the sRGB gamut (which are out of
it: a negative linear sRGB component), and the pictures the display pipeline
(:mod:`spectrace.display`) makes of the same EXR: views and white balance.
"""

from __future__ import annotations

import numpy as np

from spectrace import display as pipeline
from spectrace.studies import budget, display, save_figure
from spectrace.studies.photometry import room_image

__all__ = ["budget", "chromaticities", "develop_all", "display", "room_image", "save_figure"]

#: The pictures the notebook compares: title -> settings.
VIEWS = {
    "standard (clip)": pipeline.DisplaySettings(exposure="auto"),
    "ACES 2.0 SDR": pipeline.DisplaySettings(exposure="auto", view="aces"),
    "PBR Neutral": pipeline.DisplaySettings(exposure="auto", view="neutral"),
}
WHITE_BALANCE = {
    "no white balance": pipeline.DisplaySettings(exposure="auto"),
    "--white-balance 3000K": pipeline.DisplaySettings(exposure="auto", white_balance="3000K"),
    "--white-balance auto (grey world)": pipeline.DisplaySettings(exposure="auto",
                                                                  white_balance="auto"),
}


def chromaticities(rgb) -> tuple[np.ndarray, np.ndarray]:
    """CIE 1931 xy of the lit pixels of a linear sRGB image (XYZ by IEC 61966-2-1's matrix),
    and which of them lie outside the sRGB gamut (a negative linear component)."""
    rgb = np.asarray(rgb, np.float64).reshape(-1, 3)
    XYZ = rgb @ pipeline.rgb_to_xyz_matrix("srgb").T
    total = XYZ.sum(axis=-1)
    lit = total > 1e-9
    xy = XYZ[lit, :2] / total[lit, None]
    return xy, np.any(rgb[lit] < 0, axis=-1)


def develop_all(rgb, settings: dict) -> dict:
    """title -> the (H, W, 3) uint8 picture of each settings."""
    return {title: pipeline.develop(rgb, s).codes for title, s in settings.items()}
