"""``spotlight``: a spot light with umbra and penumbra, in W/sr, W, cd or lm.

A point at the origin of ``to_world`` that emits along its local +Z axis, full intensity
inside the penumbra half-angle, none outside the umbra half-angle and blended in between
by a ``cone_falloff`` law; an optional ``texture`` (gobo) is projected like a slide. A
surface point at distance r whose normal makes the angle theta with the direction to the
light receives E = I(alpha) falloff(r) cos(theta), with the distance laws of
``pointlight``. With ``cone_falloff`` = ``linear_angle`` and the default distance law it
renders like Mitsuba's built-in ``spot`` (``cutoff_angle`` = ``umbra_angle``,
``beam_width`` = ``penumbra_angle``: Mitsuba's names are accepted for ours, and with
``cutoff_angle`` alone the penumbra is Mitsuba's default 3/4 of it) in every variant,
unpolarized (a depolarizing Mueller matrix) in polarized ones. With ``source_radius``
the light is a disk facing +Z (see ``spectrace help sized``).

Parameters
----------

======================  =========  ==============  =======  =====================================
parameter               type       default         unit     description
======================  =========  ==============  =======  =====================================
``to_world``            transform  identity        --       placement; the light shines along
                                                            local +Z (use ``lookat``) |exposed|
``intensity``           spectrum   1               W/sr     on-axis radiant intensity I0 (value,
                                                            tabulated SPD, ``blackbody``,
                                                            ``d65``, RGB); >= 0 |exposed|
                                                            |differentiable|
``power``               spectrum   --              W        radiant flux Phi of the cone instead:
                                                            I0 = Phi / Omega (the gobo is not
                                                            counted); >= 0 |exposed|
                                                            |differentiable|
``luminous_intensity``  float      --              cd       on-axis luminous intensity instead;
                                                            >= 0 |exposed| |differentiable|
``luminous_flux``       float      --              lm       luminous flux of the cone with its
                                                            falloff instead: I0_v = Phi_v /
                                                            Omega; >= 0 |exposed|
                                                            |differentiable|
``spectrum``            spectrum   d65             --       spectral shape of a light in cd or lm
                                                            (its scale does not matter); only
                                                            with ``luminous_intensity`` or
                                                            ``luminous_flux`` |exposed|
                                                            |differentiable|
``umbra_angle``         float      30              degrees  outer half-angle u, in (0, 90]: no
                                                            light outside |exposed|
                                                            |differentiable| |discontinuous|
``penumbra_angle``      float      20              degrees  inner half-angle p, in (0, u]: full
                                                            intensity inside |exposed|
                                                            |differentiable|
``cone_falloff``        string     quadratic       --       ``quadratic``, ``smoothstep`` or
                                                            ``linear_angle`` (below)
``falloff``             string     inverse_square  --       distance law and its parameters, as
                                                            for ``pointlight`` (see ``spectrace
                                                            help falloff``)
``texture``             texture    none            --       gobo: a texture projected like a
                                                            slide; its [0, 1]^2 uv square spans
                                                            the umbra cone's tangent plane at
                                                            z = 1 (as the built-in ``spot``);
                                                            its own parameters say which are
                                                            differentiable |exposed|
``source_radius``       float      0               m        radius r of the light: 0 a point;
                                                            > 0 a disk facing local +Z of
                                                            radiance I(omega) / (pi r^2 cos
                                                            gamma), so that far away it is the
                                                            point spot (``spectrace help
                                                            sized``); needs penumbra_angle < 90;
                                                            >= 0
``source_sampling``     string     auto            --       how the disk is sampled: ``auto``
                                                            (by solid angle near it, by area
                                                            farther), ``solid_angle`` or
                                                            ``area`` (``spectrace help
                                                            opening``)
``sampling_weight``     float      1               --       relative chance that an integrator
                                                            picks this light to sample
                                                            (Mitsuba's emitters) |exposed|
======================  =========  ==============  =======  =====================================

At most one of ``intensity``, ``power``, ``luminous_intensity`` and ``luminous_flux``
may be given (none: ``intensity`` 1). Lengths in metres for the photometric units to hold.

Formula
-------

In the direction at the angle alpha from the axis, with
t = clamp((cos alpha - cos u) / (cos p - cos u), 0, 1)::

    I(alpha) = I0 cone(alpha) gobo(alpha)
    cone = t^2                                (quadratic, the default)
    cone = 3 t^2 - 2 t^3                      (smoothstep, as pbrt-v4)
    cone = clamp((u - alpha) / (u - p), 0, 1)  (linear_angle, as Mitsuba's spot; 0 beyond u)

The solid angle Omega = integral of cone(alpha) over the sphere, which turns a flux into
I0, is 2 pi [(1 - cos p) + (cos p - cos u) c] with c = 1/3 (``quadratic``: t is linear in
cos alpha) or 1/2 (``smoothstep``), and 2 pi [1 - (sin u - sin p) / (u - p)] for
``linear_angle``. Luminous quantities become radiant ones as for ``pointlight``:
I0 = I0_v s / (683 integral V s dlambda) (see ``spectrace help luminous``).

``sample_ray`` (light tracing) draws directions uniformly in the umbra cone as the built-in
does; with a gobo, wavelengths are drawn from the texture's spectral density and
``pdf_wavelengths`` reports that density. Changing ``umbra_angle``, ``penumbra_angle`` or
the luminous value through ``mi.traverse`` recomputes the cached cosines and Omega.

With ``source_radius`` r > 0 the spot is a disk of radius r in its local z = 0 plane,
facing +Z, of radiance L(omega) = I(omega) / (pi r^2 cos gamma) (gamma = alpha, the angle
from +Z; 0 behind the disk), so that its intensity far away is I(alpha) above and its flux
the same. ``penumbra_angle`` must then be < 90 degrees (refused otherwise: full intensity at
grazing angles needs an unbounded radiance); with ``umbra_angle`` 90 the cone laws vanish
at the rim and L stays finite.

Sources
-------

Pharr, Jakob, Humphreys (2023), *Physically Based Rendering* 4th ed., sec. 12.2.1
(spotlights, smoothstep falloff); Segal, Akeley (2006), *The OpenGL Graphics System 1.x
Specification*, sec. 2.14.1 (spot cut-off and exponent, the quadratic penumbra's
ancestor); Jakob, Speierer, Roussel et al. (2022), Mitsuba 3, ``src/emitters/spot.cpp``.

Example
-------

A 1000 lm stage spot aimed at the origin from 4 m, smoothstep edge::

    <emitter type="spotlight">
        <transform name="to_world">
            <lookat origin="0, 4, 0" target="0, 0, 0" up="0, 0, 1"/>
        </transform>
        <float name="luminous_flux" value="1000"/>
        <spectrum type="blackbody" name="spectrum">
            <float name="temperature" value="3200"/>
        </spectrum>
        <float name="umbra_angle" value="35"/>
        <float name="penumbra_angle" value="25"/>
        <string name="cone_falloff" value="smoothstep"/>
    </emitter>
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi
from spectrace.plugins import params
from spectrace.plugins.emitters import delta, falloff, luminous, opening, sized

from spectrace.errors import ParameterError

PLUGIN = "spotlight"
#: Smallest cos(penumbra) - cos(umbra) and umbra - penumbra (rad) used as a divisor: a
#: hard-edged cone when the two angles are equal.
MIN_WIDTH = 1e-7
#: Largest ``penumbra_angle`` (excluded) of a sized spot: full intensity at 90 degrees from
#: the disk's normal would need an infinite radiance.
MAX_SIZED_PENUMBRA = 90.0
#: spotlight's half-angles and their names in Mitsuba's built-in ``spot`` (accepted too).
MITSUBA_NAMES = {"umbra_angle": "cutoff_angle", "penumbra_angle": "beam_width"}


def _t(cos_alpha, cos_umbra, inv_cos_width):
    """t = clamp((cos alpha - cos u) / (cos p - cos u), 0, 1)."""
    return dr.clip((cos_alpha - cos_umbra) * inv_cos_width, 0.0, 1.0)


def quadratic(cos_alpha, *, cos_umbra, inv_cos_width, **_):
    """t^2: the quadratic penumbra (the default)."""
    return dr.square(_t(cos_alpha, cos_umbra, inv_cos_width))


def smoothstep(cos_alpha, *, cos_umbra, inv_cos_width, **_):
    """3 t^2 - 2 t^3: pbrt-v4's penumbra."""
    t = _t(cos_alpha, cos_umbra, inv_cos_width)
    return dr.square(t) * dr.fma(t, -2.0, 3.0)


