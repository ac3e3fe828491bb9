"""Benchmark: render time with spectrace's ``ieslight`` (an isotropic photometric file)
against ``pointlight`` of the same candela, on the same scene, with ``path`` and ``ptracer``.

The scene of ``bench_emitters.py`` (three spheres on a floor) lit by one light of 300 cd:
a ``pointlight`` with ``luminous_intensity`` 300, or an ``ieslight`` reading an LM-63 file of
300 cd in every direction (written by ``spectrace.photometry.generate`` into a temporary
folder: 73 vertical angles, rotational symmetry). The two render the same image with
``path``; the ieslight adds the profile lookup (angles of the direction, a 2D bilinear
lookup) to every light evaluation and draws ``ptracer``'s rays from its 2D cell
distribution. Each configuration is rendered once to warm up (tracing and kernel
compilation, then cached), then ``REPEATS`` times, interleaved; the table shows the
median times and their ratio ieslight / pointlight from the same run (aim: <= 1.1).

A second table times building the light (``ieslight.from_photometry``: the angle grid, the
cell weights and Mitsuba's ``DiscreteDistribution`` over them) from an in-memory table of
0.5 degrees over the whole sphere (361 x 721 angles, 259,200 cells), against loading the
``pointlight``: the cost a fine file adds to a scene's load, parsing aside. (The Python
alias-table loop it replaced took 0.74 s for 260,000 cells; the distribution takes under a
millisecond.)

Run: ``.venv/bin/python benchmarks/bench_ieslight.py [--res 256] [--spp 16] [--repeats 5]``
"""

from __future__ import annotations

import statistics
import tempfile
from pathlib import Path

from _timing import VARIANTS, interleaved, print_table, render_parser, timed_render
from bench_emitters import scene_dict

import spectrace

CANDELA = 300.0
POSITION = [-2.0, 3.0, 2.0]
INTEGRATORS = {"path": {"type": "path", "max_depth": 4},
               "ptracer": {"type": "ptracer", "max_depth": 4}}


def isotropic_file(folder: Path) -> str:
    from spectrace.photometry import generate

    return str(generate.write_ies_function(folder / "isotropic.ies",
                                           generate.isotropic(CANDELA)))


def lights(path: str) -> dict[str, dict]:
    import mitsuba as mi

    return {
        "pointlight": {"light": {"type": "pointlight", "position": POSITION,
                                 "luminous_intensity": CANDELA}},
        "ieslight": {"light": {"type": "ieslight", "filename": path,
                               "to_world": mi.ScalarTransform4f().translate(POSITION)}},
    }


def main() -> int:
    args = render_parser(__doc__, repeats=5).parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        path = isotropic_file(Path(folder))
        for variant in VARIANTS:
            spectrace.set_variant(variant)
            import mitsuba as mi

            for integrator_name, integrator in INTEGRATORS.items():
                scenes = {}
                for name, light in lights(path).items():
                    scene = scene_dict(light, args.res, args.spp)
                    scene["integrator"] = integrator
                    scenes[name] = mi.load_dict(scene)
                for scene in scenes.values():  # warm-up: trace and compile once
                    timed_render(scene, spp=args.spp, seed=0)
                times = interleaved(
                    scenes,
                    lambda scene, repeat: timed_render(scene, spp=args.spp, seed=repeat + 1),
                    args.repeats,
                )
                base = statistics.median(times["pointlight"])
                ours = statistics.median(times["ieslight"])
                rows.append((variant, integrator_name, base, ours, ours / base))

    print(f"render {args.res}x{args.res}, {args.spp} spp, max_depth 4, one light of "
          f"{CANDELA:g} cd, median of {args.repeats} after a warm-up")
    print_table([("variant", "<18", ""), ("integrator", "<10", ""),
                 ("pointlight (s)", ">14", ".3f"), ("ieslight (s)", ">12", ".3f"),
                 ("ratio", ">7", ".3f")], rows)
    print()
    print(f"building the light, median of {args.repeats}")
    print_table([("variant", "<18", ""), ("pointlight (ms)", ">15", ".2f"),
                 ("ieslight 0.5 deg (ms)", ">21", ".2f"), ("ratio", ">7", ".1f")],
                build_times(args.repeats))
    return 0


def build_times(repeats: int) -> list[tuple]:
    """(variant, pointlight load, ieslight build from a 0.5-degree in-memory table, ratio)."""
    import time

    import numpy as np
    from spectrace.photometry import Photometry, generate

    gamma, c = np.arange(0.0, 180.001, 0.5), np.arange(0.0, 360.0, 0.5)
    table = generate.tabulate(generate.wall_washer(800.0), gamma, c)
    photometry = Photometry(path="memory", format="LM-63-2002", photometric_type="C",
                            vertical_angles=gamma, horizontal_angles=c, candela=table)
    rows = []
    for variant in VARIANTS:
        spectrace.set_variant(variant)
        import mitsuba as mi
        from spectrace.plugins.emitters import ieslight

        def median_ms(build):
            times = []
            for _ in range(repeats):
                start = time.perf_counter()
                build()
                times.append(time.perf_counter() - start)
            return 1e3 * statistics.median(times)

        point = median_ms(lambda: mi.load_dict({"type": "pointlight", "position": POSITION,
                                                "luminous_intensity": CANDELA}))
        ies = median_ms(lambda: ieslight.from_photometry(photometry.replace()))
        rows.append((variant, point, ies, ies / point))
    return rows


if __name__ == "__main__":
    raise SystemExit(main())
