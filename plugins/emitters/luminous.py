"""``luminous``: photometric units of spectrace's lights (helper page, not a plugin).

A helper module executed before the lights (see ``spectrace.plugins.PLUGIN_MODULES``).
It turns the luminous quantities a lighting designer
works with, ``luminous_intensity`` in candela (cd = lm/sr) and ``luminous_flux`` in lumens
(lm), into the radiometric ones the renderer transports (W/sr, W), for ``pointlight``,
``spotlight`` and ``ieslight``. A light given in luminous units emits the radiant spectrum::

    I_e(lambda) = I_v s(lambda) / (K_m integral V(lambda) s(lambda) dlambda)

with s the light's ``spectrum`` (any Mitsuba spectrum, evaluated as Mitsuba evaluates it),
V the CIE photopic luminous efficiency function and K_m = 683 lm/W. Then
K_m * integral V I_e dlambda = I_v: the light has exactly the luminous intensity asked for,
whatever the shape and scale of s.

Parameters
----------

======================  ========  =======  ====  ================================================
parameter               type      default  unit  description
======================  ========  =======  ====  ================================================
``luminous_intensity``  float     --       cd    luminous intensity I_v (of ``pointlight``; on the
                                                 axis of ``spotlight``); >= 0 |exposed|
                                                 |differentiable|
``luminous_flux``       float     --       lm    luminous flux Phi_v over all the directions the
                                                 light emits into; >= 0 |exposed|
                                                 |differentiable|
``spectrum``            spectrum  d65      --    spectral shape s of the light (value, tabulated
                                                 SPD, ``blackbody``, ``d65``, RGB); its scale does
                                                 not matter; only with a luminous quantity
                                                 |exposed| |differentiable|
======================  ========  =======  ====  ================================================

These are parameters of the lights (see their own pages for the rest).

Formula
-------

Spectral variants: I_e = I_v s / (K_m integral V s dlambda), the integral a sum over the
1 nm grid 360-830 nm (V is below 4e-6 at both ends and outside). The luminous efficacy of
the spectrum is K = K_m integral V s / integral s (lm/W).

RGB and monochrome variants have no wavelengths: there the spectrum is a colour c (linear
Rec. 709 RGB, or one value). A colour stands for the spectra that Mitsuba's film maps to
it: a film's Y is the mean of ybar-weighted radiance, Y = integral ybar s / integral ybar,
so the colour c stands for spectra with integral V s dlambda = Y(c) integral V dlambda
(white 1 for the flat spectrum 1), and the photometric convention is::

    I_e = I_v c / (K_m Y(c) integral V dlambda),
    Y(c) = 0.2126 R + 0.7152 G + 0.0722 B  (or c in mono),   integral V dlambda = 106.857 nm

Reading lux back with the same convention (K_m integral V dlambda times the Y of the
irradiance in RGB and mono variants, as the ``illuminance`` integrator does; K_m integral
V E dlambda in spectral variants) gives the same photometric scale in every variant (100
cd at 1 m give 100 lux), and one scene renders the same image in RGB and spectral
variants, whether its lights are given in luminous or radiant units.

The factor 1 / (K_m integral V s) is computed with Dr.Jit from the spectrum's parameters,
so gradients with respect to ``spectrum`` keep the luminous quantity fixed.

Sources
-------

CIE (2019), CIE 018:2019 *The Basis of Physical Photometry*, 3rd ed. (K_m = 683 lm/W,
V(lambda)); CIE (2020), CIE S 017:2020 *ILV: International Lighting Vocabulary*, 17-21-050
(luminous efficacy of radiation); IEC (1999), IEC 61966-2-1 (the Rec. 709 luminance
weights). V(lambda) is colour-science's ``SDS_LEFS_PHOTOPIC["CIE 1924 Photopic Standard
Observer"]`` (Mansencal et al. (2023), colour-science), imported only when a light in
luminous units is loaded.

Example
-------

An 800 lm bulb of a warm 2700 K spectrum::

    <emitter type="pointlight">
        <point name="position" x="0" y="2.4" z="0"/>
        <float name="luminous_flux" value="800"/>
        <spectrum type="blackbody" name="spectrum">
            <float name="temperature" value="2700"/>
        </spectrum>
    </emitter>
"""

from __future__ import annotations

from functools import lru_cache
from typing import TYPE_CHECKING

