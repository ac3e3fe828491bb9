"""Benchmark: the ``local`` integrator against Mitsuba's ``direct`` on showcase scenes.

Scenes, 256 x 256 pixels: ``scenes/showcase.xml`` (analytic spheres on a floor, a point
light, a spot light and a constant sky, which ``local`` samples once per pixel sample),
and "meshes": an analytic sphere and two triangle-mesh spheres on a floor under a point
and a spot light (delta lights only), where the three shading models are timed. Every
integrator renders once to compile its kernel (warm-up), then once timed; the ratio is
time / time of ``direct`` with one emitter sample per light (as many shadow rays as
``local``), measured in the same run.

Second table, "lights": a mesh on a floor under 1, 4, 16 and 64 ``pointlight`` s on a ring
(``--lights``), rendered by ``local`` (phong and gouraud shading) and by ``direct`` with one
emitter sample per light. For each: the size of the render kernel (Dr.Jit operations),
its LLVM compile time, the first render (trace + compile + run) and a second, timed
render (kernel reused). ``local`` loops over the lights symbolically, so its kernel and
compile time stay the same for any number of lights. The Dr.Jit kernel cache is emptied
for this run (``HOME`` points at a temporary folder), so every compile is counted.

Third table, "shadow samples": ``scenes/soft_shadows.xml`` (a point spot and a disk spot of
radius 25 cm) rendered by ``local`` with ``shadow_samples`` 1, 4, 16, 64
(``--shadow-samples``): time and ratio to one shadow sample (only the disk takes N).

    .venv/bin/python benchmarks/bench_local.py [--res 256] [--spp 16] [--lights 1,4,16,64]
        [--shadow-samples 1,4,16,64]
"""

from __future__ import annotations

import math
import os
import tempfile
import time
from pathlib import Path

from _timing import VARIANTS, print_table, render_parser, timed_render

# An empty kernel cache, before Dr.Jit is imported: the lights table counts every compile.
os.environ["HOME"] = tempfile.mkdtemp(prefix="bench_local_home.")

import spectrace  # noqa: E402

SCENES = Path(__file__).resolve().parents[1] / "scenes"


def meshes(mi, res, spp):
    T = mi.ScalarTransform4f
    plastic = {
        "type": "roughplastic",
        "alpha": 0.15,
        "diffuse_reflectance": {"type": "rgb", "value": [0.6, 0.2, 0.1]},
    }
    return mi.load_dict(
        {
            "type": "scene",
            "sensor": {
                "type": "perspective",
                "fov": 40,
                "to_world": T().look_at(origin=[0, 3, 7], target=[0, 0.8, 0], up=[0, 1, 0]),
                "film": {"type": "hdrfilm", "width": res, "height": res},
                "sampler": {"type": "independent", "sample_count": spp},
            },
            "floor": {
                "type": "rectangle",
                "to_world": T().rotate([1, 0, 0], -90).scale(6),
                "bsdf": {
                    "type": "diffuse",
                    "reflectance": {"type": "rgb", "value": [0.5, 0.5, 0.45]},
                },
            },
            "ball": {"type": "sphere", "center": [-2.2, 1, 0], "radius": 1, "bsdf": plastic},
            "coarse": {
                "type": "obj",
                "filename": str(SCENES / "meshes" / "sphere_low.obj"),
                "to_world": T().translate([0, 1, 0]),
                "bsdf": plastic,
            },
            "fine": {
                "type": "obj",
                "filename": str(SCENES / "meshes" / "sphere_high.obj"),
                "to_world": T().translate([2.2, 1, 0]),
                "bsdf": {"type": "roughconductor", "alpha": 0.2},
            },
            "point": {
                "type": "point",
                "position": [3, 5, 3],
                "intensity": {"type": "rgb", "value": 40},
            },
            "spot": {
                "type": "spot",
                "intensity": {"type": "rgb", "value": 60},
                "cutoff_angle": 30,
                "to_world": T().look_at(origin=[-3, 5, 2], target=[0, 0, 0], up=[0, 1, 0]),
            },
        }
    )


def showcase(mi, res, spp):
    return mi.load_file(str(SCENES / "showcase.xml"), res=res, spp=spp)


#: Scene name -> (loader, number of emitters).
BENCH_SCENES = {"showcase.xml": (showcase, 3), "meshes": (meshes, 2)}

INTEGRATORS = {
    "direct (1 emitter sample per light)": {"type": "direct", "bsdf_samples": 0},
    "direct (default: 1 emitter + 1 BSDF)": {"type": "direct"},
    "local phong": {"type": "local", "shading": "phong"},
    "local flat": {"type": "local", "shading": "flat"},
    "local gouraud": {"type": "local", "shading": "gouraud"},
    "local phong + ambient + fog": {
        "type": "local",
        "ambient": 0.1,
        "fog": "exponential",
        "fog_density": 0.05,
        "fog_color": 0.3,
    },
}


