"""``solar``: where the sun is, for ``ciesky`` and ``sun`` (helper page, not a plugin).

Both daylight emitters place the sun the same way: by its ``sun_azimuth`` and
``sun_elevation`` in degrees, or by a place and a time, ``latitude``, ``longitude`` (degrees,
north and east positive) and a time-zone-aware ``datetime`` (ISO 8601 with its UTC offset,
e.g. ``2026-06-21T12:00:00+02:00``), from which NREL's Solar Position Algorithm gives the
topocentric azimuth and the refraction-corrected elevation.

Parameters
----------

=================  ========  =======  =======  ===============================================
parameter          type      default  unit     description
=================  ========  =======  =======  ===============================================
``sun_azimuth``    float     180      degree   azimuth of the sun, clockwise from north (east
                                               90, south 180)
``sun_elevation``  float     45       degree   elevation of the sun above the horizon, in
                                               [-90, 90]
``latitude``       float     --       degree   latitude of the site in [-90, 90], north
                                               positive; with ``longitude`` and ``datetime``
                                               instead of the two angles
``longitude``      float     --       degree   longitude in [-180, 180], east positive
``datetime``       string    --       --       local time with its UTC offset (ISO 8601); a
                                               time without an offset is refused
``altitude``       float     0        m        height of the site above sea level (SPA)
``up``             vector    (0,1,0)  --       the scene's up direction (zenith); east is the
                                               scene's +X made orthogonal to it, north = up x
                                               east (-Z when up is +Y)
``spectrum``       spectrum  d65      --       spectral shape of the daylight (its scale does
                                               not matter: the light is given in photometric
                                               units)
``cct``            float     --       K        instead of ``spectrum``: the CIE daylight
                                               (D series) of this correlated colour
                                               temperature, in [4000, 25000]
=================  ========  =======  =======  ===============================================

Formula
-------

With the horizon frame (east, north, up), a sun at azimuth A and elevation h lies in the
direction::

    s = cos(h) (sin(A) east + cos(A) north) + sin(h) up

The solar position is pvlib's implementation of the SPA (Reda and Andreas 2004; the
paper's example, Golden CO 2003-10-17 12:30:30 -07:00, gives zenith 50.11162 and azimuth
194.34024 degrees), imported only when a ``datetime`` is given. Atmospheric refraction
uses 101325 Pa and 12 degrees C, Delta T = 67 s.

The emitters' luminous quantities become radiance through ``spectrace help luminous``:
L_e(lambda) = L_v s(lambda) / (683 integral V s dlambda), the same convention in spectral,
RGB and mono variants. The D series is colour-science's ``sd_CIE_illuminant_D_series``
of the chromaticity ``CCT_to_xy_CIE_D`` (CIE 015:2018), imported only when ``cct`` is
given; RGB and mono variants use its linear sRGB colour.

Sources
-------

Reda, Andreas (2004), "Solar position algorithm for solar radiation applications", Solar
Energy 76(5), 577-589 (NREL/TP-560-34302); Holmgren, Hansen, Mikofski (2018), "pvlib
python: a python package for modeling solar energy systems", JOSS 3(29), 884
(``pvlib.spa``); CIE (2018), CIE 015:2018 *Colorimetry*, 4th ed., sec. 4.1.2 (daylight
illuminants); Mansencal et al. (2023), colour-science.

Example
-------

The sun over Paris at noon of the summer solstice::

    <emitter type="sun">
        <float name="latitude" value="48.8566"/>
        <float name="longitude" value="2.3522"/>
        <string name="datetime" value="2026-06-21T12:00:00+02:00"/>
    </emitter>
"""

from __future__ import annotations

import math
from datetime import datetime

from spectrace.errors import ParameterError

#: Parameters of a solar position from a place and a time.
PLACE_TIME = ("latitude", "longitude", "datetime")
#: Standard atmosphere of the refraction correction (Pa, degrees C) and Delta T (s) of SPA.
PRESSURE_PA = 101325.0
TEMPERATURE_C = 12.0
DELTA_T_S = 67.0
#: Apparent elevation of the sun's centre at sunrise/sunset (degrees, SPA's default).
ATMOS_REFRACT = 0.5667


