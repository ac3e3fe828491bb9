"""The pass loop shared by the command line and the notebooks.

A render of ``spp`` samples per pixel is split into passes of at most ``spp_per_pass``
samples (each a call of ``mi.render`` with its own seed), averaged with weights equal to
their sample counts: the counts the sensor's sampler took, since Mitsuba's ``ldsampler``,
``stratified``, ``multijitter`` and ``orthogonal`` round some counts up (``ldsampler``
makes a pass of 36 spp one of 64; :func:`scene_spp` after the pass), so a render may hold
a few more samples than asked, and its ``spp`` says how many. By default a pass holds up
to :data:`PASS_SAMPLES` samples and :data:`MAX_SPP_PER_PASS` spp
(:func:`default_spp_per_pass`). Mitsuba's LLVM backend keeps none of a pass's samples in
memory, so the pass size does not set the peak memory (measured flat from 4 to 1024 spp
per pass), but each pass costs about 12 ms of tracing and launching, and the progress bar
and Ctrl-C act between passes. A SIGINT (Ctrl-C) during a pass lets the pass finish and
then stops the loop, so the image of the completed passes can still be saved.

The local loop sums the passes in Dr.Jit (float64) and never imports numpy: a render's
pixels stay a Dr.Jit tensor (:attr:`RenderResult.pixels`) until someone asks for the numpy
array (:attr:`RenderResult.image`), so the command line starts as fast as ``mitsuba``.
The same loop with its passes on a Dask cluster is
:func:`spectrace.cluster.render_passes_distributed` (which builds on this module).
"""

from __future__ import annotations

import time
from collections.abc import Callable

from spectrace.errors import UserError
from spectrace.signals import defer_sigint

#: The samples (pixels x spp) a pass of the default size holds at most: about a second of
#: rendering, so the progress bar moves and Ctrl-C stops soon, while the 12 ms that each
#: pass costs stay under 2 % of it.
PASS_SAMPLES = 2**22
#: The default pass size never exceeds this many spp: samples of Mitsuba's low-discrepancy
#: ``ldsampler`` drawn as one pass correlate. Two 1024-spp renders of fog_volpath at 64 x 64
#: (seeds 0 and 1) differ by a relative RMS of 0.021, 0.019, 0.024 and 0.032 with passes of
#: 16, 64, 256 and 1024 spp.
MAX_SPP_PER_PASS = 64
_SEED_STRIDE = 0x9E3779B1  # golden-ratio stride: passes of nearby seeds never share seeds
#: A render's seed is stored in its EXR header as a 32-bit integer.
SEED_RANGE = (-(2**31), 2**31 - 1)


class RenderResult:
    """An averaged image and how it was made.

    ``pixels`` is the (H, W, C) float32 image with the film's channels, as made: a Dr.Jit
    tensor (``mi.TensorXf``) from the local loop, a numpy array from the distributed one.
    ``image`` is the same pixels as a numpy float32 array, converted on first access.
    """

    __slots__ = ("pixels", "spp", "passes", "seconds", "interrupted", "nonfinite", "_image")

    def __init__(self, pixels, spp: int, passes: int, seconds: float, interrupted: bool,
                 nonfinite: int = 0):
        self.pixels = pixels
        self.spp = spp  # samples per pixel actually rendered (less than asked if interrupted)
        self.passes = passes
        self.seconds = seconds
        self.interrupted = interrupted
        self.nonfinite = nonfinite  # pixel values that were NaN or infinite, set to 0
        self._image = None

    @property
    def image(self):
        """The pixels as an (H, W, C) float32 numpy array (imports numpy on first use)."""
        if self._image is None:
            import numpy as np

            self._image = np.asarray(self.pixels, dtype=np.float32)
        return self._image

    @property
    def shape(self) -> tuple[int, ...]:
        """(H, W, C) of the image."""
        return tuple(self.pixels.shape)

    @property
    def samples_per_second(self) -> float:
        h, w = self.shape[:2]
        return h * w * self.spp / self.seconds if self.seconds > 0 else float("nan")

    def __repr__(self) -> str:
        return (f"RenderResult(shape={self.shape}, spp={self.spp}, passes={self.passes}, "
                f"seconds={self.seconds:.3f}, interrupted={self.interrupted}, "
                f"nonfinite={self.nonfinite})")


def pass_seed(seed: int, index: int) -> int:
    """The seed of pass ``index`` of a render with seed ``seed`` (distinct per pass)."""
    return (seed * _SEED_STRIDE + index) & 0xFFFFFFFF


def check_sample_counts(spp: int | None, spp_per_pass: int | None) -> None:
    """UserError unless ``spp`` (None: the scene's own) and ``spp_per_pass`` (None: the
    default) are positive."""
    if spp is not None and spp <= 0:
        raise UserError(f"--spp must be a positive integer (got {spp})")
    if spp_per_pass is not None and spp_per_pass <= 0:
        raise UserError(f"--spp-per-pass must be a positive integer (got {spp_per_pass})")


