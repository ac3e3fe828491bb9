"""``illuminance``: the illuminance E_v in lux on the first surface each camera ray meets.

A measuring integrator for lighting design: for each camera ray it finds the first surface
the ray meets (or, with ``plane_point`` and ``plane_normal``, the point where the ray
crosses a virtual work plane) and estimates the illuminance there, the luminous flux per
unit area arriving on the side of the surface that the camera sees, in lux (lm/m^2) when
scene units are metres. The number comes out in an AOV channel ``lux`` of the film,
exactly, in every variant; the colour channels hold a grey preview of it.

Parameters
----------

=================  =======  =======  ====  ====================================================
parameter          type     default  unit  description
=================  =======  =======  ====  ====================================================
``max_depth``      integer  1        --    1: direct light only; K > 1 adds light reflected up
                                           to K - 1 times before it arrives (path-traced
                                           incident radiance, cosine weighted); -1: no limit
``shadows``        boolean  true     --    test the visibility of every light sample (direct
                                           light at the measured point; the interreflected
                                           light is always shadowed)
``rr_depth``       integer  5        --    depth from which the interreflected paths use
                                           Russian roulette (Mitsuba's ``path``)
``plane_point``    point    --       m     a point of the virtual work plane; with
                                           ``plane_normal`` the illuminance is measured where
                                           camera rays cross this plane
``plane_normal``   vector   --       --    normal of the work plane: the illuminance arrives on
                                           the side it points to (0, 1, 0: horizontal
                                           illuminance of a floor-parallel plane)
=================  =======  =======  ====  ====================================================

AOV channels (after the film's own channels, in this order): ``lux``, the illuminance of
each camera sample (0 where nothing is measured), and ``measured``, 1 where the sample
measured a point and 0 where it did not (a ray that hits nothing; on the work plane: a ray
parallel to it, crossing it behind the camera, or stopped by a surface before it). A
pixel's mean illuminance over its measured samples is lux / measured (where measured > 0).
Scene-level samplers and films are kept; use a ``box`` reconstruction filter for each
pixel to be the mean over its footprint.

Formula
-------

::

    E_v = K_m integral V(lambda) E(lambda) dlambda           (spectral variants)
    E_v = K_m Y(E) integral V dlambda                        (RGB and monochrome variants)
    Y = 0.2126 R + 0.7152 G + 0.0722 B (RGB), E (mono);  integral V dlambda = 106.857 nm
    E(lambda) = integral over the hemisphere of n of L_i(omega, lambda) cos(theta) domega

with K_m = 683 lm/W and V the CIE photopic efficiency, the same convention as the
luminous units of spectrace's lights, so that 100 cd at 1 m give 100 lux in every
variant. Spectral variants draw their own wavelengths for the measurement from V
(importance sampling, four stratified hero wavelengths): E_v is estimated as
K_m integral(V) mean_i E(lambda_i), unaffected by the sensor's wavelengths, response or
white point (they need random samples: a ``stratified`` sampler without jitter would draw
the same wavelengths at every pixel). The estimator of E is unbiased:

* delta lights (``pointlight``, ``spotlight``, ``ieslight``, Mitsuba's ``point``,
  ``spot``, ``directional``): the exact contribution of every light, each tested with a
  shadow ray, summed (no light is picked at random);
* other lights (area lights, ``constant``, ``envmap``): one sample of each light's own
  sampling and one cosine-weighted direction per camera sample, combined with the balance
  heuristic of multiple importance sampling (with ``shadows`` false: the light samples
  alone, unshadowed);
* ``max_depth`` > 1: along the cosine-weighted direction, pi times the radiance reflected
  towards the measured point by the surface it hits, from Mitsuba's ``path`` integrator
  (``max_depth``, emitters hidden at its first hit: their emission is counted above).

On a surface the normal is the shading normal, turned towards the camera. The measured
point needs no BSDF: the surface's material plays no part at the first hit.

Sources
-------

CIE (2019), CIE 018:2019 *The Basis of Physical Photometry* (K_m, V); CIE (2020), CIE S
017:2020 *ILV*, 17-21-060 (illuminance); Pharr, Jakob, Humphreys (2023), *Physically Based
Rendering* 4th ed., sec. 2.4 (multiple importance sampling) and 4.4 (photometry); Veach
(1997), *Robust Monte Carlo Methods for Light Transport Simulation*, ch. 9; EN 12464-1:2021
(illuminance on a work plane).

Example
-------

Horizontal illuminance on a work plane 0.85 m above the floor, with interreflections::

    <integrator type="illuminance">
        <integer name="max_depth" value="4"/>
        <point name="plane_point" x="0" y="0.85" z="0"/>
        <vector name="plane_normal" x="0" y="1" z="0"/>
    </integrator>
"""