def parse_datetime(text: str, plugin: str, name: str = "datetime") -> datetime:
    """A time-zone-aware ``datetime`` from ISO 8601 text; naive times are refused (a time
    without its UTC offset names no instant)."""
    try:
        when = datetime.fromisoformat(text.strip())
    except ValueError:
        raise ParameterError(
            f"{plugin}: parameter '{name}' must be an ISO 8601 date and time with its UTC "
            f"offset, e.g. 2026-06-21T12:00:00+02:00 (got {text!r})") from None
    if when.tzinfo is None or when.utcoffset() is None:
        raise ParameterError(
            f"{plugin}: parameter '{name}' has no UTC offset ({text!r}): add one, e.g. "
            "+02:00 or Z")
    return when


def solar_position(latitude: float, longitude: float, when: datetime,
                   altitude: float = 0.0, pressure: float = PRESSURE_PA,
                   temperature: float = TEMPERATURE_C, delta_t: float = DELTA_T_S,
                   ) -> tuple[float, float]:
    """(azimuth, elevation) of the sun in degrees by NREL's SPA (pvlib): topocentric azimuth
    clockwise from north, apparent (refracted) elevation. ``pressure`` in Pa."""
    if not -90.0 <= latitude <= 90.0:
        raise ParameterError(f"solar_position: latitude must be in [-90, 90] (got {latitude:g})")
    if not -180.0 <= longitude <= 180.0:
        raise ParameterError(
            f"solar_position: longitude must be in [-180, 180] (got {longitude:g})")
    if when.tzinfo is None:
        raise ParameterError("solar_position: the time has no UTC offset")
    import numpy as np
    from pvlib import spa

    zenith, _, _, _, azimuth, _ = spa.solar_position(
        np.array([when.timestamp()]), latitude, longitude, altitude, pressure / 100.0,
        temperature, delta_t, ATMOS_REFRACT, numthreads=1)
    return float(np.asarray(azimuth)[0]), 90.0 - float(np.asarray(zenith)[0])


def horizon_frame(up=(0.0, 1.0, 0.0)) -> tuple[tuple, tuple, tuple]:
    """(east, north, up) unit vectors of the scene: east is +X made orthogonal to ``up``
    (+Z when up is along X), north = up x east."""
    ux, uy, uz = up
    n = math.sqrt(ux * ux + uy * uy + uz * uz)
    if not n > 0.0:
        raise ParameterError("up must be a non-zero vector")
    u = (ux / n, uy / n, uz / n)
    ref = (1.0, 0.0, 0.0) if abs(u[0]) < 0.999 else (0.0, 0.0, 1.0)
    dot = sum(r * c for r, c in zip(ref, u, strict=True))
    e = tuple(r - dot * c for r, c in zip(ref, u, strict=True))
    ne = math.sqrt(sum(c * c for c in e))
    e = tuple(c / ne for c in e)
    north = (u[1] * e[2] - u[2] * e[1], u[2] * e[0] - u[0] * e[2], u[0] * e[1] - u[1] * e[0])
    return e, north, u


def direction(azimuth: float, elevation: float, frame) -> tuple[float, float, float]:
    """The unit vector towards azimuth/elevation (degrees) in the (east, north, up) frame."""
    east, north, up = frame
    a, h = math.radians(azimuth), math.radians(elevation)
    ce, cn, cu = math.cos(h) * math.sin(a), math.cos(h) * math.cos(a), math.sin(h)
    return tuple(ce * e + cn * n + cu * u for e, n, u in zip(east, north, up, strict=True))


def read_frame(props, plugin: str):
    """The (east, north, up) frame of a daylight emitter from its ``up`` parameter."""
    from spectrace.plugins import params

    up = params.read_point(props, plugin, "up", None)
    if up is None:
        return horizon_frame()
    try:
        return horizon_frame(tuple(float(c) for c in up))
    except ParameterError:
        raise ParameterError(f"{plugin}: parameter 'up' must be a non-zero vector") from None


