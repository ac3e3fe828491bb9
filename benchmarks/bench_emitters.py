"""Benchmark: render time with spectrace's ``pointlight`` + ``spotlight`` against Mitsuba's
built-in ``point`` + ``spot`` on the same scene.

The scene: three spheres on a floor, 256x256, ``path`` integrator (max_depth 4), one point
light and one spot light. Each configuration is rendered once to warm up (tracing and
kernel compilation, then cached), then ``REPEATS`` times, interleaved with the other
configurations; the table shows the median time and its ratio to the built-in lights in
the same variant. The plugin configurations: the spot with ``linear_angle`` (the built-in's
law) and with the default ``quadratic`` law, both lights in photometric units (candela and
lumens: a constant scale computed at load, so the same kernels), and both lights with a
``windowed`` distance law. Variants: RGB and spectral, and also mono and spectral_polarized
(where the lights return depolarizing Mueller matrices as the built-ins do).

Run: ``.venv/bin/python benchmarks/bench_emitters.py [--res 256] [--spp 16] [--repeats 5]``
"""

from __future__ import annotations

import statistics

from _timing import VARIANTS, interleaved, print_table, render_parser, timed_render

import spectrace

#: The lights work in every LLVM variant: also time the mono and polarized ones.
EXTRA_VARIANTS = ("llvm_ad_mono", "llvm_ad_spectral_polarized")


def scene_dict(lights: dict, res: int, spp: int) -> dict:
    import mitsuba as mi

    T = mi.ScalarTransform4f()
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 4},
        "sensor": {
            "type": "perspective",
            "fov": 40,
            "to_world": T.look_at([0, 3, 7], [0, 0.5, 0], [0, 1, 0]),
            "film": {"type": "hdrfilm", "width": res, "height": res},
            "sampler": {"type": "independent", "sample_count": spp},
        },
        "floor": {"type": "rectangle", "to_world": T.rotate([1, 0, 0], -90).scale(6),
                  "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb",
                                                                "value": [0.6, 0.6, 0.55]}}},
    }
    for i, (x, colour) in enumerate([(-1.3, [0.7, 0.1, 0.1]), (0.0, [0.1, 0.6, 0.1]),
                                     (1.3, [0.1, 0.2, 0.7])]):
        scene[f"sphere{i}"] = {"type": "sphere", "center": [x, 0.6, 0], "radius": 0.6,
                               "bsdf": {"type": "diffuse",
                                        "reflectance": {"type": "rgb", "value": colour}}}
    scene.update(lights)
    return scene


def configurations() -> dict[str, dict]:
    import mitsuba as mi

    T = mi.ScalarTransform4f()
    spot_world = T.look_at([2.5, 4, 2], [0, 0, 0], [0, 1, 0])
    point = {"position": [-2, 3, 2], "intensity": 15.0}
    return {
        "built-in point + spot": {
            "point": {"type": "point", **point},
            "spot": {"type": "spot", "to_world": spot_world, "intensity": 30.0,
                     "cutoff_angle": 30.0, "beam_width": 20.0},
        },
        "pointlight + spotlight (linear_angle)": {
            "point": {"type": "pointlight", **point},
            "spot": {"type": "spotlight", "to_world": spot_world, "intensity": 30.0,
                     "umbra_angle": 30.0, "penumbra_angle": 20.0,
                     "cone_falloff": "linear_angle"},
        },
        "pointlight + spotlight (quadratic)": {
            "point": {"type": "pointlight", **point},
            "spot": {"type": "spotlight", "to_world": spot_world, "intensity": 30.0,
                     "umbra_angle": 30.0, "penumbra_angle": 20.0},
        },
        "... in cd and lm (d65 spectrum)": {
            "point": {"type": "pointlight", "position": [-2, 3, 2],
                      "luminous_intensity": 2000.0},
            "spot": {"type": "spotlight", "to_world": spot_world, "luminous_flux": 3000.0,
                     "umbra_angle": 30.0, "penumbra_angle": 20.0},
        },
        "... with windowed falloff (radius 10)": {
            "point": {"type": "pointlight", **point, "falloff": "windowed", "radius": 10.0},
            "spot": {"type": "spotlight", "to_world": spot_world, "intensity": 30.0,
                     "umbra_angle": 30.0, "penumbra_angle": 20.0, "falloff": "windowed",
                     "radius": 10.0},
        },
    }


def main() -> int:
    args = render_parser(__doc__, repeats=5).parse_args()

    rows = []
    for variant in VARIANTS + EXTRA_VARIANTS:
        spectrace.set_variant(variant)
        import mitsuba as mi

        scenes = {name: mi.load_dict(scene_dict(lights, args.res, args.spp))
                  for name, lights in configurations().items()}
        for scene in scenes.values():  # warm-up: trace and compile once
            timed_render(scene, spp=args.spp, seed=0)
        times = interleaved(
            scenes, lambda scene, repeat: timed_render(scene, spp=args.spp, seed=repeat + 1),
            args.repeats,
        )
        base = statistics.median(times["built-in point + spot"])
        for name, values in times.items():
            median = statistics.median(values)
            rows.append((variant, name, median, median / base))

    print(f"render {args.res}x{args.res}, {args.spp} spp, path max_depth 4, "
          f"median of {args.repeats} after a warm-up")
    print_table([("variant", "<27", ""), ("lights", "<40", ""), ("time (s)", ">9", ".3f"),
                 ("ratio", ">7", ".3f")], rows)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
