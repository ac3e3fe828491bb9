"""The display pipeline: the picture a person looks at, made from the scene-referred EXR.

The EXR a render writes is linear sRGB radiance and never changes; the PNG is made from it
by four steps, each a function here, applied in this order by :func:`develop`:

1. **exposure** (:func:`exposure_scale`): a factor on the linear values.

   * ``exposure=EV``: 2^EV, photographic stops relative to the scene's own scale.
   * ``exposure="auto"``: the log-average luminance mapped to middle grey (Reinhard,
     Stark, Shirley & Ferwerda 2002, "Photographic tone reproduction for digital images",
     SIGGRAPH, eq. 1): L_avg = exp(mean(ln Y)), scale = :data:`MIDDLE_GREY` / L_avg, over the
     pixels with Y > 0 (a pixel that sees nothing is left out, instead of Reinhard's small
     delta, which would depend on the scene's units).
   * ``ev100=N``: an absolute camera (ISO 100). The saturation-based convention of ISO
     12232:2006 (as in Lagarde & de Rousiers 2014, "Moving Frostbite to PBR", section
     5.1.2): the luminance that saturates the sensor is L_max = 78 / (S q) 2^EV100 cd/m^2
     with S = 100 and q = 0.65, i.e. :data:`SATURATION_LUMINANCE` 2^EV100, and display value
     = L_v / L_max. Luminance L_v in cd/m^2 is :data:`LUMINANCE_PER_Y` times the film's Y
     (spectrace's photometric convention, ``spectrace help luminous``: K_m integral V
     dlambda), so a room lit at about 500 lux (walls of reflectance 0.5: 80 cd/m^2) comes
     out at display 0.26 (EV100 8) to 0.13 (EV100 9). With ``ev100``, ``exposure=EV`` is an
     exposure compensation on top.

2. **white balance** (:func:`white_balance_matrix`): a von Kries chromatic adaptation in
   XYZ (:data:`CAT_METHODS`, Bradford by default) from the scene's white to D65, the white
   of linear sRGB, as one 3 x 3 matrix on linear sRGB. ``"none"``; ``"D65"`` (the render's
   own white: no change); ``"3000K"`` (the white of a Planckian radiator at that CCT, xy
   from Kang et al. 2002, 1667-25000 K); ``"auto"`` (grey world: the image's mean colour is
   taken as the white, Buchsbaum 1980).

3. **view transform** (:data:`VIEWS`): ``standard`` (the values clipped to [0, 1], what
   Mitsuba's PNG shows), ``aces`` (the ACES 2.0 SDR 100-nit output transform through
   OpenColorIO's built-in ``studio-config``; the linear sRGB input is the config's ``Linear
   Rec.709 (sRGB)``, which OCIO maps to ACES2065-1 with its Bradford matrix), ``neutral``
   (the Khronos PBR Neutral tone mapper: base colours kept, highlights compressed),
   ``false-colour`` (luminance in cd/m^2 on a log scale with a labelled colour bar, as
   Radiance's ``falsecolor``; exposure and white balance do not apply to it).

4. **encoding** (:data:`DISPLAYS`): ``srgb`` or ``display-p3`` (linear sRGB converted to the
   P3-D65 primaries; both with the sRGB transfer curve), quantised to 8 or 16 bits.

Everything runs on numpy alone; OpenColorIO is imported for ``aces`` only, matplotlib's
colour maps for ``false-colour`` only, so ``spectrace view`` of the default settings stays
fast (``benchmarks/bench_view.py``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import cache, lru_cache

import numpy as np

from spectrace.display_options import (
    D65_XY,
    DISPLAYS,
    PRIMARIES,
    VIEW_NAMES,
    DisplaySettings,
    check_settings,
    parse_exposure,
    parse_white,
    photometric_scene,
    planckian_xy,
)
from spectrace.errors import ParameterError
from spectrace.spectral.srgb import LUMINANCE_WEIGHTS, encode_srgb

__all__ = ["CAT_METHODS", "DISPLAYS", "Developed", "DisplaySettings", "VIEWS", "develop",
           "exposure_scale", "photometric_scene", "planckian_xy", "white_balance_matrix",
           "write_display_png"]

#: Reinhard et al. (2002)'s key: the display value of the log-average luminance.
MIDDLE_GREY = 0.18
#: K_m (683 lm/W, CIE 018:2019) times integral V dlambda over 360-830 nm (106.857 nm): the
#: luminance in cd/m^2 of a film Y of 1 (``spectrace help luminous``).
LUMINANCE_PER_Y = 683.0 * 106.857
#: 78 / (S q) with S = 100 (ISO 100) and q = 0.65 (ISO 12232:2006, saturation-based speed):
#: cd/m^2 that saturate the sensor at EV100 = 0.
SATURATION_LUMINANCE = 78.0 / (100.0 * 0.65)

#: XYZ -> cone response matrices of von Kries adaptation: Bradford (Lam 1985), CAT16 (Li et
#: al. 2017, "Comprehensive color solutions: CAM16, CAT16, and CAM16-UCS").
CAT_METHODS: Mapping[str, tuple] = {
    "Bradford": ((0.8951, 0.2664, -0.1614), (-0.7502, 1.7135, 0.0367),
                 (0.0389, -0.0685, 1.0296)),
    "CAT16": ((0.401288, 0.650173, -0.051461), (-0.250268, 1.204414, 0.045854),
              (-0.002079, 0.048952, 0.953127)),
}
#: OpenColorIO's built-in config, its name of linear sRGB, and per display its display and
#: the ACES 2.0 view.
OCIO_CONFIG = "studio-config-latest"
OCIO_LINEAR_SRGB = "Linear Rec.709 (sRGB)"
OCIO_ACES_VIEWS = {"srgb": ("sRGB - Display", "ACES 2.0 - SDR 100 nits (Rec.709)"),
                   "display-p3": ("Display P3 - Display", "ACES 2.0 - SDR 100 nits (P3 D65)")}

#: False colour: the colour map, decades shown, and the legend's width (fraction of the
#: image height, at least :data:`LEGEND_MIN_PX` pixels).
FALSE_COLOUR_MAP = "viridis"
FALSE_COLOUR_DECADES = 4
FALSE_COLOUR_PERCENTILE = 99.5
LEGEND_FRACTION = 0.22
LEGEND_MIN_PX = 60


# -- colorimetry on numpy alone (checked against colour-science in tests/test_display.py) ----

def xy_to_XYZ(xy) -> np.ndarray:
    """XYZ of chromaticity ``xy`` with Y = 1."""
    x, y = xy
    return np.array([x / y, 1.0, (1.0 - x - y) / y])


#: Linear sRGB -> XYZ as IEC 61966-2-1:1999 tabulates it (rounded to 4 digits; its Y row
#: the Rec. 709 weights), as colour-science and :mod:`spectrace.spectral` use it.
SRGB_TO_XYZ = ((0.4124, 0.3576, 0.1805), (0.2126, 0.7152, 0.0722), (0.0193, 0.1192, 0.9505))


@cache
def rgb_to_xyz_matrix(display: str) -> np.ndarray:
    """Linear RGB -> XYZ of a display: sRGB's tabulated matrix (:data:`SRGB_TO_XYZ`), else
    the normalised primary matrix (SMPTE RP 177-1993: the columns are the primaries' XYZ
    scaled so that RGB (1, 1, 1) is D65 with Y = 1)."""
    if display == "srgb":
        return np.asarray(SRGB_TO_XYZ, np.float64)
    P = np.stack([xy_to_XYZ(p) for p in PRIMARIES[display]], axis=1)
    return P * np.linalg.solve(P, xy_to_XYZ(D65_XY))[None, :]


def adaptation_matrix(source_XYZ, target_XYZ, method: str = "Bradford") -> np.ndarray:
    """The von Kries matrix M^-1 diag(M w_t / M w_s) M that takes XYZ seen under the white
    ``source_XYZ`` to XYZ under ``target_XYZ`` (no degree of adaptation: complete)."""
    if method not in CAT_METHODS:
        raise ParameterError(f"unknown chromatic adaptation method {method!r}; one of: "
                             f"{', '.join(CAT_METHODS)}")
    M = np.asarray(CAT_METHODS[method], np.float64)
    gain = (M @ np.asarray(target_XYZ, np.float64)) / (M @ np.asarray(source_XYZ, np.float64))
    return np.linalg.solve(M, gain[:, None] * M)


def luminance(rgb: np.ndarray) -> np.ndarray:
    """Y of linear sRGB (Rec. 709 weights)."""
    return rgb @ np.asarray(LUMINANCE_WEIGHTS, rgb.dtype)


# -- the four steps ------------------------------------------------------------------------

def exposure_scale(rgb: np.ndarray, settings: DisplaySettings) -> tuple[float, str]:
    """The factor that the exposure step applies to the linear values, and a line that
    says how it was chosen (what the command line prints)."""
    exposure = parse_exposure(settings.exposure)
    if settings.ev100 is not None:
        ev = 0.0 if exposure is None else exposure
        scale = 2.0**ev * LUMINANCE_PER_Y / (SATURATION_LUMINANCE * 2.0**settings.ev100)
        extra = f" {ev:+.2f} EV" if ev else ""
        return scale, (f"exposure: EV100 {settings.ev100:g}{extra} (x{scale:.4g}; "
                       f"{SATURATION_LUMINANCE * 2.0**(settings.ev100 - ev):.4g} cd/m^2 "
                       "saturate)")
    if exposure == "auto":
        Y = luminance(np.asarray(rgb, np.float64))
        Y = Y[np.isfinite(Y) & (Y > 0)]
        if Y.size == 0:
            return 1.0, "exposure: auto, nothing lit: +0.00 EV"
        log_average = float(np.exp(np.mean(np.log(Y))))
        scale = MIDDLE_GREY / log_average
        ev100 = math.log2(log_average * LUMINANCE_PER_Y / (MIDDLE_GREY * SATURATION_LUMINANCE))
        return scale, (f"exposure: auto {math.log2(scale):+.2f} EV (log-average Y "
                       f"{log_average:.4g} to {MIDDLE_GREY}; EV100 {ev100:.2f} if the scene is in "
                       "photometric units)")
    ev = 0.0 if exposure is None else exposure
    return 2.0**ev, f"exposure: {ev:+.2f} EV (x{2.0**ev:.4g})"


def white_balance_matrix(rgb: np.ndarray, white_balance: str,
                         method: str = "Bradford") -> np.ndarray | None:
    """The 3 x 3 matrix on linear sRGB that adapts the scene's white to D65 (see the module
    notes), or None for ``"none"``."""
    white = parse_white(white_balance)
    if white is None:
        return None
    to_xyz = rgb_to_xyz_matrix("srgb")
    if white == "auto":
        mean = np.asarray(rgb, np.float64).reshape(-1, 3)
        mean = mean[np.all(np.isfinite(mean), axis=1)].mean(axis=0)
        source = to_xyz @ mean
        if not source[1] > 0 or np.any(source <= 0):
            return None  # a black (or impossible) mean: nothing to balance
        source = source / source[1]
    elif white == D65_XY:
        return np.eye(3)  # the render's own white
    else:
        source = xy_to_XYZ(white)
    # the target: sRGB's white as its tabulated matrix has it (D65 within 1e-4), so that
    # the white becomes R = G = B exactly
    cat = adaptation_matrix(source, to_xyz @ np.ones(3), method)
    return np.linalg.solve(to_xyz, cat @ to_xyz)


def view_standard(rgb: np.ndarray, display: str) -> np.ndarray:
    """Linear sRGB clipped to [0, 1] in the display's primaries, sRGB-encoded."""
    return encode_srgb(np.clip(to_display_primaries(rgb, display), 0.0, 1.0))


