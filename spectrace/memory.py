"""What a render pass or a furnace measurement needs, checked before it starts.

A film of ``-D res=100000`` ended in ``Tensor(): invalid size``, ``res=30000`` in a
floating-point exception (exit 136) and ``res=20000`` in the kernel's OOM killer after
24 GB. Two limits apply:

* Dr.Jit indexes an array with 32-bit integers: an array holds fewer than
  :data:`MAX_ARRAY_WIDTH` entries. The film's storage (pixels x channels), the developed
  image and a pass's samples (pixels x spp per pass) are such arrays.
* The pixel buffers of one pass must fit in the memory available: the film's storage
  (its channels, alpha and weight in float32), the developed image (float32), and the pass
  loop's float64 sum and its float64 copy of the pass, then the float32 mean
  (:data:`PIXEL_BUFFERS`). The LLVM backend keeps none of a pass's samples in memory
  (:mod:`spectrace.passes`), so the samples count only against the 32-bit limit.

Each check raises :class:`~spectrace.errors.ParameterError` naming the film size, what it
needs and what is there, before anything is allocated.
"""

from __future__ import annotations

import os

from spectrace.errors import ParameterError

#: Dr.Jit's arrays are indexed by 32-bit unsigned integers.
MAX_ARRAY_WIDTH = 2**32 - 1
#: Bytes per developed channel of a pixel that one pass holds at once: the developed image
#: (float32), the float64 copy of it, the float64 sum, the float32 mean.
PIXEL_BUFFERS = 4 + 8 + 8 + 4
#: The film's storage per pixel: its channels plus alpha and weight, float32.
STORAGE_EXTRA_CHANNELS = 2
#: Bytes per furnace sample held at once: the surface interaction, the sampled direction,
#: the BSDF weight (about 60 float32 in all) and the weights as float64 in numpy.
FURNACE_SAMPLE_BYTES = 60 * 4 + 3 * 8


def available_bytes() -> int:
    """The memory a new allocation can have: Linux's MemAvailable, else the physical memory."""
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return 2**63  # unknown: no memory limit is checked


def _size(n: float) -> str:
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if n < 1024 or unit == "PiB":
            return f"{n:.3g} {unit}"
        n /= 1024
    return f"{n:.3g} PiB"


def film_channels(scene, sensor=0) -> int:
    """The channels the sensor's film develops: its own (3 for RGB, N bands for a spectral
    film) and the integrator's AOVs."""
    sensor = scene.sensors()[sensor] if isinstance(sensor, int) else sensor
    integrator = scene.integrator()
    aovs = len(integrator.aov_names()) if integrator is not None else 0
    return int(sensor.film().base_channels_count()) + aovs


def check_pass(scene, spp_per_pass: int, sensor=0, available: int | None = None,
               name: str = "spp_per_pass") -> None:
    """ParameterError unless a pass of ``spp_per_pass`` samples per pixel over the film of
    ``sensor`` stays within Dr.Jit's array size and the available memory (module docstring);
    ``available`` (bytes) defaults to :func:`available_bytes`; ``name`` is what the message
    calls ``spp_per_pass`` (the command line gives its flag)."""
    sensor = scene.sensors()[sensor] if isinstance(sensor, int) else sensor
    film = sensor.film()
    width, height = (int(v) for v in film.crop_size())
    border = 0
    if film.sample_border():
        border = int(film.rfilter().border_size())
    pixels = (width + 2 * border) * (height + 2 * border)
    channels = film_channels(scene, sensor)
    storage = pixels * (channels + STORAGE_EXTRA_CHANNELS)
    film_text = f"a {width}x{height} film of {channels} channels"
    if storage > MAX_ARRAY_WIDTH:
        raise ParameterError(
            f"{film_text} holds {storage:.3g} values, more than the {MAX_ARRAY_WIDTH + 1:.3g} "
            "of a Dr.Jit array: render a smaller film (width x height)")
    samples = width * height * spp_per_pass
    if samples > MAX_ARRAY_WIDTH:
        most = MAX_ARRAY_WIDTH // max(1, width * height)
        fix = f"use {name} <= {most}" if most else "render a smaller film"
        raise ParameterError(
            f"{name} {spp_per_pass} over {film_text} makes {samples:.3g} samples in a "
            f"pass, more than the {MAX_ARRAY_WIDTH + 1:.3g} of a Dr.Jit array: {fix}")
    need = storage * 4 + width * height * channels * PIXEL_BUFFERS
    have = available_bytes() if available is None else available
    if need > have:
        raise ParameterError(
            f"{film_text} needs about {_size(need)} of memory for a pass, and "
            f"{_size(have)} is available: render a smaller film (width x height)")


def check_furnace(samples: int, angles: int, available: int | None = None) -> None:
    """ParameterError unless ``samples`` per angle at ``angles`` angles, all drawn at once,
    stay within Dr.Jit's array size and the available memory."""
    n = samples * angles
    if n > MAX_ARRAY_WIDTH:
        raise ParameterError(
            f"samples {samples} at {angles} angles make {n:.3g} samples, more than the "
            f"{MAX_ARRAY_WIDTH + 1:.3g} of a Dr.Jit array: use samples <= "
            f"{MAX_ARRAY_WIDTH // max(1, angles)}")
    need = n * FURNACE_SAMPLE_BYTES
    have = available_bytes() if available is None else available
    if need > have:
        raise ParameterError(
            f"samples {samples} at {angles} angles need about {_size(need)} of memory, and "
            f"{_size(have)} is available: use fewer samples")
