"""Spectral against RGB rendering: the study of ``notebooks/spectral_vs_rgb.ipynb``.

All spectra are resampled to :data:`GRID` (1 nm, 360-830 nm, Mitsuba's spectral range) by
linear interpolation with constant end values (the convention of :mod:`spectrace.spectral`),
so the renderer, colour-science and this module see the same piecewise-linear functions.
A chart of diffuse patches is lit at normal incidence by a ``directional`` emitter of
irradiance pi * S(lambda), so a patch of reflectance rho(lambda) has radiance
rho(lambda) S(lambda) (Lambert: L = rho E / pi). The *reference* colour of a patch is
colour-science's XYZ of that radiance spectrum (emissive, X = sum rho S xbar / sum ybar,
1 nm). The *spectral render* carries the spectra; the *RGB render* gives Mitsuba the
light's and the patch's linear sRGB values, as an RGB renderer (or its user) would: the
patch's sRGB under D65 (the sRGB white) and the light's emitted colour, multiplied channel
by channel.

White balance: none. The rendered and the reference colours are the colours the
light-and-surface radiance has on an sRGB display (white D65), so a chart under illuminant
A looks orange, as in a photograph with daylight white balance. Each light is only
*exposed*: scaled so that a perfect white diffuser reaches 1 in its brightest linear sRGB
channel. Colour differences are CIEDE2000 in CIELAB relative to the sRGB white (D65,
Y = 1), computed from XYZ without clipping to the sRGB gamut.

Sources: CIE 015:2018 Colorimetry (XYZ, CIELAB); Sharma, Wu, Dalal (2005), "The CIEDE2000
color-difference formula" (CIEDE2000); CIE 13.3-1995 (colour rendering index); Wyszecki
and Stiles (1982), Color Science, 2nd ed. (metameric blacks).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import colour
import numpy as np

from spectrace import spectral
from spectrace.errors import ParameterError
from spectrace.spectral.colorimetry import check_spd
from spectrace.studies import budget, display, save_figure, text_table

__all__ = ["GRID", "LIGHTS", "OBSERVER", "ChartLayout", "ChartRenders", "albedo_rgb", "budget",
           "chart_scene", "colorchecker", "delta_e", "display", "emitted_rgb", "exposure", "lab",
           "light_spd", "metameric_black", "metameric_pair", "reference_xyz", "render_chart",
           "resample", "rgb_render_prediction", "save_figure", "srgb8", "text_table"]

#: Wavelength grid of the colour study (nm): Mitsuba's spectral range at 1 nm.
GRID = np.arange(360.0, 831.0, 1.0)
#: The observer of every colour computation here (and of Mitsuba's spectral film).
OBSERVER = "CIE 1931 2 Degree Standard Observer"


def resample(wavelengths, values, grid=GRID) -> np.ndarray:
    """``values`` (wavelength axis last) at ``grid``: linear, constant beyond the ends."""
    wl, v = check_spd(wavelengths, values, "resample")
    v = np.asarray(v, np.float64)
    flat = v.reshape(-1, wl.size)
    out = np.stack([np.interp(grid, wl, row) for row in flat])
    return out.reshape(v.shape[:-1] + (len(grid),))


# --------------------------------------------------------------------------- lights


def _blackbody(temperature: float) -> Callable[[], np.ndarray]:
    return lambda: spectral.blackbody(GRID, temperature)


def _cie(name: str) -> Callable[[], np.ndarray]:
    def spd():
        sd = colour.SDS_ILLUMINANTS[name]
        return resample(sd.wavelengths, sd.values)

    return spd


#: The lights of the colour study: label -> relative SPD on GRID (unscaled).
LIGHTS: Mapping[str, Callable[[], np.ndarray]] = {
    "D65": _cie("D65"),
    "A": _cie("A"),
    "FL2": _cie("FL2"),
    "FL11": _cie("FL11"),
    "LED-B3": _cie("LED-B3"),
    "blackbody 4000 K": _blackbody(4000.0),
}


def light_spd(name: str) -> np.ndarray:
    """The exposed SPD of light ``name`` on GRID: relative SPD times :func:`exposure`."""
    try:
        spd = LIGHTS[name]()
    except KeyError:
        raise KeyError(f"unknown light {name!r}; one of {', '.join(LIGHTS)}") from None
    return spd * exposure(spd)


def exposure(spd) -> float:
    """Scale that brings a perfect white diffuser's brightest linear sRGB channel to 1."""
    return 1.0 / float(np.max(emitted_rgb(spd)))


