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

The second table: the lights with a size (``source_radius`` 10 cm, carried by their sphere
and disk shapes as ``spectrace render`` loads them) against the same lights as points, at
equal spp with ``path``, ``direct`` and ``local`` (aim: ratio <= 1.3). The third: noise at
equal time near a sphere and a disk light of radius 0.2 (a floor 0.1 m below the sphere,
so closer than 2 radii to its centre, and 0.1 m below the disk), each ``source_sampling``
(``direct``; the relative RMS error against a 1024-spp reference times sqrt(time),
relative to the default method).

Run: ``.venv/bin/python benchmarks/bench_emitters.py [--res 256] [--spp 16] [--repeats 5]
[--part all|builtin|sized]``
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


def sized_lights(radius: float) -> dict:
    """The point and spot lights of :func:`configurations` with ``source_radius``."""
    import mitsuba as mi

    T = mi.ScalarTransform4f()
    return {
        "point": {"type": "pointlight", "position": [-2, 3, 2], "intensity": 15.0,
                  "source_radius": radius},
        "spot": {"type": "spotlight", "to_world": T.look_at([2.5, 4, 2], [0, 0, 0], [0, 1, 0]),
                 "intensity": 30.0, "umbra_angle": 30.0, "penumbra_angle": 20.0,
                 "source_radius": radius},
    }


def sized_times(args) -> list[tuple]:
    """Sized / point render time at equal spp per integrator and variant."""
    import mitsuba as mi
    from spectrace.plugins.emitters import sized

    rows = []
    for variant in VARIANTS:
        spectrace.set_variant(variant)
        for integrator in ({"type": "path", "max_depth": 4}, {"type": "direct"},
                           {"type": "local"}):
            scenes = {}
            for radius in (0.0, 0.1):
                scene = scene_dict(sized_lights(radius), args.res, args.spp)
                scene["integrator"] = integrator
                scenes[radius] = mi.load_dict(sized.expand_dict(scene))
            for scene in scenes.values():
                timed_render(scene, spp=args.spp, seed=0)
            times = interleaved(scenes, lambda scene, repeat: timed_render(
                scene, spp=args.spp, seed=repeat + 1), args.repeats)
            point, disk = (statistics.median(times[r]) for r in (0.0, 0.1))
            rows.append((variant, integrator["type"], point, disk, disk / point))
    return rows


def near_field_noise(args) -> list[tuple]:
    """RMS error times sqrt(time) of the sampling methods near a sphere and a disk."""
    import mitsuba as mi
    import numpy as np
    from spectrace.plugins.emitters import sized

    spectrace.set_variant("llvm_ad_rgb")
    T = mi.ScalarTransform4f()
    rows = []
    lights = {
        "sphere": ({"type": "pointlight", "position": [0, 0.3, 0]},
                   ("solid_angle", "area")),
        "disk": ({"type": "spotlight", "to_world": T.look_at([0, 0.1, 0], [0, 0, 0], [0, 0, 1]),
                  "umbra_angle": 89.0, "penumbra_angle": 80.0}, ("auto", "solid_angle", "area")),
    }

    def scene(light, method: str, spp: int):
        return mi.load_dict(sized.expand_dict({
            "type": "scene", "integrator": {"type": "direct", "bsdf_samples": 0},
            "sensor": {"type": "orthographic",  # between the floor and the light
                       "to_world": T.look_at([0, 0.02, 0], [0, 0, 0], [0, 0, 1]).scale(
                           [0.6, 0.6, 1]),
                       "film": {"type": "hdrfilm", "width": args.res, "height": args.res},
                       "sampler": {"type": "independent", "sample_count": spp}},
            "floor": {"type": "rectangle", "to_world": T.rotate([1, 0, 0], -90).scale(2)},
            "light": {**light, "source_radius": 0.2, "source_sampling": method},
        }))

    for kind, (light, methods) in lights.items():
        reference = np.array(mi.render(scene(light, "area", 1024), seed=99))
        results = {}
        for method in methods:
            s = scene(light, method, args.spp)
            timed_render(s, spp=args.spp, seed=0)
            seconds = statistics.median(timed_render(s, spp=args.spp, seed=r + 1)
                                        for r in range(args.repeats))
            image = np.array(mi.render(s, spp=args.spp, seed=7))
            error = float(np.sqrt(np.mean((image - reference) ** 2)) / reference.mean())
            results[method] = (seconds, error, error * np.sqrt(seconds))
        base = results[methods[0]][2]
        for method, (seconds, error, at_equal_time) in results.items():
            rows.append((kind, method, seconds, error, at_equal_time / base))
    return rows


def main() -> int:
    parser = render_parser(__doc__, repeats=5)
    parser.add_argument("--part", choices=("all", "builtin", "sized"), default="all")
    args = parser.parse_args()
    if args.part in ("all", "builtin"):
        builtin_table(args)
    if args.part in ("all", "sized"):
        print(f"\nlights with a size (source_radius 0.1) / points, {args.res}x{args.res}, "
              f"{args.spp} spp, median of {args.repeats}")
        print_table([("variant", "<18", ""), ("integrator", "<10", ""),
                     ("point (s)", ">9", ".3f"), ("sized (s)", ">9", ".3f"),
                     ("ratio", ">7", ".3f")], sized_times(args))
        print(f"\nnear a light of radius 0.2 (floor 0.1 below the sphere, 0.1 below the "
              f"disk), direct, {args.spp} spp: noise at equal time = relative RMS error * "
              "sqrt(time), relative to the default method")
        print_table([("light", "<7", ""), ("source_sampling", "<16", ""),
                     ("time (s)", ">9", ".3f"), ("RMS error", ">10", ".4f"),
                     ("at equal time", ">14", ".2f")], near_field_noise(args))
    return 0


def builtin_table(args) -> None:
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


if __name__ == "__main__":
    raise SystemExit(main())
