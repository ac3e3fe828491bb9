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
variant. One value of integral V dlambda is used throughout: the 1 nm sum of
colour-science's CIE 1924 V over 360-830 nm, 106.857 nm (Mitsuba's film normalises its
Y by 106.750 nm, ``MI_CIE_Y_NORMALIZATION`` in ``mitsuba/core/spectrum.h``, the integral
of its 5 nm CIE table: 0.09 % less; no lux passes through the film, so that constant
plays no part here).

The lights are summed by one symbolic Dr.Jit loop over the scene's emitters (the kernel
holds the body once, whatever their number), each light tested with one shadow ray:

* delta lights (``pointlight``, ``spotlight``, ``ieslight``, Mitsuba's ``point``,
  ``spot``, ``directional``) without a spatially varying texture: **exact**, no random
  part. Their emission is s(lambda) g(x), a spectrum times a geometric term, so
  E_v(x) = g(x) s(lambda_0) F with F = K_m sum V s / s(lambda_0) (1 nm sum); F and
  lambda_0 (where V s is largest) are computed once per light and per render from the
  light's own ``sample_direction`` on the 1 nm grid (at points where it emits, found
  with its ``sample_ray``, at 1 mm to 1 m), and every measured point evaluates the light
  at lambda_0 alone. One sample per point gives the exact lux in every variant (RGB and
  mono: K_m Y(E) integral V, exact as well). A delta light whose spectrum cannot be read
  so (no visible light at any of those points) is sampled as below;
* other lights (area lights, ``constant``, ``envmap``, a gobo ``spotlight``): one sample
  of each light's own sampling and, in spectral variants, four stratified hero
  wavelengths drawn from V (weight integral V), and one cosine-weighted direction per
  camera sample, combined with the balance heuristic of multiple importance sampling
  (with ``shadows`` false: the light samples alone, unshadowed);
* ``max_depth`` > 1: along the cosine-weighted direction, pi times the radiance reflected
  towards the measured point by the surface it hits, from Mitsuba's ``path`` integrator
  (``max_depth``, emitters hidden at its first hit: their emission is counted above).

The sampled estimates are unbiased. Spectral variants draw their wavelengths for the
measurement themselves, unaffected by the sensor's wavelengths, response or white point
(they need random samples: a ``stratified`` sampler without jitter would draw the same
wavelengths at every pixel).

