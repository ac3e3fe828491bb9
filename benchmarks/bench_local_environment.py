"""Benchmark: the cost of ``local``'s environment terms (reflection, SH irradiance).

Scene ``scenes/environment_local.xml`` (three spheres on a floor, a point light, the
``daylight_sky`` envmap), rendered by ``local`` four ways: the environment sampled as a
light like any other (one emitter sample and shadow ray per pixel sample: noisy), with
``environment`` (reflection term), with ``ambient = "environment"`` (SH irradiance) and
with both (the scene's own integrator; the environment leaves the light sum). Each renders
once to compile (warm-up), then once timed; ratio = time / time of the sampled
environment, measured in the same run. Last rows: the time of the SH projection of the
map (``check_scene`` of a fresh integrator): the first with the compile of the emitter's
kernel, then again; their ratio is to the render time with both terms.

    .venv/bin/python benchmarks/bench_local_environment.py [--res 256] [--spp 16]
"""

from __future__ import annotations

import time
from pathlib import Path

from _timing import VARIANTS, print_table, render_parser, timed_render

import spectrace

SCENE = Path(__file__).resolve().parents[1] / "scenes" / "environment_local.xml"
INTEGRATORS = {
    "sampled environment": {},
    "environment (reflection)": {"environment": True},
    "ambient = environment": {"ambient": "environment"},
    "both": {"environment": True, "ambient": "environment"},
}


def local(mi, scene, extra):
    """A ``local`` integrator with ``extra`` (environment: the scene's own emitter)."""
    props = {"type": "local", **extra}
    if extra.get("environment"):
        props["environment"] = scene.environment()
    return mi.load_dict(props)


def main() -> int:
    args = render_parser(__doc__).parse_args()
    import mitsuba as mi

    from spectrace.scene import load_scene

    rows = []
    for variant in VARIANTS:
        spectrace.set_variant(variant)
        scene = load_scene(SCENE, {"res": str(args.res), "spp": str(args.spp)})
        times = {}
        for name, extra in INTEGRATORS.items():
            integrator = local(mi, scene, extra)
            integrator.check_scene(scene)
            timed_render(scene, integrator=integrator, seed=0)
            times[name] = timed_render(scene, integrator=integrator, seed=1)
        for name, seconds in times.items():
            rows.append((variant, name, seconds, seconds / times["sampled environment"]))
        projections = []
        for _ in range(2):  # the first compiles the emitter's eval kernel
            integrator = local(mi, scene, {"ambient": "environment"})
            start = time.perf_counter()
            integrator.check_scene(scene)
            projections.append(time.perf_counter() - start)
        for label, seconds in zip(("first", "again"), projections, strict=True):
            rows.append((variant, f"SH projection, {label}", seconds, seconds / times["both"]))
    print(f"scenes/environment_local.xml, {args.res} x {args.res}, {args.spp} spp; ratio: "
          "time / time with the environment sampled as a light")
    print_table([("variant", "<18", ""), ("integrator", "<26", ""), ("time (s)", ">9", ".3f"),
                 ("ratio", ">6", ".2f")], rows)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
