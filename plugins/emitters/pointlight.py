"""``pointlight``: an isotropic point light with a choice of distance falloff laws.

A point at ``position`` that emits the radiant intensity I (W/sr) in every direction. A
surface point at distance r from the light, whose normal makes the angle theta with the
direction to the light, receives the irradiance

    E = I * falloff(r) * cos(theta),        falloff(r) = 1 / r^2 by default,

so a diffuse surface of albedo rho shows the radiance rho / pi * E. With the default
``inverse_square`` law it renders exactly like Mitsuba's built-in ``point`` emitter (same
samples, same image up to float rounding).

=============  =================  ===============  ==============================================
parameter      type               default          meaning
=============  =================  ===============  ==============================================
``position``   point              origin           position of the light (or give ``to_world``,
                                                   whose translation is used; not both)
``to_world``   transform          identity         alternative to ``position``
``intensity``  spectrum           1                radiant intensity I in W/sr (any Mitsuba
                                                   spectrum: value, tabulated SPD, ``blackbody``,
                                                   ``d65``, RGB); >= 0
``power``      spectrum           --               radiant flux Phi in W instead of
                                                   ``intensity``: I = Phi / (4 pi); >= 0
``falloff``    string             inverse_square   distance law: ``inverse_square``,
                                                   ``inverse_square_epsilon``, ``polynomial``,
                                                   ``windowed``, ``none`` (see
                                                   ``spectrace.plugins.emitters.falloff`` for the
                                                   laws and their parameters ``epsilon``, ``kc``,
                                                   ``kl``, ``kq``, ``radius``)
=============  =================  ===============  ==============================================

``power`` is the lecture's "intensity / (4 pi r^2)": a light of power Phi spreads it over
the sphere of area 4 pi r^2, E = Phi / (4 pi r^2). Only ``inverse_square`` is physical;
``ptracer`` (light tracing) always produces 1/r^2.

Differentiable parameters (``mi.traverse``): ``intensity`` (or ``power``). ``position``
can be changed (non-differentiable).

Sources: M. Pharr, W. Jakob, G. Humphreys, *Physically Based Rendering* (4th ed.),
section 12.1 "Light Interface / Point Lights"; Mitsuba 3 ``src/emitters/point.cpp``.

XML example::

    <emitter type="pointlight">
        <point name="position" x="0" y="3" z="0"/>
        <blackbody name="intensity" temperature="3000"/>
        <string name="falloff" value="polynomial"/>
        <float name="kc" value="1"/>
        <float name="kq" value="0.5"/>
    </emitter>
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi

from spectrace.plugins.emitters import delta, falloff

PLUGIN = "pointlight"


class PointLight(delta.DeltaLight):
    """Isotropic point light: intensity (W/sr) times a distance falloff law."""

    def __init__(self, props):
        mi.Emitter.__init__(self, props)
        if "position" in props:
            if "to_world" in props:
                raise ValueError(
                    f"{PLUGIN}: give either parameter 'position' or parameter 'to_world', "
                    "not both"
                )
            position = mi.ScalarPoint3f(props.get("position"))
        else:
            to_world = props.get("to_world", mi.ScalarTransform4f())
            position = mi.ScalarPoint3f(to_world.translation())
        self.position = mi.Point3f(position)
        dr.make_opaque(self.position)
        self.intensity, self.from_power = falloff.parse_emission(props, PLUGIN)
        # I = Phi / (4 pi): a constant folded into the kernels.
        self.scale = 1.0 / falloff.FOUR_PI if self.from_power else None
        self.law = falloff.parse_falloff(props, PLUGIN)
        self.m_flags = mi.EmitterFlags.DeltaPosition
        self.m_needs_sample_3 = False

    # -- parameters ---------------------------------------------------------------------

    def traverse(self, callback):
        callback.put("position", self.position, mi.ParamFlags.NonDifferentiable)
        callback.put(self.emission_name, self.intensity, mi.ParamFlags.Differentiable)

    def parameters_changed(self, keys):
        # Update in place: mi.traverse holds references to the traversed arrays.
        dr.make_opaque(self.position)

    # -- helpers ------------------------------------------------------------------------

    def _intensity(self, wavelengths, active):
        return self._scaled(self.intensity.eval(self._spectral_si(wavelengths), active))

    # -- sampling and evaluation --------------------------------------------------------

    def sample_ray(self, time, wavelength_sample, sample2, sample3, active=True):
        wavelengths, weight = self.sample_wavelengths(
            dr.zeros(mi.SurfaceInteraction3f), wavelength_sample, active
        )
        ray = mi.Ray3f(
            self.position, mi.warp.square_to_uniform_sphere(sample3), time, wavelengths
        )
        return ray, weight * falloff.FOUR_PI

    def sample_direction(self, it, sample, active=True):
        ds, dist2 = self._direction_sample(it)
        return ds, self._intensity(it.wavelengths, active) * self.law(dist2)

    def eval_direction(self, it, ds, active=True):
        dist2 = dr.squared_norm(ds.p - it.p)
        return self._intensity(it.wavelengths, active) * self.law(dist2)

    def sample_position(self, time, sample, active=True):
        return self._position_sample(time), mi.Float(1.0)

    def to_string(self):
        return (
            f"PointLight[position={self.position}, "
            f"{self.emission_name}={self.intensity}, "
            f"falloff={self.law!r}]"
        )


mi.register_emitter(PLUGIN, lambda props: PointLight(props))