def linear_angle(cos_alpha, *, cos_umbra, umbra_rad, inv_angle_width, **_):
    """(umbra - alpha) / (umbra - penumbra): Mitsuba's built-in ``spot``."""
    ramp = (umbra_rad - dr.safe_acos(cos_alpha)) * inv_angle_width
    return dr.select(cos_alpha > cos_umbra, dr.minimum(ramp, 1.0), 0.0)


def _quadratic_solid_angle(*, cos_umbra, cos_penumbra, **_):
    return dr.two_pi * ((1.0 - cos_penumbra) + (cos_penumbra - cos_umbra) * (1.0 / 3.0))


def _smoothstep_solid_angle(*, cos_umbra, cos_penumbra, **_):
    return dr.two_pi * ((1.0 - cos_penumbra) + (cos_penumbra - cos_umbra) * 0.5)


def _linear_angle_solid_angle(*, umbra_rad, penumbra_rad, **_):
    # (sin u - sin p) / (u - p) = cos((u + p) / 2) * sinc((u - p) / 2), stable as u -> p.
    half = 0.5 * (umbra_rad - penumbra_rad)
    sinc = dr.select(half > 1e-4, dr.sin(half) / dr.maximum(half, 1e-4),
                     1.0 - dr.square(half) * (1.0 / 6.0))
    mean = dr.cos(0.5 * (umbra_rad + penumbra_rad)) * sinc
    return dr.two_pi * (1.0 - mean)


