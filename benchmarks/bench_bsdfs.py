"""Benchmark: render time of a showcase-like scene with spectrace's `phong` / `blinnphong`
against the same scene with Mitsuba's built-in `diffuse` and `roughplastic`.

Scene: three spheres on a floor under a point light and a uniform environment,
256 x 256, `path` integrator (max_depth 6), every surface using the BSDF under test
(four instances with different colours, so the BSDF call is a real dispatch).
For each variant (llvm_ad_rgb, llvm_ad_spectral) and BSDF, the first render (tracing
and JIT compilation, or a hit in Dr.Jit's kernel cache) is timed separately, then the
best of REPEATS warm renders, interleaved across the BSDFs so that load changes on the
machine hit all of them alike; ratios are warm times relative to `diffuse` and
`roughplastic`, all from this run.

Run: .venv/bin/python benchmarks/bench_bsdfs.py [--spp N] [--res N] [--repeats N]
"""

from __future__ import annotations

import sys

from _timing import VARIANTS, interleaved, print_table, render_parser, timed_render

import spectrace

COLOURS = ([0.7, 0.2, 0.15], [0.2, 0.6, 0.25], [0.2, 0.3, 0.7], [0.5, 0.5, 0.5])


def bsdf(kind: str, colour):
    rgb = {"type": "rgb", "value": colour}
    return {
        "diffuse": {"type": "diffuse", "reflectance": rgb},
        "roughplastic": {"type": "roughplastic", "distribution": "ggx", "alpha": 0.24,
                         "diffuse_reflectance": rgb},
        "phong": {"type": "phong", "diffuse_reflectance": rgb, "specular_reflectance": 0.3,
                  "exponent": 32.0},
        "phong normalized": {"type": "phong", "diffuse_reflectance": rgb,
                             "specular_reflectance": 0.3, "exponent": 32.0, "normalized": True},
        "blinnphong": {"type": "blinnphong", "diffuse_reflectance": rgb,
                       "specular_reflectance": 0.3, "exponent": 32.0},
    }[kind]


KINDS = ("diffuse", "roughplastic", "phong", "phong normalized", "blinnphong")


def scene_dict(kind: str, res: int, spp: int):
    import mitsuba as mi

    T = mi.ScalarTransform4f
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 6},
        "sensor": {
            "type": "perspective",
            "fov": 40,
            "to_world": T().look_at(origin=[0, 2, 7], target=[0, 0, 0], up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": res, "height": res},
            "sampler": {"type": "independent", "sample_count": spp},
        },
        "light": {"type": "point", "position": [3.0, 5.0, 4.0],
                  "intensity": {"type": "uniform", "value": 60.0}},
        "sky": {"type": "constant", "radiance": {"type": "uniform", "value": 0.3}},
        "floor": {"type": "rectangle", "bsdf": bsdf(kind, COLOURS[3]),
                  "to_world": T().translate([0, -1, 0]).rotate([1, 0, 0], -90).scale(8)},
    }
    for i, x in enumerate((-2.2, 0.0, 2.2)):
        scene[f"ball{i}"] = {"type": "sphere", "center": [x, 0, 0], "radius": 1.0,
                             "bsdf": bsdf(kind, COLOURS[i])}
    return scene


def main(argv=None) -> int:
    args = render_parser(__doc__, repeats=5).parse_args(argv)

    rows = []
    for variant in VARIANTS:
        spectrace.set_variant(variant)
        import mitsuba as mi

        scenes = {kind: mi.load_dict(scene_dict(kind, args.res, args.spp)) for kind in KINDS}
        first = {kind: timed_render(scenes[kind], spp=args.spp, seed=0) for kind in KINDS}
        warm = interleaved(scenes, lambda scene, _: timed_render(scene, spp=args.spp, seed=0),
                           args.repeats)
        times = {kind: (first[kind], min(warm[kind], default=float("inf"))) for kind in KINDS}
        base = times["diffuse"][1]
        for kind in KINDS:
            first, warm = times[kind]
            rows.append((variant, kind, first, warm, warm / base, warm / times["roughplastic"][1]))

    print(f"render {args.res}x{args.res}, {args.spp} spp, path max_depth 6, "
          f"best of {args.repeats} warm renders")
    print_table([("variant", ">16", ""), ("bsdf", ">16", ""), ("first render s", ">16", ".3f"),
                 ("warm render s", ">16", ".3f"), ("/ diffuse", ">16", ".2f"),
                 ("/ roughplastic", ">16", ".2f")], rows, sep="  ")
    return 0


if __name__ == "__main__":
    sys.exit(main())
