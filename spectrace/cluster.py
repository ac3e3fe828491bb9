"""Dask clusters for spectrace: making or joining one, and what its workers run.

:func:`connect` yields a ``distributed.Client``: by default on a ``LocalCluster`` of
worker *processes* (``threads_per_worker=1``: Dask runs one task at a time per worker and
the worker's Dr.Jit thread pool does the parallel work), or on an existing cluster given
by its scheduler address (``tcp://host:8786``). Every worker gets the :class:`Setup`
plugin once, when it starts (and again if it is restarted after dying):

* its Dr.Jit thread pool is sized to its share of its machine's cores
  (``os.cpu_count() // workers on that host``, at least 1), so that workers on one machine
  do not oversubscribe it;
* SIGINT is ignored (a Ctrl-C in the terminal reaches every process of the group: the
  client cancels the work, the workers must not die of it);
* the variant is set, lazily (:func:`ensure_variant`, once per process and variant): each
  scene registers the plugins it names as it loads.

Local workers are forked from a *fork server* (:data:`FORKSERVER_PRELOAD`), which imports
Dask and spectrace once for all of them (a spawned worker imports them itself: about a
second of CPU each), and none of them runs the user's main script
(:func:`main_script_hidden`). ``spectrace render --workers`` starts the server
(:func:`start_forkserver`) before it loads the scenes, so that its imports run meanwhile.

Kernel cache: Dr.Jit keeps compiled kernels in ``~/.drjit``; local workers inherit the
client's environment (``HOME``, ``DRJIT_LIBLLVM_PATH``), so they share one cache folder and
a kernel compiled by one worker is loaded from disk by the others.

What a remote worker needs: the same Python environment (spectrace, mitsuba, dask), and the
scene file and its assets readable at the *same absolute path* as on the client (tasks name
the scene by its path; images travel back to the client, which writes every output file,
so no shared folder is needed for the outputs).

The task functions (:func:`render_image`, :func:`render_pass`) run on the workers;
:func:`render_passes_distributed` is the pass loop of :mod:`spectrace.passes` with its
passes as tasks (this module builds on :mod:`spectrace.passes`, never the reverse).
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from spectrace.errors import ParameterError, SpectraceError, first_line
from spectrace.passes import (
    MIN_NOISE_PASSES,
    UNTIL_CLEAN_MAX_SPP,
    RenderResult,
    check_until_clean,
    pass_seed,
    pass_sizes,
    relative_error,
    render_passes,
    scene_spp,
)
from spectrace.signals import defer_sigint

#: Worker processes of the default LocalCluster. Measured on the 2-core development machine
#: with benchmarks/bench_sweep.py (small renders): two single-threaded workers beat one
#: worker with two Dr.Jit threads (see the README).
DEFAULT_WORKERS = 2
#: Seconds allowed to reach a scheduler before ``--scheduler`` is an error.
CONNECT_TIMEOUT_S = 10
#: How often a task that fails for a reason other than the user's (e.g. its worker died)
#: is run again elsewhere.
RETRIES = 2
PLUGIN_NAME = "spectrace-setup"

#: What the fork server of local workers imports before it forks them. Not Mitsuba: each
#: worker imports it after pointing Dr.Jit at the libLLVM (:func:`spectrace.set_variant`),
#: and nothing is forked from a process that holds Dr.Jit's threads.
FORKSERVER_PRELOAD = ("distributed", "numpy", "spectrace.cluster")
_POLL_S = 0.02  # how often the distributed pass loop looks for finished passes
_LOGGERS = ("distributed", "tornado", "asyncio", "bokeh")


def quiet_logs(level: int = logging.CRITICAL) -> None:
    """Silence Dask's (and its web stack's) logging in this process."""
    for name in _LOGGERS:
        logging.getLogger(name).setLevel(level)


@contextlib.contextmanager
def _sigint_ignored():
    """Ignore SIGINT while worker processes are spawned: they inherit SIG_IGN, and Python
    then installs no KeyboardInterrupt handler in them."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def _check_workers(workers: int | None) -> int:
    n = DEFAULT_WORKERS if workers is None else workers
    if n < 1:
        raise ParameterError(f"workers must be a positive integer (got {n})")
    return n


