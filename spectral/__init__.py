"""Colorimetry for spectrace: SPD -> CIE XYZ -> sRGB on numpy and colour-science.

Arrays of spectral values have the wavelength axis last and any leading shape; wavelengths
are in nm. CIE colour matching functions and illuminants come from colour-science's
datasets. Every function states its normalisation and scale in its docstring and is checked
against colour-science in tests/spectral/.

Modules: :mod:`.colorimetry` (SPD -> XYZ -> sRGB, adaptation, Planck, CCT, CRI, CIEDE2000),
:mod:`.image` (spectral images as one weight matrix), :mod:`.exr` (Fichet 2021 spectral
OpenEXR), :mod:`.datasets` (CSV files, colour-science datasets, Mitsuba spectra), :mod:`.srgb`
(the sRGB transfer function on numpy alone). Names are imported from their submodule on
first use, so ``import spectrace.spectral`` itself imports neither numpy nor colour-science.
"""

from __future__ import annotations

#: Public name -> the submodule that defines it; imported on first use (PEP 562), so that
#: ``spectrace.spectral.srgb`` (numpy only) can be used without importing colour-science.
_EXPORTS = {
    "apply_spectral_weights": "image",
    "blackbody": "colorimetry",
    "cct": "colorimetry",
    "chromatic_adaptation": "colorimetry",
    "CHROMATIC_ADAPTATION_METHODS": "colorimetry",
    "CIE_1931_2": "colorimetry",
    "CIE_1964_10": "colorimetry",
    "colorchecker": "datasets",
    "cri": "colorimetry",
    "decode_srgb": "srgb",
    "delta_e_2000": "colorimetry",
    "encode_srgb": "srgb",
    "illuminant": "datasets",
    "linear_srgb_to_xyz": "colorimetry",
    "load_spd": "datasets",
    "MITSUBA_WAVELENGTH_RANGE": "datasets",
    "OBSERVERS": "colorimetry",
    "read_spd_csv": "datasets",
    "read_spectral_exr": "exr",
    "spd_to_xyz": "colorimetry",
    "spectral_channel_name": "exr",
    "spectral_image_to_linear_srgb": "image",
    "spectral_image_to_xyz": "image",
    "to_mitsuba_spectrum": "datasets",
    "to_mitsuba_spectrum_xml": "datasets",
    "white_xyz": "colorimetry",
    "write_spectral_exr": "exr",
    "xyz_to_linear_srgb": "colorimetry",
    "xyz_to_srgb": "colorimetry",
    "xyz_weights": "colorimetry",
}


__all__ = [
    "apply_spectral_weights",
    "CHROMATIC_ADAPTATION_METHODS",
    "CIE_1931_2",
    "CIE_1964_10",
    "MITSUBA_WAVELENGTH_RANGE",
    "OBSERVERS",
    "blackbody",
    "cct",
    "chromatic_adaptation",
    "colorchecker",
    "cri",
    "decode_srgb",
    "delta_e_2000",
    "encode_srgb",
    "illuminant",
    "linear_srgb_to_xyz",
    "load_spd",
    "read_spd_csv",
    "read_spectral_exr",
    "spd_to_xyz",
    "spectral_channel_name",
    "spectral_image_to_linear_srgb",
    "spectral_image_to_xyz",
    "to_mitsuba_spectrum",
    "to_mitsuba_spectrum_xml",
    "white_xyz",
    "write_spectral_exr",
    "xyz_to_linear_srgb",
    "xyz_to_srgb",
    "xyz_weights",
]


#: The submodules, also reachable as attributes (``spectrace.spectral.colorimetry``).
_SUBMODULES = ("colorimetry", "datasets", "describe", "exr", "image", "srgb")


def __getattr__(name):
    import importlib

    if name in _SUBMODULES:
        return importlib.import_module(f"{__name__}.{name}")
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{module}"), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
