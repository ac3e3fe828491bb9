"""``spotlight``: a spot light with umbra and penumbra, a choice of cone and distance laws.

A point at the origin of ``to_world`` that emits along its local +Z axis. In the
direction at the angle alpha from the axis its radiant intensity is

    I(alpha) = I0 * cone(alpha) * gobo(alpha),

full (cone = 1) inside the penumbra half-angle, zero outside the umbra half-angle and
blended in between by the ``cone_falloff`` law of

    t = clamp((cos alpha - cos umbra) / (cos penumbra - cos umbra), 0, 1):

====================  ====================================================  ==================
``cone_falloff``      cone(alpha) between penumbra and umbra                source
====================  ====================================================  ==================
``quadratic``         t^2  (default)                                        the lecture
``smoothstep``        3 t^2 - 2 t^3                                         pbrt-v4 SpotLight
``linear_angle``      (umbra - alpha) / (umbra - penumbra), linear in the   Mitsuba's ``spot``
                      angle itself
====================  ====================================================  ==================

A surface point at distance r whose normal makes the angle theta with the direction to
the light receives the irradiance E = I(alpha) * falloff(r) * cos(theta), with the distance
laws of the point light (``falloff``, default 1/r^2). With ``cone_falloff=linear_angle``
and the default distance law it renders like Mitsuba's built-in ``spot`` with
``cutoff_angle`` = ``umbra_angle`` and ``beam_width`` = ``penumbra_angle``.

==================  =========  ==============  ==================================================
parameter           type       default         meaning
==================  =========  ==============  ==================================================
``to_world``        transform  identity        placement; the light shines along local +Z
                                               (use ``look_at``)
``intensity``       spectrum   1               on-axis radiant intensity I0 in W/sr (value,
                                               SPD, ``blackbody``, ``d65``, RGB); >= 0
``power``           spectrum   --              radiant flux Phi in W instead of ``intensity``:
                                               I0 = Phi / Omega, Omega the integral of cone()
                                               over the sphere (below); the gobo is not counted
``umbra_angle``     float      30              outer half-angle in degrees, in (0, 90]: no light
                                               outside
``penumbra_angle``  float      20              inner half-angle in degrees, in (0, umbra]: full
                                               intensity inside
``cone_falloff``    string     quadratic       ``quadratic``, ``smoothstep`` or ``linear_angle``
``falloff``         string     inverse_square  distance law and its parameters, as for
                                               ``pointlight`` (``inverse_square``,
                                               ``inverse_square_epsilon``, ``polynomial``,
                                               ``windowed``, ``none``)
``texture``         texture    none            gobo: a texture projected like a slide; its
                                               [0, 1]^2 uv square spans the umbra cone's
                                               tangent plane at z = 1 (as the built-in ``spot``)
==================  =========  ==============  ==================================================

Solid angle Omega = integral of cone(alpha) over the sphere, with p, u the penumbra and
umbra half-angles: 2 pi [(1 - cos p) + (cos p - cos u) c] with c = 1/3 (``quadratic``,
the integral of t^2 dt since t is linear in cos alpha) or 1/2 (``smoothstep``), and
2 pi [1 - (sin u - sin p) / (u - p)] for ``linear_angle``.

``sample_ray`` (light tracing) samples directions uniformly in the umbra cone as the built-in
does. Only the ``inverse_square`` law is physical: ``ptracer`` always produces 1/r^2.
Differentiable parameters (``mi.traverse``): ``intensity`` (or ``power``), ``umbra_angle``,
``penumbra_angle``, ``texture``; ``to_world`` can be changed (non-differentiable).
``parameters_changed`` recomputes the cached cosines.

Sources: pbrt-v4 (M. Pharr, W. Jakob, G. Humphreys, *Physically Based Rendering*, 4th ed.,
section 12.2.1 "Spotlights"); Mitsuba 3 ``src/emitters/spot.cpp``.

XML example::

    <emitter type="spotlight">
        <transform name="to_world">
            <lookat origin="0, 4, 0" target="0, 0, 0" up="0, 0, 1"/>
        </transform>
        <float name="intensity" value="20"/>
        <float name="umbra_angle" value="35"/>
        <float name="penumbra_angle" value="25"/>
        <string name="cone_falloff" value="smoothstep"/>
    </emitter>
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi

from spectrace.plugins.emitters import delta, falloff

PLUGIN = "spotlight"
#: Smallest cos(penumbra) - cos(umbra) and umbra - penumbra (rad) used as a divisor: a
#: hard-edged cone when the two angles are equal.
MIN_WIDTH = 1e-7


class Quadratic:
    """t^2: the lecture's penumbra."""

    @staticmethod
    def profile(light, cos_alpha):
        return dr.square(dr.clip((cos_alpha - light.cos_umbra) * light.inv_cos_width, 0.0, 1.0))

    @staticmethod
    def solid_angle(light):
        cos_p, cos_u = light.cos_penumbra, light.cos_umbra
        return dr.two_pi * ((1.0 - cos_p) + (cos_p - cos_u) * (1.0 / 3.0))


