"""Timing and table helpers shared by the benchmark scripts (not a benchmark itself).

Imported as ``import _timing`` by ``benchmarks/bench_*.py``: a script run as
``python benchmarks/bench_x.py`` has its own folder on ``sys.path``. ``make bench`` runs
only ``bench_*.py``, so this module is never run on its own.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import TypeVar

K = TypeVar("K")
V = TypeVar("V")

#: The Mitsuba variants every render benchmark compares.
VARIANTS = ("llvm_ad_rgb", "llvm_ad_spectral")


def render_parser(doc: str, res: int = 256, spp: int = 16,
                  repeats: int | None = None) -> argparse.ArgumentParser:
    """An argument parser described by the first line of ``doc`` with the options
    ``--res`` and ``--spp`` (and ``--repeats`` when a default is given)."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("--res", type=int, default=res)
    parser.add_argument("--spp", type=int, default=spp)
    if repeats is not None:
        parser.add_argument("--repeats", type=int, default=repeats)
    return parser


def timed_render(scene, **render_args) -> float:
    """Wall-clock seconds of ``mi.render(scene, **render_args)``, including the
    evaluation of the image and the wait for Dr.Jit's queued work to finish."""
    import drjit as dr
    import mitsuba as mi

    start = time.perf_counter()
    image = mi.render(scene, **render_args)
    dr.eval(image)
    dr.sync_thread()
    return time.perf_counter() - start


def interleaved(items: Mapping[K, V], measure: Callable[[V, int], float],
                repeats: int) -> dict[K, list[float]]:
    """``measure(item, repeat)`` for every item, in ``repeats`` rounds over all the items
    (so that load changes on the machine hit every item alike): key -> its times."""
    times: dict[K, list[float]] = {key: [] for key in items}
    for repeat in range(repeats):
        for key, item in items.items():
            times[key].append(measure(item, repeat))
    return times


def print_table(columns: Sequence[tuple[str, str, str]], rows: Iterable[Sequence],
                sep: str = " ") -> None:
    """Print a header and the rows; ``columns`` holds (title, alignment and width, value
    format) per column, e.g. ``("time (s)", ">9", ".3f")``."""
    print(sep.join(f"{title:{width}}" for title, width, _ in columns))
    for row in rows:
        cells = zip(columns, row, strict=True)
        print(sep.join(f"{value:{width}{fmt}}" for (_, width, fmt), value in cells))