def has_pdf_spectrum(texture) -> bool:
    """Whether ``texture`` implements ``pdf_spectrum`` (Mitsuba's ``bitmap`` does not: its
    ``sample_spectrum`` is Texture's default, uniform over [MI_CIE_MIN, MI_CIE_MAX])."""
    if not mi.is_spectral:
        return True
    try:
        texture.pdf_spectrum(luminous.grid_interaction())
    except RuntimeError as error:
        if "not implemented" in str(error):
            return False
        raise
    return True


def uniform_wavelength_pdf(wavelengths):
    """The density of Mitsuba's default ``Texture::sample_spectrum``: uniform over
    [MI_CIE_MIN, MI_CIE_MAX] nm."""
    inside = (wavelengths >= mi.MI_CIE_MIN) & (wavelengths <= mi.MI_CIE_MAX)
    return dr.select(inside, 1.0 / (mi.MI_CIE_MAX - mi.MI_CIE_MIN), 0.0)


def _angle(props, ours: str, default: float):
    """The half-angle ``ours`` or its Mitsuba ``spot`` name (not both), or ``default``."""
    theirs = MITSUBA_NAMES[ours]
    if ours in props and theirs in props:
        raise ParameterError(
            f"{PLUGIN}: give either parameter '{ours}' or Mitsuba's name for it, "
            f"'{theirs}', not both"
        )
    name = theirs if theirs in props else ours
    return falloff.parse_angle(props, PLUGIN, name, default)


def parse_cone_angles(props) -> tuple[float, float]:
    """``(umbra, penumbra)`` in degrees from ``umbra_angle``/``cutoff_angle`` and
    ``penumbra_angle``/``beam_width`` (Mitsuba's default beam width 3/4 of its cutoff
    when only ``cutoff_angle`` is given), penumbra <= umbra."""
    umbra = _angle(props, "umbra_angle", 30.0)
    mitsuba_default = "cutoff_angle" in props and "penumbra_angle" not in props
    penumbra = _angle(props, "penumbra_angle", 0.75 * umbra if mitsuba_default else 20.0)
    if penumbra > umbra:
        raise ParameterError(
            f"{PLUGIN}: parameter 'penumbra_angle' must be <= umbra_angle "
            f"(got penumbra_angle={penumbra}, umbra_angle={umbra})"
        )
    return umbra, penumbra


