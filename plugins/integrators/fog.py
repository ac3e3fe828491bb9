"""Fog laws of the ``local`` integrator: the fraction f(d) of a surface's radiance that
survives a camera distance d.

The rendered radiance is L = f(d) L_surface + (1 - f(d)) L_fog (``fog_color``).

==========================  ======================================  ===================
law                         f(d)                                    parameters
==========================  ======================================  ===================
``none``                    1                                       --
``linear``                  clamp((end - d) / (end - start), 0, 1)  ``fog_start``,
                                                                    ``fog_end``
``exponential``             exp(-density d)                         ``fog_density``
``exponential_squared``     exp(-(density d)^2)                     ``fog_density``
==========================  ======================================  ===================

Source: the fixed-function fog of OpenGL (The OpenGL Graphics System, version 1.5,
section 3.10 "Fog", equations 3.24-3.26), where d is the eye distance.

Each law is a function ``law(d, start, end, density)`` of Dr.Jit arrays and Python
floats; :data:`FOG_LAWS` maps the XML name to it. d may be the largest finite float for
rays that leave the scene: every law then gives 0 (only fog colour) unless it is
``none`` or the density is 0.
"""

from __future__ import annotations

import drjit as dr


def _none(d, start, end, density):
    return dr.full(type(d), 1.0, dr.width(d))


def _linear(d, start, end, density):
    return dr.clip((end - d) / (end - start), 0.0, 1.0)


def _exponential(d, start, end, density):
    return dr.exp(-density * d)


def _exponential_squared(d, start, end, density):
    return dr.exp(-dr.square(density * d))


#: XML name of the fog law -> f(d, start, end, density).
FOG_LAWS = {
    "none": _none,
    "linear": _linear,
    "exponential": _exponential,
    "exponential_squared": _exponential_squared,
}