import drjit as dr
import mitsuba as mi
from spectrace.spectral import srgb

from spectrace.errors import ParameterError

if TYPE_CHECKING:
    import numpy as np

#: K_m, the maximum luminous efficacy of photopic vision (lm/W), CIE 018:2019.
KM = 683.0
#: The wavelength grid (nm) on which spectra are integrated against V: 1 nm over
#: Mitsuba's spectral range.
GRID_NM = (360, 830)
#: Rec. 709 luminance weights of linear R, G, B (IEC 61966-2-1), as ``mi.luminance``.
LUMINANCE_WEIGHTS = srgb.LUMINANCE_WEIGHTS
PHOTOPIC = "CIE 1924 Photopic Standard Observer"


def _photopic_cache():
    """Where V on the 1 nm grid is kept between runs: the user's cache folder
    (``$XDG_CACHE_HOME`` or ``~/.cache``)/spectrace, the file named after the installed
    colour-science (its path and modification time), so that another colour-science
    recomputes it."""
    import hashlib
    import importlib.util
    import os

    from spectrace.plugins.cache import cache_folder

    spec = importlib.util.find_spec("colour")
    if spec is None or spec.origin is None:
        return None
    key = f"{spec.origin}:{os.stat(spec.origin).st_mtime_ns}:{PHOTOPIC}:{GRID_NM}"
    digest = hashlib.sha1(key.encode()).hexdigest()[:16]
    return cache_folder() / f"photopic-{digest}.npy"


@lru_cache(maxsize=1)
def photopic_efficiency() -> tuple[np.ndarray, np.ndarray]:
    """(wavelengths in nm, V) of the CIE 1924 photopic observer on the 1 nm grid, peak 1,
    from colour-science's dataset. colour-science takes a second or two to import, longer
    than a small render, so the values are kept in the user's cache folder after the first
    run (:func:`_photopic_cache`; written atomically, skipped when it cannot be written)."""
    import numpy as np

    wavelengths = np.arange(GRID_NM[0], GRID_NM[1] + 1, dtype=np.float64)
    cache = _photopic_cache()
    if cache is not None:
        try:
            V = np.load(cache)
            if V.shape == wavelengths.shape and np.all(np.isfinite(V)):
                return wavelengths, V
        except (OSError, ValueError):
            pass
    import colour

    sd = colour.colorimetry.SDS_LEFS_PHOTOPIC[PHOTOPIC]
    V = np.asarray(sd[wavelengths], dtype=np.float64)
    if cache is not None:
        from spectrace.images import atomic_path

        try:
            cache.parent.mkdir(parents=True, exist_ok=True)
            with atomic_path(cache) as tmp, open(tmp, "wb") as f:
                np.save(f, V)
        except OSError:
            pass
    return wavelengths, V


def photopic_spectrum():
    """V(lambda) as a Mitsuba ``regular`` spectrum texture (spectral variants), for kernels
    that weight sampled wavelengths by V."""
    wavelengths, V = photopic_efficiency()
    return mi.load_dict({
        "type": "regular",
        "wavelength_min": float(wavelengths[0]),
        "wavelength_max": float(wavelengths[-1]),
        "values": ", ".join(f"{v:.9g}" for v in V),
    })


def grid_interaction():
    """A surface interaction at rest whose wavelengths are the 1 nm grid (spectral
    variants: one lane per wavelength), or a single lane (RGB and mono variants)."""
    if not mi.is_spectral:
        return dr.zeros(mi.SurfaceInteraction3f)
    wavelengths = dr.arange(mi.Float, GRID_NM[0], GRID_NM[1] + 1)
    si = dr.zeros(mi.SurfaceInteraction3f, dr.width(wavelengths))
    si.wavelengths = mi.UnpolarizedSpectrum(wavelengths)
    return si


def evaluate_on_grid(texture) -> np.ndarray:
    """A spatially uniform spectrum texture on the 1 nm grid (spectral variants: shape (N,)),
    or its channels (RGB: (3,), mono: (1,))."""
    import numpy as np

    value = mi.unpolarized_spectrum(texture.eval(grid_interaction()))
    if mi.is_spectral:
        return np.asarray(value[0], dtype=np.float64)
    return np.array([float(dr.slice(value[i])) for i in range(len(value))], dtype=np.float64)


