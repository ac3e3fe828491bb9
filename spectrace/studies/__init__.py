"""Library code of the study notebooks (``notebooks/*.ipynb``): scenes, conversions, measurements.

The notebooks only plot; everything they compute comes from here, so that it is tested
(``tests/test_studies.py``) and shared.

Spectral against RGB rendering (``spectral_vs_rgb.ipynb``)
    All spectra are resampled to :data:`GRID` (1 nm, 360-830 nm, Mitsuba's spectral
    range) by linear interpolation with constant end values (the convention of
    :mod:`spectrace.spectral`), so the renderer, colour-science and this module see the
    same piecewise-linear functions. A chart of diffuse patches is lit at normal incidence
    by a ``directional`` emitter of irradiance pi * S(lambda), so a patch of reflectance
    rho(lambda) has radiance rho(lambda) S(lambda) (Lambert: L = rho E / pi). The
    *reference* colour of a patch is colour-science's XYZ of that radiance spectrum
    (emissive, X = sum rho S xbar / sum ybar, 1 nm). The *spectral render* carries the
    spectra; the *RGB render* gives Mitsuba the light's and the patch's linear sRGB values,
    as an RGB renderer (or its user) would: the patch's sRGB under D65 (the sRGB white)
    and the light's emitted colour, multiplied channel by channel.

    White balance: none. The rendered and the reference colours are the colours the
    light-and-surface radiance has on an sRGB display (white D65), so a chart under
    illuminant A looks orange, as in a photograph with daylight white balance. Each light
    is only *exposed*: scaled so that a perfect white diffuser reaches 1 in its brightest
    linear sRGB channel. Colour differences are CIEDE2000 in CIELAB relative to the sRGB
    white (D65, Y = 1), computed from XYZ without clipping to the sRGB gamut.

Phong against energy-conserving BSDFs (``phong_vs_energy.ipynb``)
    :func:`albedo_curves`: directional albedo (white furnace, :mod:`spectrace.furnace`)
    of a family of BSDFs over incident angles.

Light falloff (``light_falloff.ipynb``)
    Closed-form distance laws and cone falloffs (:data:`DISTANCE_LAWS`,
    :data:`CONE_FALLOFFS`, written from the formulas independently of the plugins so that
    the renders can be checked against them) and :func:`floor_irradiance`: a light above a
    white Lambertian floor seen from straight above by an orthographic camera, whose pixels
    give the irradiance E = pi L / rho along the floor.

Size: :func:`budget` shrinks resolutions and sample counts when the environment
variable ``SPECTRACE_QUICK`` is ``1`` (what the notebook tests set).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import colour
import numpy as np

from spectrace import spectral
from spectrace.spectral.colorimetry import check_spd

# --------------------------------------------------------------------------- general

#: Wavelength grid of the colour study (nm): Mitsuba's spectral range at 1 nm.
GRID = np.arange(360.0, 831.0, 1.0)
#: The observer of every colour computation here (and of Mitsuba's spectral film).
OBSERVER = "CIE 1931 2 Degree Standard Observer"
#: Environment variable: "1" renders the notebooks at test size.
QUICK_ENV = "SPECTRACE_QUICK"


def quick() -> bool:
    """Whether the notebooks should render at test size (``SPECTRACE_QUICK=1``)."""
    return os.environ.get(QUICK_ENV, "") == "1"


def budget(normal: int, small: int) -> int:
    """``small`` when :func:`quick`, else ``normal``: resolutions and sample counts."""
    return small if quick() else normal


def scene_path(name: str) -> Path:
    """Path of ``scenes/<name>`` (``.xml`` added when missing); FileNotFoundError if absent."""
    from spectrace import scenes

    path = scenes.path(name)
    if not path.is_file():
        raise FileNotFoundError(f"no scene {path}")
    return path


def resample(wavelengths, values, grid=GRID) -> np.ndarray:
    """``values`` (wavelength axis last) at ``grid``: linear, constant beyond the ends."""
    wl, v = check_spd(wavelengths, values, "resample")
    v = np.asarray(v, np.float64)
    flat = v.reshape(-1, wl.size)
    out = np.stack([np.interp(grid, wl, row) for row in flat])
    return out.reshape(v.shape[:-1] + (len(grid),))


def display(linear) -> np.ndarray:
    """Encoded sRGB of a linear sRGB image, clipped to [0, 1] first (what imshow shows)."""
    return spectral.encode_srgb(np.clip(np.asarray(linear, np.float64), 0.0, 1.0))


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
        raise ValueError("metameric_pair: base reflectance leaves no room in [margin, 1 - margin]")
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


def text_table(header: Sequence[str], rows: Sequence[Sequence]) -> str:
    """A plain-text table: columns right-aligned (numbers formatted by the caller)."""
    cells = [list(map(str, header))] + [list(map(str, r)) for r in rows]
    widths = [max(len(r[j]) for r in cells) for j in range(len(header))]
    lines = ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in cells]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def srgb8(linear) -> list[str]:
    """Display sRGB of linear colours as 8-bit triples 'R G B' (clipped), for tables."""
    enc = np.round(display(linear) * 255).astype(int)
    return [" ".join(f"{v:3d}" for v in c) for c in np.atleast_2d(enc)]


# --------------------------------------------------------------------------- Phong vs energy


def beckmann_alpha(exponent) -> np.ndarray:
    """Beckmann roughness matching a Blinn-Phong exponent: alpha = sqrt(2 / (m + 2)).

    Walter et al., "Microfacet models for refraction through rough surfaces", EGSR 2007.
    """
    return np.sqrt(2.0 / (np.asarray(exponent, np.float64) + 2.0))


#: The BSDF families of the energy study: label -> exponent m -> Mitsuba BSDF dict. The
#: Phong lobes are pure (rho = 0, rho_s = 1) so their albedo is the lobe's; roughplastic
#: is a white plastic (diffuse 1) of matching Beckmann roughness; roughconductor a perfect
#: (reflectance 1) rough mirror, the microfacet counterpart of a pure lobe.
ENERGY_FAMILIES: Mapping[str, Callable[[float], dict]] = {
    "classic Phong": lambda m: {"type": "phong", "exponent": float(m), "normalized": False,
                                "diffuse_reflectance": 0.0, "specular_reflectance": 1.0},
    "normalized Phong": lambda m: {"type": "phong", "exponent": float(m), "normalized": True,
                                   "diffuse_reflectance": 0.0, "specular_reflectance": 1.0},
    "normalized Blinn-Phong": lambda m: {"type": "blinnphong", "exponent": float(m),
                                         "normalized": True, "diffuse_reflectance": 0.0,
                                         "specular_reflectance": 1.0},
    "roughplastic (white)": lambda m: {"type": "roughplastic", "distribution": "beckmann",
                                       "alpha": float(beckmann_alpha(m)),
                                       "diffuse_reflectance": 1.0},
    "roughconductor (perfect)": lambda m: {"type": "roughconductor", "distribution": "beckmann",
                                           "alpha": float(beckmann_alpha(m)),
                                           "material": "none"},
}


def albedo_curves(exponents: Sequence[float], angles, families=None, samples: int = 1 << 16,
                  seed: int = 0) -> dict[str, np.ndarray]:
    """Directional albedo (white furnace) per family: label -> array (len(exponents), len(angles)).

    Under the active variant; the mean over channels (RGB) or wavelengths (spectral) of
    :func:`spectrace.furnace.directional_albedo` with ``samples`` per angle.
    """
    from spectrace.furnace import directional_albedo

    families = ENERGY_FAMILIES if families is None else families
    out = {}
    for label, make in families.items():
        rows = [directional_albedo(make(m), angles, samples, seed).albedo.mean(axis=1)
                for m in exponents]
        out[label] = np.asarray(rows)
    return out


def classic_phong_albedo_normal(exponent) -> np.ndarray:
    """Albedo of the classic Phong lobe (r.v)^m at normal incidence: 2 pi / (m + 2)."""
    return 2.0 * np.pi / (np.asarray(exponent, np.float64) + 2.0)


# --------------------------------------------------------------------------- light falloff


def _inverse_square(r, **_):
    return 1.0 / np.square(r)


def _inverse_square_epsilon(r, epsilon=0.01, **_):
    return 1.0 / np.square(r + epsilon)


def _polynomial(r, kc=0.0, kl=0.0, kq=1.0, **_):
    return 1.0 / (kc + kl * r + kq * np.square(r))


def _windowed(r, radius=1.0, epsilon=0.01, **_):
    window = np.square(np.clip(1.0 - (r / radius) ** 4, 0.0, 1.0))
    return window / np.maximum(np.square(r), epsilon**2)


def _none(r, **_):
    return np.ones_like(np.asarray(r, np.float64))


#: Distance laws of the lights' ``falloff`` parameter (DESIGN.md), closed form in numpy:
#: name -> f(r, **parameters), the factor with E = I f(r) on a surface facing the light.
DISTANCE_LAWS: Mapping[str, Callable[..., np.ndarray]] = {
    "inverse_square": _inverse_square,
    "inverse_square_epsilon": _inverse_square_epsilon,
    "polynomial": _polynomial,
    "windowed": _windowed,
    "none": _none,
}


def _cone_t(alpha, umbra, penumbra):
    cu, cp = np.cos(np.radians(umbra)), np.cos(np.radians(penumbra))
    return np.clip((np.cos(alpha) - cu) / (cp - cu), 0.0, 1.0)


def _quadratic(alpha, umbra, penumbra):
    return np.square(_cone_t(alpha, umbra, penumbra))


def _smoothstep(alpha, umbra, penumbra):
    t = _cone_t(alpha, umbra, penumbra)
    return t * t * (3.0 - 2.0 * t)


def _linear_angle(alpha, umbra, penumbra):
    u, p = np.radians(umbra), np.radians(penumbra)
    return np.clip((u - np.asarray(alpha, np.float64)) / (u - p), 0.0, 1.0)


#: Cone falloffs of ``spotlight`` (DESIGN.md): name -> f(alpha in rad, umbra deg, penumbra
#: deg) in [0, 1]: 1 inside the penumbra half-angle, 0 outside the umbra half-angle.
CONE_FALLOFFS: Mapping[str, Callable[..., np.ndarray]] = {
    "quadratic": _quadratic,
    "smoothstep": _smoothstep,
    "linear_angle": _linear_angle,
}


@dataclass
class FloorProfile:
    """Irradiance on the floor along the line y = 0 through the light's foot point."""

    x: np.ndarray  # floor position of each pixel centre (m)
    measured: np.ndarray  # E = pi Y / rho from the render (W/m^2 per unit intensity)
    expected: np.ndarray  # I f(r) cone(alpha) cos(theta), the formula
    image: np.ndarray  # the whole render (H, W, 3), linear sRGB


