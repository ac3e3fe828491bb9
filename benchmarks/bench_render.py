"""Render throughput and peak memory of the showcase, rendered in passes by the CLI.

Each configuration runs `spectrace render` in a child process; its peak RSS comes from
os.wait4 (that child alone). With passes, memory must not grow with spp: the table shows
the peak RSS at 1024 spp over the peak at 64 spp (1.00 means no growth).

    python benchmarks/bench_render.py [--res 256] [--spp-per-pass 16]
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "showcase.xml"
VARIANTS = ("llvm_ad_rgb", "llvm_ad_spectral")
SPPS = (64, 1024)


def run_render(variant: str, spp: int, res: int, spp_per_pass: int, out: Path):
    cmd = [sys.executable, "-m", "spectrace.cli", "render", str(SCENE), "-o", str(out),
           "--variant", variant, "--spp", str(spp), "--spp-per-pass", str(spp_per_pass),
           "-D", f"res={res}", "-q"]
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    stdout = proc.stdout.read()
    stderr = proc.stderr.read()
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"render failed: {' '.join(cmd)}\n{stderr}")
    m = re.search(r"([\d.]+) s, ([\d.]+) M samples/s", stdout)
    render_s, msps = float(m.group(1)), float(m.group(2))
    return {"render_s": render_s, "msps": msps, "wall_s": wall,
            "rss_mib": usage.ru_maxrss / 1024.0}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--res", type=int, default=256)
    parser.add_argument("--spp-per-pass", type=int, default=16)
    args = parser.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for variant in VARIANTS:
            # warm the kernel cache so the table compares rendering, not first compilation
            run_render(variant, 16, args.res, args.spp_per_pass, Path(tmp) / "warm.exr")
            for spp in SPPS:
                r = run_render(variant, spp, args.res, args.spp_per_pass, Path(tmp) / "o.exr")
                rows.append((variant, spp, r))
    print(f"showcase {args.res}x{args.res}, passes of {args.spp_per_pass} spp, "
          f"{os.cpu_count()} cores")
    print(f"{'variant':18s} {'spp':>5s} {'render s':>9s} {'Msamples/s':>11s} "
          f"{'process s':>10s} {'peak RSS MiB':>13s}")
    for variant, spp, r in rows:
        print(f"{variant:18s} {spp:5d} {r['render_s']:9.2f} {r['msps']:11.2f} "
              f"{r['wall_s']:10.2f} {r['rss_mib']:13.0f}")
    print()
    for variant in VARIANTS:
        lo, hi = (r for v, _, r in rows if v == variant)
        print(f"{variant}: peak RSS 1024 spp / 64 spp = {hi['rss_mib'] / lo['rss_mib']:.2f}, "
              f"throughput 1024 / 64 = {hi['msps'] / lo['msps']:.2f}")
    rgb = [r for v, s, r in rows if v == VARIANTS[0] and s == SPPS[-1]][0]
    spec = [r for v, s, r in rows if v == VARIANTS[1] and s == SPPS[-1]][0]
    print(f"spectral / RGB render time at {SPPS[-1]} spp = "
          f"{spec['render_s'] / rgb['render_s']:.2f}")


if __name__ == "__main__":
    main()
