"""Benchmark: light groups: a render with 8 layers against one without, spectrace's
``lightgroups`` path tracer against Mitsuba's C++ ``path``, and relighting time.

Scene: three spheres (diffuse, rough plastic, glass) on a floor lit by 8 emitters (4 of
Mitsuba's ``point``, 2 of spectrace's ``pointlight``, a rectangular area light and a
uniform sky), RES x RES, max_depth 6. Renders:

* ``path``: Mitsuba's C++ path tracer (no layers);
* ``lightgroups, 1 group``: spectrace's path tracer, every emitter in one group (the cost
  of the Python/Dr.Jit integrator itself; aim <= 1.5x ``path``);
* ``lightgroups, 8 groups``: one layer per emitter (aim <= 1.3x one group).

For each variant the first render (tracing and compilation, or a kernel-cache hit) is
timed apart, then the best of REPEATS warm renders interleaved across the three, in
wall-clock time and in process CPU time (steadier on a shared machine).
Both film filters (``gaussian``, hdrfilm's default, and ``box``) are measured: Mitsuba's
``path`` splats every channel into the filter's footprint (5 x 5 pixels for ``gaussian``),
``lightgroups`` importance-samples the filter (one pixel per sample, however many layers).
Relighting: 8 RGB layers of 1024 x 1024 (random data, which ZIP cannot compress: the worst
case for the EXR steps): reading the layered EXR, ``lightgroups.relight`` (aim < 0.5 s),
writing the EXR (beauty and scaled layers) and the PNG (what ``spectrace relight`` does),
each the best of REPEATS. Then 8 spectral layers of 16 bands (about 0.5 GB of float32):
reading the spectral EXR, and ``relight_spectral`` dimming and with a new lamp spectrum
(aim: within 1.5x of the read).

Memory: each of the three renders in a fresh subprocess (box filter), once to compile
its kernels, then (Dr.Jit's allocation cache flushed) again; the peak resident set of that
second render (VmHWM, reset just before it) less the resident set before it is the
render's own memory. The aim for 8 groups is at most
1.2x that of the render without groups (``path``; 1 group beside it) plus the layers
themselves, once (what the image ``mi.render`` returns holds; the film's accumulation
buffer is the film's, kept between renders): the resident memory of the 8-group image
less that of ``path``'s, each measured in the same subprocess as the RSS growth of
allocating a Dr.Jit array of the image's size (Dr.Jit asks for transparent huge pages
for large arrays, so an array is resident in 2 MiB steps: the 24 x 256^2 float32 of 8
layers and the beauty, 7.1 MB, take 8.4 MB).

Run: .venv/bin/python benchmarks/bench_light_groups.py [--spp N] [--res N] [--repeats N]
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _timing import VARIANTS, interleaved, print_table, render_parser, timed_render

import spectrace

RELIGHT_RES = 1024
GROUPS = 8
SPECTRAL_BANDS = 16
#: The film's reconstruction filters: hdrfilm's default ``gaussian`` (which ``path`` splats
#: into 5 x 5 pixels and ``lightgroups`` importance-samples) and ``box``.
FILTERS = ("gaussian", "box")


def scene_dict(res: int, spp: int, rfilter: str = "gaussian"):
    import mitsuba as mi

    T = mi.ScalarTransform4f
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 6},
        "sensor": {"type": "perspective", "fov": 40,
                   "to_world": T().look_at(origin=[0, 2, 7], target=[0, 0, 0], up=[0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": res, "height": res,
                            "rfilter": {"type": rfilter}},
                   "sampler": {"type": "independent", "sample_count": spp}},
        "floor": {"type": "rectangle", "bsdf": {"type": "diffuse"},
                  "to_world": T().translate([0, -1, 0]).rotate([1, 0, 0], -90).scale(8)},
        "ball0": {"type": "sphere", "center": [-2.2, 0, 0], "bsdf": {"type": "diffuse"}},
        "ball1": {"type": "sphere", "center": [0, 0, 0], "bsdf": {"type": "roughplastic"}},
        "ball2": {"type": "sphere", "center": [2.2, 0, 0], "bsdf": {"type": "dielectric"}},
        "panel_shape": {"type": "rectangle",
                        "to_world": T().look_at([0, 4, 0], [0, 0, 0], [0, 0, 1]),
                        "emitter": {"type": "area", "id": "panel", "radiance": 3.0}},
        "sky": {"type": "constant", "radiance": 0.2},
    }
    for i, (x, z) in enumerate([(-3, 3), (3, 3), (-3, -3), (3, -3)]):
        scene[f"point{i}"] = {"type": "point", "position": [x, 4, z], "intensity": 10.0}
    for i, x in enumerate((-1.0, 1.0)):
        scene[f"bulb{i}"] = {"type": "pointlight", "position": [x, 3, 2], "intensity": 5.0}
    return scene


def timed_cpu_render(scene, **render_args) -> tuple[float, float]:
    """(wall-clock, process CPU) seconds of one render, evaluated and synchronised. The
    CPU time (all of Dr.Jit's threads) is the steadier measure on a shared machine."""
    import drjit as dr
    import mitsuba as mi

    wall, cpu = time.perf_counter(), time.process_time()
    dr.eval(mi.render(scene, **render_args))
    dr.sync_thread()
    return time.perf_counter() - wall, time.process_time() - cpu


def render_rows(args):
    from spectrace import lightgroups

    rows = []
    for variant, rfilter in [(v, f) for v in VARIANTS for f in FILTERS]:
        spectrace.set_variant(variant)
        import mitsuba as mi

        scene = mi.load_dict(scene_dict(args.res, args.spp, rfilter))
        names = lightgroups.emitter_names(scene)
        assert len(names) == GROUPS, names
        integrators = {
            "path": scene.integrator(),
            "lightgroups, 1 group": lightgroups.integrator_for(scene, {"all": names}),
            "lightgroups, 8 groups": lightgroups.integrator_for(scene, True),
        }
        first = {k: timed_render(scene, spp=args.spp, seed=0, integrator=i)
                 for k, i in integrators.items()}

        def measure(integrator, repeat, scene=scene):
            return timed_cpu_render(scene, spp=args.spp, seed=repeat, integrator=integrator)

        warm = interleaved(integrators, measure, args.repeats)
        wall = {k: min(t[0] for t in v) for k, v in warm.items()}
        cpu = {k: min(t[1] for t in v) for k, v in warm.items()}
        for k in integrators:
            rows.append((variant, rfilter, k, first[k], wall[k], cpu[k],
                         wall[k] / wall["path"], cpu[k] / cpu["path"],
                         wall[k] / wall["lightgroups, 1 group"],
                         cpu[k] / cpu["lightgroups, 1 group"]))
    return rows


def _resident_bytes() -> int:
    """The process's resident set now (Linux: /proc/self/statm)."""
    import os

    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def _reset_peak() -> tuple[int, bool]:
    """(the resident set now, whether the peak was reset to it): Linux resets the
    process's peak resident set (VmHWM) when 5 is written to /proc/self/clear_refs."""
    before = _resident_bytes()
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        return before, True
    except OSError:
        return before, False


def _peak_bytes(reset: bool) -> int:
    """The peak resident set since :func:`_reset_peak` (VmHWM), or of the whole process
    (``ru_maxrss``) where it could not be reset."""
    if reset:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # KiB on Linux


def memory_child(variant: str, kind: str, res: int, spp: int) -> None:
    """In a subprocess: one render of ``kind`` (a key of :func:`render_rows`'s
    integrators); prints {"before": bytes, "peak": bytes} as JSON."""
    import drjit as dr

    spectrace.set_variant(variant)
    import mitsuba as mi

    from spectrace import lightgroups

    scene = mi.load_dict(scene_dict(res, spp, "box"))
    names = lightgroups.emitter_names(scene)
    integrator = {"path": lambda: scene.integrator(),
                  "lightgroups, 1 group": lambda: lightgroups.integrator_for(scene,
                                                                             {"all": names}),
                  "lightgroups, 8 groups": lambda: lightgroups.integrator_for(scene, True),
                  }[kind]()
    # the resident memory of an array of the image's size, first (a fresh allocation)
    start = _resident_bytes()
    same = dr.arange(mi.Float, res * res * (3 + len(integrator.aov_names()))) * 2.0
    dr.eval(same)
    dr.sync_thread()
    image_bytes = _resident_bytes() - start
    del same
    dr.eval(mi.render(scene, spp=spp, seed=0, integrator=integrator))  # compiles
    dr.sync_thread()
    dr.flush_malloc_cache()  # its arrays go back to the system, to be allocated anew
    before, reset = _reset_peak()
    image = mi.render(scene, spp=spp, seed=1, integrator=integrator)
    dr.eval(image)
    dr.sync_thread()
    print(json.dumps({"before": before, "peak": _peak_bytes(reset), "image": image_bytes}))


def memory_rows(args):
    """(variant, integrator, peak MB, render's own MB, own / path, image MB, layers MB,
    allowed MB, aim met)
    per render, each measured in its own subprocess (see the module docstring)."""
    kinds = ("path", "lightgroups, 1 group", "lightgroups, 8 groups")
    rows = []
    for variant in VARIANTS:
        own, peak, image = {}, {}, {}
        for kind in kinds:
            out = subprocess.run([sys.executable, __file__, "--memory-child", variant, kind,
                                  "--res", str(args.res), "--spp", str(args.spp)],
                                 capture_output=True, text=True, check=True).stdout
            m = json.loads(out.strip().splitlines()[-1])
            peak[kind] = m["peak"] / 1e6
            own[kind] = (m["peak"] - m["before"]) / 1e6
            image[kind] = m["image"] / 1e6
        layers_mb = image["lightgroups, 8 groups"] - image["path"]  # resident, see above
        allowed = 1.2 * own["path"] + layers_mb
        for kind in kinds:
            rows.append((variant, kind, peak[kind], own[kind], own[kind] / own["path"],
                         image[kind], layers_mb, allowed,
                         "-" if kind == "path" else ("yes" if own[kind] <= allowed else "no")))
    return rows


def relight_rows(repeats: int):
    import numpy as np

    from spectrace import lightgroups
    from spectrace.images import write_png

    rng = np.random.default_rng(1)
    layers = {f"light{i}": rng.random((RELIGHT_RES, RELIGHT_RES, 3), dtype=np.float32)
              for i in range(GROUPS)}
    scales = {g: 0.5 for g in list(layers)[:4]}
    steps = {"read EXR": [], "relight()": [], "write EXR": [], "write PNG": []}
    with tempfile.TemporaryDirectory() as tmp:
        src = Path(tmp) / "layers.exr"
        lightgroups.write_layers_exr(src, sum(layers.values()), layers)
        for _ in range(repeats):
            t0 = time.perf_counter()
            _, read, _ = lightgroups.read_layers_exr(src)
            t1 = time.perf_counter()
            image, scaled = lightgroups.relight(read, scales)
            t2 = time.perf_counter()
            lightgroups.write_layers_exr(Path(tmp) / "out.exr", image, scaled)
            t3 = time.perf_counter()
            write_png(Path(tmp) / "out.png", image)
            t4 = time.perf_counter()
            for key, t in zip(steps, (t1 - t0, t2 - t1, t3 - t2, t4 - t3), strict=True):
                steps[key].append(t)
    return [(k, min(v)) for k, v in steps.items()]


def spectral_relight_rows(repeats: int):
    """8 spectral layers of SPECTRAL_BANDS bands (about 0.5 GB of float32): reading them
    from the EXR, dimming them, and giving one group a new lamp spectrum."""
    import numpy as np

    from spectrace import lightgroups
    from spectrace.spectral_film import band_centres

    rng = np.random.default_rng(2)
    wl = band_centres(SPECTRAL_BANDS)
    shape = (RELIGHT_RES, RELIGHT_RES, SPECTRAL_BANDS)
    layers = {f"light{i}": rng.random(shape, dtype=np.float32) for i in range(GROUPS)}
    spectra = {g: np.ones(SPECTRAL_BANDS) for g in layers}
    new = {"light0": (wl, np.linspace(0.5, 1.5, wl.size))}
    steps = {"read spectral EXR": [], "relight_spectral(), dimming": [],
             "relight_spectral(), a new spectrum": []}
    with tempfile.TemporaryDirectory() as tmp:
        src = Path(tmp) / "layers.spectral.exr"
        total = sum(layers.values())
        lightgroups.write_spectral_layers_exr(src, total, layers, wl,
                                              np.zeros(shape[:2] + (3,)), spectra)
        del layers, total
        for _ in range(repeats):
            t0 = time.perf_counter()
            _, read, wl, old, _ = lightgroups.read_spectral_layers_exr(src)
            t1 = time.perf_counter()
            lightgroups.relight_spectral(read, wl, {"light1": 0.5}, {}, old)
            t2 = time.perf_counter()
            lightgroups.relight_spectral(read, wl, {"light1": 0.5}, new, old)
            t3 = time.perf_counter()
            for key, t in zip(steps, (t1 - t0, t2 - t1, t3 - t2), strict=True):
                steps[key].append(t)
            del read
    best = {k: min(v) for k, v in steps.items()}
    read = best["read spectral EXR"]
    return [(k, v, v / read) for k, v in best.items()]


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["--memory-child"]:
        memory_child(argv[1], argv[2], *render_parser(__doc__).parse_args(argv[3:]).__dict__
                     .values())
        return 0
    parser = render_parser(__doc__, repeats=3)
    parser.add_argument("--memory-only", action="store_true",
                        help="only the memory table")
    args = parser.parse_args(argv)
    print(f"memory {args.res}x{args.res}, {args.spp} spp, box filter, one render per "
          "subprocess (own = peak RSS of a warm render - RSS before it)")
    print_table([("variant", ">16", ""), ("integrator", ">21", ""), ("peak MB", ">8", ".1f"),
                 ("own MB", ">7", ".1f"), ("own/path", ">8", ".2f"),
                 ("image MB", ">8", ".1f"), ("layers MB", ">9", ".1f"), ("aim MB", ">7", ".1f"),
                 ("aim met", ">7", "")],
                memory_rows(args), sep="  ")
    print()
    if args.memory_only:
        return 0
    rows = render_rows(args)
    print(f"render {args.res}x{args.res}, {args.spp} spp, max_depth 6, {GROUPS} emitters, "
          f"best of {args.repeats} warm renders")
    print_table([("variant", ">16", ""), ("rfilter", ">8", ""), ("integrator", ">21", ""),
                 ("first s", ">7", ".3f"), ("wall s", ">6", ".3f"), ("CPU s", ">6", ".3f"),
                 ("wall/path", ">9", ".2f"), ("CPU/path", ">8", ".2f"),
                 ("wall/1 group", ">12", ".2f"), ("CPU/1 group", ">11", ".2f")], rows,
                sep="  ")
    print()
    print(f"relight {RELIGHT_RES}x{RELIGHT_RES}, {GROUPS} RGB layers, best of "
          f"{args.repeats}")
    print_table([("step", ">36", ""), ("seconds", ">8", ".3f")],
                relight_rows(args.repeats), sep="  ")
    print()
    print(f"relight {RELIGHT_RES}x{RELIGHT_RES}, {GROUPS} spectral layers of "
          f"{SPECTRAL_BANDS} bands, best of {args.repeats}")
    print_table([("step", ">36", ""), ("seconds", ">8", ".3f"), ("/ read", ">7", ".2f")],
                spectral_relight_rows(args.repeats), sep="  ")
    return 0


if __name__ == "__main__":
    sys.exit(main())
