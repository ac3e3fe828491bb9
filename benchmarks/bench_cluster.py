"""One render's passes on a local Dask cluster against the local pass loop, on the same cores.

Where the time of ``spectrace render --workers N`` goes on one machine, measured in one run:

* start: the LocalCluster of N worker processes (spawned interpreters importing Dask);
* setup: every worker sets the variant (imports Mitsuba, Dr.Jit's pool sized to its share);
* first pass: each worker loads the scene and its kernels (compiled, or read from the
  kernel cache ``~/.drjit``) on its first task;
* steady: the whole render on warm workers (scenes cached, kernels loaded) against
  :func:`spectrace.passes.render_passes` in this process with all cores, the same passes.

Then the whole command, cold (``spectrace render --workers N`` against ``spectrace render``,
fresh processes). Rounds are interleaved (load changes on a shared machine hit every
configuration alike); the table shows each configuration's median and the median of the
per-round ratios. CPU seconds (all processes) are shown beside wall seconds for the warm
renders: on a busy machine they are the steadier measure.

    python benchmarks/bench_cluster.py [--res 128] [--spp 1024] [--workers 2] [--rounds 3]
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import _timing

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "showcase.xml"
VARIANT = "llvm_ad_spectral"
#: The issue's aim: the cluster's render within this factor of the local loop.
AIM = 1.1


def cpu_seconds() -> float:
    """User + system CPU seconds of this process (on a worker: of that worker)."""
    t = os.times()
    return t.user + t.system


def timed(fn) -> tuple[float, float, object]:
    start, cpu = time.perf_counter(), cpu_seconds()
    out = fn()
    return time.perf_counter() - start, cpu_seconds() - cpu, out


def command(args: list[str]) -> tuple[float, float]:
    """Wall seconds of ``spectrace ARGS``, and NaN for its CPU seconds: the workers are
    forked by a fork server, which no one waits for, so ``os.times`` would miss them."""
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "spectrace.cli", *args], capture_output=True,
                          text=True)
    if done.returncode:
        raise SystemExit(done.stderr[-2000:])
    return time.perf_counter() - start, float("nan")


def main() -> None:
    parser = _timing.render_parser(__doc__, res=128, spp=1024, repeats=3)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--no-command", action="store_true",
                        help="skip the cold command-line runs")
    args = parser.parse_args()

    from distributed import Client

    import spectrace
    from spectrace import cluster
    from spectrace.passes import render_passes, scene_spp_per_pass
    from spectrace.scene import load_scene

    cluster.quiet_logs()
    params = {"res": str(args.res)}
    spectrace.set_variant(VARIANT, lazy=True)
    scene = load_scene(SCENE, params)
    per_pass = scene_spp_per_pass(scene, args.spp)
    spec = cluster.SceneSpec.make(SCENE, params, VARIANT)
    load = os.getloadavg()[0]

    start, _, local = timed(lambda: cluster.start_local(args.workers))
    client = Client(local, set_as_default=False)
    setup, _, _ = timed(lambda: cluster.setup_workers(client, variant=VARIANT))
    first, _, _ = timed(lambda: cluster.render_passes_distributed(
        client, spec, per_pass * args.workers, seed=99, spp_per_pass=per_pass))
    render_passes(scene, per_pass, seed=99)  # this process's kernels, as the workers'

    def distributed():
        workers = sum(client.run(cpu_seconds).values())
        wall, cpu, result = timed(lambda: cluster.render_passes_distributed(
            client, spec, args.spp, seed=1, spp_per_pass=per_pass))
        return wall, cpu + sum(client.run(cpu_seconds).values()) - workers

    def local_loop():
        wall, cpu, _ = timed(lambda: render_passes(scene, args.spp, seed=1))
        return wall, cpu

    configs = {"local loop, 1 process": local_loop,
               f"{args.workers} workers, warm": distributed}
    try:
        times = _timing.interleaved(configs, lambda fn, _: fn(), args.repeats)
    finally:
        client.close()
        local.close()

    with tempfile.TemporaryDirectory() as tmp:
        out = str(Path(tmp) / "x.exr")
        base = ["render", str(SCENE), "-D", f"res={args.res}", "--spp", str(args.spp),
                "--variant", VARIANT, "-o", out, "-q"]
        if not args.no_command:
            cold = {"spectrace render": base,
                    f"spectrace render --workers {args.workers}":
                        [*base, "--workers", str(args.workers)]}
            times.update(_timing.interleaved(cold, lambda a, _: command(a), args.repeats))

    print(f"showcase {args.res}x{args.res}, {args.spp} spp in passes of {per_pass}, {VARIANT}, "
          f"{os.cpu_count()} cores, {args.workers} workers of "
          f"{cluster.dr_thread_share(args.workers)} Dr.Jit threads; {args.repeats} "
          f"interleaved rounds; load average before {load:.2f}")
    print(f"cluster start {start:.2f} s, worker setup {setup:.2f} s, first pass on each "
          f"worker (scene load, kernels) {first:.2f} s")
    names = list(times)
    pairs = [(names[0], names[1])] + ([(names[2], names[3])] if len(names) > 2 else [])
    rows = []
    for base_name, name in pairs:
        for n in (base_name, name):
            wall = [t for t, _ in times[n]]
            cpu = [c for _, c in times[n]]
            ratio = statistics.median(t / b for (t, _), (b, _) in
                                      zip(times[n], times[base_name], strict=True))
            cpu_ratio = statistics.median(c / b for (_, c), (_, b) in
                                          zip(times[n], times[base_name], strict=True))
            rows.append((n, statistics.median(wall), ratio, statistics.median(cpu), cpu_ratio,
                         " ".join(f"{t:.2f}" for t in wall)))
    _timing.print_table([("configuration", "<36", ""), ("wall s", ">7", ".2f"),
                         ("/ base", ">7", ".2f"), ("CPU s", ">7", ".2f"), ("/ base", ">7", ".2f"),
                         ("  wall s of every round", "", "")], rows)
    warm = rows[1][2]
    print(f"\nwarm cluster / local loop: {warm:.2f} ({'within' if warm <= AIM else 'above'} "
          f"the aim of {AIM}x)")


if __name__ == "__main__":
    main()
