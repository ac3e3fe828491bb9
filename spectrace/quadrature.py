"""Quadrature weights on numpy alone, shared by the colorimetry of sampled spectra
(:mod:`spectrace.spectral.colorimetry`) and the flux of photometric tables
(:mod:`spectrace.photometry.model`)."""

from __future__ import annotations

import numpy as np


def trapezoid_weights(x: np.ndarray) -> np.ndarray:
    """w with sum(w f) = the integral over [x0, xN] of the piecewise-linear f through the
    samples f(x) (the trapezoid rule on an irregular grid ``x``, increasing)."""
    x = np.asarray(x, dtype=np.float64)
    w = np.zeros_like(x)
    h = np.diff(x)
    w[:-1] += h / 2
    w[1:] += h / 2
    return w