def emitted_rgb(spd) -> np.ndarray:
    """Linear sRGB of an emission spectrum on GRID (X = sum S xbar / sum ybar, no adaptation)."""
    return spectral.xyz_to_linear_srgb(spectral.spd_to_xyz(GRID, spd, observer=OBSERVER))


# --------------------------------------------------------------------------- reflectances


def colorchecker(chart: str = "ColorChecker N Ohta") -> tuple[list[str], np.ndarray]:
    """Patch names and reflectances (24, len(GRID)) of a colour-science ColorChecker."""
    sds = colour.SDS_COLOURCHECKERS[chart]
    names = list(sds)
    values = np.stack([resample(sds[n].wavelengths, sds[n].values) for n in names])
    return names, values


def albedo_rgb(reflectance) -> np.ndarray:
    """The sRGB albedo an RGB renderer gets for a reflectance: its colour under D65, linear.

    XYZ under D65 with a perfect white at Y = 1, then the sRGB matrix (D65 is sRGB's
    white, so no adaptation), clipped to [0, 1] as a texture would be.
    """
    xyz = spectral.spd_to_xyz(GRID, reflectance, illuminant="D65", observer=OBSERVER)
    return np.clip(spectral.xyz_to_linear_srgb(xyz), 0.0, 1.0)


def metameric_black(light: str = "D65", against: str = "A", channel: int | None = None):
    """A metameric black for ``light``: a spectrum b on GRID with XYZ(b under light) = 0.

    b is the part of the colour-matching functions weighted by ``against`` (one of its
    X, Y, Z rows, ``channel``; by default the one giving the largest b) that is orthogonal
    to the three XYZ weight vectors of ``light``: so adding b to a reflectance leaves its
    colour under ``light`` unchanged and changes it as much as possible under ``against``.
    Normalised to max |b| = 1.
    """
    w_light = spectral.xyz_weights(GRID, illuminant=_illuminant_arg(light), observer=OBSERVER)
    w_against = spectral.xyz_weights(GRID, illuminant=_illuminant_arg(against), observer=OBSERVER)
    q, _ = np.linalg.qr(w_light)  # orthonormal basis of the space a light "sees"
    candidates = [w_against[:, c] - q @ (q.T @ w_against[:, c]) for c in range(3)]
    if channel is None:
        channel = int(np.argmax([np.linalg.norm(c) / np.linalg.norm(w_against[:, i])
                                 for i, c in enumerate(candidates)]))
    b = candidates[channel]
    return b / np.max(np.abs(b))


def _illuminant_arg(name: str):
    return (GRID, LIGHTS[name]()) if name in LIGHTS else name


def metameric_pair(base, light: str = "D65", against: str = "A", margin: float = 0.02):
    """Two reflectances with the same colour under ``light``: ``base`` and base + t b.

    b is :func:`metameric_black` and t the largest amplitude keeping the second in
    [margin, 1 - margin]. Returns an array (2, len(GRID)).
    """
    base = np.asarray(base, np.float64)
    b = metameric_black(light, against)
    with np.errstate(divide="ignore"):
        up = np.where(b > 0, (1.0 - margin - base) / b, np.inf)
        down = np.where(b < 0, (margin - base) / b, np.inf)
    t = float(min(up.min(), down.min()))
    if t <= 0:
        raise ParameterError(
            "metameric_pair: base reflectance leaves no room in [margin, 1 - margin]")
    return np.stack([base, base + t * b])


# --------------------------------------------------------------------------- colours


def reference_xyz(reflectances, spd) -> np.ndarray:
    """colour-science's XYZ of the radiance rho * S of each reflectance under SPD S (GRID).

    Emissive integration at 1 nm: X = sum rho S xbar / sum ybar (``colour.sd_to_XYZ``,
    method "Integration", no illuminant, divided by 100). Shape (..., 3).
    """
    cmfs = colour.MSDS_CMFS[OBSERVER]
    radiance = np.asarray(reflectances, np.float64) * np.asarray(spd, np.float64)
    flat = radiance.reshape(-1, GRID.size)
    shape = colour.SpectralShape(GRID[0], GRID[-1], 1.0)
    out = [
        colour.sd_to_XYZ(colour.SpectralDistribution(row, shape), cmfs, method="Integration")
        / 100.0
        for row in flat
    ]
    return np.asarray(out).reshape(radiance.shape[:-1] + (3,))