def to_display_primaries(rgb: np.ndarray, display: str) -> np.ndarray:
    """Linear sRGB expressed in the primaries of ``display`` (same D65 white)."""
    if display == "srgb":
        return rgb
    M = np.linalg.solve(rgb_to_xyz_matrix(display), rgb_to_xyz_matrix("srgb"))
    return rgb @ M.T.astype(rgb.dtype)


@lru_cache(maxsize=4)
def _ocio_processor(display: str):
    import PyOpenColorIO as ocio

    config = ocio.Config.CreateFromBuiltinConfig(OCIO_CONFIG)
    device, view = OCIO_ACES_VIEWS[display]
    return config.getProcessor(OCIO_LINEAR_SRGB, device, view,
                               ocio.TRANSFORM_DIR_FORWARD).getDefaultCPUProcessor()


def view_aces(rgb: np.ndarray, display: str) -> np.ndarray:
    """The ACES 2.0 SDR output transform (OpenColorIO), display-encoded in [0, 1]."""
    out = np.ascontiguousarray(rgb, dtype=np.float32).copy()
    _ocio_processor(display).applyRGB(out)
    return np.clip(out, 0.0, 1.0)


#: Khronos PBR Neutral: the compression starts at this value (0.8 - 0.04) and desaturates
#: highlights by this rate.
NEUTRAL_START = 0.76
NEUTRAL_DESATURATION = 0.15