@contextlib.contextmanager
def main_script_hidden():
    """While inside, worker processes started by ``multiprocessing`` (Dask's nannies use its
    *spawn* method) do not run the user's main script.

    A spawned child imports the parent's ``__main__`` (its ``__file__``, or the module of
    ``__spec__`` for ``python -m``) as ``__mp_main__`` before it runs anything, so a plain
    script that calls :func:`spectrace.sweep` without ``if __name__ == "__main__":`` ran
    its top level again in every worker, whose nested cluster then failed ("Nanny failed
    to start"). The workers need nothing of that script (their tasks are spectrace
    functions), so both attributes are set aside here and restored on exit. A main module
    without them (Jupyter, ``python -c``) is left alone."""
    main = sys.modules.get("__main__")
    saved = {name: main.__dict__[name] for name in ("__file__", "__spec__")
             if main is not None and main.__dict__.get(name) is not None}
    main.__dict__.pop("__file__", None)
    if "__spec__" in saved:
        main.__spec__ = None  # (spawn reads the attribute: it must exist)
    try:
        yield
    finally:
        for name, value in saved.items():
            setattr(main, name, value)


@contextlib.contextmanager
def forkserver():
    """While inside, Dask's nannies start their workers from a fork server that has
    imported :data:`FORKSERVER_PRELOAD` (the server starts with the first worker and lives
    as long as this process)."""
    import multiprocessing

    import dask

    with dask.config.set({"distributed.worker.multiprocessing-method": "forkserver"}):
        from distributed.utils import get_mp_context

        get_mp_context()  # Dask's own preload list, set once; then this one
        multiprocessing.get_context("forkserver").set_forkserver_preload(
            list(FORKSERVER_PRELOAD))
        yield


def start_forkserver() -> None:
    """Start the fork server of :func:`forkserver` now (SIGINT ignored, as its workers
    will have it): its imports of :data:`FORKSERVER_PRELOAD` then run beside what this
    process does until it starts a LocalCluster (``spectrace render --workers`` loads the
    scenes meanwhile)."""
    import multiprocessing
    from multiprocessing import forkserver as _forkserver

    multiprocessing.get_context("forkserver").set_forkserver_preload(list(FORKSERVER_PRELOAD))
    with _sigint_ignored(), main_script_hidden():
        _forkserver.ensure_running()


def start_local(workers: int | None = None):
    """A LocalCluster of ``workers`` processes, one Dask thread each, quiet; its workers do
    not run the user's main script (:func:`main_script_hidden`, while they start: use
    :func:`connect` to keep that for the cluster's life, as when a worker is restarted)."""
    from distributed import LocalCluster

    n = _check_workers(workers)
    quiet_logs()
    with _sigint_ignored(), warnings.catch_warnings(), main_script_hidden(), forkserver():
        # another cluster on this machine holds port 8787: the scheduler's HTTP server
        # (health checks; the dashboard is off) takes another port and says so
        warnings.filterwarnings("ignore", message="Port .* is already in use")
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.CRITICAL)
    return cluster


