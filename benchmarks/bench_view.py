"""Benchmark: ``spectrace view`` of a 1024 x 1024 EXR (issue 19: under 0.2 s).

Two figures per display setting: the in-process time of reading the EXR, developing it and
writing the PNG (``spectrace.cli.main(["view", ...])`` in a warm interpreter: what the
command itself costs, without the interpreter's start-up; also its CPU time, the steadier
figure on a machine that others load), and the wall time of a whole
``spectrace view`` process (start-up included). The image is a smooth gradient with noise
(a render-like PNG to compress), written once with ``spectrace.images.write_exr``.
The ratio column is each setting's in-process time over the default's.

    .venv/bin/python benchmarks/bench_view.py [--size 1024] [--repeats 5]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

SETTINGS = {
    "default": [],
    "exposure auto": ["--exposure", "auto"],
    "white balance 3000K": ["--white-balance", "3000K"],
    "16-bit PNG": ["--png-bits", "16"],
    "display-p3": ["--display", "display-p3"],
    "aces (OCIO)": ["--view", "aces"],
    "false-colour": ["--view", "false-colour"],
}
TARGET_S = 0.2


def test_image(size: int) -> np.ndarray:
    rng = np.random.default_rng(0)
    y, x = np.mgrid[0:size, 0:size] / size
    base = np.stack([x, y, 1 - x * y], axis=-1) * 1.5
    return (base * rng.normal(1.0, 0.05, base.shape)).astype(np.float32)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    from spectrace.cli import main as cli
    from spectrace.images import write_exr

    with tempfile.TemporaryDirectory() as folder:
        exr = Path(folder) / "image.exr"
        write_exr(exr, test_image(args.size))
        rows = []
        for name, options in SETTINGS.items():
            argv = ["view", str(exr), "-o", str(Path(folder) / "out.png"), *options]
            cli(argv)  # warm: imports, OCIO's config, colour maps
            inside, cpu = [], []
            for _ in range(args.repeats):
                start, start_cpu = time.perf_counter(), time.process_time()
                cli(argv)
                inside.append(time.perf_counter() - start)
                cpu.append(time.process_time() - start_cpu)
            start = time.perf_counter()
            subprocess.run([sys.executable, "-m", "spectrace.cli", *argv], check=True,
                           capture_output=True)
            whole = time.perf_counter() - start
            rows.append((name, statistics.median(inside), statistics.median(cpu), whole))
    base = rows[0][1]
    print(f"\nspectrace view, {args.size} x {args.size}, median of {args.repeats} "
          f"(target {TARGET_S} s in process)")
    print(f"{'setting':<22}{'in process s':>14}{'CPU s':>8}{'ratio':>8}{'whole process s':>18}")
    for name, inside, cpu, whole in rows:
        print(f"{name:<22}{inside:>14.3f}{cpu:>8.3f}{inside / base:>8.2f}{whole:>18.2f}")


if __name__ == "__main__":
    main()