def view_neutral(rgb: np.ndarray, display: str) -> np.ndarray:
    """The Khronos PBR Neutral tone mapper (Khronos 3D Formats WG 2024, "Khronos PBR Neutral
    Tone Mapper", Apache-2.0 reference): colours below 0.76 stay as they are (up to a small
    toe offset), brighter ones are compressed towards 1 with hue kept and highlights
    desaturated; on the display's primaries, sRGB-encoded. A filmic-like alternative to
    ACES that keeps base colours (the AgX and Filmic configs are not in OpenColorIO's
    built-in configs)."""
    c = to_display_primaries(np.asarray(rgb, np.float64), display)
    x = c.min(axis=-1, keepdims=True)
    c = c - np.where(x < 0.08, x - 6.25 * x * x, 0.04)
    peak = c.max(axis=-1, keepdims=True)
    d = 1.0 - NEUTRAL_START
    safe = np.maximum(peak, 1e-12)
    new_peak = 1.0 - d * d / (peak + d - NEUTRAL_START)
    g = 1.0 - 1.0 / (NEUTRAL_DESATURATION * (peak - new_peak) + 1.0)
    compressed = c * (new_peak / safe) * (1.0 - g) + new_peak * g
    out = np.where(peak < NEUTRAL_START, c, compressed)
    return encode_srgb(np.clip(out, 0.0, 1.0))


