"""Colorimetry for spectrace: SPD -> CIE XYZ -> sRGB on numpy and colour-science."""
