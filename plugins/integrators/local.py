"""``local``: the classic local illumination model of computer graphics, by ray casting.

For each camera ray the first hit is shaded with the local (direct-only) illumination
model -- ambient plus, for every light, its incident radiance times the BSDF and the
cosine -- then fog is applied. The lights are summed by one symbolic Dr.Jit loop over the
scene's emitters, so the kernel (and its compile time) does not grow with their number.
Only one bounce is ever traced: no indirect light (``ambient`` stands in for it) and no
light through smooth (delta) BSDFs, whose ``eval`` is 0.

Parameters
----------

==================  ========  =======  ========  ==============================================
parameter           type      default  unit      description
==================  ========  =======  ========  ==============================================
``shading``         string    phong    --        ``flat``: the face (geometric) normal;
                                                 ``phong``: the interpolated shading normal;
                                                 ``gouraud``: the whole model evaluated at the
                                                 three vertices of the hit triangle and the
                                                 radiances interpolated (below)
``shadows``         boolean   true     --        cast a shadow ray towards every light
``shadow_samples``  integer   1        --        light samples (shadow rays) per light with a
                                                 size (``source_radius`` > 0, area lights),
                                                 averaged: the penumbra's noise falls as
                                                 1/sqrt(N); delta lights always take one, >= 1
``shadow_bias``     float     0.001    m         offset of the shadow-ray origin along the
                                                 geometric normal, >= 0; the ray starts at p +
                                                 bias n with no further automatic offset, so 0
                                                 shows shadow acne
``ambient``         spectrum  0        W/m^2     irradiance of the indirect light (an emission
                    or                           spectrum: RGB values are illuminants,
                    string                       D65-based in spectral variants), >= 0; adds
                                                 rho / pi * ambient; or ``"environment"``:
                                                 the environment's irradiance E_SH(n)
                                                 (below) instead of a constant
``environment``     ref       none     --        the scene's environment emitter (``envmap``,
                                                 ``constant``, ``ciesky``), as
                                                 ``<ref name="environment" id="..."/>``: adds
                                                 the reflection term rho_s L_env(r) (below)
``fog``             string    none     --        fog law f(d): ``none``, ``linear``,
                                                 ``exponential``, ``exponential_squared`` (see
                                                 ``spectrace help fog``)
``fog_start``       float     0        m         ``linear``: distance where fog begins, >= 0
``fog_end``         float     1        m         ``linear``: distance of full fog, > fog_start
``fog_density``     float     1        1/m       exponential laws: density, >= 0
``fog_color``       spectrum  0        W/m^2/sr  radiance of the fog, >= 0 (an emission
                                                 spectrum)
``hide_emitters``   boolean   false    --        do not show emitters seen directly
==================  ========  =======  ========  ==============================================

The parameters are read at load; none is exposed to ``mi.traverse``. Defaults of the fog
parameters are OpenGL's (start 0, end 1, density 1, colour black).

Formula
-------

::

    L = L_e + sum over lights j of V_j L_j f(l_j, v) (n . l_j) + rho / pi E_ambient
    L_fog = f(d) L + (1 - f(d)) fog_color

``L_j`` is the incident radiance the light's ``sample_direction`` reports for the shaded
point (for the delta lights ``pointlight``, ``spotlight``, ``point``, ``spot``,
``directional``: intensity times the distance and cone falloff, exactly); ``f (n . l)``
is the hit BSDF's ``eval`` (which includes the cosine); ``rho`` is the BSDF's
``eval_diffuse_reflectance``; ``V_j`` is 1, or the visibility of light j when
``shadows`` is on. ``L_e`` is the radiance of an area light or environment map seen
directly (unless ``hide_emitters``). d is the distance from the camera (the hit's ray
parameter t; the camera rays are normalized). Rays that hit nothing have d = infinity:
with fog on they get fog_color (f = 0), except with density 0.

Environment (reflection mapping and irradiance environment map)
-----------------------------------------------------------------

::

    L += rho_s L_env(r),  r = 2 (n . v) n - v          (environment)
    L += rho / pi E_SH(n)                              (ambient = "environment")

``r`` is the view direction v mirrored about the shading normal n (Blinn and Newell
1976): ``L_env(r)`` is the environment emitter's own ``eval`` along r (so its to_world,
scale and spectra apply), front side only, with no ray traced along r (the map is taken
as infinitely far and unoccluded, as reflection mapping does). ``rho_s`` is the BSDF's
``specular_reflectance`` attribute: that of ``phong`` and ``blinnphong`` (whatever their
exponent or ``normalized``: reflection mapping treats the lobe as a mirror), and of any
Mitsuba BSDF that has one as an attribute (``conductor``: 1 unless given, its Fresnel
factor not applied); a BSDF without it (``diffuse``, ``plastic``, ``dielectric``,
``roughconductor`` without one, ...) has rho_s = 0 and reflects no environment.

``E_SH(n)`` is the irradiance of the order-2 spherical-harmonics projection of the
environment (9 coefficients per channel; Ramamoorthi and Hanrahan 2001, eqs. 7-8:
E(n) = sum A_l L_lm Y_lm(n), A = pi, 2 pi/3, pi/4), clamped at 0, at the shading normal
turned towards the viewer; no occlusion. The coefficients are projected once per scene,
when ``spectrace.scene.load_scene`` loads it (``check_scene``) or else at the first
render, by Gauss-Legendre quadrature in cos(theta) (``QUADRATURE_MIN`` = 64 nodes, or the
map's height for an ``envmap``, at most ``QUADRATURE_MAX`` = 256) of the emitter's
``eval``: any environment emitter works (``envmap`` with its to_world, ``constant``,
``ciesky``). In spectral variants they are tabulated from 360 to 830 nm every 5 nm and
interpolated at each ray's wavelengths. A constant environment of radiance L gives
E_SH = pi L exactly. Changes made to the environment through ``mi.traverse`` after the
projection do not reach E_SH (the reflection term sees them).

``ambient = "environment"`` uses the ``environment`` reference, or else the scene's
environment emitter; a scene without one is refused (a ParameterError naming
``ambient``). The environment used by either term is left out of the sum over lights
(its light comes in through these two terms only, noise-free, as in the classic
environment-mapping model); without ``environment`` and ``ambient = "environment"`` an
environment is sampled like any other light (below).

Non-delta emitters (lights with a ``source_radius``, area lights, environment maps) are
*sampled*, not rejected: each gets ``shadow_samples`` emitter samples (``sample_direction``
with fresh 2D samples, each with its shadow ray) per pixel sample, averaged, an unbiased
but noisy estimate of its direct light (the noise of a penumbra); raise ``shadow_samples``
or ``spp`` for them.

Details and choices:

* Shadow rays start at ``p + shadow_bias * n``, n the geometric normal turned towards the
  light, go towards the light sample and stop just before it (relative epsilon
  ``mi.math.ShadowEpsilon`` on the distance). The shadow test is done at the hit point
  for all shading modes; with ``gouraud`` the light's interpolated contribution is
  multiplied by the pixel's visibility (per-vertex lighting, per-pixel shadows, as a
  rasteriser with shadow maps does), so shadows stay sharp on coarse meshes.
* ``gouraud``: vertex position, vertex normal (the face normal for meshes without vertex
  normals), view direction from the vertex to the camera and vertex texture coordinates
  come from Mitsuba's surface interaction at the corners of the hit triangle (so
  instanced and transformed meshes work); each light's sample is shared by the hit and
  the three vertices. It needs triangle meshes: hits on other shapes (``sphere``,
  ``rectangle``, ...) fall back to ``phong``, and a warning is logged once per scene
  when the scene has such shapes. ``flat`` on an analytic shape uses its geometric
  normal, which equals its shading normal.
* The camera position used for the Gouraud view directions is the camera ray's origin
  (exact for a pinhole ``perspective`` sensor).
* Participating media are ignored (fog stands in for them; compare with ``volpath``).
  Pixels where fog is on count as valid (alpha 1) even when the ray hits nothing.
* Every variant: RGB, mono, spectral and their polarized forms (unpolarized ambient and
  fog terms), LLVM and CUDA (tested on LLVM).

Sources
-------

Phong (1975), "Illumination for computer generated pictures", *Communications of the
ACM* 18(6) (the reflection model and interpolated normals); Gouraud (1971), "Continuous
shading of curved surfaces", *IEEE Transactions on Computers* C-20(6); Segal, Akeley
(2003), *The OpenGL Graphics System 1.5 Specification*, sec. 3.10 (fog);
Akenine-Moeller, Haines, Hoffman et al. (2018), *Real-Time Rendering* 4th ed., ch. 5
(the local model with ambient term) and ch. 10 (environment mapping); Blinn, Newell (1976),
"Texture and reflection in computer generated images", *CACM* 19(10) (reflection
mapping); Ramamoorthi, Hanrahan (2001), "An efficient representation for irradiance
environment maps", SIGGRAPH (order-2 spherical harmonics).

Example
-------

Gouraud shading with a little ambient light and bluish exponential fog::

    <integrator type="local">
        <string name="shading" value="gouraud"/>
        <boolean name="shadows" value="true"/>
        <float name="shadow_bias" value="0.001"/>
        <rgb name="ambient" value="0.1"/>
        <string name="fog" value="exponential"/>
        <float name="fog_density" value="0.05"/>
        <rgb name="fog_color" value="0.6, 0.65, 0.7"/>
    </integrator>

A reflection-mapped object under an environment map, its diffuse part lit by the map's
irradiance::

    <emitter type="envmap" id="sky">
        <string name="filename" value="textures/daylight_sky.exr"/>
    </emitter>
    <integrator type="local">
        <ref name="environment" id="sky"/>
        <string name="ambient" value="environment"/>
    </integrator>
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi
from spectrace.plugins import params
from spectrace.plugins.integrators.fog import FOG_METHODS

from spectrace.errors import ParameterError

PLUGIN = "local"


def _shade_phong(si, *, integrator, scene, sampler, ray, pi, bsdf, active):
    """Model evaluated at the hit with its interpolated shading frame."""

    def light(emitter, sample, active):
        ds, radiance = emitter.sample_direction(si, sample, active)
        lit = integrator._visible(scene, si, ds, radiance, active)
        return integrator._light_term(bsdf, si, ds, radiance, lit)

    L = integrator._sum_over_lights(scene, sampler, light, active)
    return L + integrator._ambient_term(bsdf, si, active)


def _shade_flat(si, *, integrator, scene, sampler, ray, pi, bsdf, active):
    """Model evaluated at the hit with the face (geometric) normal as shading normal."""
    si = mi.SurfaceInteraction3f(si)
    si.sh_frame = mi.Frame3f(si.n)
    si.wi = si.to_local(-ray.d)
    return _shade_phong(si, integrator=integrator, scene=scene, sampler=sampler, ray=ray,
                        pi=pi, bsdf=bsdf, active=active)


def _shade_gouraud(si, *, integrator, scene, sampler, ray, pi, bsdf, active):
    """Model evaluated at the triangle's vertices, radiance interpolated barycentrically.

    The surface interaction at vertex k is Mitsuba's own one at the barycentric corner k
    of the hit triangle (vertex position, vertex normal or else face normal, vertex
    texture coordinates; instances and flipped normals handled by the shape), with the
    view direction from the vertex to the camera. Each light's sample is shared by the
    hit (its shadow ray) and the three vertices."""
    is_mesh = active & si.shape.is_mesh()
    u, v = pi.prim_uv.x, pi.prim_uv.y
    weights = (
        dr.select(is_mesh, 1.0 - u - v, 1.0),
        dr.select(is_mesh, u, 0.0),
        dr.select(is_mesh, v, 0.0),
    )
    vertices = []
    for corner in ((0.0, 0.0), (1.0, 0.0), (0.0, 1.0)):
        pi_k = mi.PreliminaryIntersection3f(pi)
        pi_k.prim_uv = mi.Point2f(*corner)
        si_k = pi_k.compute_surface_interaction(ray, mi.RayFlags.All, is_mesh)
        si_k.wi = si_k.to_local(dr.normalize(ray.o - si_k.p))
        vertices.append(dr.select(is_mesh, si_k, si))

    def light(emitter, sample, active):
        ds, radiance = emitter.sample_direction(si, sample, active)
        lit = integrator._visible(scene, si, ds, radiance, active)
        L = dr.zeros(mi.Spectrum, dr.width(lit))
        for weight, si_k in zip(weights, vertices, strict=True):
            ds_k, radiance_k = emitter.sample_direction(si_k, sample, active)
            L += weight * integrator._light_term(bsdf, si_k, ds_k, radiance_k, lit)
        return L

    L = integrator._sum_over_lights(scene, sampler, light, active)
    for weight, si_k in zip(weights, vertices, strict=True):
        L += weight * integrator._ambient_term(bsdf, si_k, active)
    return L


class _EnvironmentState:
    """What ``local`` needs of a scene's environment: the emitter, its index among the
    scene's emitters (left out of the light sum) and, for ``ambient="environment"``, its
    order-2 spherical-harmonics irradiance ``irradiance(n, wavelengths)``."""

    def __init__(self, integrator, scene):
        env = integrator.environment
        if env is None:
            env = scene.environment()
        if env is None:
            raise ParameterError(
                f"{PLUGIN}: parameter 'ambient' = \"environment\" needs an environment "
                "emitter (envmap, constant, ciesky) in the scene, and it has none"
            )
        self.emitter = env
        self.index = next((j for j, e in enumerate(scene.emitters()) if e == env), None)
        self.irradiance = None
        if integrator.ambient_environment:
            self.irradiance = _sh_irradiance_function(env)


#: Nodes in y = cos(theta) of the quadrature that projects an environment (the azimuth
#: takes twice as many): at least this many, or the map's height for an ``envmap``, at most
#: :data:`QUADRATURE_MAX`.
QUADRATURE_MIN = 64
QUADRATURE_MAX = 256
#: Wavelength step (nm) of the spectral variants' table of SH coefficients, 360 to 830 nm
#: (the CIE range), interpolated linearly at each ray's wavelengths.
SH_WAVELENGTH_STEP = 5.0


def _environment_radiance(env, directions, wavelengths=None):
    """L_env(d) (N, C) of emitter ``env`` at world directions (N, 3) (numpy), via its
    ``eval``: the light arriving from d, at ``wavelengths`` (4 values, spectral variants)."""
    import numpy as np

    si = dr.zeros(mi.SurfaceInteraction3f, len(directions))
    si.wi = -mi.Vector3f(*(np.ascontiguousarray(directions[:, k]) for k in range(3)))
    if wavelengths is not None:
        si.wavelengths = type(si.wavelengths)(*(float(x) for x in wavelengths))
    L = mi.unpolarized_spectrum(env.eval(si))
    dr.eval(L)
    L = np.array(L).reshape(dr.size_v(mi.UnpolarizedSpectrum), -1)
    return np.broadcast_to(L, (L.shape[0], len(directions))).T  # (a constant: width 1)


def _sh_irradiance_function(env):
    """``irradiance(n, wavelengths)``: the order-2 SH irradiance E(n) of emitter ``env``
    (Ramamoorthi and Hanrahan 2001), projected here by quadrature of its ``eval``."""
    import numpy as np

    from spectrace import envmaps

    n = QUADRATURE_MIN
    if env.class_name() == "EnvironmentMapEmitter":
        n = max(n, int(mi.traverse(env)["data"].shape[0]))
    d, w = envmaps.sphere_quadrature(min(n, QUADRATURE_MAX))
    if not mi.is_spectral:
        c = envmaps.sh_irradiance_coefficients(envmaps.sh_project_samples(
            _environment_radiance(env, d), w, d))  # (9, C)

        def irradiance(normal, wavelengths):
            Y = _sh_basis(normal)
            return mi.UnpolarizedSpectrum(*(
                dr.maximum(sum(float(c[k, ch]) * Y[k] for k in range(9)), 0.0)
                for ch in range(c.shape[1])))
        return irradiance

    lambdas = np.arange(mi.MI_CIE_MIN, mi.MI_CIE_MAX + 0.5 * SH_WAVELENGTH_STEP,
                        SH_WAVELENGTH_STEP)
    columns = []
    for start in range(0, len(lambdas), 4):
        group = [lambdas[min(start + i, len(lambdas) - 1)] for i in range(4)]
        L = _environment_radiance(env, d, group)
        columns.append(envmaps.sh_irradiance_coefficients(envmaps.sh_project_samples(
            L, w, d)))
    table = np.concatenate(columns, axis=1)[:, : len(lambdas)].T  # (n_lambda, 9)
    coefficients = mi.Float(np.ascontiguousarray(table, dtype=np.float32).ravel())
    last = len(lambdas) - 1

    def irradiance(normal, wavelengths):
        Y = _sh_basis(normal)
        channels = []
        for ch in range(len(wavelengths)):
            x = dr.clip((wavelengths[ch] - float(lambdas[0])) / SH_WAVELENGTH_STEP, 0, last)
            i0 = dr.minimum(mi.UInt32(dr.floor(x)), last - 1)
            f = x - mi.Float(i0)
            E = mi.Float(0.0)
            for k in range(9):
                c0 = dr.gather(mi.Float, coefficients, i0 * 9 + k)
                c1 = dr.gather(mi.Float, coefficients, (i0 + 1) * 9 + k)
                E += Y[k] * dr.lerp(c0, c1, f)
            channels.append(dr.maximum(E, 0.0))
        return mi.UnpolarizedSpectrum(*channels)
    return irradiance


def _sh_basis(d):
    """The 9 real spherical harmonics of :func:`spectrace.envmaps.sh_basis` at the Dr.Jit
    unit vectors ``d`` (same order and normalization)."""
    from spectrace.envmaps import SH_NORMALIZATION

    c0, c1, c2 = (float(c) for c in SH_NORMALIZATION)
    x, y, z = d.x, d.y, d.z
    return (dr.full(mi.Float, c0, dr.width(x)), c1 * y, c1 * z, c1 * x, c2 * x * y,
            c2 * y * z, 0.5 * c2 / 3.0 ** 0.5 * (3.0 * z * z - 1.0), c2 * x * z,
            0.5 * c2 * (x * x - y * y))


#: The shading models, colour-science's ``*_METHODS`` style: ``shading`` value ->
#: ``shade(si, *, integrator, scene, sampler, ray, pi, bsdf, active)``, the reflected
#: radiance of the hit ``si``.
SHADING_METHODS = {
    "flat": _shade_flat,
    "gouraud": _shade_gouraud,
    "phong": _shade_phong,
}


class Local(mi.SamplingIntegrator):
    """The local illumination model; see the module docstring."""

    def __init__(self, props):
        super().__init__(props)
        self.shading = params.read_choice(props, PLUGIN, "shading", "phong", SHADING_METHODS)
        self.shadows = params.read_bool(props, PLUGIN, "shadows", True)
        self.shadow_samples = params.read_int(props, PLUGIN, "shadow_samples", 1, minimum=1)
        self.shadow_bias = params.read_float(props, PLUGIN, "shadow_bias", 1e-3, minimum=0.0,
                                             finite=True)
        self.ambient_environment = self._is_environment_ambient(props)
        self.ambient = None if self.ambient_environment else self._spectrum(props, "ambient")
        self.environment = self._environment_reference(props)
        self.fog = params.read_choice(props, PLUGIN, "fog", "none", FOG_METHODS)
        self.fog_start = params.read_float(props, PLUGIN, "fog_start", 0.0, minimum=0.0,
                                           finite=True)
        self.fog_end = params.read_float(props, PLUGIN, "fog_end", 1.0, finite=True)
        self.fog_density = params.read_float(props, PLUGIN, "fog_density", 1.0, minimum=0.0,
                                             finite=True)
        self.fog_color = self._spectrum(props, "fog_color")
        if not self.fog_end > self.fog_start:
            raise ParameterError(
                f"{PLUGIN}: parameter 'fog_end' must be > fog_start = {self.fog_start:g} "
                f"(got {self.fog_end:g})"
            )

    @staticmethod
    def _is_environment_ambient(props):
        """Whether ``ambient`` is the string "environment" (any other string is refused)."""
        if "ambient" not in props or props.type("ambient") != mi.Properties.Type.String:
            return False
        value = props.get("ambient")
        if value != "environment":
            raise ParameterError(
                f"{PLUGIN}: parameter 'ambient' must be a spectrum or \"environment\" "
                f"(got {value!r})"
            )
        return True

    @staticmethod
    def _environment_reference(props):
        """The emitter of ``<ref name="environment" id="..."/>`` (an environment: infinite,
        not a delta light), or None."""
        if "environment" not in props:
            return None
        value = props.get("environment") if props.type("environment") == \
            mi.Properties.Type.Object else None
        flags = value.flags() if isinstance(value, mi.Emitter) else None
        if flags is None or not mi.has_flag(flags, mi.EmitterFlags.Infinite) or \
                mi.has_flag(flags, mi.EmitterFlags.Delta):
            got = value.class_name() if hasattr(value, "class_name") else params._got(
                props, "environment")
            raise ParameterError(
                f"{PLUGIN}: parameter 'environment' must be a reference to an environment "
                f"emitter (envmap, constant, ciesky: <ref name=\"environment\" id=\"...\"/>), "
                f"got {got}"
            )
        return value

    @staticmethod
    def _spectrum(props, name):
        """Emission-type spectrum ``name`` (>= 0); None (black) when absent or all zero, since
        Mitsuba cannot build an emission spectrum of value 0 in spectral variants."""
        if name not in props:
            return None
        if props.type(name) in (
            mi.Properties.Type.Float,
            mi.Properties.Type.Integer,
            mi.Properties.Type.Color,
        ):
            value = props.get(name)
            values = (
                [float(value)] if isinstance(value, (int, float)) else [float(c) for c in value]
            )
            if min(values) < 0.0:
                shown = ", ".join(f"{v:g}" for v in values)
                raise ParameterError(f"{PLUGIN}: parameter '{name}' must be >= 0 (got {shown})")
            if max(values) == 0.0:
                props.mark_queried(name)
                return None
        return params.read_texture(props, PLUGIN, name, None, minimum=0.0, emissive=True,
                                   what="a spectrum or texture")

    # -- pieces of the model ---------------------------------------------------------

    def _sum_over_lights(self, scene, sampler, light, active):
        """sum over the scene's emitters j of ``light(emitter_j, sample_j, active)``, with
        ``sample_j = sampler.next_2d()``, as one symbolic Dr.Jit loop over the emitter
        pointers: the kernel holds the body once, whatever the number of lights.

        Light groups (``spectrace.lightgroups``): with ``self.light_group_of`` set (a
        UInt32 table, emitter index j -> group index, and ``self.light_group_count``),
        each light's term is also added to its group's sum, left in
        ``self.light_layers``."""
        n = len(scene.emitters())
        L = dr.zeros(mi.Spectrum, dr.width(active))
        group_of = getattr(self, "light_group_of", None)
        Lg = [] if group_of is None else [
            dr.zeros(mi.Spectrum, dr.width(active)) for _ in range(self.light_group_count)]
        self.light_layers = Lg
        if n == 0:
            return L
        emitters = scene.emitters_dr()
        state = self._environment_now
        skip = None if state is None else state.index

        def body(j, L, Lg, sampler):
            on = active if skip is None else active & (j != skip)
            emitter = dr.gather(mi.EmitterPtr, emitters, j, on)
            if self.shadow_samples == 1:
                term = light(emitter, sampler.next_2d(active), on)
            else:
                term = self._averaged_light(emitter, sampler, light, on)
            L += term
            if Lg:
                g = dr.gather(mi.UInt32, group_of, j, on)
                Lg = [x + dr.select(g == i, term, 0.0) for i, x in enumerate(Lg)]
            return j + 1, L, Lg, sampler

        _, L, Lg, _ = dr.while_loop(
            state=(dr.zeros(mi.UInt32, dr.width(active)), L, Lg, sampler),
            cond=lambda j, L, Lg, sampler: j < n,
            body=body,
            labels=("j", "L", "Lg", "sampler"),
            label="local: lights",
        )
        self.light_layers = Lg
        return L

    def _averaged_light(self, emitter, sampler, light, active):
        """The mean of ``shadow_samples`` evaluations of ``light`` for a light with a size
        (one for a delta light: its samples are all the same), as a symbolic loop."""
        count = dr.select(mi.has_flag(emitter.flags(), mi.EmitterFlags.Delta),
                          mi.UInt32(1), mi.UInt32(self.shadow_samples))

        def body(k, L, sampler):
            L += light(emitter, sampler.next_2d(active), active)
            return k + 1, L, sampler

        _, L, _ = dr.while_loop(
            state=(dr.zeros(mi.UInt32, dr.width(active)), dr.zeros(mi.Spectrum,
                                                                  dr.width(active)), sampler),
            cond=lambda k, L, sampler: k < count,
            body=body,
            labels=("k", "L", "sampler"),
            label="local: shadow samples",
        )
        return L * dr.rcp(mi.Float(count))

    def _visible(self, scene, si, ds, radiance, active):
        """Whether the light sample is lit and unoccluded, the shadow ray starting at
        p + shadow_bias * n (n: geometric normal on the light's side), no extra offset."""
        lit = active & dr.any(mi.unpolarized_spectrum(radiance) != 0.0)
        if self.shadows:
            n = dr.mulsign(si.n, dr.dot(si.n, ds.d))
            origin = si.p + self.shadow_bias * n
            # Towards the sampled point itself from the offset origin when the light has a
            # surface (else the ray would end inside it); along ds.d for delta lights.
            to_light = mi.Vector3f(ds.p - origin)
            dist = dr.select(ds.delta, ds.dist, dr.norm(to_light))
            d = dr.select(ds.delta, ds.d, to_light * dr.rcp(dist))
            shadow_ray = mi.Ray3f(
                origin, d, dist * (1.0 - mi.math.ShadowEpsilon), si.time, si.wavelengths
            )
            lit &= ~scene.ray_test(shadow_ray, lit)
        return lit

    def _light_term(self, bsdf, si, ds, radiance, lit):
        """V_j L_j f(l_j, v) (n . l_j) at ``si`` (``lit``: V_j)."""
        f = bsdf.eval(mi.BSDFContext(), si, si.to_local(ds.d), lit)
        return dr.select(lit, f * radiance, 0.0)

    def _ambient_term(self, bsdf, si, active):
        """rho/pi * ambient at ``si`` (0 without ``ambient``), plus the environment's terms:
        rho/pi * E_SH(n) (``ambient="environment"``) and rho_s * L_env(r) (``environment``)."""
        if self.ambient is None and self._environment_now is None:
            return dr.zeros(mi.Spectrum, dr.width(active))
        rho = bsdf.eval_diffuse_reflectance(si, active)
        if self.ambient is not None:
            E = self.ambient.eval(si, active)
        else:
            E = dr.zeros(mi.UnpolarizedSpectrum, dr.width(active))
        state = self._environment_now
        if state is not None and state.irradiance is not None:
            # The normal on the viewer's side: the irradiance of the side that is seen.
            n = dr.mulsign(si.sh_frame.n, si.wi.z)
            E += state.irradiance(n, si.wavelengths)
        ambient = mi.unpolarized_spectrum(rho) * dr.inv_pi * E
        if self.environment is not None:
            ambient += self._reflection_term(bsdf, si, active)
        return dr.select(active, mi.depolarizer(ambient), 0.0)

    def _reflection_term(self, bsdf, si, active):
        """rho_s L_env(r), r = 2 (n . v) n - v the mirror of the view direction about the
        shading normal (front side only; no ray is traced along r)."""
        front = active & (si.wi.z > 0)
        rho_s = bsdf.eval_attribute("specular_reflectance", si, front)
        r = si.to_world(mi.Vector3f(-si.wi.x, -si.wi.y, si.wi.z))
        si_env = mi.SurfaceInteraction3f(si)
        si_env.wi = -r
        L = mi.unpolarized_spectrum(self.environment.eval(si_env, front))
        return dr.select(front, mi.unpolarized_spectrum(rho_s) * L, 0.0)

    @property
    def _environment_now(self):
        """The environment state of the scene being rendered (None without environment)."""
        return self.__dict__.get("_environment_state")

    def check_scene(self, scene):
        """Prepare the environment terms for ``scene`` now, at load, rather than at its first
        render (``spectrace.scene.load_scene`` calls it): a missing environment is a
        ParameterError here, not an error inside a render."""
        self._prepare_environment(scene)

    def _prepare_environment(self, scene):
        """Find the environment of ``scene`` and project its irradiance, once per scene."""
        if self.environment is None and not self.ambient_environment:
            return
        cache = self.__dict__.setdefault("_environment_cache", {})
        key = (id(scene), len(scene.emitters()))
        if key not in cache:
            cache[key] = _EnvironmentState(self, scene)
        self.__dict__["_environment_state"] = cache[key]

    def fog_fraction(self, d):
        """f(d) of the configured fog law for camera distances ``d``."""
        return FOG_METHODS[self.fog](d, start=self.fog_start, end=self.fog_end,
                                     density=self.fog_density)

    # -- Mitsuba interface -----------------------------------------------------------

    def sample(self, scene, sampler, ray, medium=None, active=True):
        active = mi.Bool(active)
        if self.shading == "gouraud":
            self._warn_gouraud_fallback(scene)
        self._prepare_environment(scene)
        pi = scene.ray_intersect_preliminary(ray, coherent=True, active=active)
        si = pi.compute_surface_interaction(ray, mi.RayFlags.All, active)
        hit = active & si.is_valid()

        L = dr.zeros(mi.Spectrum)
        if not self.hide_emitters:
            L += si.emitter(scene, active).eval(si, active)
        bsdf = si.bsdf(ray)
        L += SHADING_METHODS[self.shading](si, integrator=self, scene=scene, sampler=sampler,
                                           ray=ray, pi=pi, bsdf=bsdf, active=hit)

        valid = hit
        if self.fog != "none":
            d = dr.select(hit, si.t, dr.largest(mi.Float))
            f = self.fog_fraction(d)
            L = f * L
            if self.fog_color is not None:
                L += (1.0 - f) * mi.depolarizer(self.fog_color.eval(si, active))
            valid = active
        return L, valid, []

    def _warn_gouraud_fallback(self, scene):
        """Log, once per scene (not once per pass), that non-mesh shapes fall back to phong."""
        warned = self.__dict__.setdefault("_gouraud_warned", set())
        if id(scene) in warned:
            return
        warned.add(id(scene))
        if not all(shape.is_mesh() or shape.class_name() == "Instance"
                   for shape in scene.shapes()):
            mi.Log(
                mi.LogLevel.Warn,
                "local: shading 'gouraud' needs triangle meshes; "
                "hits on other shapes are shaded with 'phong'",
            )

    def to_string(self):
        return (
            f"Local[shading={self.shading!r}, shadows={self.shadows}, "
            f"shadow_samples={self.shadow_samples}, shadow_bias={self.shadow_bias}, "
            f"fog={self.fog!r}]"
        )


mi.register_integrator("local", lambda props: Local(props))