def false_colour_range(L: np.ndarray) -> tuple[float, float]:
    """(lowest, highest) luminance of the scale: the highest a power of ten at or above the
    :data:`FALSE_COLOUR_PERCENTILE` th percentile, :data:`FALSE_COLOUR_DECADES` below it."""
    lit = L[np.isfinite(L) & (L > 0)]
    top = float(np.percentile(lit, FALSE_COLOUR_PERCENTILE)) if lit.size else 1.0
    high = 10.0 ** math.ceil(math.log10(top))
    return high / 10.0**FALSE_COLOUR_DECADES, high


def view_false_colour(rgb: np.ndarray, display: str) -> np.ndarray:
    """Luminance L_v = :data:`LUMINANCE_PER_Y` Y in cd/m^2 on a log scale of
    :data:`FALSE_COLOUR_DECADES` decades (:func:`false_colour_range`), with a colour bar
    labelled at each decade on the right; display-encoded."""
    from matplotlib import colormaps

    L = luminance(np.asarray(rgb, np.float64)) * LUMINANCE_PER_Y
    low, high = false_colour_range(L)
    t = (np.log10(np.maximum(np.nan_to_num(L, nan=0.0), low)) - math.log10(low)) \
        / FALSE_COLOUR_DECADES
    cmap = colormaps[FALSE_COLOUR_MAP]
    image = cmap(np.clip(t, 0.0, 1.0))[..., :3]
    out = np.concatenate([image, _legend(image.shape[0], cmap, low)], axis=1)
    if display != "srgb":  # the map's colours are sRGB: the same colours on the display
        from spectrace.spectral.srgb import decode_srgb

        out = encode_srgb(np.clip(to_display_primaries(decode_srgb(out), display), 0, 1))
    return out


