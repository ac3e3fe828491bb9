"""The pass loop shared by the command line and the notebooks.

A render of ``spp`` samples per pixel is split into passes of at most ``spp_per_pass``
samples (each a call of ``mi.render`` with its own seed), averaged with weights equal to
their sample counts. Memory therefore depends on ``spp_per_pass``, not on ``spp``.
A SIGINT (Ctrl-C) during a pass lets the pass finish and then stops the loop, so the
image of the completed passes can still be saved.
"""

from __future__ import annotations

import signal
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from spectrace.errors import UserError

DEFAULT_SPP_PER_PASS = 16
_POLL_S = 0.02  # how often the distributed loop looks for finished passes
_SEED_STRIDE = 0x9E3779B1  # golden-ratio stride: passes of nearby seeds never share seeds


@dataclass
class RenderResult:
    """An averaged image and how it was made."""

    image: np.ndarray  # (H, W, C) float32, the film's channels
    spp: int  # samples per pixel actually rendered (less than asked if interrupted)
    passes: int
    seconds: float
    interrupted: bool
    nonfinite: int = 0  # pixel values that were NaN or infinite, set to 0 in ``image``

    @property
    def samples_per_second(self) -> float:
        h, w = self.image.shape[:2]
        return h * w * self.spp / self.seconds if self.seconds > 0 else float("nan")


def pass_seed(seed: int, index: int) -> int:
    """The seed of pass ``index`` of a render with seed ``seed`` (distinct per pass)."""
    return (seed * _SEED_STRIDE + index) & 0xFFFFFFFF


def check_sample_counts(spp: int | None, spp_per_pass: int) -> None:
    """UserError unless ``spp`` (None: the scene's own) and ``spp_per_pass`` are positive."""
    if spp is not None and spp <= 0:
        raise UserError(f"--spp must be a positive integer (got {spp})")
    if spp_per_pass <= 0:
        raise UserError(f"--spp-per-pass must be a positive integer (got {spp_per_pass})")


def scene_spp(scene, sensor: int = 0) -> int:
    """The samples per pixel the scene's sensor asks for (its sampler's sample_count)."""
    return int(scene.sensors()[sensor].sampler().sample_count())


def pass_sizes(spp: int, spp_per_pass: int) -> list[int]:
    """Samples per pass: full passes of ``spp_per_pass``, then the remainder."""
    check_sample_counts(spp, spp_per_pass)
    full, rest = divmod(spp, spp_per_pass)
    return [spp_per_pass] * full + ([rest] if rest else [])


class _StopOnSigint:
    """Context manager: SIGINT sets a flag instead of raising, on the main thread only."""

    def __init__(self):
        self.requested = False
        self._previous = None

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            self._previous = signal.signal(signal.SIGINT, self._handle)
        return self

    def _handle(self, signum, frame):
        self.requested = True

    def __exit__(self, *exc):
        if self._previous is not None:
            signal.signal(signal.SIGINT, self._previous)
        return False


def render_passes(
    scene,
    spp: int,
    seed: int = 0,
    spp_per_pass: int = DEFAULT_SPP_PER_PASS,
    sensor: int = 0,
    integrator=None,
    on_pass: Callable[[int, int], None] | None = None,
) -> RenderResult:
    """Render ``scene`` with ``spp`` samples per pixel in passes; see the module docstring.

    ``on_pass(done_spp, total_spp)`` is called after each pass (the CLI's progress bar).
    Returns the sample-weighted mean of the passes as float32 (H, W, C); NaN or infinite
    values (a plugin's bug) are set to 0 and counted in ``RenderResult.nonfinite``.
    """
    import mitsuba as mi

    sizes = pass_sizes(spp, spp_per_pass)
    accum = None
    done = 0
    start = time.perf_counter()
    with _StopOnSigint() as stop:
        for index, n in enumerate(sizes):
            img = mi.render(
                scene, spp=n, seed=pass_seed(seed, index), sensor=sensor, integrator=integrator
            )
            img = np.asarray(img, dtype=np.float64)
            accum = img * n if accum is None else accum + img * n
            done += n
            if on_pass is not None:
                on_pass(done, spp)
            if stop.requested:
                break
        interrupted = stop.requested and done < spp
    seconds = time.perf_counter() - start
    return _result(accum, done, index + 1, seconds, interrupted)


def _result(accum, done: int, passes: int, seconds: float, interrupted: bool) -> RenderResult:
    """The mean image from the sample-weighted sum ``accum`` of ``done`` samples."""
    image = (accum / done).astype(np.float32)
    bad = ~np.isfinite(image)
    nonfinite = int(bad.sum())
    if nonfinite:  # never a NaN in an image: zero them and report the count
        image[bad] = 0.0
    return RenderResult(image, done, passes, seconds, interrupted, nonfinite)


def render_passes_distributed(
    client,
    spec,
    spp: int,
    seed: int = 0,
    spp_per_pass: int = DEFAULT_SPP_PER_PASS,
    on_pass: Callable[[int, int], None] | None = None,
    window: int | None = None,
) -> RenderResult:
    """:func:`render_passes` with its passes run as tasks on a Dask ``client``'s workers.

    ``spec`` is a :class:`spectrace.cluster.SceneSpec` (what each worker loads). Pass
    ``index`` has the local loop's seed :func:`pass_seed(seed, index) <pass_seed>` and sample
    count, and the passes are summed in index order with weights equal to their sample
    counts, so the image equals the local render's (up to the film's float additions).
    At most ``window`` passes (default: twice the workers' threads) are outstanding at a
    time. A SIGINT (Ctrl-C) cancels the outstanding passes and returns the mean of the
    passes done (``interrupted`` set). A pass whose worker dies is run again elsewhere.
    """
    from distributed import as_completed

    from spectrace.cluster import RETRIES, render_pass

    sizes = pass_sizes(spp, spp_per_pass)
    if window is None:
        threads = sum(w.get("nthreads", 1) for w in
                      client.scheduler_info(n_workers=-1)["workers"].values())
        window = 2 * max(1, threads)
    images: dict[int, np.ndarray] = {}
    ready = as_completed(loop=client.loop)
    pending: dict = {}  # future -> pass index
    next_index = 0
    done = 0
    start = time.perf_counter()
    with _StopOnSigint() as stop:
        while (pending or next_index < len(sizes)) and not stop.requested:
            while next_index < len(sizes) and len(pending) < window:
                future = client.submit(render_pass, spec, seed, next_index, sizes[next_index],
                                       pure=False, retries=RETRIES)
                pending[future] = next_index
                ready.add(future)
                next_index += 1
            if not ready.has_ready():
                time.sleep(_POLL_S)
                continue
            for future in ready.next_batch(block=False):
                index = pending.pop(future)
                images[index] = future.result()  # a task's own error propagates
                done += sizes[index]
                if on_pass is not None:
                    on_pass(done, spp)
        if pending:
            client.cancel(list(pending))
        interrupted = stop.requested and done < spp
    seconds = time.perf_counter() - start
    if not images:  # stopped before the first pass finished: nothing to average
        return RenderResult(np.zeros((0, 0, 3), np.float32), 0, 0, seconds, True)
    accum = None
    for index in sorted(images):
        img = np.asarray(images[index], dtype=np.float64) * sizes[index]
        accum = img if accum is None else accum + img
    return _result(accum, done, len(images), seconds, interrupted)
