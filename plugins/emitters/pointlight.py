"""``pointlight``: an isotropic point light in W/sr, W, cd or lm, with a choice of distance laws.

A point at ``position`` that emits the same radiant intensity I (W/sr) in every direction.
A surface point at distance r from the light, whose normal makes the angle theta with the
direction to the light, receives the irradiance E = I falloff(r) cos(theta), so a diffuse
surface of albedo rho shows the radiance rho / pi * E. With the default
``inverse_square`` law it renders exactly like Mitsuba's built-in ``point`` emitter
(same samples, same image up to float rounding) in every variant, and in polarized
variants it emits unpolarized light (a depolarizing Mueller matrix) as ``point`` does.
Only ``inverse_square`` is physical: ``ptracer`` (light tracing) always produces 1/r^2.
With ``source_radius`` > 0 the light is a sphere (the law must then be ``inverse_square``):
``spectrace render`` carries it on a black ``sphere`` shape so that camera and BSDF rays
hit it (``spectrace help sized``).

Parameters
----------

======================  =========  ==============  ====  ==========================================
parameter               type       default         unit  description
======================  =========  ==============  ====  ==========================================
``position``            point      (0, 0, 0)       m     position of the light; or give ``to_world``
                                                         (its translation is used), not both
                                                         |exposed|
``to_world``            transform  identity        --    alternative to ``position``
``intensity``           spectrum   1               W/sr  radiant intensity I (value, tabulated SPD,
                                                         ``blackbody``, ``d65``, RGB); >= 0
                                                         |exposed| |differentiable|
``power``               spectrum   --              W     radiant flux Phi instead of ``intensity``:
                                                         I = Phi / (4 pi); >= 0 |exposed|
                                                         |differentiable|
``luminous_intensity``  float      --              cd    luminous intensity I_v instead; >= 0
                                                         |exposed| |differentiable|
``luminous_flux``       float      --              lm    luminous flux Phi_v instead: I_v = Phi_v /
                                                         (4 pi); >= 0 |exposed| |differentiable|
``spectrum``            spectrum   d65             --    spectral shape of a light given in cd or lm
                                                         (its scale does not matter); only with
                                                         ``luminous_intensity`` or
                                                         ``luminous_flux`` |exposed|
                                                         |differentiable|
``falloff``             string     inverse_square  --    distance law: ``inverse_square``,
                                                         ``inverse_square_epsilon``,
                                                         ``polynomial``, ``windowed``, ``none``
                                                         (see ``spectrace help falloff`` for the
                                                         laws and their parameters ``epsilon``,
                                                         ``kc``, ``kl``, ``kq``, ``radius``)
``source_radius``       float      0               m     radius r of the light: 0 a point; > 0 a
                                                         Lambertian sphere of radiance I / (pi r^2),
                                                         the same I, power and flux, soft shadows,
                                                         seen by the camera (``spectrace help
                                                         sized``); >= 0
``source_sampling``     string     solid_angle     --    how the sphere is sampled: ``solid_angle``
                                                         or ``area`` (``spectrace help opening``)
``sampling_weight``     float      1               --    relative chance that an integrator
                                                         picks this light to sample
                                                         (Mitsuba's emitters) |exposed|
======================  =========  ==============  ====  ==========================================

At most one of ``intensity``, ``power``, ``luminous_intensity`` and ``luminous_flux``
may be given (none: ``intensity`` 1). Lengths are in scene units, metres for the units
above to hold: 100 cd at 1 m give 100 lux.

Formula
-------

::

    E(r, theta) = I falloff(r) cos(theta),        falloff(r) = 1 / r^2 by default
    I = Phi / (4 pi)                               (power: the sphere's 4 pi sr)
    I = I_v s / (683 integral V s dlambda)         (candela; lumens: I_v = Phi_v / (4 pi))

A light of power Phi spreads it over the sphere of area 4 pi r^2: E = Phi / (4 pi r^2)
facing the light. In RGB and mono variants the luminous conversion uses Y(s) integral V
dlambda, Y the luminance of the colour s (see ``spectrace help luminous``), so a light in
cd gives the same lux and the same image in every variant.

Sources
-------

Pharr, Jakob, Humphreys (2023), *Physically Based Rendering* 4th ed., sec. 12.1
(point lights) and 4.4.1 (photometry); Jakob, Speierer, Roussel et al. (2022), Mitsuba 3,
``src/emitters/point.cpp``; CIE (2019), CIE 018:2019 (K_m = 683 lm/W, V(lambda)).

Example
-------

A 3000 K lamp of 800 lm, 2.4 m above the floor, with OpenGL's attenuation::

    <emitter type="pointlight">
        <point name="position" x="0" y="2.4" z="0"/>
        <float name="luminous_flux" value="800"/>
        <spectrum type="blackbody" name="spectrum">
            <float name="temperature" value="3000"/>
        </spectrum>
        <string name="falloff" value="polynomial"/>
        <float name="kc" value="1"/>
        <float name="kq" value="0.5"/>
    </emitter>
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi
from spectrace.plugins import params
from spectrace.plugins.emitters import delta, falloff, opening, sized

from spectrace.errors import ParameterError

PLUGIN = "pointlight"


class PointLight(delta.DeltaLight):
    """Isotropic point light: intensity (W/sr) times a distance falloff law."""

    def __init__(self, props):
        mi.Emitter.__init__(self, props)
        if "position" in props:
            if "to_world" in props:
                raise ParameterError(
                    f"{PLUGIN}: give either parameter 'position' or parameter 'to_world', "
                    "not both"
                )
            position = params.read_point(props, PLUGIN, "position", None)
        else:
            to_world = props.get("to_world", mi.ScalarTransform4f())
            position = mi.ScalarPoint3f(to_world.translation())
        self.position = mi.Point3f(position)
        self._init_emission(props, PLUGIN)
        self.law = falloff.parse_falloff(props, PLUGIN)
        self.source_radius = sized.read_source_radius(props, PLUGIN)
        if self.source_radius > 0:
            sized.check_sized(PLUGIN, self.law, props.get("to_world", None))
            self.sampling = params.read_choice(props, PLUGIN, "source_sampling",
                                               opening.DEFAULT_SAMPLING,
                                               opening.SPHERE_SAMPLING_METHODS)
            # Not Surface: Mitsuba's scene drops top-level Surface emitters (see sized).
            self.m_flags = mi.EmitterFlags.Empty
        else:
            self.m_flags = mi.EmitterFlags.DeltaPosition
            self.m_needs_sample_3 = False
        self._update()

    # -- parameters ---------------------------------------------------------------------

    def _update(self):
        """Recompute the emission scale (I = Phi / (4 pi) for a flux; W per lumen for a
        luminous light) from the traversed parameters, which are never rebound."""
        self.scale = self._emission_scale(falloff.FOUR_PI)
        if self.source_radius > 0:  # L = I / (pi r^2)
            self.scale = self._scaled(mi.Float(1.0)) * dr.rcp(
                opening.sphere_projected_area(mi.Float(self.source_radius)))
        dr.make_opaque(self.position)
        if self.luminous is not None:
            dr.make_opaque(self.scale)

    def traverse(self, callback):
        callback.put("position", self.position, mi.ParamFlags.NonDifferentiable)
        self._traverse_emission(callback)

    def parameters_changed(self, keys):
        # Update in place: mi.traverse holds references to the traversed arrays.
        self._check_emission()
        self._update()

    # -- helpers ------------------------------------------------------------------------

    def _intensity(self, wavelengths, active):
        return self._scaled(self.intensity.eval(self._spectral_si(wavelengths), active))

    # -- sampling and evaluation --------------------------------------------------------

    def sample_ray(self, time, wavelength_sample, sample2, sample3, active=True):
        wavelengths, weight = self.sample_wavelengths(
            dr.zeros(mi.SurfaceInteraction3f), wavelength_sample, active
        )
        if self.source_radius > 0:
            # A point uniform on the sphere, a cosine-distributed direction about its
            # normal: weight L pi A = 4 pi I, as the point light's.
            n = mi.warp.square_to_uniform_sphere(sample2)
            d = mi.Frame3f(n).to_world(mi.warp.square_to_cosine_hemisphere(sample3))
            origin = mi.Point3f(self.position + self.source_radius * n)
            ray = sized.spawn_ray(origin, mi.Normal3f(n), d, time, wavelengths)
            return ray, self._out(weight * dr.pi * self._area())
        ray = mi.Ray3f(
            self.position, mi.warp.square_to_uniform_sphere(sample3), time, wavelengths
        )
        return ray, self._out(weight * falloff.FOUR_PI)

    def sample_direction(self, it, sample, active=True):
        if self.source_radius > 0:
            p, n, pdf = opening.sphere_sample_direction(
                self.position, self.source_radius, it.p, sample, self.sampling)
            ds = sized.direction_sample(self, it, p, n, pdf)
            lit = active & (pdf > 0.0)
            value = self._intensity(it.wavelengths, lit) * dr.rcp(pdf)
            return ds, self._out(dr.select(lit, value, 0.0))
        ds, dist2 = self._direction_sample(it)
        return ds, self._out(self._intensity(it.wavelengths, active) * self.law(dist2))

    def eval_direction(self, it, ds, active=True):
        if self.source_radius > 0:
            lit = active & (dr.dot(ds.d, ds.n) < 0.0)
            return self._out(dr.select(lit, self._intensity(it.wavelengths, lit), 0.0))
        dist2 = dr.squared_norm(ds.p - it.p)
        return self._out(self._intensity(it.wavelengths, active) * self.law(dist2))

    def pdf_direction(self, it, ds, active=True):
        if self.source_radius > 0:
            pdf = opening.sphere_pdf_direction(self.position, self.source_radius, it.p,
                                               ds.p, ds.n, self.sampling)
            return dr.select(active & (dr.dot(ds.d, ds.n) < 0.0), pdf, 0.0)
        return super().pdf_direction(it, ds, active)

    def eval(self, si, active=True):
        if self.source_radius > 0:
            lit = active & (mi.Frame3f.cos_theta(si.wi) > 0.0)
            return self._out(dr.select(lit, self._intensity(si.wavelengths, lit), 0.0))
        return super().eval(si, active)

    def sample_position(self, time, sample, active=True):
        if self.source_radius > 0:
            n = mi.Normal3f(mi.warp.square_to_uniform_sphere(sample))
            ps, weight = sized.position_sample(
                time, mi.Point3f(self.position + self.source_radius * n), n, self._area())
            return ps, weight if self.get_shape() is not None else weight * 0.0
        return self._position_sample(time), mi.Float(1.0)

    def pdf_position(self, ps, active=True):
        if self.source_radius > 0:
            return dr.select(active, dr.rcp(self._area()), 0.0)
        return super().pdf_position(ps, active)

    def _area(self):
        """The sphere's area 4 pi r^2."""
        return 4.0 * opening.sphere_projected_area(mi.Float(self.source_radius))

    def bbox(self):
        if self.source_radius > 0:
            p = mi.ScalarPoint3f(dr.slice(self.position, 0))
            return mi.ScalarBoundingBox3f(p - self.source_radius, p + self.source_radius)
        return super().bbox()

    def to_string(self):
        return (
            f"PointLight[position={self.position}, "
            f"{self._emission_string()}, source_radius={self.source_radius}, "
            f"falloff={self.law!r}]"
        )


mi.register_emitter(PLUGIN, lambda props: PointLight(props))
