"""``fog``: the fog laws of the ``local`` integrator (helper page, not a plugin).

The ``fog`` parameter of ``local`` picks the fraction f(d) of a surface's radiance that
survives the camera distance d; the rest is replaced by the fog's radiance:
L = f(d) L_surface + (1 - f(d)) fog_color. Each law is a function
``law(d, start=..., end=..., density=...)`` of Dr.Jit arrays and Python floats;
:data:`FOG_METHODS` maps the XML name to it. d may be the largest finite float for rays
that leave the scene: every law then gives 0 (only fog colour) unless it is ``none`` or
the density is 0.

Parameters
----------

Set on ``local`` (see ``spectrace help local``):

===============  ======  =======  ====  ==============================================
parameter        type    default  unit  description
===============  ======  =======  ====  ==============================================
``fog``          string  none     --    the law: ``none``, ``linear``, ``exponential``
                                        or ``exponential_squared`` (below)
``fog_start``    float   0        m     ``linear``: distance where fog begins, >= 0
``fog_end``      float   1        m     ``linear``: distance of full fog, > fog_start
``fog_density``  float   1        1/m   exponential laws: density, >= 0
===============  ======  =======  ====  ==============================================

Formula
-------

::

    none                   f(d) = 1
    linear                 f(d) = clamp((end - d) / (end - start), 0, 1)
    exponential            f(d) = exp(-density d)
    exponential_squared    f(d) = exp(-(density d)^2)

Sources
-------

Segal, Akeley (2003), *The OpenGL Graphics System 1.5 Specification*, sec. 3.10 "Fog",
equations 3.24-3.26 (d is the eye distance there too).

Example
-------

Linear fog from 2 m to 12 m::

    <integrator type="local">
        <string name="fog" value="linear"/>
        <float name="fog_start" value="2"/>
        <float name="fog_end" value="12"/>
        <rgb name="fog_color" value="0.7, 0.7, 0.75"/>
    </integrator>
"""

from __future__ import annotations

import drjit as dr


def _none(d, **_):
    return dr.full(type(d), 1.0, dr.width(d))


def _linear(d, *, start, end, **_):
    return dr.clip((end - d) / (end - start), 0.0, 1.0)


def _exponential(d, *, density, **_):
    return dr.exp(-density * d)


def _exponential_squared(d, *, density, **_):
    return dr.exp(-dr.square(density * d))


#: The fog laws, colour-science's ``*_METHODS`` style: ``fog`` value ->
#: ``f(d, **parameters)`` with the keywords ``start``, ``end``, ``density`` (each law takes
#: those it uses).
FOG_METHODS = {
    "none": _none,
    "linear": _linear,
    "exponential": _exponential,
    "exponential_squared": _exponential_squared,
}