from __future__ import annotations

import math

import drjit as dr
import mitsuba as mi
from spectrace.plugins import params
from spectrace.plugins.emitters import luminous

from spectrace.errors import ParameterError

PLUGIN = "illuminance"
#: The AOV channels the integrator adds to the film, in this order.
AOV_NAMES = ("lux", "measured")
#: Relative tolerance on the ray parameter: a surface this close before the work plane
#: (a floor coinciding with it) does not hide it.
PLANE_EPSILON = 1e-4
#: Smallest |cos| between a camera ray and the work plane's normal for a crossing.
PLANE_MIN_COSINE = 1e-6


class Illuminance(mi.SamplingIntegrator):
    """Illuminance in lux at the first hit or on a work plane; see the module docstring."""

    def __init__(self, props):
        super().__init__(props)
        self.max_depth = params.read_int(props, PLUGIN, "max_depth", 1, minimum=-1)
        if self.max_depth == 0:
            raise ParameterError(
                f"{PLUGIN}: parameter 'max_depth' must be >= 1, or -1 for no limit (got 0)"
            )
        self.rr_depth = params.read_int(props, PLUGIN, "rr_depth", 5, minimum=1)
        self.shadows = params.read_bool(props, PLUGIN, "shadows", True)
        point = params.read_point(props, PLUGIN, "plane_point", None)
        normal = params.read_point(props, PLUGIN, "plane_normal", None)
        if (point is None) != (normal is None):
            given, missing = ("plane_point", "plane_normal") if normal is None else \
                ("plane_normal", "plane_point")
            raise ParameterError(
                f"{PLUGIN}: parameter '{given}' needs parameter '{missing}' (a work plane is "
                "a point and a normal)"
            )
        self.plane = None
        if point is not None:
            values = [float(c) for c in point] + [float(c) for c in normal]
            if not all(math.isfinite(v) for v in values):
                raise ParameterError(f"{PLUGIN}: the work plane must be finite (got {values})")
            length = math.sqrt(sum(c * c for c in values[3:]))
            if not length > 0.0:
                raise ParameterError(
                    f"{PLUGIN}: parameter 'plane_normal' must be a non-zero vector (got "
                    f"{values[3]:g}, {values[4]:g}, {values[5]:g})"
                )
            self.plane = (tuple(values[:3]), tuple(v / length for v in values[3:]))
        self.path = None
        if self.max_depth != 1:
            self.path = mi.load_dict({"type": "path", "max_depth": self.max_depth,
                                      "rr_depth": self.rr_depth, "hide_emitters": True})
        self.V = luminous.photopic_spectrum() if mi.is_spectral else None

    def aov_names(self):
        return list(AOV_NAMES)

    # -- the photometric weighting ---------------------------------------------------

    def _wavelengths(self, sampler, active):
        """Wavelengths for the measurement and the weight V / pdf of each (spectral
        variants: drawn from V, weight integral V); nothing in RGB and mono variants."""
        if not mi.is_spectral:
            return mi.Color0f(), None
        si = dr.zeros(mi.SurfaceInteraction3f)
        return self.V.sample_spectrum(si, mi.sample_shifted(sampler.next_1d(active)), active)

    @staticmethod
    def _lux(E, weight):
        """K_m times the photometric integral of the irradiance spectrum E."""
        return luminous.illuminance_lux(E, weight)

    # -- the measured point ----------------------------------------------------------

    def _surface_point(self, scene, ray, active):
        """The first surface hit, its shading normal turned towards the camera."""
        si = scene.ray_intersect(ray, mi.RayFlags.All, coherent=True, active=active)
        measured = active & si.is_valid()
        towards_camera = dr.dot(si.n, ray.d) < 0.0
        n = dr.select(towards_camera, si.sh_frame.n, -si.sh_frame.n)
        return si, n, measured

    def _plane_point(self, scene, ray, active):
        """Where the ray crosses the work plane, unless it is parallel to it, crosses it
        behind the camera, or a surface stops it before."""
        (px, py, pz), (nx, ny, nz) = self.plane
        n = mi.Vector3f(nx, ny, nz)
        cos = dr.dot(ray.d, n)
        t = dr.dot(mi.Point3f(px, py, pz) - ray.o, n) / cos
        measured = active & (dr.abs(cos) > PLANE_MIN_COSINE) & (t > 0.0) & dr.isfinite(t)
        measured &= t < ray.maxt
        pi = scene.ray_intersect_preliminary(ray, coherent=True, active=measured)
        measured &= ~(pi.is_valid() & (pi.t < t * (1.0 - PLANE_EPSILON)))
        t = dr.select(measured, t, 0.0)
        it = dr.zeros(mi.SurfaceInteraction3f)
        it.p = ray(t)
        it.t = t
        it.n = n
        it.sh_frame = mi.Frame3f(n)
        it.wi = it.sh_frame.to_local(-ray.d)
        it.time = ray.time
        it.wavelengths = ray.wavelengths
        return it, n, measured

    # -- the incident light ----------------------------------------------------------

    def _visible(self, scene, it, ds, active):
        if not self.shadows:
            return active
        return active & ~scene.ray_test(it.spawn_ray_to(ds.p), active)

    def _irradiance(self, scene, sampler, it, n, active):
        """Unbiased estimate of the irradiance spectrum E at ``it`` on the side of ``n``."""
        E = dr.zeros(mi.Spectrum)
        emitters = scene.emitters()
        delta = [mi.has_flag(e.flags(), mi.EmitterFlags.Delta) for e in emitters]
        mis = self.shadows and not all(delta)
        for emitter, is_delta in zip(emitters, delta, strict=True):
            ds, weight = emitter.sample_direction(it, sampler.next_2d(active), active)
            cos = dr.dot(n, ds.d)
            lit = active & (cos > 0.0) & (ds.pdf > 0.0) & dr.isfinite(ds.pdf) & dr.any(
                mi.unpolarized_spectrum(weight) != 0.0)
            lit = self._visible(scene, it, ds, lit)
            if is_delta or not mis:
                w = 1.0
            else:  # balance heuristic against the cosine-weighted direction
                w = ds.pdf / (ds.pdf + cos * dr.inv_pi)
            E += dr.select(lit, weight * (cos * w), 0.0)
        if not (mis or self.path is not None):
            return E
        # one cosine-weighted direction: emission by MIS, and the interreflected light
        frame = mi.Frame3f(n)
        wo = mi.warp.square_to_cosine_hemisphere(sampler.next_2d(active))
        ray = it.spawn_ray(frame.to_world(wo))
        if mis:
            pdf = mi.warp.square_to_cosine_hemisphere_pdf(wo)
            si = scene.ray_intersect(ray, active)
            emitter = si.emitter(scene, active)
            hit = active & (emitter != None)  # noqa: E711 - an EmitterPtr comparison
            ds = mi.DirectionSample3f(scene, si, it)
            emitter_pdf = emitter.pdf_direction(it, ds, hit)
            Le = emitter.eval(si, hit)
            # Le cos / pdf * pdf / (pdf + emitter_pdf), with cos / pdf = pi
            w = pdf / (pdf + emitter_pdf)
            E += dr.select(hit & (pdf > 0.0) & dr.isfinite(w), Le * (dr.pi * w), 0.0)
        if self.path is not None:
            Lr, _, _ = self.path.sample(scene, sampler, mi.RayDifferential3f(ray), None, active)
            E += dr.select(active, Lr * dr.pi, 0.0)
        return E

    # -- Mitsuba interface -----------------------------------------------------------

    def sample(self, scene, sampler, ray, medium=None, active=True):
        active = mi.Bool(active)
        wavelengths, weight = self._wavelengths(sampler, active)
        ray = mi.Ray3f(ray.o, ray.d, ray.maxt, ray.time, wavelengths if mi.is_spectral
                       else ray.wavelengths)
        if self.plane is None:
            it, n, measured = self._surface_point(scene, ray, active)
        else:
            it, n, measured = self._plane_point(scene, ray, active)
        E = self._irradiance(scene, sampler, it, n, measured)
        lux = dr.select(measured, self._lux(E, weight), 0.0)
        preview = mi.depolarizer(mi.UnpolarizedSpectrum(lux))
        return preview, measured, [lux, dr.select(measured, 1.0, 0.0)]

    def to_string(self):
        plane = "none" if self.plane is None else f"point {self.plane[0]}, normal {self.plane[1]}"
        return (f"Illuminance[max_depth={self.max_depth}, shadows={self.shadows}, "
                f"plane={plane}]")


mi.register_integrator(PLUGIN, lambda props: Illuminance(props))