def read_sun_position(props, plugin: str, default_elevation: float = 45.0):
    """(azimuth, elevation) in degrees from ``sun_azimuth``/``sun_elevation`` or from
    ``latitude``/``longitude``/``datetime`` (all three), never both ways."""
    from spectrace.plugins import params

    angles = [name for name in ("sun_azimuth", "sun_elevation") if name in props]
    place = [name for name in PLACE_TIME if name in props]
    if angles and place:
        raise ParameterError(
            f"{plugin}: give the sun's position either by 'sun_azimuth'/'sun_elevation' or "
            f"by 'latitude'/'longitude'/'datetime', not both (got '{angles[0]}' and "
            f"'{place[0]}')")
    if place:
        missing = [name for name in PLACE_TIME if name not in props]
        if missing:
            raise ParameterError(
                f"{plugin}: parameter '{missing[0]}' is required with "
                f"{', '.join(repr(p) for p in place)}")
        latitude = params.read_float(props, plugin, "latitude", params.REQUIRED,
                                     minimum=-90.0, maximum=90.0)
        longitude = params.read_float(props, plugin, "longitude", params.REQUIRED,
                                      minimum=-180.0, maximum=180.0)
        when = parse_datetime(params.read_string(props, plugin, "datetime", params.REQUIRED),
                              plugin)
        altitude = params.read_float(props, plugin, "altitude", 0.0, finite=True)
        return solar_position(latitude, longitude, when, altitude)
    azimuth = params.read_float(props, plugin, "sun_azimuth", 180.0, finite=True)
    elevation = params.read_float(props, plugin, "sun_elevation", default_elevation,
                                  minimum=-90.0, maximum=90.0)
    return azimuth % 360.0, elevation


#: Range of correlated colour temperatures of the CIE D series (K), CIE 015:2018.
CCT_RANGE = (4000.0, 25000.0)


def daylight_spd(cct: float):
    """(wavelengths in nm, values) of the CIE daylight illuminant of correlated colour
    temperature ``cct`` (K) on 360-830 nm, from colour-science."""
    import colour
    import numpy as np

    xy = colour.temperature.CCT_to_xy_CIE_D(cct)
    sd = colour.sd_CIE_illuminant_D_series(xy)
    wavelengths = np.arange(360.0, 831.0, 5.0)
    return wavelengths, np.asarray(sd.copy().align(colour.SpectralShape(360, 830, 5))[wavelengths])


def read_daylight_spectrum(props, plugin: str):
    """The spectral shape of a daylight emitter: ``spectrum`` (emissive, uniform; D65 by
    default in spectral variants, white in RGB ones) or the D series at ``cct``. Returns
    (texture, watts per lumen)."""
    import mitsuba as mi
    from spectrace.plugins import params
    from spectrace.plugins.emitters import luminous

    if "cct" in props:
        if "spectrum" in props:
            raise ParameterError(f"{plugin}: give either parameter 'spectrum' or 'cct', not both")
        cct = params.read_float(props, plugin, "cct", params.REQUIRED, minimum=CCT_RANGE[0],
                                maximum=CCT_RANGE[1])
        wavelengths, values = daylight_spd(cct)
        if mi.is_spectral:
            from spectrace.spectral import to_mitsuba_spectrum

            texture = mi.load_dict(to_mitsuba_spectrum(wavelengths, values))
        else:  # RGB and mono variants: the SPD's linear sRGB colour (its scale is free)
            import numpy as np
            from spectrace.spectral import spd_to_xyz, xyz_to_linear_srgb

            rgb = np.clip(xyz_to_linear_srgb(spd_to_xyz(wavelengths, values)), 0.0, None)
            rgb = rgb / rgb.max()
            texture = mi.load_dict({"type": "rgb", "value": [float(c) for c in rgb]})
    else:
        texture = params.read_spectrum(props, plugin, "spectrum", 1.0)
    return texture, luminous.watts_per_lumen(texture, plugin)
