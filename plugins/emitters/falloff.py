"""``falloff``: the distance laws of spectrace's lights (helper page, not a plugin).

The ``falloff`` parameter of ``pointlight``, ``spotlight`` and ``ieslight`` picks how the
light fades with the distance r between the light and the lit point. The law multiplies the
radiant intensity I (W/sr) to give the irradiance on a surface facing the light,
E = I falloff(r) (W/m^2 for ``inverse_square`` with r in metres). The law's parameters sit
beside ``falloff`` on the light; a parameter of another law is reported by Mitsuba as
unused. Only ``inverse_square`` is physically consistent: light tracing (``ptracer``,
which starts paths with ``sample_ray``) produces 1/r^2 through the density of the rays it
traces and cannot apply another law; integrators that connect to the light (``direct``,
``path``, ``prb``, ``local``, ``illuminance``) apply every law. A helper module executed
before the lights (see ``spectrace.plugins.PLUGIN_MODULES``).

Parameters
----------

===========  ======  ==============  =====  =======================================================
parameter    type    default         unit   description
===========  ======  ==============  =====  =======================================================
``falloff``  string  inverse_square  --     the law: ``inverse_square``, ``inverse_square_epsilon``,
                                            ``polynomial``, ``windowed`` or ``none`` (below)
``epsilon``  float   0.01            m      offset of ``inverse_square_epsilon`` (>= 0) and smallest
                                            distance of ``windowed`` (> 0)
``kc``       float   0               m^2    constant term of ``polynomial``; >= 0
``kl``       float   0               m      linear term of ``polynomial``; >= 0
``kq``       float   1               --     quadratic term of ``polynomial``; >= 0; kc, kl, kq not
                                            all 0
``radius``   float   (required)      m      radius R of ``windowed``, where the light reaches 0; > 0
===========  ======  ==============  =====  =======================================================

Formula
-------

::

    inverse_square           falloff(r) = 1 / r^2
    inverse_square_epsilon   falloff(r) = 1 / (r + epsilon)^2
    polynomial               falloff(r) = 1 / (kc + kl r + kq r^2)
    windowed                 falloff(r) = clamp(1 - (r / R)^4, 0, 1)^2 / max(r^2, epsilon^2)
    none                     falloff(r) = 1

Sources
-------

Segal, Akeley (2006), *The OpenGL Graphics System 1.x Specification*, sec. 2.14.1
(``GL_CONSTANT_ATTENUATION``, ``GL_LINEAR_ATTENUATION``, ``GL_QUADRATIC_ATTENUATION``:
``polynomial``); Karis (2013), "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course
*Physically Based Shading in Theory and Practice* (``windowed``: reaches exactly zero at
r = R so that far lights can be culled); Pharr, Jakob, Humphreys (2023), *Physically Based
Rendering* 4th ed., sec. 12.1 (the inverse square law).

Example
-------

A light whose reach ends at 8 m::

    <emitter type="pointlight">
        <point name="position" x="0" y="2" z="0"/>
        <float name="intensity" value="10"/>
        <string name="falloff" value="windowed"/>
        <float name="radius" value="8"/>
    </emitter>
"""

from __future__ import annotations

import math

import drjit as dr
import mitsuba as mi
from spectrace.plugins import params

from spectrace.errors import ParameterError

DEFAULT_LAW = "inverse_square"


def inverse_square(dist2):
    """1 / r^2: the physical law of a point source."""
    return dr.rcp(dist2)


def inverse_square_epsilon(dist2, *, epsilon):
    """1 / (r + epsilon)^2: finite (1/epsilon^2) at the light."""
    return dr.rcp(dr.square(dr.sqrt(dist2) + epsilon))


def polynomial(dist2, *, kc, kl, kq):
    """1 / (kc + kl r + kq r^2): OpenGL's constant, linear and quadratic attenuation (the
    terms of value 0 are left out of the kernel)."""
    denominator = kq * dist2
    if kl != 0:
        denominator = denominator + kl * dr.sqrt(dist2)
    if kc != 0:
        denominator = denominator + kc
    return dr.rcp(denominator)


def windowed(dist2, *, radius, epsilon):
    """clamp(1 - (r/R)^4, 0, 1)^2 / max(r^2, eps^2): Karis' windowed inverse square."""
    window = dr.clip(1.0 - dr.square(dist2) * (1.0 / radius**4), 0.0, 1.0)
    return dr.square(window) / dr.maximum(dist2, epsilon**2)