def ring_of_lights(mi, n, res, spp):
    """A coarse mesh sphere on a floor under ``n`` point lights on a ring (total 20 W/sr)."""
    T = mi.ScalarTransform4f
    scene = {
        "type": "scene",
        "sensor": {
            "type": "perspective",
            "fov": 50,
            "to_world": T().look_at(origin=[0, 4, 6], target=[0, 0, 0], up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": res, "height": res},
            "sampler": {"type": "independent", "sample_count": spp},
        },
        "floor": {"type": "rectangle", "to_world": T().rotate([1, 0, 0], -90).scale(5),
                  "bsdf": {"type": "phong"}},
        "mesh": {"type": "obj", "filename": str(SCENES / "meshes" / "sphere_low.obj"),
                 "to_world": T().translate([0, 1, 0]), "bsdf": {"type": "blinnphong"}},
    }
    for k in range(n):
        angle = 2 * math.pi * k / n
        scene[f"light{k}"] = {"type": "pointlight", "intensity": 20.0 / n,
                              "position": [3 * math.cos(angle), 3, 3 * math.sin(angle)]}
    return mi.load_dict(scene)


def kernel_run(dr, mi, scene, integrator):
    """(first render s, operations and compile s of its largest kernel, second render s)."""
    dr.kernel_history()  # clear
    start = time.perf_counter()
    dr.eval(mi.render(scene, integrator=integrator, seed=0))
    dr.sync_thread()
    first = time.perf_counter() - start
    kernels = [k for k in dr.kernel_history() if k["type"] == dr.KernelType.JIT]
    largest = max(kernels, key=lambda k: k["operation_count"])
    second = timed_render(scene, integrator=integrator, seed=1)
    return first, largest["operation_count"], largest["backend_time"] / 1000.0, second


def lights_table(args) -> None:
    import drjit as dr

    counts = [int(n) for n in args.lights.split(",")]
    rows = []
    for variant in VARIANTS:
        spectrace.set_variant(variant)
        import mitsuba as mi

        dr.set_flag(dr.JitFlag.KernelHistory, True)
        for n in counts:
            scene = ring_of_lights(mi, n, args.res, args.spp)
            integrators = {
                "local phong": {"type": "local", "shading": "phong"},
                "local gouraud": {"type": "local", "shading": "gouraud"},
                "direct (1 emitter sample per light)": {
                    "type": "direct", "bsdf_samples": 0, "emitter_samples": n},
            }
            for name, d in integrators.items():
                first, ops, compile_s, second = kernel_run(dr, mi, scene, mi.load_dict(d))
                rows.append((variant, n, name, ops, compile_s, first, second))
        dr.set_flag(dr.JitFlag.KernelHistory, False)
    print(f"\nlocal vs number of lights, {args.res}x{args.res}, {args.spp} spp, empty kernel cache")
    print_table([("variant", "<18", ""), ("lights", ">6", "d"), ("integrator", "<38", ""),
                 ("kernel ops", ">10", "d"), ("compile [s]", ">11", ".3f"),
                 ("first [s]", ">9", ".3f"), ("render [s]", ">10", ".3f")], rows)


def shadow_samples_table(args) -> None:
    from spectrace.scene import load_scene

    counts = [int(n) for n in args.shadow_samples.split(",")]
    rows = []
    for variant in VARIANTS:
        spectrace.set_variant(variant)
        import mitsuba as mi

        scene = load_scene(SCENES / "soft_shadows.xml", {"res": str(args.res)})
        integrators = {n: mi.load_dict({"type": "local", "shadow_samples": n}) for n in counts}
        for integrator in integrators.values():  # warm-up
            timed_render(scene, integrator=integrator, spp=args.spp, seed=0)
        times = {n: timed_render(scene, integrator=integrator, spp=args.spp, seed=1)
                 for n, integrator in integrators.items()}
        rows += [(variant, n, t, t / times[counts[0]]) for n, t in times.items()]
    print(f"\nlocal on soft_shadows.xml against shadow_samples, {args.res}x{args.res}, "
          f"{args.spp} spp")
    print_table([("variant", "<18", ""), ("shadow_samples", ">14", "d"),
                 ("time [s]", ">9", ".3f"), ("ratio", ">7", ".2f")], rows)


def main() -> int:
    parser = render_parser(__doc__)
    parser.add_argument("--shadow-samples", default="1,4,16,64",
                        help="shadow_samples of the third table (default 1,4,16,64)")
    parser.add_argument("--lights", default="1,4,16,64",
                        help="numbers of lights of the lights table (default 1,4,16,64)")
    args = parser.parse_args()

    rows = []
    for variant in VARIANTS:
        spectrace.set_variant(variant)
        import mitsuba as mi

        mi.set_log_level(mi.LogLevel.Error)  # the gouraud fallback warning on analytic shapes
        for scene_name, (load, n_emitters) in BENCH_SCENES.items():
            scene = load(mi, args.res, args.spp)
            integrators = {}
            for name, d in INTEGRATORS.items():
                if scene_name == "showcase.xml" and d.get("shading") in ("flat", "gouraud"):
                    continue  # no meshes there
                if name.startswith("direct (1 emitter"):
                    d = dict(d, emitter_samples=n_emitters)
                integrators[name] = mi.load_dict(d)
            for integrator in integrators.values():  # warm-up: compile every kernel
                timed_render(scene, integrator=integrator, seed=0)
            times = {
                name: timed_render(scene, integrator=integrator, seed=1)
                for name, integrator in integrators.items()
            }
            reference = times[next(iter(INTEGRATORS))]
            rows += [(variant, scene_name, name, t, t / reference) for name, t in times.items()]

    print(f"local vs direct, {args.res}x{args.res}, {args.spp} spp, one timed run after warm-up")
    print_table([("variant", "<18", ""), ("scene", "<13", ""), ("integrator", "<38", ""),
                 ("time [s]", ">9", ".3f"), ("ratio", ">7", ".2f")], rows)
    lights_table(args)
    shadow_samples_table(args)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
