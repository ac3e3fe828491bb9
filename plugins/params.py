"""``params``: the typed parameters of spectrace's plugins (helper module, not a plugin).

Every plugin reads its XML parameters through these functions, so that every plugin
follows one contract:

* no coercion from the wrong XML type: a ``<string value="no"/>`` where a ``boolean``
  belongs, a ``<string>`` where a ``float`` belongs, a ``<float>`` where an ``integer``
  belongs are errors (an ``<integer>`` is accepted for a float, as Mitsuba does);
* a value out of range (NaN included) is an error, and so is a non-finite spectrum or
  texture value or one beyond float32 (``power=1e39``);
* a reflectance texture is checked against its range: by value for a ``float`` or
  ``rgb``, else by evaluating it (on a grid of uv positions and, in spectral variants,
  of wavelengths); a texture that cannot be evaluated for the check is refused, never
  accepted unchecked;
* every error is one :class:`~spectrace.errors.ParameterError` (a ``ValueError``) line that
  names the plugin, the parameter, what was expected and what came: ``local: parameter
  'shadows' must be a boolean (got a string "no")``. Mitsuba's loader turns it into its
  load error, which :func:`spectrace.scene.load_error` turns back into this class.

A missing parameter gives ``default``; pass :data:`REQUIRED` to make it mandatory.
Mitsuba types are looked up when a function runs, so the module needs no re-execution
after a variant switch (it is not in ``spectrace.plugins.PLUGIN_MODULES``).
"""

from __future__ import annotations

import math

import drjit as dr
import mitsuba as mi

from spectrace.errors import ParameterError, first_line

__all__ = [
    "REQUIRED", "xml_type", "read_float", "read_int", "read_bool", "read_choice",
    "read_string", "read_point", "read_texture", "read_reflectance", "read_spectrum",
    "texture_range",
]


class _Required:
    def __repr__(self):
        return "REQUIRED"


#: Default that makes a parameter mandatory.
REQUIRED = _Required()

#: uv positions per axis at which a spatially varying texture is checked.
GRID_UV = 32
#: Wavelength step (nm) of the spectral check, over Mitsuba's 360-830 nm range.
GRID_NM_STEP = 5.0
GRID_NM = (360.0, 830.0)
#: Slack of the range check of evaluated textures (float32 spectral upsampling of an
#: RGB value in [0, 1] may exceed 1 by a few ulps).
RANGE_SLACK = 1e-5
#: The largest float32: a parameter beyond it becomes infinite in Mitsuba.
FLOAT32_MAX = 3.4028234663852886e38


def xml_type(props, name: str) -> str:
    """The XML type of parameter ``name`` as a user wrote it (float, string, rgb, ...)."""
    kind = str(props.type(name)).split(".")[-1]
    return {"Bool": "boolean", "Color": "rgb", "Vector": "point/vector",
            "Object": "nested object", "ResolvedReference": "reference",
            "Reference": "reference"}.get(kind, kind.lower())


def _got(props, name: str) -> str:
    """What a user gave, for an error message: ``a string "no"``."""
    text = props.as_string(name)
    if len(text) > 60 or "\n" in text:
        text = text.splitlines()[0][:57] + "..."
    kind = xml_type(props, name)
    return f"{'an' if kind[0] in 'aeiou' else 'a'} {kind} {text}"


def _missing(plugin: str, name: str, what: str):
    return ParameterError(f"{plugin}: parameter '{name}' is required ({what})")


def _check_range(plugin, name, value, what, minimum, maximum, strict_minimum):
    """Raise when ``value`` lies outside [minimum, maximum] ((minimum, ...] if strict)."""
    rules = []
    ok = not (isinstance(value, float) and math.isnan(value))
    if minimum is not None:
        rules.append(f"> {minimum:g}" if strict_minimum else f">= {minimum:g}")
        ok &= value > minimum if strict_minimum else value >= minimum
    if maximum is not None:
        rules.append(f"<= {maximum:g}")
        ok &= value <= maximum
    if not ok:
        rule = " and ".join(rules) if rules else "a number"
        raise ParameterError(f"{plugin}: parameter '{name}' must be {rule} (got {value:g})")
    return value