def rgb_render_prediction(reflectances, spd) -> np.ndarray:
    """What an RGB renderer computes for each patch: albedo_rgb * emitted_rgb (linear sRGB)."""
    return albedo_rgb(reflectances) * emitted_rgb(spd)


def lab(xyz) -> np.ndarray:
    """CIELAB relative to the sRGB white (linear (1, 1, 1): D65 with Y = 1)."""
    white = spectral.linear_srgb_to_xyz(np.ones(3))
    return colour.XYZ_to_Lab(np.asarray(xyz, np.float64) / white[1], white[:2] / white.sum())


def delta_e(xyz_a, xyz_b) -> np.ndarray:
    """CIEDE2000 between XYZ colours (in CIELAB relative to the sRGB white, unclipped).

    Equals :func:`spectrace.spectral.delta_e_2000` on the encoded sRGB of colours inside
    the sRGB gamut; unlike it, also defined for colours outside (no clipping).
    """
    return np.asarray(colour.delta_E(lab(xyz_a), lab(xyz_b), method="CIE 2000"))


def srgb8(linear) -> list[str]:
    """Display sRGB of linear colours as 8-bit triples 'R G B' (clipped), for tables."""
    enc = np.round(display(linear) * 255).astype(int)
    return [" ".join(f"{v:3d}" for v in c) for c in np.atleast_2d(enc)]


# --------------------------------------------------------------------------- chart scene