@contextlib.contextmanager
def connect(workers: int | None = None, scheduler: str | None = None, *,
            variant: str | None = None, dr_threads: int | None = None,
            connect_timeout: float | None = None) -> Iterator:
    """Yield a Client on a new LocalCluster of ``workers`` processes or on ``scheduler``.

    ``variant``: set on every worker at start-up (others are set on first use).
    ``dr_threads``: Dr.Jit threads per worker (default: its share of its host's cores).
    An unreachable or malformed scheduler address is a SpectraceError after ``connect_timeout``
    seconds (default :data:`CONNECT_TIMEOUT_S`).
    Closes the client (and the LocalCluster it made) on exit.
    """
    from distributed import Client

    if workers is not None and scheduler:
        raise ParameterError("workers and scheduler exclude each other")
    quiet_logs()
    cluster = None
    with contextlib.ExitStack() as stack:
        if scheduler:
            check_address(scheduler)
            try:
                timeout = CONNECT_TIMEOUT_S if connect_timeout is None else connect_timeout
                client = Client(scheduler, timeout=timeout, set_as_default=False)
            except Exception as e:  # OSError, TimeoutError, ValueError for a bad address
                raise ParameterError(f"cannot reach scheduler {scheduler}: {first_line(e)}") \
                    from None
        else:
            # also when a nanny restarts a worker
            stack.enter_context(main_script_hidden())
            stack.enter_context(forkserver())
            cluster = start_local(workers)
            client = Client(cluster, set_as_default=False)
        try:
            setup_workers(client, variant=variant, dr_threads=dr_threads)
            yield client
        finally:
            with _sigint_ignored():
                client.close()
                if cluster is not None:
                    cluster.close()


def check_address(address: str) -> None:
    """ParameterError unless ``address`` reads as a scheduler address, e.g. tcp://host:8786."""
    from distributed.comm.addressing import get_address_host_port

    try:
        get_address_host_port(address if "://" in address else f"tcp://{address}")
    except (ValueError, TypeError) as e:
        raise ParameterError(f"scheduler {address}: not a scheduler address such as "
                             f"tcp://host:8786 ({first_line(e)})") from None


def setup_workers(client, variant: str | None = None, dr_threads: int | None = None) -> None:
    """Register :class:`Setup` on every worker (present and future)."""
    from distributed.comm import get_address_host

    workers = client.scheduler_info(n_workers=-1)["workers"]
    per_host: dict[str, int] = {}
    for address in workers:
        host = get_address_host(address)
        per_host[host] = per_host.get(host, 0) + 1
    client.register_plugin(Setup(per_host, variant, dr_threads), name=PLUGIN_NAME)


