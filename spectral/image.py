"""Spectral images (..., N) -> CIE XYZ / linear sRGB as one matrix product.

The conversion is :func:`spectrace.spectral.spd_to_xyz` on every pixel. Since it is linear
in the spectral values, it is ``XYZ = image @ W`` with the (N, 3) weight matrix of
:func:`spectrace.spectral.colorimetry.xyz_weights`, computed once per wavelength grid,
observer, illuminant and extrapolation (cached) and applied with one BLAS matrix product
over all pixels: the image is read once, which puts the cost near one copy of the image
(see benchmarks/bench_spectral.py).
"""

from __future__ import annotations

import numpy as np

from spectrace.errors import ParameterError

from .colorimetry import _M_XYZ_TO_RGB, CIE_1931_2, check_wavelengths, xyz_weights

#: pixels per block of the matrix product (with 31 float32 bands: 8 MiB)
CHUNK = 1 << 16

__all__ = ["apply_spectral_weights", "spectral_image_to_linear_srgb", "spectral_image_to_xyz"]


def _apply(image, wavelengths, matrix_fn, where, check_finite):
    wl = check_wavelengths(wavelengths, where)
    img = np.asarray(image)
    if img.ndim == 0 or img.size == 0:
        raise ParameterError(f"{where}: image is empty (shape {img.shape})")
    if img.shape[-1] != wl.size:
        raise ParameterError(
            f"{where}: image has {img.shape[-1]} channels on its last axis but there are "
            f"{wl.size} wavelengths / weight rows (mismatched lengths)"
        )
    dtype = img.dtype if img.dtype in (np.float32, np.float64) else np.float64
    w = matrix_fn(wl).astype(dtype)
    flat = img.reshape(-1, wl.size)  # a view for contiguous images
    out = np.empty((flat.shape[0], w.shape[1]), dtype)
    # Blocks of CHUNK pixels: each block is still in cache when the product reads it, and
    # other dtypes (float16, integers) are converted one block at a time, not as a full copy.
    for start in range(0, flat.shape[0], CHUNK):
        block = flat[start : start + CHUNK]
        np.matmul(block.astype(dtype, copy=False), w, out=out[start : start + CHUNK])
    out = out.reshape(img.shape[:-1] + (w.shape[1],))
    # NaN/inf in any band shows up in the (10x smaller) result: check there, not the input.
    if check_finite and not np.isfinite(out).all():
        bad = np.argwhere(~np.isfinite(out).all(axis=-1))[0]
        raise ParameterError(
            f"{where}: image contains NaN or infinite values (first at index {tuple(bad)})"
        )
    return out


def apply_spectral_weights(image, weights, check_finite: bool = True) -> np.ndarray:
    """``image @ weights`` over all pixels: (..., N) @ (N, C) -> (..., C), one BLAS product.

    The kernel behind :func:`spectral_image_to_xyz`, for precomputed weight matrices
    (e.g. the band deconvolution of :mod:`spectrace.spectral_film`). float32 images stay
    float32. Shapes are checked; NaN/inf raise ``ParameterError`` as in spectral_image_to_xyz.
    """
    w = np.asarray(weights, np.float64)
    if w.ndim != 2:
        raise ParameterError(
            f"apply_spectral_weights: weights must be (N, C) (got shape {w.shape})")
    return _apply(
        image, np.arange(1.0, w.shape[0] + 1), lambda wl: w, "apply_spectral_weights", check_finite
    )


def spectral_image_to_xyz(
    image,
    wavelengths,
    illuminant=None,
    observer: str = CIE_1931_2,
    extrapolation: str = "constant",
    check_finite: bool = True,
) -> np.ndarray:
    """CIE XYZ of every pixel of a spectral image of shape (..., N); returns (..., 3).

    Same normalisation and conventions as :func:`spd_to_xyz` (emissive: Y of a constant
    spectrum 1 is 1; reflective under ``illuminant``: Y of a perfect white is 1). float32
    images give float32 XYZ (the weights are cast to float32), others float64. With
    ``check_finite`` a NaN/inf value anywhere raises ``ParameterError``, a ``ValueError``
    (checked on the result).
    """
    return _apply(
        image,
        wavelengths,
        lambda wl: xyz_weights(wl, illuminant, observer, extrapolation),
        "spectral_image_to_xyz",
        check_finite,
    )


def spectral_image_to_linear_srgb(
    image,
    wavelengths,
    illuminant=None,
    observer: str = CIE_1931_2,
    extrapolation: str = "constant",
    check_finite: bool = True,
) -> np.ndarray:
    """Linear sRGB of every pixel: ``xyz_to_linear_srgb(spectral_image_to_xyz(...))``.

    Done as one product with the (N, 3) matrix ``W @ M_XYZ_to_RGB^T`` (same scale as
    :func:`xyz_to_linear_srgb`: Y = 1 white -> (1, 1, 1)).
    """
    return _apply(
        image,
        wavelengths,
        lambda wl: xyz_weights(wl, illuminant, observer, extrapolation) @ _M_XYZ_TO_RGB.T,
        "spectral_image_to_linear_srgb",
        check_finite,
    )
