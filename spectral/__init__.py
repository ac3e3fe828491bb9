"""Colorimetry for spectrace: SPD -> CIE XYZ -> sRGB on numpy and colour-science.

Arrays of spectral values have the wavelength axis last and any leading shape; wavelengths
are in nm. CIE colour matching functions and illuminants come from colour-science's
datasets. Every function states its normalisation and scale in its docstring and is checked
against colour-science in tests/spectral/.

Modules: :mod:`.colorimetry` (SPD -> XYZ -> sRGB, adaptation, Planck, CCT, CRI, CIEDE2000),
:mod:`.image` (spectral images as one weight matrix), :mod:`.exr` (Fichet 2021 spectral
OpenEXR), :mod:`.datasets` (CSV files, colour-science datasets, Mitsuba spectra).
"""

from .colorimetry import (
    CHROMATIC_ADAPTATION_METHODS,
    CIE_1931_2,
    CIE_1964_10,
    OBSERVERS,
    blackbody,
    cct,
    chromatic_adaptation,
    cri,
    decode_srgb,
    delta_e_2000,
    encode_srgb,
    linear_srgb_to_xyz,
    spd_to_xyz,
    white_xyz,
    xyz_to_linear_srgb,
    xyz_to_srgb,
    xyz_weights,
)
from .datasets import (
    MITSUBA_WAVELENGTH_RANGE,
    colorchecker,
    illuminant,
    load_spd,
    read_spd_csv,
    to_mitsuba_spectrum,
    to_mitsuba_spectrum_xml,
)
from .exr import read_spectral_exr, spectral_channel_name, write_spectral_exr
from .image import apply_spectral_weights, spectral_image_to_linear_srgb, spectral_image_to_xyz

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
