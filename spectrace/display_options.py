"""The display pipeline's settings (:mod:`spectrace.display`), parsed and checked with the
standard library alone: ``spectrace render`` reads them before it knows whether its PNG
needs the pipeline (numpy), and a plain scene's render imports no numpy.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass

from spectrace.errors import ParameterError

#: The view transforms of :data:`spectrace.display.VIEWS`, in the order the help lists them.
VIEW_NAMES = ("standard", "aces", "neutral", "false-colour")

#: CIE xy of the whites and primaries (IEC 61966-2-1 for sRGB, SMPTE EG 432-1 for P3-D65).
D65_XY = (0.3127, 0.3290)
PRIMARIES = {
    "srgb": ((0.64, 0.33), (0.30, 0.60), (0.15, 0.06)),
    "display-p3": ((0.680, 0.320), (0.265, 0.690), (0.150, 0.060)),
}
#: The encodings of the PNG: display name -> the PNG's cICP chunk (ITU-T H.273 colour
#: primaries 1 = BT.709 / 12 = P3-D65, transfer 13 = sRGB, matrix 0, full range).
DISPLAYS: Mapping[str, bytes] = {"srgb": bytes((1, 13, 0, 1)),
                                 "display-p3": bytes((12, 13, 0, 1))}
PNG_BITS = (8, 16)

#: The range of CCTs of Kang et al. (2002)'s Planckian locus approximation.
CCT_RANGE = (1667.0, 25000.0)


@dataclass(frozen=True)
class DisplaySettings:
    """The options of the display pipeline (see the module notes); the defaults make
    today's PNG: no exposure change, no white balance, the standard view, 8-bit sRGB."""

    exposure: float | str | None = None  # stops, "auto", or None (0 stops)
    ev100: float | None = None
    white_balance: str = "none"
    view: str = "standard"
    display: str = "srgb"
    png_bits: int = 8

    def __post_init__(self):
        check_settings(self)

    @property
    def is_default(self) -> bool:
        """Whether these settings make the plain clipped sRGB PNG."""
        return self == DisplaySettings()


def parse_exposure(value) -> float | str | None:
    """``value`` as stops (a finite float), ``"auto"`` or None; ParameterError otherwise."""
    if value is None or value == "auto":
        return value
    try:
        ev = float(value)
    except (TypeError, ValueError):
        ev = math.nan
    if not math.isfinite(ev):
        raise ParameterError(f"exposure must be a finite number of stops or 'auto' (got "
                             f"{value!r})")
    return ev


_CCT = re.compile(r"^\s*([-+0-9.eE]+)\s*[kK]\s*$")


def parse_white(value: str):
    """``"none"`` -> None, ``"auto"``, ``"D65"`` -> D65's xy, ``"<CCT>K"`` -> the Planckian xy;
    ParameterError for anything else or a CCT outside :data:`CCT_RANGE`."""
    text = str(value).strip()
    if text.lower() == "none":
        return None
    if text.lower() == "auto":
        return "auto"
    if text.upper() == "D65":
        return D65_XY
    m = _CCT.match(text)
    if m is None:
        raise ParameterError(f"white_balance must be none, D65, auto or a colour temperature "
                             f"such as 3000K (got {value!r})")
    try:
        cct = float(m.group(1))
    except ValueError:
        cct = math.nan
    low, high = CCT_RANGE
    if not low <= cct <= high:  # NaN fails too
        raise ParameterError(f"white_balance {value!r}: the colour temperature must be "
                             f"between {low:g} K and {high:g} K")
    return planckian_xy(cct)


def check_settings(settings: DisplaySettings) -> None:
    """ParameterError naming the first setting that has a value it cannot take."""
    parse_exposure(settings.exposure)
    if settings.ev100 is not None and not math.isfinite(settings.ev100):
        raise ParameterError(f"ev100 must be a finite number (got {settings.ev100!r})")
    if settings.ev100 is not None and settings.exposure == "auto":
        raise ParameterError("ev100 and exposure='auto' exclude each other")
    parse_white(settings.white_balance)
    if settings.view not in VIEW_NAMES:
        raise ParameterError(f"unknown view {settings.view!r}; one of: {', '.join(VIEW_NAMES)}")
    if settings.display not in DISPLAYS:
        raise ParameterError(f"unknown display {settings.display!r}; one of: "
                             f"{', '.join(DISPLAYS)}")
    if settings.png_bits not in PNG_BITS:
        raise ParameterError(f"png_bits must be 8 or 16 (got {settings.png_bits!r})")


def planckian_xy(cct: float) -> tuple[float, float]:
    """CIE 1931 xy of a Planckian radiator, Kang, Moon, Hong, Lee, Cho & Kim (2002), "Design
    of advanced color temperature control system for HDTV applications", J. Korean Phys.
    Soc. 41(6), eqs. 5-6 (cubic fits, 1667-25000 K)."""
    t = 1e3 / cct
    if cct <= 4000.0:
        x = -0.2661239 * t**3 - 0.2343589 * t**2 + 0.8776956 * t + 0.179910
    else:
        x = -3.0258469 * t**3 + 2.1070379 * t**2 + 0.2226347 * t + 0.240390
    if cct <= 2222.0:
        y = -1.1063814 * x**3 - 1.34811020 * x**2 + 2.18555832 * x - 0.20219683
    elif cct <= 4000.0:
        y = -0.9549476 * x**3 - 1.37418593 * x**2 + 2.09137015 * x - 0.16748867
    else:
        y = 3.0817580 * x**3 - 5.87338670 * x**2 + 3.75112997 * x - 0.37001483
    return float(x), float(y)



#: Emitter types and parameters that make a scene photometric (absolute luminous units).
PHOTOMETRIC_EMITTERS = ("ieslight",)
PHOTOMETRIC_PARAMETERS = ("luminous_flux", "luminous_intensity")


def photometric_scene(root) -> bool:
    """Whether a scene's XML tree (``xml.etree`` element) has a light in luminous units: an
    ``ieslight``, or an emitter with a ``luminous_*`` parameter. Such a scene's PNG is
    exposed automatically by default (its values are luminances over
    :data:`spectrace.display.LUMINANCE_PER_Y`, far from [0, 1])."""
    for emitter in root.iter("emitter"):
        if emitter.get("type") in PHOTOMETRIC_EMITTERS:
            return True
        if any(child.get("name") in PHOTOMETRIC_PARAMETERS for child in emitter.iter()):
            return True
    return False
