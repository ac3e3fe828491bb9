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

Render until clean (the local loop): with ``noise=TARGET`` the loop stops at the first pass
after which the estimated relative error of the image (:func:`relative_error`, from the
spread between passes) is below TARGET, and with ``time_limit=SECONDS`` at the first pass
boundary after that wall time; ``spp`` is then the most it renders.

The local loop sums the passes in Dr.Jit (float64) and never imports numpy: a render's
pixels stay a Dr.Jit tensor (:attr:`RenderResult.pixels`) until someone asks for the numpy
array (:attr:`RenderResult.image`), so the command line starts as fast as ``mitsuba``.
The same loop with its passes on a Dask cluster is
:func:`spectrace.cluster.render_passes_distributed` (which builds on this module).
"""

from __future__ import annotations

import time
from collections.abc import Callable

from spectrace.errors import ParameterError
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
#: ``noise``: the estimate is trusted from this many passes on (the spread of fewer passes
#: says little: its relative uncertainty is about 1 / sqrt(2 (passes - 1))).
MIN_NOISE_PASSES = 8
#: ``noise`` or ``time_limit`` without ``spp``: the most samples per pixel it renders.
UNTIL_CLEAN_MAX_SPP = 2**16
#: A render's seed is stored in its EXR header as a 32-bit integer.
SEED_RANGE = (-(2**31), 2**31 - 1)


class RenderResult:
    """An averaged image and how it was made.

    ``pixels`` is the (H, W, C) float32 image with the film's channels, as made: a Dr.Jit
    tensor (``mi.TensorXf``) from the local loop, a numpy array from the distributed one.
    ``image`` is the same pixels as a numpy float32 array, converted on first access.
    """

    __slots__ = ("pixels", "spp", "passes", "seconds", "interrupted", "nonfinite", "noise",
                 "stopped_by", "_image", "light_groups")

    def __init__(self, pixels, spp: int, passes: int, seconds: float, interrupted: bool,
                 nonfinite: int = 0, noise: float | None = None, stopped_by: str = "spp"):
        self.pixels = pixels
        # the estimated relative error (:func:`relative_error`) when the loop measured it
        self.noise = noise
        self.stopped_by = stopped_by  # what ended the loop: "spp", "noise", "time", "interrupt"
        self.spp = spp  # samples per pixel actually rendered (less than asked if interrupted)
        self.passes = passes
        self.seconds = seconds
        self.interrupted = interrupted
        self.nonfinite = nonfinite  # pixel values that were NaN or infinite, set to 0
        self._image = None
        self.light_groups = None  # the group names of a light-group render (layers last)

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


def check_sample_counts(spp: int | None, spp_per_pass: int | None,
                        names: tuple[str, str] = ("spp", "spp_per_pass")) -> None:
    """ParameterError unless ``spp`` (None: the scene's own) and ``spp_per_pass`` (None: the
    default) are positive integers; ``names`` are what the message calls them (the command
    line gives its flags)."""
    for value, name in zip((spp, spp_per_pass), names, strict=True):
        if value is not None and not (_is_integer(value) and value > 0):
            raise ParameterError(f"{name} must be a positive integer (got {value!r})")


def _is_integer(value) -> bool:
    """An int (numpy's too), not a bool or a float such as 2.5 or 2.0."""
    import operator

    try:
        operator.index(value)
    except TypeError:
        return False
    return not isinstance(value, bool)


def check_seed(seed: int, option: str = "seed") -> int:
    """``seed`` as an int; ParameterError naming ``option`` unless it is an integer that fits
    the EXR header's 32-bit integer (:data:`SEED_RANGE`)."""
    low, high = SEED_RANGE
    if not _is_integer(seed):
        raise ParameterError(f"{option} must be an integer (got {seed!r})")
    if not low <= int(seed) <= high:
        raise ParameterError(f"{option} must be between {low} and {high} (got {seed}): it is "
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


def check_until_clean(noise: float | None, time_limit: float | None) -> None:
    """ParameterError unless ``noise`` (a relative error) and ``time_limit`` (seconds) are
    None or finite and positive (``noise`` below 1)."""
    if noise is not None and not (isinstance(noise, (int, float)) and 0 < noise < 1):
        raise ParameterError(f"render_passes: noise must be a relative error between 0 and 1, "
                             f"exclusive (got {noise!r})")
    if time_limit is not None and not (isinstance(time_limit, (int, float))
                                       and 0 < time_limit < float("inf")):
        raise ParameterError(f"render_passes: time_limit must be a positive number of seconds "
                             f"(got {time_limit!r})")


def relative_error(sum_w, sum_w2, done: int, passes: int):
    """The estimated relative RMS error of the mean image, from the spread between passes.

    Pass i holds n_i samples per pixel and has the image I_i; the render is the weighted
    mean M = sum n_i I_i / N (N = sum n_i). With independent passes (distinct seeds), each
    pixel value's per-sample variance is estimated without bias by
    s^2 = sum n_i (I_i - M)^2 / (P - 1) = (sum n_i I_i^2 - N M^2) / (P - 1) over the P
    passes, and the variance of M by s^2 / N. The image's relative error is the RMS of that
    standard error over every pixel and channel against the RMS of the image:

        e = sqrt(mean(s^2 / N)) / sqrt(mean(M^2)),

    the estimate of ||M - R|| / ||R|| for the converged image R (checked against a reference
    render in tests/cli/test_view_command.py). ``sum_w``, ``sum_w2``: the float64 sums
    sum n_i I_i and sum n_i I_i^2, flat Dr.Jit arrays (the local loop) or numpy arrays (what
    a distributed loop holds). Returns a Python float (inf with fewer than 2 passes or a
    black image)."""
    if passes < 2:
        return float("inf")
    mean = sum_w / done
    if type(sum_w).__module__.startswith("drjit"):
        import drjit as dr

        spread = dr.maximum(sum_w2 - mean * sum_w, 0.0)  # sum n_i (I_i - M)^2
        variance_of_mean = float(dr.sum(spread)[0]) / ((passes - 1) * done)
        power = float(dr.sum(mean * mean)[0])
    else:
        import numpy as np

        spread = np.maximum(sum_w2 - mean * sum_w, 0.0)
        variance_of_mean = float(spread.sum()) / ((passes - 1) * done)
        power = float((mean * mean).sum())
    if not power > 0:
        return float("inf")
    return (variance_of_mean / power) ** 0.5


def render_passes(
    scene,
    spp: int | None = None,
    seed: int = 0,
    spp_per_pass: int | None = None,
    sensor: int = 0,
    integrator=None,
    on_pass: Callable[[int, int], None] | None = None,
    noise: float | None = None,
    time_limit: float | None = None,
    on_noise: Callable[[float], None] | None = None,
    light_groups=None,
) -> RenderResult:
    """Render ``scene`` with ``spp`` samples per pixel in passes of ``spp_per_pass`` (None:
    :func:`default_spp_per_pass`); see the module docstring. A count that is not a positive
    integer, a seed beyond 32 bits or a film too large (:mod:`spectrace.memory`) is a
    :class:`~spectrace.errors.ParameterError` naming it.

    ``noise``: stop at the first pass (from the :data:`MIN_NOISE_PASSES`-th on) after which
    the estimated relative error (:func:`relative_error`) is below ``noise``;
    ``time_limit``: stop at the first pass that ends after ``time_limit`` seconds. With
    either, ``spp`` is the most it renders (None: :data:`UNTIL_CLEAN_MAX_SPP`); without,
    None means the scene's sample count. ``on_pass(done_spp, total_spp)`` is called after
    each pass (the CLI's progress bar), ``on_noise(estimate)`` too when ``noise`` is given.

    ``light_groups`` (True, ``{name: [emitter ids]}`` or ``["name=id1,id2", ...]``) renders
    with the ``lightgroups`` integrator in place of ``integrator`` (see
    :mod:`spectrace.lightgroups`): the pixels then end with three channels per group (N with
    spectral layers), whose names are the result's ``light_groups``
    (:func:`spectrace.lightgroups.split`).
    Returns the sample-weighted mean of the passes (summed in float64) as a float32
    (H, W, C) tensor; NaN or infinite values (a plugin's bug) are set to 0 and counted in
    ``RenderResult.nonfinite``; ``RenderResult.noise`` is the estimate when ``noise`` or
    ``time_limit`` was given.
    """
    import drjit as dr
    import mitsuba as mi

    check_until_clean(noise, time_limit)
    until_clean = noise is not None or time_limit is not None
    if spp is None:
        spp = UNTIL_CLEAN_MAX_SPP if until_clean else scene_spp(scene, sensor)
    check_sample_counts(spp, spp_per_pass)  # before the default pass size reads them
    seed, spp = check_seed(seed), int(spp)
    spp_per_pass = None if spp_per_pass is None else int(spp_per_pass)
    sizes = pass_sizes(spp, scene_spp_per_pass(scene, spp, spp_per_pass, sensor))
    if light_groups is not None:
        from spectrace.lightgroups import integrator_for

        integrator = integrator_for(scene, light_groups, integrator, sensor)
    from spectrace.memory import check_pass

    check_pass(scene, sizes[0], sensor)  # the film and a pass fit (32-bit arrays, memory)
    accum = None  # flat float64 sum of the passes weighted by their spp
    accum2 = None  # with until_clean: the same sum of the squared pass images
    shape = None
    done = 0
    estimate = None
    stopped_by = "spp"
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
                if until_clean:
                    accum2 = dr.opaque(mi.Float64, 0, dr.width(img.array))
            # an opaque weight: every pass (the remainder too) runs the same kernel
            weight = dr.opaque(mi.Float64, n)
            value = mi.Float64(img.array)
            accum = accum + value * weight
            if until_clean:
                accum2 = accum2 + value * value * weight
                dr.eval(accum, accum2)
            else:
                dr.eval(accum)
            done += n
            if until_clean:
                estimate = relative_error(accum, accum2, done, index + 1)
                if on_noise is not None and noise is not None:
                    on_noise(estimate)
            if on_pass is not None:
                on_pass(done, spp)
            if stop.seen:
                stopped_by = "interrupt"
                break
            if noise is not None and index + 1 >= MIN_NOISE_PASSES and estimate < noise:
                stopped_by = "noise"
                break
            if time_limit is not None and time.perf_counter() - start >= time_limit:
                stopped_by = "time"
                break
        interrupted = stop.seen and done < spp
    mean = mi.Float(accum / dr.opaque(mi.Float64, done))
    bad = ~dr.isfinite(mean)
    mean = dr.select(bad, 0.0, mean)
    dr.eval(mean, bad)  # one kernel; ``seconds`` includes it
    nonfinite = int(dr.count(bad)[0])
    seconds = time.perf_counter() - start
    result = RenderResult(mi.TensorXf(mean, shape), done, index + 1, seconds, interrupted,
                          nonfinite, estimate, stopped_by)
    if light_groups is not None:
        result.light_groups = list(integrator.names)
    return result