#: The cone laws, colour-science's ``*_METHODS`` style: ``cone_falloff`` value ->
#: ``cone(cos_alpha, **angles)``, with ``angles`` the light's cached keywords
#: (:meth:`SpotLight.angles`: ``cos_umbra``, ``cos_penumbra``, ``umbra_rad``,
#: ``penumbra_rad``, ``inv_cos_width``, ``inv_angle_width``; each law takes those it uses).
CONE_METHODS = {
    "quadratic": quadratic,
    "smoothstep": smoothstep,
    "linear_angle": linear_angle,
}
#: ``cone_falloff`` value -> ``Omega(**angles)``, the integral of the law over the sphere.
CONE_SOLID_ANGLE_METHODS = {
    "quadratic": _quadratic_solid_angle,
    "smoothstep": _smoothstep_solid_angle,
    "linear_angle": _linear_angle_solid_angle,
}


class SpotLight(delta.DeltaLight):
    """Spot light: on-axis intensity times a cone profile, a gobo and a distance law."""

    def __init__(self, props):
        mi.Emitter.__init__(self, props)
        self.to_world = falloff.parse_to_world(props)
        self._init_emission(props, PLUGIN)
        umbra, penumbra = parse_cone_angles(props)
        self.cone_name = params.read_choice(props, PLUGIN, "cone_falloff", "quadratic",
                                            CONE_METHODS)
        self.law = falloff.parse_falloff(props, PLUGIN)
        self.texture = params.read_texture(props, PLUGIN, "texture", None, minimum=0.0,
                                           what="a texture (gobo)")
        self.gobo_has_pdf = self.texture is not None and has_pdf_spectrum(self.texture)
        self.umbra_angle = mi.Float(umbra)
        self.penumbra_angle = mi.Float(penumbra)
        self.source_radius = sized.read_source_radius(props, PLUGIN)
        flags = mi.EmitterFlags.DeltaPosition
        if self.source_radius > 0:
            sized.check_sized(PLUGIN, self.law, props.get("to_world", None))
            self.sampling = params.read_choice(props, PLUGIN, "source_sampling",
                                               opening.DEFAULT_DISK_SAMPLING,
                                               opening.DISK_SAMPLING_METHODS)
            if not penumbra < MAX_SIZED_PENUMBRA:
                raise ParameterError(
                    f"{PLUGIN}: parameter 'penumbra_angle' must be < {MAX_SIZED_PENUMBRA:g} "
                    f"with source_radius > 0 (got {penumbra:g}: the disk's radiance I / (pi "
                    "r^2 cos gamma) would be unbounded at grazing angles)"
                )
            # Not Surface: Mitsuba's scene drops top-level Surface emitters (see sized).
            flags = mi.EmitterFlags.Empty
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
        self.scale = self._emission_scale(
            CONE_SOLID_ANGLE_METHODS[self.cone_name](**self.angles()))
        dr.make_opaque(
            self.to_world, self.to_local, self.position, self.umbra_rad, self.penumbra_rad,
            self.cos_umbra, self.cos_penumbra, self.inv_cos_width, self.inv_angle_width,
            self.uv_factor,
        )
        if self.scale is not None:
            dr.make_opaque(self.scale)

    def angles(self) -> dict:
        """The cached angles the cone laws take as keywords (see :data:`CONE_METHODS`)."""
        return {"cos_umbra": self.cos_umbra, "cos_penumbra": self.cos_penumbra,
                "umbra_rad": self.umbra_rad, "penumbra_rad": self.penumbra_rad,
                "inv_cos_width": self.inv_cos_width, "inv_angle_width": self.inv_angle_width}

    def _cone(self, cos_alpha):
        return CONE_METHODS[self.cone_name](cos_alpha, **self.angles())

    def traverse(self, callback):
        self._traverse_emission(callback)
        if self.texture is not None:
            callback.put("texture", self.texture, mi.ParamFlags.Differentiable)
        callback.put("umbra_angle", self.umbra_angle, mi.ParamFlags.Differentiable)
        callback.put("penumbra_angle", self.penumbra_angle, mi.ParamFlags.Differentiable)
        callback.put("to_world", self.to_world, mi.ParamFlags.NonDifferentiable)

    def parameters_changed(self, keys):
        umbra, penumbra = dr.slice(self.umbra_angle), dr.slice(self.penumbra_angle)
        if not (0 < penumbra <= umbra <= 90):
            raise ParameterError(
                f"{PLUGIN}: parameters 'umbra_angle' and 'penumbra_angle' must satisfy "
                f"0 < penumbra_angle <= umbra_angle <= 90 (got {penumbra}, {umbra})"
            )
        self._check_emission()
        self._update()

    # -- helpers ------------------------------------------------------------------------

    def _direction_to_uv(self, local_d):
        inv = dr.rcp(local_d.z * self.uv_factor)
        return mi.Point2f(dr.fma(0.5 * local_d.x, inv, 0.5), dr.fma(0.5 * local_d.y, inv, 0.5))

    def _emitted(self, local_d, wavelengths, time, active):
        """I(alpha) in the local direction ``local_d`` (not normalized)."""
        cone = self._cone(local_d.z * dr.rsqrt(dr.squared_norm(local_d)))
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
        if self.source_radius > 0:  # position on the disk from sample2, direction sample3
            origin, normal = opening.disk_point(self.to_world, self.source_radius, sample2)
            sample2 = sample3
        local_d = mi.warp.square_to_uniform_cone(sample2, self.cos_umbra)
        pdf = mi.warp.square_to_uniform_cone_pdf(local_d, self.cos_umbra)
        si = dr.zeros(mi.SurfaceInteraction3f)
        si.time = time
        si.p = self.position
        if self.texture is not None:
            si.uv = self._direction_to_uv(local_d)
        wavelengths, weight = delta.DeltaLight.sample_wavelengths(self, si, wavelength_sample,
                                                                  active)
        cone = self._cone(local_d.z)
        # Sized: L cos(gamma) A / (pdf_A pdf_omega) = I / pdf_omega, as the point spot.
        if self.source_radius > 0:
            ray = sized.spawn_ray(origin, normal, self.to_world @ local_d, time, wavelengths)
        else:
            ray = mi.Ray3f(self.position, self.to_world @ local_d, time, wavelengths)
        return ray, self._out(weight * (cone / pdf))

    def sample_direction(self, it, sample, active=True):
        if self.source_radius > 0:
            p, n, pdf = opening.disk_sample_direction(
                self.to_world, self.to_local, self.source_radius, it.p, sample, self.sampling)
            ds = sized.direction_sample(self, it, p, n, pdf)
            lit = active & (pdf > 0.0)
            value = self._radiance(self.to_local @ (-ds.d), it.wavelengths, it.time, lit)
            return ds, dr.select(lit, value * dr.rcp(pdf), 0.0)
        ds, dist2 = self._direction_sample(it)
        local_d = self.to_local @ (-ds.d)
        value = self._emitted(local_d, it.wavelengths, it.time, active) * self.law(dist2)
        return ds, self._out(value)

    def eval_direction(self, it, ds, active=True):
        if self.source_radius > 0:
            return self._radiance(self.to_local @ (-ds.d), it.wavelengths, it.time, active)
        d = mi.Vector3f(it.p - ds.p)  # (Point3f - Point3f is a Point3f in Mitsuba's Python)
        local_d = self.to_local @ d
        value = self._emitted(local_d, it.wavelengths, it.time, active)
        return self._out(value * self.law(dr.squared_norm(d)))

    def eval(self, si, active=True):
        if self.source_radius > 0:
            local_d = self.to_local @ si.to_world(si.wi)
            return self._radiance(local_d, si.wavelengths, si.time, active)
        return super().eval(si, active)

    def _radiance(self, local_d, wavelengths, time, active):
        """L = I(omega) / (pi r^2 cos gamma) of the sized spot in the unit local direction
        ``local_d`` (0 behind the disk)."""
        lit = active & (local_d.z > 0.0)
        area = opening.disk_projected_area(self.source_radius, local_d.z)
        value = self._emitted(local_d, wavelengths, time, lit) * dr.rcp(area)
        return self._out(dr.select(lit, value, 0.0))

    def pdf_direction(self, it, ds, active=True):
        if self.source_radius > 0:
            pdf = opening.disk_pdf_direction(self.to_world, self.to_local, self.source_radius,
                                             it.p, ds.p, ds.n, self.sampling)
            return dr.select(active, pdf, 0.0)
        return super().pdf_direction(it, ds, active)

    def sample_position(self, time, sample, active=True):
        if self.source_radius > 0:
            p, n = opening.disk_point(self.to_world, self.source_radius, sample)
            ps, weight = sized.position_sample(time, p, n, self._area())
            return ps, weight if self.get_shape() is not None else weight * 0.0
        ps = self._position_sample(time)
        ps.n = self.to_world @ mi.Vector3f(0.0, 0.0, 1.0)
        ps.uv = mi.Point2f(0.5)
        ps.pdf = 1.0
        return ps, mi.Float(1.0)

    def pdf_position(self, ps, active=True):
        if self.source_radius > 0:
            return dr.select(active, dr.rcp(self._area()), 0.0)
        return super().pdf_position(ps, active)

    def _area(self):
        """The disk's area pi r^2."""
        return opening.disk_projected_area(mi.Float(self.source_radius), 1.0)

    def bbox(self):
        if self.source_radius > 0:
            p = mi.ScalarPoint3f(dr.slice(self.position, 0))
            return mi.ScalarBoundingBox3f(p - self.source_radius, p + self.source_radius)
        return super().bbox()

    def sample_wavelengths(self, si, sample, active=True):
        """Wavelengths and weight of the emission; for the sized spot at the point ``si``
        of the disk towards the world direction ``si.wi`` (what ``ptracer`` asks when it
        connects a visible light to the camera): L(omega) / p(lambda), 0 behind the disk
        or from a disk that is not attached to a shape (invisible)."""
        if self.source_radius <= 0:
            return super().sample_wavelengths(si, sample, active)
        local_d = self.to_local @ si.wi
        si = mi.SurfaceInteraction3f(si)
        if self.texture is not None:
            si.uv = self._direction_to_uv(local_d)
        wavelengths, weight = super().sample_wavelengths(si, sample, active)
        area = opening.disk_projected_area(self.source_radius, local_d.z)
        factor = dr.select(local_d.z > 0.0, self._cone(local_d.z) * dr.rcp(area), 0.0)
        if self.get_shape() is None:
            factor = 0.0
        return wavelengths, weight * factor

    def _sample_spectrum(self, si, samples, active):
        """With a gobo, wavelengths follow the texture (as the built-in ``spot``), weighted
        by the intensity at them."""
        if self.texture is None:
            return super()._sample_spectrum(si, samples, active)
        wavelengths, weight = self.texture.sample_spectrum(si, samples, active)
        si = mi.SurfaceInteraction3f(si)
        si.wavelengths = wavelengths
        return wavelengths, weight * self.intensity.eval(si, active)

    def pdf_wavelengths(self, wavelengths, active=True):
        """The density ``sample_wavelengths`` draws from: the gobo texture's when there is
        one (as ``_sample_spectrum``), the emitted spectrum's otherwise."""
        if self.texture is None:
            return super().pdf_wavelengths(wavelengths, active)
        if self.gobo_has_pdf:
            return self.texture.pdf_spectrum(self._spectral_si(wavelengths), active)
        return uniform_wavelength_pdf(wavelengths)

    def to_string(self):
        return (
            f"SpotLight[to_world={self.to_world}, "
            f"{self._emission_string()}, "
            f"umbra_angle={self.umbra_angle}, penumbra_angle={self.penumbra_angle}, "
            f"cone_falloff={self.cone_name}, falloff={self.law!r}, texture={self.texture}, "
            f"source_radius={self.source_radius}]"
        )


mi.register_emitter(PLUGIN, lambda props: SpotLight(props))