@lru_cache(maxsize=1)
def v_integral() -> float:
    """integral V dlambda (nm) over the 1 nm grid: 106.857 nm, the photometric integral that
    a colour of luminance 1 stands for in RGB and mono variants (see the module page)."""
    import numpy as np

    return float(np.sum(photopic_efficiency()[1]))


def luminance(value):
    """The luminance Y of a colour (Dr.Jit): Rec. 709 weights in RGB variants, the value in
    mono variants."""
    if mi.is_rgb:
        r, g, b = LUMINANCE_WEIGHTS
        return r * value[0] + g * value[1] + b * value[2]
    return value[0]


def photometric_integral_dr(texture) -> mi.Float:
    """integral V s dlambda (nm) as a Dr.Jit Float of width 1, differentiable with respect
    to the texture's parameters: the 1 nm sum in spectral variants, Y(c) integral V dlambda
    in RGB and mono variants (the convention of the module page)."""
    value = mi.unpolarized_spectrum(texture.eval(grid_interaction()))
    if mi.is_spectral:
        _, V = photopic_efficiency()
        return dr.sum(value[0] * mi.Float(V))  # 1 nm steps, V ~ 0 at both ends
    return mi.Float(luminance(value) * v_integral())


def illuminance_lux(E, weight=None):
    """K_m integral V E dlambda (lux) of an irradiance E (W/m^2 per nm, Dr.Jit): in spectral
    variants the mean over the sampled wavelengths of E * ``weight`` (V / pdf); in RGB and
    mono variants K_m Y(E) integral V dlambda (the convention of the module page)."""
    E = mi.unpolarized_spectrum(E)
    if mi.is_spectral:
        return KM * dr.mean(E * weight, axis=0)
    return (KM * v_integral()) * luminance(E)


def photometric_integral(texture) -> float:
    """integral V s dlambda (nm) of a spectrum texture in spectral variants; Y(c) integral
    V dlambda of its colour in RGB and mono variants."""
    return float(dr.slice(dr.detach(photometric_integral_dr(texture))))


def check_luminous_content(texture, plugin: str, name: str = "spectrum") -> float:
    """integral V s of ``texture``; raises ``ValueError`` naming the parameter when it is
    not positive (a light of that spectrum would need infinite power per lumen)."""
    integral = photometric_integral(texture)
    if not integral > 0.0:
        raise ParameterError(
            f"{plugin}: parameter '{name}' has no luminous content (integral of "
            f"V(lambda) s(lambda) is {integral:g}): a light in candela or lumens needs a "
            "spectrum that the eye can see"
        )
    return integral


def watts_per_lumen(texture, plugin: str, name: str = "spectrum") -> float:
    """The factor F with I_e = I_v * F * s (see the module docstring): 1 / (K_m integral V s).

    Raises ``ValueError`` naming the parameter when the spectrum has no luminous content
    (it would need infinite power).
    """
    return 1.0 / (KM * check_luminous_content(texture, plugin, name))


def watts_per_lumen_dr(texture) -> mi.Float:
    """1 / (K_m integral V s) as a differentiable Dr.Jit Float (no check: call
    :func:`watts_per_lumen` or :func:`check_luminous_content` first)."""
    return dr.rcp(KM * photometric_integral_dr(texture))


def luminous_efficacy(texture) -> float:
    """K = K_m integral V s / integral s (lm/W) of a spectrum (spectral variants only):
    colour-science's ``luminous_efficacy`` of the spectrum evaluated on the 1 nm grid (the
    same V(lambda), K_m = its ``CONSTANT_K_M`` = KM; trapezoidal integrals).
    colour-science is imported here, when the function is called: the renderer's own
    conversion (:func:`watts_per_lumen_dr`) stays in Dr.Jit, where it is differentiable
    with respect to the spectrum."""
    import colour
    import numpy as np

    from spectrace.errors import ParameterError

    if not mi.is_spectral:
        raise ParameterError("luminous_efficacy: the luminous efficacy of a spectrum needs a "
                             "spectral variant")
    wavelengths = np.arange(GRID_NM[0], GRID_NM[1] + 1, dtype=np.float64)
    sd = colour.SpectralDistribution(evaluate_on_grid(texture), wavelengths)
    return float(colour.luminous_efficacy(sd, colour.colorimetry.SDS_LEFS_PHOTOPIC[PHOTOPIC]))