Light groups (``spectrace render SCENE --light-groups``: per-light lux): with a table
``light_group_of`` (emitter index -> group index) and ``light_group_count`` set on the
integrator, the loop over the lights also adds each light's lux to its group's sum, the
MIS companion's emission goes to the group of the emitter it hit
(``light_group_by_pointer``: the table by the emitter's registry index), and the
interreflected light (``max_depth`` > 1) to one more group, ``indirect`` (after one bounce
the light's emitter is not tracked); they are left in ``light_lux`` (one Float per group,
``indirect`` last) and sum to the lux. ``IlluminanceLightGroups`` in the ``lightgroups``
plugin's module writes them as layers.

Other kinds of illuminance at a point (for ``spectrace lux --points``, through
:meth:`Illuminance.measure`): a plane of normal n (the above), ``cylindrical`` E_z, the
mean illuminance on the curved surface of a small vertical cylinder, and
``semicylindrical`` E_sc, on the half of it facing the horizontal direction f::

    E_z  = (1 / pi) integral L_i(omega) sin(theta) domega
    E_sc = (1 / pi) integral L_i(omega) (sin(theta) + omega_h . f) domega

(theta from the vertical +Y, the scene's up axis; omega_h the horizontal part of omega;
the definitions of cylindrical and semi-cylindrical illuminance in EN 12464-1:2021,
clause 3, and CIE S 017:2020). These two take light samples only (no MIS companion) and
direct light only.

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
from spectrace.plugins.arrays import host_array
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
#: Emitted rays per light (from its ``sample_ray``) and distances (m) along them at whose
#: points the light's spectrum is evaluated on the 1 nm grid, for the exact luminous factor
#: F of a delta light (several distances: a windowed falloff may end before one metre).
REFERENCE_RAYS = 16
REFERENCE_DISTANCES = (1e-3, 1e-2, 1e-1, 1.0)
#: The scene's up axis (+Y, as Mitsuba's scenes), the axis of the cylinders of E_z and E_sc.
UP = (0.0, 1.0, 0.0)
def _planar(n, d):
    """cos between the surface normal n and the direction d towards the light."""
    return dr.dot(n, d)


def _cylindrical(n, d):
    """sin(theta) / pi, theta the angle of d from the vertical (E_z's kernel)."""
    up = mi.Vector3f(*UP)
    return dr.safe_sqrt(1.0 - dr.square(dr.dot(up, d))) * dr.inv_pi


def _semicylindrical(n, d):
    """(sin(theta) + d_h . f) / pi, f the horizontal unit facing direction made of n."""
    up = mi.Vector3f(*UP)
    f = dr.normalize(n - dr.dot(n, up) * up)
    d_h = d - dr.dot(d, up) * up
    return (dr.norm(d_h) + dr.dot(d_h, f)) * dr.inv_pi


#: Kind of illuminance -> its directional kernel k(n, d): E = integral L_i k domega.
#: ``planar``: on a plane of normal n (horizontal, vertical or any); ``cylindrical``:
#: E_z; ``semicylindrical``: E_sc facing the horizontal part of n.
ILLUMINANCE_KINDS = {
    "planar": _planar,
    "cylindrical": _cylindrical,
    "semicylindrical": _semicylindrical,
}


def is_exact(emitter) -> bool:
    """Whether the light's illuminance is computed exactly: a delta light whose emitted
    spectrum is the same in every direction (no spatially varying texture)."""
    flags = emitter.flags()
    return mi.has_flag(flags, mi.EmitterFlags.Delta) and \
        not mi.has_flag(flags, mi.EmitterFlags.SpatiallyVarying)


def luminous_factors(scene):
    """(F, lambda_0) per emitter of ``scene`` as two numpy arrays: lambda_0 (nm) where
    V s is largest and F = K_m sum_1nm V s / s(lambda_0), so that an exact light's lux is
    F times its emitted value at lambda_0 times the geometric term (see the module page);
    F = -1 for a light that is sampled instead. Spectral variants only. The light's
    spectrum is read through its own ``sample_direction``, at the points REFERENCE_DISTANCES
    along REFERENCE_RAYS rays it emits (``sample_ray``), on the 1 nm grid; the point of most
    luminous value is used. A light that gives no visible light at any of them, or that
    cannot be evaluated so, stays sampled (F = -1)."""
    import numpy as np

    emitters = scene.emitters()
    F = np.full(len(emitters), -1.0)
    lam0 = np.full(len(emitters), 550.0)
    exact = [j for j, e in enumerate(emitters) if is_exact(e)]
    if not exact:
        return F, lam0
    grid, V = luminous.photopic_efficiency()
    width = len(mi.UnpolarizedSpectrum())  # wavelengths per lane
    groups = -(-len(grid) // width)
    padded = np.concatenate([grid, np.full(groups * width - len(grid), grid[-1])])
    V_padded = np.concatenate([V, np.zeros(groups * width - len(grid))])
    n_ref = REFERENCE_RAYS * len(REFERENCE_DISTANCES)
    index = np.repeat(np.asarray(exact, dtype=np.uint32), n_ref * groups)
    ref = np.tile(np.repeat(np.arange(n_ref), groups), len(exact))
    group = np.tile(np.arange(groups), len(exact) * n_ref)
    ray_index, distance = ref % REFERENCE_RAYS, np.asarray(REFERENCE_DISTANCES)[
        ref // REFERENCE_RAYS]
    # stratified emitted rays, the same for every wavelength group of a reference
    u = mi.Float(host_array((ray_index + 0.5) / REFERENCE_RAYS))
    v = mi.Float(host_array(np.modf((ray_index + 0.5) * 0.6180339887498949)[0]))
    lanes = padded.reshape(groups, width)[group]
    try:
        emitter = dr.gather(mi.EmitterPtr, scene.emitters_dr(),
                            mi.UInt32(host_array(index, "uint32")))
        ray, _ = emitter.sample_ray(0.0, 0.5, mi.Point2f(u, v), mi.Point2f(v, u))
        it = dr.zeros(mi.SurfaceInteraction3f, len(index))
        it.p = ray(mi.Float(host_array(distance)))
        it.wavelengths = mi.UnpolarizedSpectrum(*[mi.Float(host_array(lanes[:, k]))
                                                 for k in range(width)])
        _, weight = emitter.sample_direction(it, mi.Point2f(0.5), True)
        w = np.array(mi.unpolarized_spectrum(weight), dtype=np.float64)  # (width, lanes)
    except (RuntimeError, TypeError, ValueError, NotImplementedError) as e:
        mi.Log(mi.LogLevel.Warn, f"{PLUGIN}: the lights' spectra could not be read for the "
               f"exact direct light; they are sampled ({str(e).splitlines()[0]})")
        return F, lam0
    w = w.T.reshape(len(exact), n_ref, groups * width)
    w = np.where(np.isfinite(w), w, 0.0)
    VW = w * V_padded
    for k, j in enumerate(exact):
        best = int(np.argmax(VW[k].sum(axis=1)))
        i0 = int(np.argmax(VW[k, best]))
        if not VW[k, best, i0] > 0.0:  # no visible light found: left to sampling
            continue
        F[j] = luminous.KM * VW[k, best].sum() / w[k, best, i0]
        lam0[j] = padded[i0]
    return F, lam0


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

    def is_exact(self, scene) -> bool:
        """Whether this integrator's lux in ``scene`` has no random part (every light
        exact, direct light only): one sample per point is the answer."""
        return self.path is None and all(is_exact(e) for e in scene.emitters())

    # -- the photometric weighting ---------------------------------------------------

    def _wavelengths(self, sampler, active):
        """Wavelengths for the sampled lights, drawn from V (spectral variants; their
        weight V / pdf is the constant integral V dlambda); nothing in RGB and mono."""
        if not mi.is_spectral:
            return mi.Color0f()
        si = dr.zeros(mi.SurfaceInteraction3f)
        wavelengths, _ = self.V.sample_spectrum(si, mi.sample_shifted(sampler.next_1d(active)),
                                                active)
        return wavelengths

    @staticmethod
    def _lux(E):
        """K_m integral V E dlambda of an irradiance E at wavelengths drawn from V (the
        one integral V of :func:`luminous.v_integral` as their weight)."""
        return luminous.illuminance_lux(E, luminous.v_integral())

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
        it = point_interaction(ray(t), n, ray.time, ray.wavelengths)
        it.t = t
        it.wi = it.sh_frame.to_local(-ray.d)
        return it, n, measured

    # -- the incident light ----------------------------------------------------------

    def _visible(self, scene, it, ds, active):
        if not self.shadows:
            return active
        return active & ~scene.ray_test(it.spawn_ray_to(ds.p), active)

    def _factors(self, scene):
        """The luminous factors (F, lambda_0) of the scene's lights as Dr.Jit arrays
        (spectral variants), computed at each render: a light's parameters may change."""
        F, lam0 = luminous_factors(scene)
        return mi.Float(host_array(F)), mi.Float(host_array(lam0))

    def _direct_lux(self, scene, sampler, it, n, kernel, mis, active):
        """sum over the scene's lights of their lux at ``it`` (one symbolic loop, one
        shadow ray per light): exact for exact lights, one light sample otherwise (with
        the balance-heuristic weight against cosine sampling when ``mis``)."""
        count = len(scene.emitters())
        lux = dr.zeros(mi.Float, dr.width(active))
        if count == 0:
            return lux
        emitters = scene.emitters_dr()
        factors = self._factors(scene) if mi.is_spectral else None
        group_of = getattr(self, "light_group_of", None)
        Eg = [] if group_of is None else [
            dr.zeros(mi.Float, dr.width(active)) for _ in range(self.light_group_count)]

        def body(j, lux, Eg, sampler):
            emitter = dr.gather(mi.EmitterPtr, emitters, j, active)
            it_j = mi.SurfaceInteraction3f(it)
            if factors is not None:
                F = dr.gather(mi.Float, factors[0], j, active)
                exact = F >= 0.0
                lam0 = dr.gather(mi.Float, factors[1], j, active)
                it_j.wavelengths = dr.select(exact, mi.UnpolarizedSpectrum(lam0),
                                             it.wavelengths)
            ds, weight = emitter.sample_direction(it_j, sampler.next_2d(active), active)
            k = kernel(n, ds.d)
            value = mi.unpolarized_spectrum(weight)
            lit = active & (k > 0.0) & (ds.pdf > 0.0) & dr.isfinite(ds.pdf) & dr.any(
                value != 0.0)
            lit = self._visible(scene, it_j, ds, lit)
            if mis:  # balance heuristic against the cosine-weighted direction
                w = dr.select(ds.delta, 1.0, ds.pdf / (ds.pdf + k * dr.inv_pi))
            else:
                w = 1.0
            if factors is not None:
                v = dr.select(exact, F * value[0], self._lux(value))
            else:
                v = self._lux(value)
            term = dr.select(lit, v * (k * w), 0.0)
            lux += term
            if Eg:  # light groups: the light's term to its group too
                g = dr.gather(mi.UInt32, group_of, j, active)
                Eg = [x + dr.select(g == i, term, 0.0) for i, x in enumerate(Eg)]
            return j + 1, lux, Eg, sampler

        _, lux, Eg, _ = dr.while_loop(
            state=(dr.zeros(mi.UInt32, dr.width(active)), lux, Eg, sampler),
            cond=lambda j, lux, Eg, sampler: j < count,
            body=body,
            labels=("j", "lux", "Eg", "sampler"),
            label="illuminance: lights",
        )
        self.light_lux = Eg
        return lux

    def measure(self, scene, sampler, it, n, active, kind="planar"):
        """The illuminance in lux at the points ``it`` (a surface interaction with
        positions, time and, in spectral variants, the wavelengths drawn by
        :meth:`wavelengths`) for the normals (or facing directions) ``n``: of ``kind``
        in ILLUMINANCE_KINDS. ``planar`` includes the MIS companion direction and the
        interreflections; the other kinds take direct light by light sampling only."""
        kernel = ILLUMINANCE_KINDS[kind]
        planar = kind == "planar"
        emitters = scene.emitters()
        mis = planar and self.shadows and not all(
            mi.has_flag(e.flags(), mi.EmitterFlags.Delta) for e in emitters)
        self.light_lux = []
        lux = self._direct_lux(scene, sampler, it, n, kernel, mis, active)
        if getattr(self, "light_group_of", None) is not None:
            self.light_lux = [*self.light_lux, dr.zeros(mi.Float, dr.width(active))]
        if not planar or not (mis or self.path is not None):
            return lux
        # one cosine-weighted direction: emission by MIS, and the interreflected light
        E = dr.zeros(mi.Spectrum)
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
            Ee = dr.select(hit & (pdf > 0.0) & dr.isfinite(w), Le * (dr.pi * w), 0.0)
            E += Ee
            table = getattr(self, "light_group_by_pointer", None)
            if table is not None:  # the MIS companion: the group of the emitter it hit
                g = dr.gather(mi.UInt32, table, dr.reinterpret_array(mi.UInt32, emitter), hit)
                lux_e = dr.select(active, self._lux(Ee), 0.0)
                self.light_lux = [x + dr.select(hit & (g == i), lux_e, 0.0)
                                  for i, x in enumerate(self.light_lux)]
        if self.path is not None:
            Lr, _, _ = self.path.sample(scene, sampler, mi.RayDifferential3f(ray), None, active)
            Er = dr.select(active, Lr * dr.pi, 0.0)
            E += Er
            if self.light_lux:  # the interreflected light: the last group, 'indirect'
                self.light_lux[-1] = self.light_lux[-1] + dr.select(active, self._lux(Er),
                                                                     0.0)
        return lux + dr.select(active, self._lux(E), 0.0)

    def wavelengths(self, sampler, active):
        """The wavelengths of a measurement (see :meth:`measure`)."""
        return self._wavelengths(sampler, active)

    # -- Mitsuba interface -----------------------------------------------------------

    def sample(self, scene, sampler, ray, medium=None, active=True):
        active = mi.Bool(active)
        wavelengths = self._wavelengths(sampler, active)
        ray = mi.Ray3f(ray.o, ray.d, ray.maxt, ray.time, wavelengths if mi.is_spectral
                       else ray.wavelengths)
        if self.plane is None:
            it, n, measured = self._surface_point(scene, ray, active)
        else:
            it, n, measured = self._plane_point(scene, ray, active)
        lux = dr.select(measured, self.measure(scene, sampler, it, n, measured), 0.0)
        preview = mi.depolarizer(mi.UnpolarizedSpectrum(lux))
        return preview, measured, [lux, dr.select(measured, 1.0, 0.0)]

    def to_string(self):
        plane = "none" if self.plane is None else f"point {self.plane[0]}, normal {self.plane[1]}"
        return (f"Illuminance[max_depth={self.max_depth}, shadows={self.shadows}, "
                f"plane={plane}]")


def point_interaction(p, n, time=0.0, wavelengths=None):
    """A surface interaction at the points ``p`` with the normal (and shading frame)
    ``n``: where :meth:`Illuminance.measure` measures, on no surface."""
    it = dr.zeros(mi.SurfaceInteraction3f, dr.width(p))
    it.p = p
    it.n = n
    it.sh_frame = mi.Frame3f(n)
    it.time = time
    if wavelengths is not None:
        it.wavelengths = wavelengths
    return it


mi.register_integrator(PLUGIN, lambda props: Illuminance(props))