def _legend(height: int, cmap, low: float) -> np.ndarray:
    """The colour bar (H, w, 3) in [0, 1]: the map from bottom (low) to top, a label per
    decade, and 'cd/m2' at the top."""
    from PIL import Image, ImageDraw

    width = max(LEGEND_MIN_PX, int(LEGEND_FRACTION * height))
    top, bottom = 16, 7  # room for the unit above the bar and half a label below it
    bar = max(6, width // 6)
    ys = np.arange(height)
    span = max(1, height - top - bottom - 1)
    t = 1.0 - (ys - top) / span
    strip = np.ones((height, width, 3))
    inside = (ys >= top) & (ys <= height - bottom - 1)
    strip[inside, 2:2 + bar] = cmap(t[inside])[:, None, :3]
    text = Image.new("L", (width, height), 255)
    draw = ImageDraw.Draw(text)
    for k in range(FALSE_COLOUR_DECADES + 1):
        y = top + (1.0 - k / FALSE_COLOUR_DECADES) * span
        draw.line([(2 + bar, y), (5 + bar, y)], fill=0)
        draw.text((7 + bar, y), _decade_label(low * 10.0**k), fill=0, anchor="lm")
    draw.text((2, 2), "cd/m2", fill=0, anchor="lt")
    shade = np.asarray(text, np.float64)[..., None] / 255.0
    return np.minimum(strip, shade)


def _decade_label(value: float) -> str:
    """0.01, 0.1, 1, 10, 100, 1000, then 1e4, 1e5, ..."""
    exponent = round(math.log10(value))
    return f"{value:g}" if -2 <= exponent <= 3 else f"1e{exponent}"


#: View name -> function(linear sRGB after exposure and white balance, display) -> encoded
#: display values in [0, 1].
VIEWS: Mapping[str, Callable[[np.ndarray, str], np.ndarray]] = dict(zip(
    VIEW_NAMES, (view_standard, view_aces, view_neutral, view_false_colour), strict=True))
#: Views that show the scene's absolute luminance: exposure and white balance do not apply.
ABSOLUTE_VIEWS = ("false-colour",)


@dataclass(frozen=True)
class Developed:
    """A developed picture: integer codes (H, W', 3) for the PNG, the PNG's cICP chunk, and
    what was done (``exposure``: the factor, ``notes``: lines to print)."""

    codes: np.ndarray
    cicp: bytes
    exposure: float
    notes: tuple[str, ...]

    @property
    def display_linear(self) -> np.ndarray:
        """The picture as display-referred linear values in [0, 1] (float32, the display's
        primaries): the codes with the sRGB curve undone, what ``OUT.display.exr`` holds."""
        from spectrace.spectral.srgb import decode_srgb

        top = np.float32(np.iinfo(self.codes.dtype).max)
        return decode_srgb(self.codes.astype(np.float32) / top)


def develop(rgb, settings: DisplaySettings | None = None) -> Developed:
    """Linear sRGB (H, W, 3) (or a mono image: :func:`spectrace.images.as_rgb`) -> the PNG's
    codes through exposure, white balance, view and encoding. The input is not changed.
    NaN and infinite values show as 0 (black)."""
    from spectrace.images import as_rgb

    rgb = np.asarray(as_rgb(rgb), np.float32)
    if not np.isfinite(rgb).all():
        rgb = np.nan_to_num(rgb, nan=0.0, posinf=0.0, neginf=0.0)
    settings = DisplaySettings() if settings is None else settings
    check_settings(settings)
    notes = []
    scale = 1.0
    if settings.view not in ABSOLUTE_VIEWS:
        scale, line = exposure_scale(rgb, settings)
        notes.append(line)
        M = white_balance_matrix(rgb, settings.white_balance)
        if M is not None:
            rgb = rgb @ (scale * M).T.astype(np.float32)
            notes.append(f"white balance: {settings.white_balance} -> D65 (Bradford)")
        elif scale != 1.0:
            rgb = rgb * np.float32(scale)
    else:
        notes.append("false colour: luminance in cd/m^2 at the scene's scale (no exposure)")
    encoded = VIEWS[settings.view](rgb, settings.display)
    top = 2**settings.png_bits - 1
    dtype = np.uint8 if settings.png_bits == 8 else np.uint16
    codes = np.clip(encoded, 0.0, 1.0)
    codes *= top
    codes = np.round(codes, out=codes).astype(dtype)  # finite: the input was made finite
    return Developed(codes, DISPLAYS[settings.display], scale, tuple(notes))


#: Views :func:`develop_pair` can give back as linear sRGB (an sRGB-encoded result).
PAIR_VIEWS = ("standard", "aces", "neutral")


def develop_pair(a, b, settings: DisplaySettings):
    """Two linear sRGB images developed alike for a comparison: the exposure and white
    balance found for ``a`` applied to both (so that a difference stays a difference),
    then the view (:data:`PAIR_VIEWS`, sRGB display), decoded back to linear sRGB (what
    :func:`spectrace.comparison.compare_images` takes). Returns (a, b, notes)."""
    from spectrace.spectral.srgb import decode_srgb

    if settings.view not in PAIR_VIEWS or settings.display != "srgb":
        raise ParameterError(f"develop_pair: view must be one of {', '.join(PAIR_VIEWS)} on "
                             f"the srgb display (got {settings.view!r}, {settings.display!r})")
    a = np.asarray(a, np.float32)
    scale, line = exposure_scale(a, settings)
    M = white_balance_matrix(a, settings.white_balance)
    M = scale * (np.eye(3) if M is None else M)
    out = []
    for image in (a, np.asarray(b, np.float32)):
        image = image @ M.T.astype(np.float32)
        if settings.view != "standard":
            image = decode_srgb(VIEWS[settings.view](image, "srgb"))
        out.append(image)
    return out[0], out[1], (line,)


def write_display_png(path, rgb, settings: DisplaySettings | None = None,
                      display_exr=None) -> Developed:
    """:func:`develop` ``rgb`` and write the PNG (atomic), and with ``display_exr`` (a path)
    the display-referred copy there (:attr:`Developed.display_linear`, with the settings
    in its header); returns what was developed."""
    from spectrace.images import write_exr, write_png_codes

    settings = DisplaySettings() if settings is None else settings
    developed = develop(rgb, settings)
    write_png_codes(path, developed.codes, cicp=developed.cicp)
    if display_exr is not None:
        header = {"view": settings.view, "display": settings.display,
                  "exposure_scale": float(developed.exposure),
                  "white_balance": settings.white_balance}
        write_exr(display_exr, developed.display_linear, header)
    return developed