def no_falloff(dist2):
    """1: the light does not fade with distance."""
    return 1.0


#: The distance laws, colour-science's ``*_METHODS`` style: ``falloff`` value ->
#: ``law(dist2, **parameters)`` of the squared distance (a Dr.Jit Float) and the law's
#: keyword parameters (Python floats), giving the attenuation factor.
FALLOFF_METHODS = {
    "inverse_square": inverse_square,
    "inverse_square_epsilon": inverse_square_epsilon,
    "polynomial": polynomial,
    "windowed": windowed,
    "none": no_falloff,
}


def _epsilon(props, plugin: str, strict: bool) -> float:
    return params.read_float(props, plugin, "epsilon", 0.01, minimum=0.0,
                             strict_minimum=strict, finite=True)


def _polynomial_parameters(props, plugin: str) -> dict:
    terms = {name: params.read_float(props, plugin, name, default, minimum=0.0, finite=True)
             for name, default in (("kc", 0.0), ("kl", 0.0), ("kq", 1.0))}
    if not any(terms.values()):
        raise ParameterError(
            f"{plugin}: parameters 'kc', 'kl', 'kq' of the polynomial falloff must not "
            "all be 0 (the attenuation 1/(kc + kl r + kq r^2) would be infinite)"
        )
    return terms


def _windowed_parameters(props, plugin: str) -> dict:
    if "radius" not in props:
        raise ParameterError(f"{plugin}: falloff 'windowed' needs parameter 'radius' (> 0, m)")
    radius = params.read_float(props, plugin, "radius", None, minimum=0.0,
                               strict_minimum=True, finite=True)
    return {"radius": radius, "epsilon": _epsilon(props, plugin, True)}


#: ``falloff`` value -> reader of the law's keyword parameters from the light's properties
#: (validated, one-line errors naming them); laws without parameters are absent.
FALLOFF_PARAMETERS = {
    "inverse_square_epsilon": lambda props, plugin: {"epsilon": _epsilon(props, plugin,
                                                                         False)},
    "polynomial": _polynomial_parameters,
    "windowed": _windowed_parameters,
}


class Law:
    """A distance law bound to its parameters: ``law(dist2)`` is
    ``FALLOFF_METHODS[name](dist2, **parameters)``; ``repr`` names it with them."""

    def __init__(self, name: str, parameters: dict):
        self.name, self.parameters = name, parameters
        self.function = FALLOFF_METHODS[name]

    def __call__(self, dist2):
        return self.function(dist2, **self.parameters)

    def __repr__(self):
        if not self.parameters:
            return self.name
        shown = ", ".join(f"{k}={v}" for k, v in self.parameters.items())
        return f"{self.name}({shown})"


def parse_falloff(props, plugin: str) -> Law:
    """The distance law named by ``props['falloff']``, its parameters read and validated
    (``ValueError`` naming the parameter on a bad value)."""
    name = params.read_choice(props, plugin, "falloff", DEFAULT_LAW, FALLOFF_METHODS)
    reader = FALLOFF_PARAMETERS.get(name)
    return Law(name, {} if reader is None else reader(props, plugin))


def parse_angle(props, plugin: str, name: str, default: float) -> float:
    """A half-angle in degrees from ``props``, in (0, 90]."""
    return params.read_float(props, plugin, name, default, minimum=0.0, maximum=90.0,
                             strict_minimum=True)


FOUR_PI = 4.0 * math.pi


def parse_to_world(props) -> mi.Transform4f:
    """The light's ``to_world`` transform (identity when absent), in single precision
    with the inverse computed by the parser (as the built-in emitters get it)."""
    if "to_world" not in props:
        return mi.Transform4f()
    to_world = props.get("to_world")
    return mi.Transform4f(
        mi.Matrix4f(mi.ScalarMatrix4f(to_world.matrix)),
        mi.Matrix4f(mi.ScalarMatrix4f(to_world.inverse_transpose)),
    )


def shifted_wavelength_samples(sample):
    """The wavelength samples of ``sample`` shifted over the spectral channels
    (``mi.sample_shifted``, stratified hero wavelengths); an empty array in RGB variants."""
    return mi.sample_shifted(sample) if mi.is_spectral else mi.Color0f()