def read_float(props, plugin: str, name: str, default, *, minimum=None, maximum=None,
               strict_minimum: bool = False, finite: bool = False):
    """A ``<float>`` (or ``<integer>``) parameter in [minimum, maximum], as a Python float.

    ``strict_minimum`` makes the lower bound exclusive; ``finite`` refuses infinities.
    NaN is always refused. ``default`` is returned unchecked when the parameter is absent.
    """
    if name not in props:
        if default is REQUIRED:
            raise _missing(plugin, name, "a float")
        return default
    if props.type(name) not in (mi.Properties.Type.Float, mi.Properties.Type.Integer):
        raise ParameterError(
            f"{plugin}: parameter '{name}' must be a float (got {_got(props, name)})"
        )
    value = float(props.get(name))
    if finite and not _finite32(value):
        raise ParameterError(f"{plugin}: parameter '{name}' must be a finite float "
                             f"(got {value:g}{_beyond32(value)})")
    return _check_range(plugin, name, value, "a float", minimum, maximum, strict_minimum)


def read_int(props, plugin: str, name: str, default, *, minimum=None, maximum=None):
    """An ``<integer>`` parameter (a ``<float>`` is refused, even 2.0) in [minimum, maximum]."""
    if name not in props:
        if default is REQUIRED:
            raise _missing(plugin, name, "an integer")
        return default
    if props.type(name) != mi.Properties.Type.Integer:
        raise ParameterError(
            f"{plugin}: parameter '{name}' must be an integer (got {_got(props, name)})"
        )
    value = int(props.get(name))
    return _check_range(plugin, name, value, "an integer", minimum, maximum, False)


def read_bool(props, plugin: str, name: str, default):
    """A ``<boolean>`` parameter; ``<string value="no"/>`` or ``<integer value="0"/>`` are
    errors, never read as true or false."""
    if name not in props:
        if default is REQUIRED:
            raise _missing(plugin, name, "a boolean")
        return default
    if props.type(name) != mi.Properties.Type.Bool:
        raise ParameterError(
            f"{plugin}: parameter '{name}' must be a boolean, true or false "
            f"(got {_got(props, name)})"
        )
    return bool(props.get(name))


def read_string(props, plugin: str, name: str, default):
    """A ``<string>`` parameter."""
    if name not in props:
        if default is REQUIRED:
            raise _missing(plugin, name, "a string")
        return default
    if props.type(name) != mi.Properties.Type.String:
        raise ParameterError(
            f"{plugin}: parameter '{name}' must be a string (got {_got(props, name)})"
        )
    return str(props.get(name))


def read_choice(props, plugin: str, name: str, default, options):
    """A ``<string>`` parameter that must be one of ``options`` (any iterable of str)."""
    options = list(options)
    listed = ", ".join(options)
    if name not in props:
        if default is REQUIRED:
            raise _missing(plugin, name, f"one of {listed}")
        return default
    if props.type(name) != mi.Properties.Type.String:
        raise ParameterError(
            f"{plugin}: parameter '{name}' must be one of {listed} (got {_got(props, name)})"
        )
    value = str(props.get(name))
    if value not in options:
        raise ParameterError(
            f"{plugin}: parameter '{name}' must be one of {listed} (got {value!r})")
    return value


def read_point(props, plugin: str, name: str, default):
    """A ``<point>`` or ``<vector>`` parameter, as a ``mi.ScalarPoint3f``."""
    if name not in props:
        if default is REQUIRED:
            raise _missing(plugin, name, "a point")
        return default
    if props.type(name) != mi.Properties.Type.Vector:
        raise ParameterError(
            f"{plugin}: parameter '{name}' must be a point (got {_got(props, name)})"
        )
    return mi.ScalarPoint3f(props.get(name))


# -- textures and spectra ------------------------------------------------------------------