#: Reflectance of the measurement floor.
FLOOR_ALBEDO = 0.5
#: Formula samples per pixel side when averaging it over a pixel's footprint.
SUBPIXELS = 8


def floor_irradiance(light: Mapping, height: float = 1.0, half_width: float = 5.0,
                     res: int = 128, spp: int = 4, cone: tuple | None = None) -> FloorProfile:
    """Render a light ``height`` m above a Lambertian floor (reflectance 0.5) from straight above.

    ``light``: the emitter's parameters besides its placement (``type`` ``pointlight``,
    ``spotlight`` or Mitsuba's ``point`` / ``spot``, a scalar ``intensity`` I, ``falloff``
    and its parameters, the cone parameters); it is put at (0, 0, height), a spot pointing
    straight down. The floor z = 0 is seen by an orthographic camera over
    [-half_width, half_width]^2 with the ``direct`` integrator, so a pixel's luminance is
    Y = rho E / pi and the measured irradiance is E = pi Y / rho. Expected along y = 0:
    E = I f(r) cone(alpha) cos(theta) with r = sqrt(x^2 + h^2), cos(theta) = h / r and
    alpha = theta for a spot (``cone`` = (name, umbra, penumbra) to include it; taken from
    ``light`` by default), averaged over each pixel's footprint. Works in RGB and spectral
    variants (Y of a constant spectrum c is c).
    """
    import mitsuba as mi

    T = mi.ScalarTransform4f
    light = dict(light)
    if light.get("type") in ("spotlight", "spot"):
        light["to_world"] = T().look_at(origin=[0, 0, height], target=[0, 0, 0], up=[0, 1, 0])
        if cone is None and light["type"] == "spotlight":
            cone = (light.get("cone_falloff", "quadratic"), light.get("umbra_angle", 30.0),
                    light.get("penumbra_angle", 20.0))
        elif cone is None:  # Mitsuba's spot: linear in the angle, beam_width = 3/4 cutoff
            cutoff = light.get("cutoff_angle", 20.0)
            cone = ("linear_angle", cutoff, light.get("beam_width", 0.75 * cutoff))
    else:
        light["position"] = [0.0, 0.0, float(height)]
    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "direct", "bsdf_samples": 0},
        "sensor": {
            "type": "orthographic",
            "to_world": T().look_at(origin=[0, 0, height + 1.0], target=[0, 0, 0], up=[0, 1, 0])
            @ T().scale([half_width, half_width, 1]),
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {"type": "hdrfilm", "width": res, "height": res,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        },
        "floor": {"type": "rectangle", "to_world": T().scale(2.0 * half_width),
                  "bsdf": {"type": "diffuse", "reflectance": FLOOR_ALBEDO}},
        "light": light,
    })
    from spectrace import render

    image = render(scene, spp=spp, seed=0).image
    luminance = spectral.linear_srgb_to_xyz(np.asarray(image, np.float64))[..., 1]
    pixel = 2.0 * half_width / res
    rows = slice(res // 2 - 1, res // 2 + 1)  # the two pixel rows around y = 0
    measured = np.pi * luminance[rows].mean(axis=0) / FLOOR_ALBEDO
    x = -half_width + (np.arange(res) + 0.5) * pixel
    # The formula averaged over each pixel's footprint (what a pixel measures), on a
    # SUBPIXELS^2 grid per pixel over the two rows y in [-pixel, pixel].
    sub = (np.arange(SUBPIXELS) + 0.5) / SUBPIXELS - 0.5
    xs = x[:, None, None] + pixel * sub[None, :, None]
    ys = 2.0 * pixel * sub[None, None, :]
    r = np.sqrt(xs**2 + ys**2 + height**2)
    cos_theta = height / r
    law = DISTANCE_LAWS[light.get("falloff", "inverse_square")]
    params = {k: float(v) for k, v in light.items()
              if k in ("epsilon", "kc", "kl", "kq", "radius")}
    expected = float(light.get("intensity", 1.0)) * law(r, **params) * cos_theta
    if cone is not None:
        name, umbra, penumbra = cone
        expected = expected * CONE_FALLOFFS[name](np.arccos(cos_theta), umbra, penumbra)
    expected = expected.mean(axis=(1, 2))
    return FloorProfile(x, measured, expected, image)


def _fog_none(d, start=0.0, end=1.0, density=1.0):
    return np.ones_like(np.asarray(d, np.float64))


def _fog_linear(d, start=0.0, end=1.0, density=1.0):
    return np.clip((end - np.asarray(d, np.float64)) / (end - start), 0.0, 1.0)


def _fog_exponential(d, start=0.0, end=1.0, density=1.0):
    return np.exp(-density * np.asarray(d, np.float64))


def _fog_exponential_squared(d, start=0.0, end=1.0, density=1.0):
    return np.exp(-np.square(density * np.asarray(d, np.float64)))


#: Fog laws of ``local`` (DESIGN.md, OpenGL 1.5 section 3.10): name -> f(d, start, end,
#: density), the fraction of a surface's radiance left at camera distance d (m).
FOG_LAWS: Mapping[str, Callable[..., np.ndarray]] = {
    "none": _fog_none,
    "linear": _fog_linear,
    "exponential": _fog_exponential,
    "exponential_squared": _fog_exponential_squared,
}


# --------------------------------------------------------------------------- scenes, AOVs


def load_scene(name: str, **params):
    """``mi.load_file`` of ``scenes/<name>`` with its ``<default>`` parameters overridden."""
    import mitsuba as mi

    return mi.load_file(str(scene_path(name)), **{k: str(v) if isinstance(v, bool) else v
                                                  for k, v in params.items()})


def box_filtered_sensor(scene):
    """A copy of the scene's first sensor (perspective or orthographic) with a box filter.

    Same placement, field of view, clip planes and film size; a box reconstruction filter
    keeps every sample in its own pixel, so an AOV rendered with one sample per pixel holds
    values of single hits (no blending of neighbours across silhouettes).
    """
    import drjit as dr
    import mitsuba as mi

    sensor = scene.sensors()[0]
    params = mi.traverse(sensor)
    matrix = np.asarray(params["to_world"].matrix, np.float64).reshape(4, 4)
    width, height = (int(v) for v in sensor.film().size())
    spec = {
        "to_world": mi.ScalarTransform4f(matrix),
        "near_clip": float(params["near_clip"]),
        "far_clip": float(params["far_clip"]),
        "film": {"type": "hdrfilm", "width": width, "height": height,
                 "rfilter": {"type": "box"}, "pixel_format": "rgb"},
    }
    if "x_fov" in params:
        spec.update(type="perspective", fov=float(dr.ravel(params["x_fov"])[0]), fov_axis="x")
    else:
        spec["type"] = "orthographic"
    return mi.load_dict(spec)


def aov(scene, kind: str, seed: int = 0) -> np.ndarray:
    """One AOV of ``scene`` (Mitsuba's ``aov`` integrator): (H, W, C) float64.

    e.g. ``depth`` (camera distance of the first hit, 0 where nothing is hit; C = 1) or
    ``position`` (world position of the first hit; C = 3). One sample per pixel through
    :func:`box_filtered_sensor`, so each pixel holds one hit's value.
    """
    import mitsuba as mi

    integrator = mi.load_dict({"type": "aov", "aovs": f"a:{kind}"})
    sensor = box_filtered_sensor(scene)
    return np.asarray(mi.render(scene, spp=1, seed=seed, sensor=sensor, integrator=integrator),
                      np.float64)


def shape_labels(scene, tolerance: float = 1e-3) -> tuple[np.ndarray, np.ndarray]:
    """Which sphere-like shape each pixel sees: labels (H, W) (-1: none) and the centres.

    Label k is ``scene.shapes()[k]``, whose bounding-box centre is ``centres[k]`` (n, 3).

    A pixel belongs to shape k when its first hit (``position`` AOV) lies on the sphere
    inscribed in shape k's bounding box (within ``tolerance`` of its radius): exact for
    ``sphere`` shapes, whose hits are on that sphere (``tolerance`` is relative to the
    radius).
    """
    position = aov(scene, "position")
    labels = np.full(position.shape[:2], -1)
    centres = []
    for k, shape in enumerate(scene.shapes()):
        box = shape.bbox()
        lo, hi = np.array(box.min, np.float64).ravel(), np.array(box.max, np.float64).ravel()
        centre, radius = (lo + hi) / 2, float(np.min(hi - lo)) / 2
        on = np.abs(np.linalg.norm(position - centre, axis=-1) - radius) <= tolerance * radius
        labels[on & (labels < 0)] = k
        centres.append(centre)
    return labels, np.asarray(centres)


def grid_position(centres) -> tuple[np.ndarray, np.ndarray]:
    """Row (top to bottom, by decreasing y) and column (by increasing x) of each centre."""
    centres = np.asarray(centres, np.float64)
    ys = np.unique(np.round(centres[:, 1], 6))[::-1]
    xs = np.unique(np.round(centres[:, 0], 6))
    rows = np.searchsorted(-ys, -np.round(centres[:, 1], 6))
    cols = np.searchsorted(xs, np.round(centres[:, 0], 6))
    return rows, cols


def label_means(image, labels, count: int) -> np.ndarray:
    """Mean of ``image`` (H, W, C) over the pixels of each label 0..count-1 (NaN if none)."""
    image = np.asarray(image, np.float64)
    out = np.full((count, image.shape[-1]), np.nan)
    for k in range(count):
        mask = labels == k
        if mask.any():
            out[k] = image[mask].mean(axis=0)
    return out


def luminance(linear) -> np.ndarray:
    """Y (CIE 1931) of linear sRGB values: the Y row of the sRGB matrix."""
    return spectral.linear_srgb_to_xyz(np.asarray(linear, np.float64))[..., 1]


def sphere_grid_scene(families: Mapping[str, Callable[[float], dict]], exponents: Sequence[float],
                      res: int = 128, spp: int = 16, environment: float = 0.25,
                      light: float | None = 40.0, max_depth: int = 6) -> dict:
    """Spheres in rows (families, top to bottom) and columns (exponents, left to right).

    Lit by a uniform ``environment`` radiance and, unless ``light`` is None, a Mitsuba
    ``point`` light of that intensity (W/sr) up and to the right of the camera. With
    ``light=None`` and ``environment=1`` it is a white furnace: a sphere that conserves
    energy looks no brighter than the background. ``path`` integrator of ``max_depth``;
    orthographic camera, 1 unit per sphere cell. Shape k is row k // len(exponents).
    """
    import mitsuba as mi

    T = mi.ScalarTransform4f
    rows, cols = len(families), len(exponents)
    half = max(rows, cols) / 2
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": max_depth},
        "sensor": {
            "type": "orthographic",
            "to_world": T().look_at(origin=[0, 0, 10], target=[0, 0, 0], up=[0, 1, 0])
            @ T().scale([cols / 2, cols / 2, 1]),
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {"type": "hdrfilm", "width": res, "height": max(1, res * rows // cols),
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        },
        "environment": {"type": "constant", "radiance": {"type": "rgb", "value": environment}},
    }
    if light is not None:
        scene["light"] = {"type": "point", "position": [2.0 * half, 2.0 * half, 6.0],
                          "intensity": {"type": "rgb", "value": light}}
    for i, make in enumerate(families.values()):
        for j, m in enumerate(exponents):
            scene[f"sphere_{i}_{j}"] = {
                "type": "sphere", "radius": 0.42,
                "center": [j + 0.5 - cols / 2, rows / 2 - i - 0.5, 0.0],
                "bsdf": make(m),
            }
    return scene


def closed_box_scene(bsdf: dict, res: int = 32, spp: int = 16, max_depth: int = 2) -> dict:
    """The inside of a closed cube (side 2 m) lined with ``bsdf``, a 1 W/sr point light in it.

    Light cannot escape, so with path tracing every bounce adds the reflected light of the
    previous one: the image brightness after k bounces is a partial sum of a series whose
    ratio is (about) the walls' albedo. An energy-conserving BSDF (albedo <= 1) converges
    as max_depth grows; one reflecting more than it receives diverges. The camera (a
    pinhole at the centre, fov 90 degrees) looks at a wall; ``rr_depth`` is set past
    ``max_depth`` so that Russian roulette does not add noise.
    """
    import mitsuba as mi

    T = mi.ScalarTransform4f
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": max_depth, "rr_depth": max_depth + 1},
        "sensor": {
            "type": "perspective", "fov": 90.0,
            "to_world": T().look_at(origin=[0, 0, 0], target=[0, 0, -1], up=[0, 1, 0]),
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {"type": "hdrfilm", "width": res, "height": res,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        },
        "box": {"type": "cube", "flip_normals": True, "bsdf": bsdf},
        "light": {"type": "point", "position": [0.3, 0.5, 0.2],
                  "intensity": {"type": "rgb", "value": 1.0}},
    }


def bounce_series(bsdf: dict, depths: Sequence[int], res: int = 32, spp: int = 16,
                  seed: int = 0) -> np.ndarray:
    """Mean luminance of :func:`closed_box_scene` for each ``max_depth`` in ``depths``."""
    import mitsuba as mi

    import spectrace

    out = []
    for depth in depths:
        scene = mi.load_dict(closed_box_scene(bsdf, res, spp, depth))
        out.append(luminance(spectrace.render(scene, spp=spp, seed=seed).image).mean())
    return np.asarray(out)


def fog_fraction(fogged, clear, depth, min_contrast: float = 0.02) -> np.ndarray:
    """f = (L - L_fog) / (L_clear - L_fog) per pixel: the fraction of surface radiance left.

    ``fogged``, ``clear``: (H, W, 3) renders with and without fog; ``depth`` (H, W) the
    ``depth`` AOV (0 where no surface is hit). The fog colour L_fog is measured as the
    mean of the fogged render where nothing is hit (the background takes the fog colour).
    Luminances are used; pixels where L_clear is within ``min_contrast`` of L_fog (f is
    ill-conditioned there), and background pixels, are NaN. Pixels on silhouettes mix
    surfaces at different distances and scatter around the law.
    """
    depth = np.asarray(depth, np.float64).reshape(np.shape(fogged)[:2])
    background = depth <= 0
    if not background.any():
        raise ValueError("fog_fraction: no background pixel shows the fog colour")
    y_fog = luminance(np.asarray(fogged, np.float64)[background]).mean()
    num = luminance(fogged) - y_fog
    den = luminance(clear) - y_fog
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where((np.abs(den) > min_contrast) & ~background, num / den, np.nan)
