"""A 16-image sweep of the showcase: a plain loop in one process against spectrace.sweep on Dask.

Three ways to make the same 16 images (4 max_depth values x 4 seeds, EXR + PNG each):

* loop: one process, load + render (``render_passes``) + write, one image after another,
  Dr.Jit on all cores;
* sweep, 1 worker x all threads: ``spectrace.sweeps.run`` on a LocalCluster of one worker
  process whose Dr.Jit pool has all the cores;
* sweep, 2 workers x 1 thread: two worker processes, one Dr.Jit thread each.

Every configuration is warmed first (kernels compiled or loaded from the cache, variant set
on every worker), so the table compares the steady state; the rounds are interleaved and
the table shows each configuration's fastest (the machine may be shared). Wall time and
CPU time (all processes: client, scheduler, workers) are both shown: on a busy machine the
CPU time is the steadier measure of the overhead. The sweep's overhead per image o is
(sweep CPU - loop CPU) / 16 on one worker, and c is the CPU the client and scheduler spend
per image (every image passes through them); the speed-up over the loop on N machines of W
workers is then estimated as min(N W t / (t + o), t / c) for images of t seconds (the
images, or passes, are independent; it holds while there are at least N W tasks).

    python benchmarks/bench_sweep.py [--res 64] [--spp 16]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "showcase.xml"
VARIANT = "llvm_ad_rgb"
DEPTHS = ("2", "3", "4", "5")
SEEDS = (0, 1, 2, 3)
#: The issue's aim for the sweep on one worker against the loop.
AIM = 1.1


def grid(res: int, spp: int):
    from spectrace import sweeps

    return sweeps.Grid.make(SCENE, {"res": str(res), "max_depth": list(DEPTHS)},
                           variants=VARIANT, seeds=list(SEEDS), spp=spp)


def run_loop(g, outdir: Path) -> tuple[float, float]:
    """What 16 calls of `spectrace render` do, in one process (no start-up):
    (wall seconds, CPU seconds of the process)."""
    from spectrace import sweeps
    from spectrace.images import write_exr, write_png
    from spectrace.passes import render_passes
    from spectrace.scene import load_scene

    start, cpu = time.perf_counter(), time.process_time()
    for combo in g.combinations():
        scene = load_scene(SCENE, combo.defines)
        rgb = render_passes(scene, g.spp, seed=combo.seed).image[..., :3]
        exr = outdir / f"{sweeps.stem(combo)}.exr"
        write_png(exr.with_suffix(".png"), rgb)
        write_exr(exr, rgb, {"spp": g.spp, "seed": combo.seed})
    return time.perf_counter() - start, time.process_time() - cpu


def _worker_cpu() -> float:
    return time.process_time()


class SweepRunner:
    """A LocalCluster of ``workers`` processes, warmed up, that times sweeps of a grid."""

    def __init__(self, workers: int, g, outdir: Path):
        from distributed import Client

        from spectrace import cluster, sweeps

        self.local = cluster.start_local(workers)
        self.client = Client(self.local, set_as_default=False)
        cluster.setup_workers(self.client, variant=VARIANT)
        warm = sweeps.Grid.make(SCENE, {"res": g.params["res"], "max_depth": list(DEPTHS)},
                               variants=VARIANT, seeds=[99], spp=g.spp)
        sweeps.run(warm, self.client, outdir / "warm")  # every worker loads its kernels
        self.g, self.outdir, self.rounds = g, outdir, 0
        self.client_cpu: list[float] = []  # CPU s of the client process (and its scheduler)

    def __call__(self) -> tuple[float, float]:
        """(wall seconds, CPU seconds of the client, its scheduler and the workers)."""
        from spectrace import sweeps

        self.rounds += 1
        workers = sum(self.client.run(_worker_cpu).values())
        start, cpu = time.perf_counter(), time.process_time()
        outcomes = sweeps.run(self.g, self.client, self.outdir / f"run{self.rounds}")
        seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
        self.client_cpu.append(cpu)
        cpu += sum(self.client.run(_worker_cpu).values()) - workers
        assert all(o.status == "rendered" for o in outcomes), outcomes
        return seconds, cpu

    def close(self):
        self.client.close()
        self.local.close()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--res", type=int, default=64)
    parser.add_argument("--spp", type=int, default=16)
    parser.add_argument("--rounds", type=int, default=3,
                        help="interleaved rounds; the table shows each configuration's fastest")
    args = parser.parse_args()

    import spectrace
    from spectrace.cluster import quiet_logs

    quiet_logs()
    spectrace.set_variant(VARIANT)
    g = grid(args.res, args.spp)
    n = len(g.combinations())
    load = os.getloadavg()[0]
    cores = os.cpu_count()
    names = ("loop, one process", f"sweep, 1 worker x {cores} threads",
             "sweep, 2 workers x 1 thread")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for sub in ("warm", "loop"):
            (tmp / sub).mkdir()
        run_loop(g, tmp / "warm")  # kernels compiled once, as the workers' warm-up
        runners = [lambda: run_loop(g, tmp / "loop"), SweepRunner(1, g, tmp / "one"),
                   SweepRunner(2, g, tmp / "two")]
        times: dict[str, list[tuple[float, float]]] = {name: [] for name in names}
        try:
            for _ in range(args.rounds):  # interleaved: load changes hit every configuration
                for name, runner in zip(names, runners, strict=True):
                    times[name].append(runner())
        finally:
            for runner in runners[1:]:
                runner.close()
    best = {name: min(t for t, _ in ts) for name, ts in times.items()}
    cpu = {name: min(c for _, c in ts) for name, ts in times.items()}
    loop, one, two = (best[name] for name in names)
    print(f"{n} renders of the showcase, {args.res}x{args.res}, {args.spp} spp, {VARIANT}, "
          f"{cores} cores; fastest of {args.rounds} interleaved rounds; load average before "
          f"{load:.2f}")
    print(f"{'configuration':34s} {'wall s':>7s} {'/ loop':>7s} {'CPU s':>7s} {'/ loop':>7s}"
          f"  wall s of every round")
    for name in names:
        rounds = " ".join(f"{t:.2f}" for t, _ in times[name])
        print(f"{name:34s} {best[name]:7.3f} {best[name] / loop:7.2f} {cpu[name]:7.3f} "
              f"{cpu[name] / cpu[names[0]]:7.2f}  {rounds}")
    overhead = max(0.0, (one - loop) / n)
    cpu_overhead = max(0.0, (cpu[names[1]] - cpu[names[0]]) / n)
    central = min(runners[1].client_cpu) / n
    t = loop / n
    print()
    print(f"sweep overhead per image (1 worker against the loop): {overhead * 1e3:.1f} ms wall "
          f"({'within' if one <= AIM * loop else 'above'} the aim of {AIM}x), "
          f"{cpu_overhead * 1e3:.1f} ms CPU")
    print(f"client + scheduler CPU per image (receives it, writes EXR + PNG): "
          f"{central * 1e3:.1f} ms")
    faster = "1 worker x all threads" if one <= two else "2 workers x 1 thread"
    print(f"faster on this machine: {faster}")
    print(f"estimated speed-up over the loop on N machines of W workers, images of {t:.3f} s: "
          f"min(N W x {t / (t + cpu_overhead):.2f}, {t / central:.0f}) (the client and "
          f"scheduler handle every image)")

if __name__ == "__main__":
    main()