_TEXTURE_TYPES = ("Float", "Integer", "Color", "Spectrum", "Object", "ResolvedReference",
                  "Reference")


def _grid_interaction(spatial: bool):
    """A surface interaction at the check points: a GRID_UV^2 grid of uv cell centres when
    ``spatial``, times the wavelength grid in spectral variants (one wavelength a lane)."""
    n_uv = GRID_UV * GRID_UV if spatial else 1
    n_wl = 1
    if mi.is_spectral:
        n_wl = int(round((GRID_NM[1] - GRID_NM[0]) / GRID_NM_STEP)) + 1
    index = dr.arange(mi.UInt32, n_uv * n_wl)
    si = dr.zeros(mi.SurfaceInteraction3f, n_uv * n_wl)
    if spatial:
        cell = index % n_uv
        u = (mi.Float(cell % GRID_UV) + 0.5) / GRID_UV
        v = (mi.Float(cell // GRID_UV) + 0.5) / GRID_UV
        si.uv = mi.Point2f(u, v)
    if mi.is_spectral:
        wavelength = GRID_NM[0] + GRID_NM_STEP * mi.Float(index // n_uv)
        si.wavelengths = mi.UnpolarizedSpectrum(wavelength)
    si.n = mi.Vector3f(0, 0, 1)
    si.sh_frame = mi.Frame3f(si.n)
    si.wi = mi.Vector3f(0, 0, 1)
    return si


def texture_range(texture) -> tuple[float, float]:
    """(smallest, largest) value of ``texture`` over the check grid (uv positions when it
    is spatially varying, wavelengths in spectral variants; its ``max()`` too when it has
    one). Raises whatever the evaluation raises."""
    si = _grid_interaction(texture.is_spatially_varying())
    value = dr.detach(mi.unpolarized_spectrum(texture.eval(si)))
    low = float(dr.slice(dr.min(value, axis=None)))
    high = float(dr.slice(dr.max(value, axis=None)))
    try:
        high = max(high, float(texture.max()))
    except Exception:  # noqa: BLE001 - Texture::max() is not implemented by every texture
        pass
    return low, high


def _given_values(props, name: str):
    """The numbers of a ``<float>``, ``<integer>`` or ``<rgb>`` parameter, else None."""
    kind = props.type(name)
    if kind in (mi.Properties.Type.Float, mi.Properties.Type.Integer):
        return [float(props.get(name))]
    if kind == mi.Properties.Type.Color:
        return [float(c) for c in props.get(name)]
    return None


def read_texture(props, plugin: str, name: str, default, *, minimum=None, maximum=None,
                 emissive: bool = False, uniform: bool = False,
                 what: str = "a spectrum or texture", noun: str = "a texture with values"):
    """A texture parameter (float, rgb, spectrum or nested texture) in [minimum, maximum].

    ``emissive`` reads it as an emission spectrum (RGB values are illuminants, D65-based
    in spectral variants; ``Properties.get_emissive_texture``), else as a reflectance-type
    texture (``get_texture``). ``uniform`` refuses spatially varying textures. The range is
    checked on the values as written for ``<float>``/``<integer>``/``<rgb>`` and by
    :func:`texture_range` otherwise; a texture whose evaluation fails is refused.
    ``default`` (a float, or None for "absent") is used when the parameter is not given.
    ``what`` (expected type) and ``noun`` (expected range: "``noun`` in [0, 1]") word the
    errors.
    """
    if name not in props:
        if default is REQUIRED:
            raise _missing(plugin, name, what)
        if default is None:
            return None
        texture = props.get_emissive_texture(name, default) if emissive else \
            props.get_texture(name, default)
        return texture
    kind = str(props.type(name)).split(".")[-1]
    if kind not in _TEXTURE_TYPES:
        raise ParameterError(
            f"{plugin}: parameter '{name}' must be {what} (got {_got(props, name)})")
    rule = _rule(minimum, maximum)
    if rule is not None:
        rule = f"{noun} {rule}" if noun else rule
    given = _given_values(props, name)
    if given is not None and not all(_finite32(v) for v in given):
        shown = ", ".join(f"{v:g}" for v in given)
        raise ParameterError(f"{plugin}: parameter '{name}' must be finite (got {shown}"
                             f"{max((_beyond32(v) for v in given), key=len)})")
    if given is not None and rule is not None:
        low, high = min(given), max(given)
        if not _in_range(low, high, minimum, maximum, 0.0):
            shown = ", ".join(f"{v:g}" for v in given)
            raise ParameterError(f"{plugin}: parameter '{name}' must be {rule} (got {shown})")
    try:
        texture = props.get_emissive_texture(name) if emissive else props.get_texture(name)
    except Exception as error:  # noqa: BLE001 - Mitsuba's message does not name our plugin
        raise ParameterError(
            f"{plugin}: parameter '{name}' must be {what} ({first_line(error)})"
        ) from None
    if uniform and texture.is_spatially_varying():
        raise ParameterError(
            f"{plugin}: parameter '{name}' must be a spectrum, not a spatially varying "
            f"texture (got {texture.class_name()})"
        )
    if given is None and rule is not None:
        try:
            low, high = texture_range(texture)
        except Exception as error:  # noqa: BLE001 - refused, never accepted unchecked
            if not mi.is_spectral and "non-spectral" in str(error):  # e.g. a blackbody
                raise ParameterError(
                    f"{plugin}: parameter '{name}': {texture.class_name()} needs a spectral "
                    f"variant (e.g. llvm_ad_spectral; this is {mi.variant()})"
                ) from None
            raise ParameterError(
                f"{plugin}: parameter '{name}' must be {rule}, and {texture.class_name()} "
                f"cannot be evaluated to check it in variant {mi.variant()} "
                f"({first_line(error)})"
            ) from None
        if not (math.isfinite(low) and math.isfinite(high)):
            raise ParameterError(
                f"{plugin}: parameter '{name}' must be finite (got {texture.class_name()} "
                f"with values from {low:g} to {high:g})"
            )
        if not _in_range(low, high, minimum, maximum, RANGE_SLACK):
            raise ParameterError(
                f"{plugin}: parameter '{name}' must be {rule} (got {texture.class_name()} "
                f"with values from {low:g} to {high:g})"
            )
    return texture


def read_reflectance(props, plugin: str, name: str, default):
    """A reflectance texture: values in [0, 1] everywhere (see :func:`read_texture`)."""
    return read_texture(props, plugin, name, default, minimum=0.0, maximum=1.0,
                        what="a reflectance (spectrum or texture)", noun="a reflectance")


def read_spectrum(props, plugin: str, name: str, default, *, minimum=0.0, maximum=None,
                  emissive: bool = True):
    """A spatially uniform spectrum (>= ``minimum``), by default an emission spectrum."""
    return read_texture(props, plugin, name, default, minimum=minimum, maximum=maximum,
                        emissive=emissive, uniform=True, what="a spectrum", noun="")


def _finite32(value: float) -> bool:
    """Finite, and still finite as the float32 that Mitsuba stores (|value| <= FLOAT32_MAX)."""
    return math.isfinite(value) and abs(value) <= FLOAT32_MAX


def _beyond32(value: float) -> str:
    """', beyond float32' for a finite value that float32 makes infinite, else ''."""
    return ", beyond float32" if math.isfinite(value) and abs(value) > FLOAT32_MAX else ""


def _rule(minimum, maximum):
    if minimum is None and maximum is None:
        return None
    if maximum is None:
        return f">= {minimum:g}"
    if minimum is None:
        return f"<= {maximum:g}"
    return f"in [{minimum:g}, {maximum:g}]"


def _in_range(low, high, minimum, maximum, slack):
    if math.isnan(low) or math.isnan(high):
        return False
    if minimum is not None and low < minimum - slack:
        return False
    return not (maximum is not None and high > maximum + slack)
