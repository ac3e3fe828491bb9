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

DEFAULT_LAW = "inverse_square"


class InverseSquare:
    """1 / r^2: the physical law of a point source."""

    def __init__(self, props, plugin: str):
        pass

    def __call__(self, dist2):
        return dr.rcp(dist2)

    def __repr__(self):
        return "inverse_square"


class InverseSquareEpsilon:
    """1 / (r + epsilon)^2: finite (1/epsilon^2) at the light."""

    def __init__(self, props, plugin: str):
        self.epsilon = params.read_float(props, plugin, "epsilon", 0.01, minimum=0.0,
                                         finite=True)

    def __call__(self, dist2):
        return dr.rcp(dr.square(dr.sqrt(dist2) + self.epsilon))

    def __repr__(self):
        return f"inverse_square_epsilon(epsilon={self.epsilon})"


class Polynomial:
    """1 / (kc + kl r + kq r^2): OpenGL's constant, linear and quadratic attenuation."""

    def __init__(self, props, plugin: str):
        self.kc, self.kl, self.kq = (
            params.read_float(props, plugin, name, default, minimum=0.0, finite=True)
            for name, default in (("kc", 0.0), ("kl", 0.0), ("kq", 1.0))
        )
        if self.kc == self.kl == self.kq == 0:
            raise ValueError(
                f"{plugin}: parameters 'kc', 'kl', 'kq' of the polynomial falloff must not "
                "all be 0 (the attenuation 1/(kc + kl r + kq r^2) would be infinite)"
            )

    def __call__(self, dist2):
        denominator = self.kq * dist2
        if self.kl != 0:
            denominator = denominator + self.kl * dr.sqrt(dist2)
        if self.kc != 0:
            denominator = denominator + self.kc
        return dr.rcp(denominator)

    def __repr__(self):
        return f"polynomial(kc={self.kc}, kl={self.kl}, kq={self.kq})"


class Windowed:
    """clamp(1 - (r/R)^4, 0, 1)^2 / max(r^2, eps^2): Karis' windowed inverse square."""

    def __init__(self, props, plugin: str):
        if "radius" not in props:
            raise ValueError(f"{plugin}: falloff 'windowed' needs parameter 'radius' (> 0, m)")
        self.radius = params.read_float(props, plugin, "radius", None, minimum=0.0,
                                        strict_minimum=True, finite=True)
        self.epsilon = params.read_float(props, plugin, "epsilon", 0.01, minimum=0.0,
                                         strict_minimum=True, finite=True)
        self.inv_radius4 = 1.0 / self.radius**4
        self.epsilon2 = self.epsilon**2

    def __call__(self, dist2):
        window = dr.clip(1.0 - dr.square(dist2) * self.inv_radius4, 0.0, 1.0)
        return dr.square(window) / dr.maximum(dist2, self.epsilon2)

    def __repr__(self):
        return f"windowed(radius={self.radius}, epsilon={self.epsilon})"


class NoFalloff:
    """1: the light does not fade with distance."""

    def __init__(self, props, plugin: str):
        pass

    def __call__(self, dist2):
        return 1.0

    def __repr__(self):
        return "none"


#: The one mapping from the lights' ``falloff`` value to its law.
FALLOFF_LAWS = {
    "inverse_square": InverseSquare,
    "inverse_square_epsilon": InverseSquareEpsilon,
    "polynomial": Polynomial,
    "windowed": Windowed,
    "none": NoFalloff,
}


def parse_falloff(props, plugin: str):
    """The distance law named by ``props['falloff']``, its parameters read and validated.

    The returned object is called with the squared distance (a Dr.Jit Float) and gives
    the attenuation factor. Raises ``ValueError`` naming the parameter on a bad value.
    """
    name = params.read_choice(props, plugin, "falloff", DEFAULT_LAW, FALLOFF_LAWS)
    return FALLOFF_LAWS[name](props, plugin)


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
