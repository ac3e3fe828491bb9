"""Benchmark: what Open Image Denoise buys (``render --denoise``), against more samples.

Per scene, RMSE (linear sRGB) against a reference of 16 N spp (another seed) of: the
noisy render at N spp, the noisy render at 4 N spp, and the N-spp render denoised with its
albedo and normal buffers (:mod:`spectrace.denoise`). The ratio columns are each RMSE over
the noisy N-spp one (below 1: better); the reference's own noise (about a quarter of the
noisy N-spp error) is in every figure. Scenes: ``showcase.xml`` (path tracer, rough and
Phong spheres), Mitsuba's Cornell box (``mi.cornell_box()``) with a glass and a mirror
sphere (``path``), and ``luminaires.xml`` (``local`` with shadows).

    .venv/bin/python benchmarks/bench_denoise.py [--res 128] [--spp 16]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
VARIANT = "llvm_ad_rgb"


def cornell_box_with_spheres(res: int):
    import mitsuba as mi

    scene = mi.cornell_box()
    scene["sensor"]["film"]["width"] = scene["sensor"]["film"]["height"] = res
    scene["glass"] = {"type": "sphere", "center": [-0.45, -0.6, 0.2], "radius": 0.35,
                      "bsdf": {"type": "dielectric"}}
    scene["mirror"] = {"type": "sphere", "center": [0.45, -0.6, -0.3], "radius": 0.35,
                       "bsdf": {"type": "conductor"}}
    return mi.load_dict(scene)


def scenes(res: int):
    from spectrace.scene import load_scene

    yield "showcase", load_scene(ROOT / "scenes" / "showcase.xml", {"res": str(res)})
    yield "cornell box, glass + mirror", cornell_box_with_spheres(res)
    yield "luminaires (local)", load_scene(ROOT / "scenes" / "luminaires.xml",
                                           {"res": str(res)})


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--res", type=int, default=128)
    parser.add_argument("--spp", type=int, default=16)
    args = parser.parse_args()
    import spectrace

    spectrace.set_variant(VARIANT)
    from spectrace.denoise import denoise_image, render_features

    n = args.spp
    rows = []
    for name, scene in scenes(args.res):
        reference = spectrace.render(scene, 16 * n, seed=1000).image

        def rmse(image, reference=reference):
            return float(np.sqrt(np.mean((image - reference) ** 2)))

        noisy = spectrace.render(scene, n, seed=1).image
        more = spectrace.render(scene, 4 * n, seed=2).image
        start = time.perf_counter()
        albedo, normal = render_features(scene, n, seed=3)
        denoised = denoise_image(noisy, albedo, normal)
        seconds = time.perf_counter() - start
        rows.append((name, rmse(noisy), rmse(more), rmse(denoised), seconds))
    print(f"\nRMSE against {16 * n} spp, {args.res} x {args.res}, {VARIANT}")
    print(f"{'scene':<30}{f'noisy {n}':>11}{f'noisy {4 * n}':>11}{f'denoised {n}':>13}"
          f"{f'{4 * n}/{n}':>9}{f'den/{n}':>9}{'den s':>8}")
    for name, a, b, c, s in rows:
        print(f"{name:<30}{a:>11.4f}{b:>11.4f}{c:>13.4f}{b / a:>9.2f}{c / a:>9.2f}{s:>8.2f}")


if __name__ == "__main__":
    main()
