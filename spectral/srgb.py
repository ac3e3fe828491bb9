"""The sRGB transfer function (IEC 61966-2-1) on numpy alone.

A module of its own so that writing a PNG (``spectrace.images``) does not import
colour-science: ``import spectrace.spectral.srgb`` loads numpy only.
"""

from __future__ import annotations

import numpy as np

__all__ = ["decode_srgb", "encode_srgb"]


def encode_srgb(linear) -> np.ndarray:
    """IEC 61966-2-1 transfer function: 12.92 L for L <= 0.0031308, else 1.055 L^(1/2.4) - 0.055.

    Values stay unclipped; negative values are encoded as -encode(-L) (odd extension, as
    IEC 61966-2-2 does for extended ranges), so encode/decode round-trip on all reals.
    """
    a = np.asarray(linear)
    if a.dtype.kind != "f":
        a = a.astype(np.float64)
    m = np.abs(a)
    enc = np.where(m <= 0.0031308, 12.92 * m, 1.055 * np.power(m, 1 / 2.4) - 0.055)
    return np.copysign(enc, a).astype(a.dtype, copy=False)


def decode_srgb(encoded) -> np.ndarray:
    """Inverse of :func:`encode_srgb`: V/12.92 for V <= 0.04045, else ((V + 0.055)/1.055)^2.4."""
    a = np.asarray(encoded)
    if a.dtype.kind != "f":
        a = a.astype(np.float64)
    m = np.abs(a)
    dec = np.where(m <= 0.04045, m / 12.92, np.power((m + 0.055) / 1.055, 2.4))
    return np.copysign(dec, a).astype(a.dtype, copy=False)