class Smoothstep:
    """3 t^2 - 2 t^3: pbrt-v4's penumbra."""

    @staticmethod
    def profile(light, cos_alpha):
        t = dr.clip((cos_alpha - light.cos_umbra) * light.inv_cos_width, 0.0, 1.0)
        return dr.square(t) * dr.fma(t, -2.0, 3.0)

    @staticmethod
    def solid_angle(light):
        cos_p, cos_u = light.cos_penumbra, light.cos_umbra
        return dr.two_pi * ((1.0 - cos_p) + (cos_p - cos_u) * 0.5)


class LinearAngle:
    """(umbra - alpha) / (umbra - penumbra): Mitsuba's built-in ``spot``."""

    @staticmethod
    def profile(light, cos_alpha):
        ramp = (light.umbra_rad - dr.safe_acos(cos_alpha)) * light.inv_angle_width
        return dr.select(cos_alpha > light.cos_umbra, dr.minimum(ramp, 1.0), 0.0)

    @staticmethod
    def solid_angle(light):
        # (sin u - sin p) / (u - p) = cos((u + p) / 2) * sinc((u - p) / 2), stable as u -> p.
        half = 0.5 * (light.umbra_rad - light.penumbra_rad)
        sinc = dr.select(half > 1e-4, dr.sin(half) / dr.maximum(half, 1e-4),
                         1.0 - dr.square(half) * (1.0 / 6.0))
        mean = dr.cos(0.5 * (light.umbra_rad + light.penumbra_rad)) * sinc
        return dr.two_pi * (1.0 - mean)


#: The one mapping from ``cone_falloff`` to its law.
CONE_FALLOFFS = {
    "quadratic": Quadratic,
    "smoothstep": Smoothstep,
    "linear_angle": LinearAngle,
}