def check_seed(seed: int, option: str = "--seed") -> int:
    """``seed`` as an int; UserError naming ``option`` unless it fits the EXR header's
    32-bit integer (:data:`SEED_RANGE`)."""
    low, high = SEED_RANGE
    if not low <= int(seed) <= high:
        raise UserError(f"{option} must be between {low} and {high} (got {seed}): it is "
                        "stored in the EXR header as a 32-bit integer")
    return int(seed)


def _sensor(scene, sensor):
    """``sensor`` itself, or the scene's sensor of that index."""
    return scene.sensors()[sensor] if isinstance(sensor, int) else sensor


def scene_spp(scene, sensor=0) -> int:
    """The samples per pixel of the sensor's sampler (``sensor``: an index into the scene's
    sensors, or a sensor): what the scene asks for, until a render. ``mi.render`` sets the
    count it is given on that sampler, which rounds it to one it can make, so after a render
    it is the count that render took."""
    return int(_sensor(scene, sensor).sampler().sample_count())


def default_spp_per_pass(pixels: int, spp: int) -> int:
    """The default pass size of a render of ``pixels`` pixels at ``spp`` samples per pixel:
    the largest power of 4 up to :data:`MAX_SPP_PER_PASS` whose pass holds at most
    :data:`PASS_SAMPLES` samples (at least 1 spp), and no more than ``spp``. Powers of 4 are
    the counts that Mitsuba's ``ldsampler`` takes as they are (it rounds others up) and
    perfect squares (``stratified``, ``multijitter``)."""
    k = 1
    while 4 * k <= MAX_SPP_PER_PASS and 4 * k * max(pixels, 1) <= PASS_SAMPLES:
        k *= 4
    return max(1, min(k, spp))


def scene_spp_per_pass(scene, spp: int, spp_per_pass: int | None = None, sensor=0) -> int:
    """``spp_per_pass``, or when None the default for the film of ``sensor`` (an index into
    the scene's sensors, or a sensor) (:func:`default_spp_per_pass`)."""
    if spp_per_pass is not None:
        return spp_per_pass
    width, height = (int(v) for v in _sensor(scene, sensor).film().crop_size())
    return default_spp_per_pass(width * height, spp)


def pass_sizes(spp: int, spp_per_pass: int) -> list[int]:
    """Samples per pass: full passes of ``spp_per_pass``, then the remainder."""
    check_sample_counts(spp, spp_per_pass)
    full, rest = divmod(spp, spp_per_pass)
    return [spp_per_pass] * full + ([rest] if rest else [])


def render_passes(
    scene,
    spp: int,
    seed: int = 0,
    spp_per_pass: int | None = None,
    sensor: int = 0,
    integrator=None,
    on_pass: Callable[[int, int], None] | None = None,
) -> RenderResult:
    """Render ``scene`` with ``spp`` samples per pixel in passes of ``spp_per_pass`` (None:
    :func:`default_spp_per_pass`); see the module docstring.

    ``on_pass(done_spp, total_spp)`` is called after each pass (the CLI's progress bar).
    Returns the sample-weighted mean of the passes (summed in float64) as a float32
    (H, W, C) tensor; NaN or infinite values (a plugin's bug) are set to 0 and counted in
    ``RenderResult.nonfinite``.
    """
    import drjit as dr
    import mitsuba as mi

    sizes = pass_sizes(spp, scene_spp_per_pass(scene, spp, spp_per_pass, sensor))
    accum = None  # flat float64 sum of the passes weighted by their spp
    shape = None
    done = 0
    start = time.perf_counter()
    with defer_sigint(stop_only=True) as stop:
        for index, n in enumerate(sizes):
            img = mi.render(
                scene, spp=n, seed=pass_seed(seed, index), sensor=sensor, integrator=integrator
            )
            n = scene_spp(scene, sensor)  # the count the sampler took
            if accum is None:
                shape = tuple(img.shape)
                accum = dr.opaque(mi.Float64, 0, dr.width(img.array))
            # an opaque weight: every pass (the remainder too) runs the same kernel
            accum = accum + mi.Float64(img.array) * dr.opaque(mi.Float64, n)
            dr.eval(accum)
            done += n
            if on_pass is not None:
                on_pass(done, spp)
            if stop.seen:
                break
        interrupted = stop.seen and done < spp
    mean = mi.Float(accum / dr.opaque(mi.Float64, done))
    bad = ~dr.isfinite(mean)
    mean = dr.select(bad, 0.0, mean)
    dr.eval(mean, bad)  # one kernel; ``seconds`` includes it
    nonfinite = int(dr.count(bad)[0])
    seconds = time.perf_counter() - start
    return RenderResult(mi.TensorXf(mean, shape), done, index + 1, seconds, interrupted,
                        nonfinite)
