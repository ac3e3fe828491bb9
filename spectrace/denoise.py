"""Denoising of pictures with Intel Open Image Denoise (``pyoidn``), never of measurements.

:func:`render_features` renders the feature buffers that OIDN's ``RT`` filter takes
beside the noisy colour: the albedo and the shading normal (world space) of the first
surface each pixel sees, with Mitsuba's ``aov`` integrator through the scene's own sensor
and film (the same pixel filter). :func:`denoise_image` runs the filter (HDR colour,
prefiltered auxiliary images: ``clean_aux=False``). The denoised image is a picture: it
goes to ``OUT.denoised.exr`` and the PNG, the noisy EXR is kept, and ``lux`` or any
measurement never sees it. How much it helps, and where it loses against more samples, is
measured in ``benchmarks/bench_denoise.py``.

Source: Intel Open Image Denoise (Apache-2.0), https://www.openimagedenoise.org, through
the ``pyoidn`` binding.
"""

from __future__ import annotations

from spectrace.errors import ParameterError

#: The feature buffers are cheap (one bounce, no light): rendered at the beauty pass's spp
#: up to this many.
FEATURE_SPP = 64
#: Mitsuba's AOV names of the two buffers.
FEATURE_AOVS = "albedo:albedo,nn:sh_normal"


def check_denoiser():
    """The ``pyoidn`` module; ParameterError (one line) when it is not installed."""
    try:
        import pyoidn
    except ImportError:
        raise ParameterError("denoise: needs Intel Open Image Denoise's Python binding "
                             "(pip install pyoidn)") from None
    return pyoidn


def render_features(scene, spp: int, seed: int = 0, sensor: int = 0):
    """(albedo, normal), each (H, W, 3) float32 numpy, of the scene's first hits through
    its sensor ``sensor`` (``aov`` integrator, ``min(spp, FEATURE_SPP)`` samples per
    pixel); a mono variant's one-channel albedo as grey."""
    import mitsuba as mi
    import numpy as np

    from spectrace.images import as_rgb

    aov = mi.load_dict({"type": "aov", "aovs": FEATURE_AOVS})
    image = np.asarray(mi.render(scene, integrator=aov, sensor=sensor, seed=seed,
                                 spp=max(1, min(int(spp), FEATURE_SPP))), np.float32)
    albedo, normal = image[..., :-3], image[..., -3:]
    return (np.clip(as_rgb(albedo), 0.0, 1.0).astype(np.float32),
            np.clip(normal, -1.0, 1.0).astype(np.float32))


def denoise_image(rgb, albedo=None, normal=None):
    """The OIDN ``RT`` filter on an HDR linear (H, W, 3) image with optional feature
    buffers (normals only with an albedo, as OIDN requires); float32 numpy out. Negative
    values (none in a render) are clipped to 0 first: OIDN takes non-negative HDR."""
    import numpy as np

    pyoidn = check_denoiser()
    color = np.ascontiguousarray(np.maximum(np.asarray(rgb, np.float32), 0.0))
    if normal is not None and albedo is None:
        raise ParameterError("denoise_image: normal needs albedo (OIDN's RT filter)")
    out = pyoidn.denoise(color, albedo, normal, hdr=True)
    return np.asarray(out, np.float32)