class SpotLight(delta.DeltaLight):
    """Spot light: on-axis intensity times a cone profile, a gobo and a distance law."""

    def __init__(self, props):
        mi.Emitter.__init__(self, props)
        self.to_world = falloff.parse_to_world(props)
        self.intensity, self.from_power = falloff.parse_emission(props, PLUGIN)
        umbra = falloff.parse_angle(props, PLUGIN, "umbra_angle", 30.0)
        penumbra = falloff.parse_angle(props, PLUGIN, "penumbra_angle", 20.0)
        if penumbra > umbra:
            raise ValueError(
                f"{PLUGIN}: parameter 'penumbra_angle' must be <= umbra_angle "
                f"(got penumbra_angle={penumbra}, umbra_angle={umbra})"
            )
        cone_name = props.get("cone_falloff", "quadratic")
        self.cone = CONE_FALLOFFS.get(cone_name)
        if self.cone is None:
            raise ValueError(
                f"{PLUGIN}: parameter 'cone_falloff' must be one of "
                f"{', '.join(CONE_FALLOFFS)} (got {cone_name!r})"
            )
        self.cone_name = cone_name
        self.law = falloff.parse_falloff(props, PLUGIN)
        self.texture = props.get_texture("texture") if "texture" in props else None
        self.umbra_angle = mi.Float(umbra)
        self.penumbra_angle = mi.Float(penumbra)
        flags = mi.EmitterFlags.DeltaPosition
        if self.texture is not None:
            flags = flags | mi.EmitterFlags.SpatiallyVarying
        self.m_flags = flags
        self._update()

    # -- parameters ---------------------------------------------------------------------

    def _update(self):
        """Recompute the cached angles, cosines, transforms and power scale (from the
        traversed parameters, which are never rebound: mi.traverse holds references)."""
        self.to_local = self.to_world.inverse()
        self.position = self.to_world.translation()
        self.umbra_rad = dr.deg2rad(mi.Float(self.umbra_angle))
        self.penumbra_rad = dr.deg2rad(mi.Float(self.penumbra_angle))
        self.cos_umbra = dr.cos(self.umbra_rad)
        self.cos_penumbra = dr.cos(self.penumbra_rad)
        self.inv_cos_width = dr.rcp(dr.maximum(self.cos_penumbra - self.cos_umbra, MIN_WIDTH))
        self.inv_angle_width = dr.rcp(dr.maximum(self.umbra_rad - self.penumbra_rad, MIN_WIDTH))
        self.uv_factor = dr.tan(self.umbra_rad)
        self.scale = dr.rcp(self.cone.solid_angle(self)) if self.from_power else None
        dr.make_opaque(
            self.to_world, self.to_local, self.position, self.umbra_rad, self.penumbra_rad,
            self.cos_umbra, self.cos_penumbra, self.inv_cos_width, self.inv_angle_width,
            self.uv_factor,
        )
        if self.scale is not None:
            dr.make_opaque(self.scale)

    def traverse(self, callback):
        callback.put(self.emission_name, self.intensity, mi.ParamFlags.Differentiable)
        if self.texture is not None:
            callback.put("texture", self.texture, mi.ParamFlags.Differentiable)
        callback.put("umbra_angle", self.umbra_angle, mi.ParamFlags.Differentiable)
        callback.put("penumbra_angle", self.penumbra_angle, mi.ParamFlags.Differentiable)
        callback.put("to_world", self.to_world, mi.ParamFlags.NonDifferentiable)

    def parameters_changed(self, keys):
        umbra, penumbra = dr.slice(self.umbra_angle), dr.slice(self.penumbra_angle)
        if not (0 < penumbra <= umbra <= 90):
            raise ValueError(
                f"{PLUGIN}: parameters 'umbra_angle' and 'penumbra_angle' must satisfy "
                f"0 < penumbra_angle <= umbra_angle <= 90 (got {penumbra}, {umbra})"
            )
        self._update()

    # -- helpers ------------------------------------------------------------------------

    def _direction_to_uv(self, local_d):
        inv = dr.rcp(local_d.z * self.uv_factor)
        return mi.Point2f(dr.fma(0.5 * local_d.x, inv, 0.5), dr.fma(0.5 * local_d.y, inv, 0.5))

    def _emitted(self, local_d, wavelengths, time, active):
        """I(alpha) in the local direction ``local_d`` (not normalized)."""
        cone = self.cone.profile(self, local_d.z * dr.rsqrt(dr.squared_norm(local_d)))
        si = self._spectral_si(wavelengths)
        value = self.intensity.eval(si, active)
        if self.texture is not None:
            si.time = time
            si.uv = self._direction_to_uv(local_d)
            value = value * self.texture.eval(si, active & (cone > 0.0))
        if self.scale is not None:
            cone = cone * self.scale
        return value * cone

    # -- sampling and evaluation --------------------------------------------------------

    def sample_ray(self, time, wavelength_sample, sample2, sample3, active=True):
        local_d = mi.warp.square_to_uniform_cone(sample2, self.cos_umbra)
        pdf = mi.warp.square_to_uniform_cone_pdf(local_d, self.cos_umbra)
        si = dr.zeros(mi.SurfaceInteraction3f)
        si.time = time
        si.p = self.position
        if self.texture is not None:
            si.uv = self._direction_to_uv(local_d)
        wavelengths, weight = self.sample_wavelengths(si, wavelength_sample, active)
        cone = self.cone.profile(self, local_d.z)
        ray = mi.Ray3f(self.position, self.to_world @ local_d, time, wavelengths)
        return ray, weight * (cone / pdf)

    def sample_direction(self, it, sample, active=True):
        ds, dist2 = self._direction_sample(it)
        local_d = self.to_local @ (-ds.d)
        return ds, self._emitted(local_d, it.wavelengths, it.time, active) * self.law(dist2)

    def eval_direction(self, it, ds, active=True):
        d = mi.Vector3f(it.p - ds.p)  # (Point3f - Point3f is a Point3f in Mitsuba's Python)
        local_d = self.to_local @ d
        value = self._emitted(local_d, it.wavelengths, it.time, active)
        return value * self.law(dr.squared_norm(d))

    def sample_position(self, time, sample, active=True):
        ps = self._position_sample(time)
        ps.n = self.to_world @ mi.Vector3f(0.0, 0.0, 1.0)
        ps.uv = mi.Point2f(0.5)
        ps.pdf = 1.0
        return ps, mi.Float(1.0)

    def _sample_spectrum(self, si, samples, active):
        """With a gobo, wavelengths follow the texture (as the built-in ``spot``), weighted
        by the intensity at them."""
        if self.texture is None:
            return super()._sample_spectrum(si, samples, active)
        wavelengths, weight = self.texture.sample_spectrum(si, samples, active)
        si = mi.SurfaceInteraction3f(si)
        si.wavelengths = wavelengths
        return wavelengths, weight * self.intensity.eval(si, active)

    def to_string(self):
        return (
            f"SpotLight[to_world={self.to_world}, "
            f"{self.emission_name}={self.intensity}, "
            f"umbra_angle={self.umbra_angle}, penumbra_angle={self.penumbra_angle}, "
            f"cone_falloff={self.cone_name}, falloff={self.law!r}, texture={self.texture}]"
        )


mi.register_emitter(PLUGIN, lambda props: SpotLight(props))
