"""Photometric units for spectrace's lights: from candela and lumens to W/sr and W.

Not a plugin: a helper module executed before the lights (see
``spectrace.plugins.PLUGIN_MODULES``). A light given in luminous units (``luminous_intensity``
in cd, ``luminous_flux`` in lm, or the candela of an IES/EULUMDAT file) emits the radiant
spectrum

    I_e(lambda) = I_v * s(lambda) / (K_m * integral V(lambda) s(lambda) dlambda),

with s the light's ``spectrum`` (any Mitsuba spectrum, evaluated as Mitsuba evaluates it),
V the CIE 1924 photopic luminous efficiency function and K_m = 683 lm/W. Then
K_m * integral V I_e dlambda = I_v: the light has exactly the luminous intensity asked for,
whatever the shape and scale of s. Equivalently I_e = I_v / K * s / integral s, with
K = K_m integral V s / integral s the luminous efficacy of the spectrum (lm/W).

RGB and monochrome variants have no wavelengths: there the spectrum is a colour c (linear
Rec. 709 RGB, or one value) and the photometric convention is

    I_e = I_v * c / (K_m * Y(c)),       Y(c) = 0.2126 R + 0.7152 G + 0.0722 B  (or c in mono),

so that K_m * Y(I_e) = I_v. The ``illuminance`` integrator reads lux back with the same
convention (K_m times the Y of the irradiance), so the photometric scale of a scene is the
same in every variant.

Data: V(lambda) is colour-science's ``SDS_LEFS_PHOTOPIC["CIE 1924 Photopic Standard
Observer"]`` (360-830 nm, 1 nm), imported only when a light in luminous units is loaded.
Sources: CIE 018:2019 "The basis of physical photometry"; CIE S 017:2020 (ILV) 17-21-050
(luminous efficacy of radiation).
"""

from __future__ import annotations

from functools import lru_cache

import drjit as dr
import mitsuba as mi
import numpy as np

#: K_m, the maximum luminous efficacy of photopic vision (lm/W), CIE 018:2019.
KM = 683.0
#: The wavelength grid (nm) on which spectra are integrated against V: 1 nm over
#: Mitsuba's spectral range.
GRID_NM = (360, 830)
#: Rec. 709 luminance weights of linear R, G, B (IEC 61966-2-1), as ``mi.luminance``.
LUMINANCE_WEIGHTS = (0.2126, 0.7152, 0.0722)
PHOTOPIC = "CIE 1924 Photopic Standard Observer"


@lru_cache(maxsize=1)
def photopic_efficiency() -> tuple[np.ndarray, np.ndarray]:
    """(wavelengths in nm, V) of the CIE 1924 photopic observer on the 1 nm grid, peak 1."""
    import colour

    wavelengths = np.arange(GRID_NM[0], GRID_NM[1] + 1, dtype=np.float64)
    sd = colour.colorimetry.SDS_LEFS_PHOTOPIC[PHOTOPIC]
    return wavelengths, np.asarray(sd[wavelengths], dtype=np.float64)


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


def evaluate_on_grid(texture) -> np.ndarray:
    """A spatially uniform spectrum texture on the 1 nm grid (spectral variants: shape (N,)),
    or its channels (RGB: (3,), mono: (1,))."""
    if mi.is_spectral:
        wavelengths = dr.arange(mi.Float, GRID_NM[0], GRID_NM[1] + 1)
        si = dr.zeros(mi.SurfaceInteraction3f, dr.width(wavelengths))
        si.wavelengths = mi.Spectrum(wavelengths, wavelengths, wavelengths, wavelengths)
        value = mi.unpolarized_spectrum(texture.eval(si))
        return np.asarray(value[0], dtype=np.float64)
    value = mi.unpolarized_spectrum(texture.eval(dr.zeros(mi.SurfaceInteraction3f)))
    return np.array([float(dr.slice(value[i])) for i in range(len(value))], dtype=np.float64)


def photometric_integral(texture) -> float:
    """integral V s dlambda (nm) of a spectrum texture in spectral variants; Y(c) of its
    colour in RGB variants; its value in monochrome variants."""
    values = evaluate_on_grid(texture)
    if mi.is_spectral:
        _, V = photopic_efficiency()
        return float(np.sum(V * values))  # 1 nm steps, V ~ 0 at both ends
    if mi.is_rgb:
        return float(np.dot(LUMINANCE_WEIGHTS, values[:3]))
    return float(values[0])


def watts_per_lumen(texture, plugin: str, name: str = "spectrum") -> float:
    """The factor F with I_e = I_v * F * s (see the module docstring): 1 / (K_m integral V s).

    Raises ``ValueError`` naming the parameter when the spectrum has no luminous content
    (it would need infinite power).
    """
    integral = photometric_integral(texture)
    if not integral > 0.0:
        raise ValueError(
            f"{plugin}: parameter '{name}' has no luminous content (integral of "
            f"V(lambda) s(lambda) is {integral:g}): a light in candela or lumens needs a "
            "spectrum that the eye can see"
        )
    return 1.0 / (KM * integral)


def luminous_efficacy(texture) -> float:
    """K = K_m integral V s / integral s (lm/W) of a spectrum (spectral variants only)."""
    if not mi.is_spectral:
        raise ValueError("the luminous efficacy of a spectrum needs a spectral variant")
    values = evaluate_on_grid(texture)
    return KM * photometric_integral(texture) / float(np.sum(values))
