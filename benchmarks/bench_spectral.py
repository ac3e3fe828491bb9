"""Benchmark: spectral image -> XYZ, spectrace vs colour-science vs a plain copy.

Run: .venv/bin/python benchmarks/bench_spectral.py [--size 1024] [--bands 31]

Times (best of several runs, one process) the conversion of an H x W x 31 float32 image
(400-700 nm every 10 nm) to CIE XYZ under D65:
* spectrace: ``spectral_image_to_xyz`` (one cached (31, 3) weight matrix, one BLAS product);
* spectrace (cold): the same, with the weight matrix cache cleared first;
* colour-science: ``colour.colorimetry.msds_to_XYZ_integration`` on the same array;
* plain copies of the image (``np.copy``: a new array; ``np.copyto``: into an existing one),
  the memory-bandwidth floor of a pass over the image.
Prints a table with each time and its ratio to spectrace, and the agreement of the results.
"""

from __future__ import annotations

import argparse
import time

import colour
import numpy as np
from spectrace.spectral import colorimetry

from spectrace import spectral as S


def best_of(fn, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--bands", type=int, default=31)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()

    wl = np.linspace(400.0, 700.0, args.bands)
    rng = np.random.default_rng(0)
    # smooth spectra (random mixtures of 4 Gaussian bumps), as rendered images have
    basis = np.exp(-0.5 * ((wl - np.array([[450.0], [530.0], [600.0], [660.0]])) / 40.0) ** 2)
    weights = rng.uniform(0, 1, (args.size, args.size, 4)).astype(np.float32)
    image = (weights @ basis.astype(np.float32)).astype(np.float32)
    target = np.empty_like(image)
    shape = colour.SpectralShape(wl[0], wl[-1], wl[1] - wl[0])
    cmfs = colour.MSDS_CMFS[S.CIE_1931_2]
    d65 = colour.SDS_ILLUMINANTS["D65"]

    def cold():
        colorimetry._weights_cached.cache_clear()
        return S.spectral_image_to_xyz(image, wl, "D65")

    methods = {
        "spectrace spectral_image_to_xyz": lambda: S.spectral_image_to_xyz(image, wl, "D65"),
        "spectrace, weight cache cleared": cold,
        "spectrace spectral_image_to_linear_srgb": lambda: S.spectral_image_to_linear_srgb(
            image, wl, "D65"
        ),
        "colour-science msds_to_XYZ_integration": lambda: (
            colour.colorimetry.msds_to_XYZ_integration(image, cmfs, d65, shape=shape)
        ),
        "plain copy, np.copy (new array)": lambda: np.copy(image),
        "plain copy, np.copyto (existing array)": lambda: np.copyto(target, image),
    }
    # Interleaved rounds, best of each: every method sees the same machine load.
    best = dict.fromkeys(methods, np.inf)
    results = {}
    for _ in range(args.repeat):
        for name, fn in methods.items():
            t, results[name] = best_of(fn, 1)
            best[name] = min(best[name], t)
    rows = list(best.items())
    t_ours = best["spectrace spectral_image_to_xyz"]
    t_colour = best["colour-science msds_to_XYZ_integration"]
    xyz = results["spectrace spectral_image_to_xyz"]
    theirs = results["colour-science msds_to_XYZ_integration"]

    mb = image.nbytes / 2**20
    print(
        f"image {args.size}x{args.size}x{args.bands} float32 ({mb:.0f} MiB), XYZ under D65, "
        f"best of {args.repeat}"
    )
    print(f"{'method':44s} {'time (ms)':>10s} {'GiB/s read':>10s} {'time / spectrace':>17s}")
    for name, t in rows:
        print(f"{name:44s} {t * 1e3:10.2f} {mb / 1024 / t:10.2f} {t / t_ours:17.2f}")
    print(f"speed-up over colour-science: {t_colour / t_ours:.1f}x")
    # colour-science resamples the image's 10 nm data with its own interpolator (Sprague),
    # we interpolate linearly: on smooth spectra they agree to about 1e-3.
    rel = np.abs(xyz - theirs / 100).max() / np.abs(theirs / 100).max()
    print(f"max |ours - colour-science / 100| / max XYZ: {rel:.2e}")


if __name__ == "__main__":
    main()