@dataclass(frozen=True)
class ChartLayout:
    """Patches on a grid of ``cols`` columns, ``cell`` pixels apart, row by row from the top."""

    count: int
    cols: int = 6
    cell: int = 16
    fill: float = 0.75  # patch side / cell side

    @property
    def rows(self) -> int:
        return -(-self.count // self.cols)

    @property
    def size(self) -> tuple[int, int]:
        """Film (width, height) in pixels."""
        return self.cols * self.cell, self.rows * self.cell

    def centre(self, k: int) -> tuple[float, float]:
        """World (x, y) of patch k; one cell is one unit, the chart centred at the origin."""
        r, c = divmod(k, self.cols)
        return c + 0.5 - self.cols / 2, self.rows / 2 - r - 0.5

    def paint(self, colours) -> np.ndarray:
        """An image (H, W, C) of the chart with patch k filled with ``colours[k]``."""
        colours = np.asarray(colours, np.float64)
        width, height = self.size
        image = np.zeros((height, width, colours.shape[-1]))
        lo = int(round(self.cell * (1 - self.fill) / 2))
        for k, colour_k in enumerate(colours):
            r, c = divmod(k, self.cols)
            image[r * self.cell + lo:(r + 1) * self.cell - lo,
                  c * self.cell + lo:(c + 1) * self.cell - lo] = colour_k
        return image

    def means(self, image, inner: float = 0.5) -> np.ndarray:
        """Mean of each patch over its central ``inner`` fraction of the cell: (count, C)."""
        image = np.asarray(image, np.float64)
        half = max(1, int(round(self.cell * inner / 2)))
        out = []
        for k in range(self.count):
            r, c = divmod(k, self.cols)
            y, x = r * self.cell + self.cell // 2, c * self.cell + self.cell // 2
            out.append(image[y - half:y + half, x - half:x + half].reshape(-1, image.shape[-1])
                       .mean(axis=0))
        return np.asarray(out)


def chart_scene(reflectances, spd, rgb: bool, layout: ChartLayout | None = None,
                spp: int = 16) -> dict:
    """A Mitsuba scene dict (active variant) of diffuse patches under a directional light.

    ``reflectances`` (n, len(GRID)), ``spd`` (GRID): with ``rgb`` false the patches and
    the light carry the spectra (:func:`spectrace.spectral.to_mitsuba_spectrum`); with
    ``rgb`` true they carry :func:`albedo_rgb` and :func:`emitted_rgb` (an RGB renderer's
    inputs; render in ``llvm_ad_rgb``). The light's irradiance is pi * S at normal
    incidence, so a patch's radiance is rho * S. Orthographic camera (Mitsuba's maps
    [-1, 1] across the film's width and the same scale vertically), box filter, black
    background, ``direct`` integrator.
    """
    import mitsuba as mi

    reflectances = np.atleast_2d(np.asarray(reflectances, np.float64))
    layout = layout or ChartLayout(len(reflectances))
    width, height = layout.size
    T = mi.ScalarTransform4f
    if rgb:
        light = {"type": "rgb", "value": (math.pi * emitted_rgb(spd)).tolist()}
    else:
        light = spectral.to_mitsuba_spectrum(GRID, math.pi * np.asarray(spd, np.float64))
    scene = {
        "type": "scene",
        "integrator": {"type": "direct", "bsdf_samples": 0},
        "sensor": {
            "type": "orthographic",
            "to_world": T().look_at(origin=[0, 0, 2], target=[0, 0, 0], up=[0, 1, 0])
            @ T().scale([width / layout.cell / 2, width / layout.cell / 2, 1]),
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {"type": "hdrfilm", "width": width, "height": height,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        },
        "light": {"type": "directional", "direction": [0, 0, -1], "irradiance": light},
    }
    for k, rho in enumerate(reflectances):
        x, y = layout.centre(k)
        if rgb:
            reflectance = {"type": "rgb", "value": albedo_rgb(rho).tolist()}
        else:
            reflectance = spectral.to_mitsuba_spectrum(GRID, rho)
        scene[f"patch_{k:02d}"] = {
            "type": "rectangle",
            "to_world": T().translate([x, y, 0]) @ T().scale(layout.fill / 2),
            "bsdf": {"type": "diffuse", "reflectance": reflectance},
        }
    return scene


@dataclass
class ChartRenders:
    """A chart under one light: reference colours, spectral and RGB renders, patch colours."""

    light: str
    spd: np.ndarray  # exposed SPD on GRID
    layout: ChartLayout
    reference: np.ndarray  # (n, 3) XYZ, colour-science
    spectral_image: np.ndarray  # (H, W, 3) linear sRGB, llvm_ad_spectral
    rgb_image: np.ndarray  # (H, W, 3) linear sRGB, llvm_ad_rgb
    spectral_xyz: np.ndarray  # (n, 3) patch means
    rgb_xyz: np.ndarray

    @property
    def cri(self) -> float:
        """CIE 13.3 general colour rendering index Ra of the light."""
        return float(spectral.cri(GRID, self.spd))

    @property
    def delta_e_spectral(self) -> np.ndarray:
        return delta_e(self.spectral_xyz, self.reference)

    @property
    def delta_e_rgb(self) -> np.ndarray:
        return delta_e(self.rgb_xyz, self.reference)

    def reference_image(self) -> np.ndarray:
        """The reference colours painted in the chart layout (linear sRGB, black gaps)."""
        return self.layout.paint(spectral.xyz_to_linear_srgb(self.reference))


def render_chart(reflectances, light: str, spp: int = 64, layout: ChartLayout | None = None,
                 seed: int = 0) -> ChartRenders:
    """Render ``reflectances`` under ``light`` (a :data:`LIGHTS` name) spectrally and in RGB.

    Switches to ``llvm_ad_spectral`` then ``llvm_ad_rgb`` (:func:`spectrace.set_variant`)
    and renders :func:`chart_scene` in each with ``spp`` samples per pixel.
    """
    import spectrace

    reflectances = np.atleast_2d(np.asarray(reflectances, np.float64))
    layout = layout or ChartLayout(len(reflectances))
    spd = light_spd(light)
    images = {}
    for variant, rgb in (("llvm_ad_spectral", False), ("llvm_ad_rgb", True)):
        spectrace.set_variant(variant)
        import mitsuba as mi

        scene = mi.load_dict(chart_scene(reflectances, spd, rgb=rgb, layout=layout, spp=spp))
        images[variant] = spectrace.render(scene, spp=spp, seed=seed).image
    spectral_image, rgb_image = images["llvm_ad_spectral"], images["llvm_ad_rgb"]
    return ChartRenders(
        light, spd, layout, reference_xyz(reflectances, spd), spectral_image, rgb_image,
        spectral.linear_srgb_to_xyz(layout.means(spectral_image)),
        spectral.linear_srgb_to_xyz(layout.means(rgb_image)),
    )
