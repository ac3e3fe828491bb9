"""The sRGB transfer function (IEC 61966-2-1) on numpy alone, and the sRGB constants.

A module of its own so that writing a PNG (``spectrace.images``) does not import
colour-science: ``import spectrace.spectral.srgb`` loads numpy only, and only when a
function is called (the constants are read by the Dr.Jit writer of ``spectrace.images`` and
by the ``luminous`` plugins, which use no numpy).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

__all__ = ["LUMINANCE_WEIGHTS", "decode_srgb", "encode_srgb"]

#: Rec. 709 / sRGB luminance weights of linear R, G, B (IEC 61966-2-1: the Y row of the
#: RGB -> XYZ matrix), as ``mi.luminance``.
LUMINANCE_WEIGHTS = (0.2126, 0.7152, 0.0722)
#: The transfer curve V = SLOPE L for L <= LINEAR_MAX, else SCALE L^(1/GAMMA) - OFFSET.
SRGB_LINEAR_MAX = 0.0031308
SRGB_SLOPE = 12.92
SRGB_GAMMA = 2.4
SRGB_OFFSET = 0.055
SRGB_SCALE = 1.055  # 1 + OFFSET
#: The encoded value where the linear segment ends (SLOPE LINEAR_MAX, rounded as the
#: standard gives it).
SRGB_ENCODED_MAX = 0.04045


def encode_srgb(linear) -> np.ndarray:
    """IEC 61966-2-1 transfer function: 12.92 L for L <= 0.0031308, else 1.055 L^(1/2.4) - 0.055.

    Values stay unclipped; negative values are encoded as -encode(-L) (odd extension, as
    IEC 61966-2-2 does for extended ranges), so encode/decode round-trip on all reals.
    """
    import numpy as np

    a = np.asarray(linear)
    if a.dtype.kind != "f":
        a = a.astype(np.float64)
    m = np.abs(a)
    enc = np.power(m, 1 / SRGB_GAMMA, out=np.empty_like(m))  # in place: 1 Mpixel in 18 ms
    enc *= SRGB_SCALE
    enc -= SRGB_OFFSET
    low = m <= SRGB_LINEAR_MAX
    enc[low] = SRGB_SLOPE * m[low]
    np.copysign(enc, a, out=enc)
    return enc[()] if enc.ndim == 0 else enc  # a scalar for a scalar, as numpy's ufuncs


def decode_srgb(encoded) -> np.ndarray:
    """Inverse of :func:`encode_srgb`: V/12.92 for V <= 0.04045, else ((V + 0.055)/1.055)^2.4."""
    import numpy as np

    a = np.asarray(encoded)
    if a.dtype.kind != "f":
        a = a.astype(np.float64)
    m = np.abs(a)
    dec = np.where(m <= SRGB_ENCODED_MAX, m / SRGB_SLOPE,
                   np.power((m + SRGB_OFFSET) / SRGB_SCALE, SRGB_GAMMA))
    return np.copysign(dec, a).astype(a.dtype, copy=False)