def dr_thread_share(workers_on_host: int, cores: int | None = None) -> int:
    """Dr.Jit threads of one of ``workers_on_host`` workers: its share of the cores, >= 1."""
    cores = cores or os.cpu_count() or 1
    return max(1, cores // max(1, workers_on_host))


# ---------------------------------------------------------------- on the workers

try:
    from distributed.diagnostics.plugin import WorkerPlugin as _WorkerPlugin
except ImportError:  # pragma: no cover - dask is a dependency
    _WorkerPlugin = object


class Setup(_WorkerPlugin):
    """Worker set-up: SIGINT ignored, Dr.Jit thread pool sized, variant and plugins."""

    def __init__(self, workers_per_host: dict[str, int], variant: str | None = None,
                 dr_threads: int | None = None):
        self.workers_per_host = dict(workers_per_host)
        self.variant = variant
        self.dr_threads = dr_threads

    def setup(self, worker):
        from distributed.comm import get_address_host

        with contextlib.suppress(ValueError):  # only possible on the main thread
            signal.signal(signal.SIGINT, signal.SIG_IGN)
        quiet_logs()
        threads = self.dr_threads or dr_thread_share(
            self.workers_per_host.get(get_address_host(worker.address), 1))
        _state.dr_threads = threads  # applied by ensure_variant, now or at the first task
        if self.variant:
            ensure_variant(self.variant)


@dataclass
class _WorkerState:
    variant: str | None = None
    dr_threads: int | None = None
    setups: int = 0  # how often set_variant ran in this process
    scenes: dict = field(default_factory=dict)


_state = _WorkerState()
_SCENE_CACHE_SIZE = 2


def ensure_variant(variant: str) -> None:
    """Set ``variant``, unless this process already did: lazily, as the command line does
    (each scene registers the plugins it names as it loads: a worker does not execute
    every plugin and Mitsuba's Python integrators at start-up)."""
    if _state.variant == variant:
        return
    import spectrace

    spectrace.set_variant(variant, lazy=True)
    _state.variant = variant
    _state.setups += 1
    _state.scenes.clear()
    if _state.dr_threads:
        import drjit as dr

        dr.set_thread_count(_state.dr_threads)


def worker_info() -> dict:
    """What a worker process runs with (for tests and ``--verbose`` reports)."""
    info = {"pid": os.getpid(), "variant": _state.variant, "setups": _state.setups,
            "kernel_cache": str(Path.home() / ".drjit"), "dr_threads": None}
    if _state.variant:
        import drjit as dr

        info["dr_threads"] = dr.thread_count()
    return info


@dataclass(frozen=True)
class SceneSpec:
    """A scene as a worker loads it: absolute path, ``-D`` parameters, variant, film bands,
    light groups."""

    path: str
    params: tuple[tuple[str, str], ...] = ()
    variant: str = "llvm_ad_spectral"
    bands: int | None = None  # --film spectral: that many bands (spectrace.spectral_film)
    #: ``light_groups`` of :func:`spectrace.lightgroups.integrator_for`: True (one group per
    #: emitter) or the ``lightgroups`` plugin's ``groups`` string; None: the scene's own
    #: integrator. With ``bands``: spectral layers on the scene's film.
    light_groups: bool | str | None = None

    @classmethod
    def make(cls, path, params: dict | None = None, variant: str = "llvm_ad_spectral",
             bands: int | None = None, light_groups=None) -> SceneSpec:
        """``light_groups``: True, a ``groups`` string, or ``["name=id1,id2", ...]``."""
        items = tuple((str(k), str(v)) for k, v in (params or {}).items())
        if light_groups is not None and not isinstance(light_groups, bool | str):
            light_groups = ";".join(str(g) for g in light_groups)
        return cls(str(Path(path).resolve()), items, variant, bands, light_groups)

    def load(self):
        """Set the variant and load the scene (SpectraceError for the user's mistakes)."""
        from spectrace.scene import load_scene, read_scene_xml

        ensure_variant(self.variant)
        params = dict(self.params)
        if self.bands is None or self.light_groups is not None:
            return load_scene(self.path, params)
        from spectrace.spectral_film import replace_film

        root = read_scene_xml(self.path)
        replace_film(root, bands=self.bands)
        return load_scene(self.path, params, root=root)

    def integrator(self, scene):
        """The integrator of a render of ``scene``: the ``lightgroups`` one with
        ``light_groups``, else None (the scene's own)."""
        if self.light_groups is None:
            return None
        from spectrace.lightgroups import integrator_for

        wavelengths = None
        if self.bands is not None:
            from spectrace.spectral_film import band_centres

            wavelengths = band_centres(self.bands)
        return integrator_for(scene, self.light_groups, band_wavelengths=wavelengths)


def _cached_scene(spec: SceneSpec):
    """The loaded scene of ``spec`` and its integrator (None: the scene's own); the last
    few are kept (passes of one render share them)."""
    try:
        mtime = os.stat(spec.path).st_mtime_ns
    except OSError:
        mtime = None
    key = (spec, mtime)
    loaded = _state.scenes.get(key)
    if loaded is None:
        scene = spec.load()
        loaded = (scene, spec.integrator(scene))
        while len(_state.scenes) >= _SCENE_CACHE_SIZE:
            _state.scenes.pop(next(iter(_state.scenes)))
        _state.scenes[key] = loaded
    return loaded


def render_pass(spec: SceneSpec, seed: int, index: int, n: int) -> tuple[np.ndarray, int]:
    """Task: pass ``index`` (``n`` spp) of a render with seed ``seed``: the float32
    (H, W, C) image (with light groups: the layers' channels after the beauty's) and the
    samples per pixel the sampler took (see :func:`spectrace.passes.scene_spp`).

    The same ``mi.render`` call, with the same pass seed, as the local loop's pass
    ``index`` (:func:`spectrace.passes.render_passes`).
    """
    import mitsuba as mi

    scene, integrator = _cached_scene(spec)
    img = mi.render(scene, spp=n, seed=pass_seed(seed, index), integrator=integrator)
    # a copy, and the tensor freed here: a view would keep it alive until the worker's
    # event loop drops the sent result, and Dr.Jit's frees there contend with the next pass
    image = np.array(img, dtype=np.float32)
    del img
    return image, scene_spp(scene)


def render_image(spec: SceneSpec, spp: int | None, seed: int,
                 spp_per_pass: int | None) -> dict:
    """Task: one whole image, as ``spectrace render`` makes it (the same pass loop).

    Returns ``{"image": float32 (H, W, 3) linear sRGB (a mono film as grey), "spp",
    "seconds", "render_seconds", "nonfinite"}``, or
    ``{"error": message}`` for a user's mistake (a bad parameter value): that is an
    answer, not a failure Dask should retry.
    """
    from spectrace.images import as_rgb

    start = time.perf_counter()
    try:
        scene = spec.load()
        n = spp or scene_spp(scene)
        result = render_passes(scene, n, seed=seed, spp_per_pass=spp_per_pass)
    except SpectraceError as e:
        return {"error": str(e)}
    spp_done, render_seconds, nonfinite = result.spp, result.seconds, result.nonfinite
    image = np.array(as_rgb(result.image), dtype=np.float32)  # a copy (see render_pass)
    del result
    return {"image": image, "spp": spp_done,
            "seconds": time.perf_counter() - start, "render_seconds": render_seconds,
            "nonfinite": nonfinite}


# ---------------------------------------------------------------- on the client

def _mean_of(accum, done: int, passes: int, seconds: float, interrupted: bool,
             noise: float | None = None, stopped_by: str = "spp") -> RenderResult:
    """The numpy mean image from the sample-weighted float64 sum ``accum`` of ``done``
    samples."""
    image = (accum / done).astype(np.float32)
    bad = ~np.isfinite(image)
    nonfinite = int(bad.sum())
    if nonfinite:  # never a NaN in an image: zero them and report the count
        image[bad] = 0.0
    return RenderResult(image, done, passes, seconds, interrupted, nonfinite, noise,
                        stopped_by)


class _PassSums:
    """The sample-weighted float64 sum of a render's passes. Without ``squares`` the passes
    are added in index order (held back while an earlier one is missing), so the sum is
    the local loop's, bit for bit; with ``squares`` (render until clean) as they arrive,
    beside the sum of n_i I_i^2 that :func:`spectrace.passes.relative_error` needs."""

    def __init__(self, squares: bool):
        self.squares = squares
        self.sum_w = self.sum_w2 = None
        self.waiting: dict[int, tuple[np.ndarray, int]] = {}
        self.next_index = 0
        self.done = 0
        self.passes = 0

    def add(self, index: int, image: np.ndarray, n: int) -> None:
        self.done += n
        self.passes += 1
        if self.squares:
            self._fold(image, n)
            return
        self.waiting[index] = (image, n)
        while self.next_index in self.waiting:
            self._fold(*self.waiting.pop(self.next_index))
            self.next_index += 1

    def finish(self) -> None:
        """Add the passes still held back (those after a cancelled one), in index order."""
        for index in sorted(self.waiting):
            self._fold(*self.waiting.pop(index))

    def _fold(self, image: np.ndarray, n: int) -> None:
        value = np.asarray(image, dtype=np.float64)
        weighted = value * n
        self.sum_w = weighted if self.sum_w is None else self.sum_w + weighted
        if self.squares:
            squared = weighted * value
            self.sum_w2 = squared if self.sum_w2 is None else self.sum_w2 + squared

    def relative_error(self) -> float:
        return relative_error(self.sum_w, self.sum_w2, self.done, self.passes)


def render_passes_distributed(
    client,
    spec,
    spp: int | None = None,
    seed: int = 0,
    spp_per_pass: int = 16,
    on_pass: Callable[[int, int], None] | None = None,
    window: int | None = None,
    noise: float | None = None,
    time_limit: float | None = None,
    on_noise: Callable[[float], None] | None = None,
) -> RenderResult:
    """:func:`spectrace.passes.render_passes` with its passes as tasks on ``client``'s workers.

    ``spec`` is a :class:`SceneSpec` (what each worker loads: with ``light_groups`` the
    passes hold the layers too, and are summed with them); the client does not load the
    scene, so the pass size is given (the command line gives
    :func:`~spectrace.passes.scene_spp_per_pass` of the scene it loaded, the local loop's
    default). Pass ``index`` has the local loop's seed
    :func:`~spectrace.passes.pass_seed` ``(seed, index)`` and sample count, and the passes
    are summed in index order with weights equal to their sample counts, so the image
    equals the local render's (up to the film's float additions).
    At most ``window`` passes (default: twice the workers' threads) are outstanding at a
    time. A SIGINT (Ctrl-C) cancels the outstanding passes and returns the mean of the
    passes done (``interrupted`` set). A pass whose worker dies is run again elsewhere.
    ``noise``, ``time_limit``, ``on_noise``: render until clean as the local loop does
    (the estimate after each finished pass, from :data:`~spectrace.passes.MIN_NOISE_PASSES`
    passes on); when the target or the time is reached no more passes are submitted and
    the outstanding ones are cancelled; ``spp`` is then the most it renders (None:
    :data:`~spectrace.passes.UNTIL_CLEAN_MAX_SPP`), and the result's ``noise`` and
    ``stopped_by`` say how it ended.
    The result's ``pixels`` are a numpy array (the workers send numpy arrays).
    """
    from distributed import as_completed

    check_until_clean(noise, time_limit)
    until_clean = noise is not None or time_limit is not None
    if spp is None:
        if not until_clean:
            raise ParameterError("render_passes_distributed: spp is needed without noise "
                                 "or time_limit (the client does not load the scene)")
        spp = UNTIL_CLEAN_MAX_SPP
    sizes = pass_sizes(spp, spp_per_pass)
    if window is None:
        threads = sum(w.get("nthreads", 1) for w in
                      client.scheduler_info(n_workers=-1)["workers"].values())
        window = 2 * max(1, threads)
    sums = _PassSums(squares=until_clean)
    ready = as_completed(loop=client.loop)
    pending: dict = {}  # future -> pass index
    next_index = 0
    estimate = None
    stopped_by = "spp"
    start = time.perf_counter()
    with defer_sigint(stop_only=True) as stop:
        while (pending or next_index < len(sizes)) and not stop.seen and stopped_by == "spp":
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
                image, taken = future.result()  # a task's own error propagates
                sums.add(index, image, taken)  # the count the worker's sampler took
                if on_pass is not None:
                    on_pass(sums.done, spp)
                if until_clean:
                    estimate = sums.relative_error()
                    if on_noise is not None and noise is not None:
                        on_noise(estimate)
                    stopped_by = _until_clean_stop(estimate, sums.passes, noise, time_limit,
                                                   time.perf_counter() - start)
                    if stopped_by != "spp":
                        break
        if pending:
            client.cancel(list(pending))
        if stop.seen:
            stopped_by = "interrupt"
        interrupted = stop.seen and sums.done < spp
    sums.finish()
    seconds = time.perf_counter() - start
    if not sums.passes:  # stopped before the first pass finished: nothing to average
        return RenderResult(np.zeros((0, 0, 3), np.float32), 0, 0, seconds, True)
    return _mean_of(sums.sum_w, sums.done, sums.passes, seconds, interrupted, estimate,
                    stopped_by)


def _until_clean_stop(estimate: float, passes: int, noise: float | None,
                      time_limit: float | None, elapsed: float) -> str:
    """What ends a render until clean after a pass: "noise", "time", or "spp" (go on)."""
    if noise is not None and passes >= MIN_NOISE_PASSES and estimate < noise:
        return "noise"
    if time_limit is not None and elapsed >= time_limit:
        return "time"
    return "spp"
