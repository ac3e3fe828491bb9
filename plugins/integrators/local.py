"""Local illumination integrator (``local``): the lecture's shading pipeline by ray casting.

For each camera ray the first hit is shaded with the local (direct-only) illumination
model

    L = L_e + sum over lights j of V_j * L_j * falloff_j * f(l_j, v) (n . l_j)
            + rho / pi * E_ambient,

then fog is applied. ``L_j * falloff_j`` is the incident radiance the light's
``sample_direction`` reports for the shaded point (for the delta lights ``pointlight``,
``spotlight``, ``point``, ``spot``, ``directional``: intensity times the distance and
cone falloff, exactly); ``f * (n . l)`` is the hit BSDF's ``eval`` (which includes the
cosine); ``rho`` is the BSDF's ``eval_diffuse_reflectance``; ``V_j`` is 1, or the
visibility of light j when ``shadows`` is on. ``L_e`` is the radiance of an area light
or environment map seen directly (unless ``hide_emitters``).

Non-delta emitters (area lights, environment maps) are *sampled*, not rejected: each
gets one emitter sample (``sample_direction`` with a fresh 2D sample) per pixel sample,
an unbiased but noisy estimate of its direct light; raise ``spp`` for them. Only one
bounce is ever traced: no indirect light (that is what ``ambient`` stands in for) and no
light through smooth (delta) BSDFs, whose ``eval`` is 0.

Parameters
----------

=================  ===========  ============  ================================================
name               type         default       meaning
=================  ===========  ============  ================================================
``shading``        string       ``phong``     ``flat``: the face (geometric) normal;
                                              ``phong``: the interpolated shading normal;
                                              ``gouraud``: the whole model (lights, BSDF,
                                              ambient) evaluated at the three vertices of the
                                              hit triangle -- vertex position, vertex normal,
                                              view direction from the vertex to the camera,
                                              vertex texture coordinates -- and the three
                                              radiances interpolated with the hit's
                                              barycentric coordinates.
``shadows``        boolean      true          cast a shadow ray towards every light.
``shadow_bias``    float >= 0   0.001         offset of the shadow-ray origin along the
                                              geometric normal, in scene units (metres):
                                              the ray starts at p + bias * n with *no* further
                                              automatic offset, so 0 shows shadow acne.
``ambient``        spectrum     0             irradiance of the indirect light (W/m^2, an
                                              emission-type spectrum: RGB values are
                                              illuminants, D65-based in spectral variants);
                                              adds rho / pi * ambient.
``fog``            string       ``none``      fog law f(d): ``none``, ``linear``,
                                              ``exponential``, ``exponential_squared``
                                              (see :mod:`spectrace.plugins.integrators.fog`).
``fog_start``      float >= 0   0             ``linear``: distance where fog begins (m).
``fog_end``        float        1             ``linear``: distance of full fog (m), > start.
``fog_density``    float >= 0   1             exponential laws: density (1/m).
``fog_color``      spectrum     0             radiance of the fog (emission-type spectrum).
``hide_emitters``  boolean      false         do not show emitters seen directly.
=================  ===========  ============  ================================================

Fog: L = f(d) L + (1 - f(d)) fog_color with d the distance from the camera (the hit's
ray parameter t; the camera rays are normalized). Rays that hit nothing have d = infinity:
with fog on they get fog_color (f = 0), except with density 0.

Defaults of the fog parameters are OpenGL's (start 0, end 1, density 1, colour black).

Details and choices:

* Shadow rays start at ``p + shadow_bias * n``, n the geometric normal turned towards the
  light, go towards the light sample and stop just before it (relative epsilon
  ``mi.math.ShadowEpsilon`` on the distance). The shadow test is done at the hit point
  for all shading modes; with ``gouraud`` the light's interpolated contribution is
  multiplied by the pixel's visibility (per-vertex lighting, per-pixel shadows, as a
  rasteriser with shadow maps does), so shadows stay sharp on coarse meshes.
* ``gouraud`` needs triangle meshes. Hits on other shapes (``sphere``, ``rectangle``,
  ...) fall back to ``phong``; a warning is logged when the scene has such shapes. ``flat`` on an
  analytic shape uses its geometric normal, which equals its shading normal.
* The camera position used for the Gouraud view directions is the camera ray's origin
  (exact for a pinhole ``perspective`` sensor). The vertex data (position, vertex normal
  -- the face normal for meshes without vertex normals --, texture coordinates) come from
  Mitsuba's surface interaction at the corners of the hit triangle, so instanced and
  transformed meshes work.
* Participating media are ignored (fog stands in for them; compare with ``volpath``).
  Pixels where fog is on count as valid (alpha 1) even when the ray hits nothing.
* Written for every variant (RGB, spectral; LLVM and CUDA; tested on the LLVM ones):
  one Dr.Jit kernel, with a Python loop over the scene's emitters when it is traced.

Source: the lecture's local illumination model; H. Gouraud, "Continuous shading of
curved surfaces", IEEE Trans. Computers C-20(6), 1971; B. T. Phong, "Illumination for
computer generated pictures", CACM 18(6), 1975; fog: OpenGL 1.5 specification,
section 3.10.

XML example::

    <integrator type="local">
        <string name="shading" value="gouraud"/>
        <boolean name="shadows" value="true"/>
        <float name="shadow_bias" value="0.001"/>
        <rgb name="ambient" value="0.1"/>
        <string name="fog" value="exponential"/>
        <float name="fog_density" value="0.05"/>
        <rgb name="fog_color" value="0.6, 0.65, 0.7"/>
    </integrator>
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi
from spectrace.plugins.integrators.fog import FOG_LAWS


def _fail(name, rule, value):
    raise ValueError(f"local: parameter '{name}' {rule} (got {value!r})")


def _shade_phong(integrator, scene, ray, pi, si, bsdf, samples, active):
    """Model evaluated at the hit with its interpolated shading frame."""
    lights = integrator._light_samples(scene, si, samples, active)
    visible = integrator._visibility(scene, si, lights, active)
    return integrator._model(bsdf, si, lights, visible, active)


def _shade_flat(integrator, scene, ray, pi, si, bsdf, samples, active):
    """Model evaluated at the hit with the face (geometric) normal as shading normal."""
    si = mi.SurfaceInteraction3f(si)
    si.sh_frame = mi.Frame3f(si.n)
    si.wi = si.to_local(-ray.d)
    return _shade_phong(integrator, scene, ray, pi, si, bsdf, samples, active)


def _shade_gouraud(integrator, scene, ray, pi, si, bsdf, samples, active):
    """Model evaluated at the triangle's vertices, radiance interpolated barycentrically.

    The surface interaction at vertex k is Mitsuba's own one at the barycentric corner k
    of the hit triangle (vertex position, vertex normal or else face normal, vertex
    texture coordinates; instances and flipped normals handled by the shape), with the
    view direction from the vertex to the camera."""
    lights = integrator._light_samples(scene, si, samples, active)
    visible = integrator._visibility(scene, si, lights, active)

    is_mesh = active & si.shape.is_mesh()
    u, v = pi.prim_uv.x, pi.prim_uv.y
    weights = (
        dr.select(is_mesh, 1.0 - u - v, 1.0),
        dr.select(is_mesh, u, 0.0),
        dr.select(is_mesh, v, 0.0),
    )
    corners = ((0.0, 0.0), (1.0, 0.0), (0.0, 1.0))

    L = dr.zeros(mi.Spectrum)
    for k in range(3):
        pi_k = mi.PreliminaryIntersection3f(pi)
        pi_k.prim_uv = mi.Point2f(*corners[k])
        si_k = pi_k.compute_surface_interaction(ray, mi.RayFlags.All, is_mesh)
        si_k.wi = si_k.to_local(dr.normalize(ray.o - si_k.p))
        si_k = dr.select(is_mesh, si_k, si)
        lights_k = integrator._light_samples(scene, si_k, samples, active)
        L += weights[k] * integrator._model(bsdf, si_k, lights_k, visible, active)
    return L


#: XML name of the shading model -> function computing the reflected radiance of a hit.
SHADING_MODELS = {
    "flat": _shade_flat,
    "gouraud": _shade_gouraud,
    "phong": _shade_phong,
}


class Local(mi.SamplingIntegrator):
    """The lecture's local illumination model; see the module docstring."""

    def __init__(self, props):
        super().__init__(props)
        self.shading = props.get("shading", "phong")
        if self.shading not in SHADING_MODELS:
            _fail("shading", f"must be one of {', '.join(sorted(SHADING_MODELS))}", self.shading)
        self.shadows = bool(props.get("shadows", True))
        self.shadow_bias = float(props.get("shadow_bias", 1e-3))
        if not self.shadow_bias >= 0.0:
            _fail("shadow_bias", "must be >= 0", self.shadow_bias)

        self.ambient = self._spectrum(props, "ambient")
        self.fog = props.get("fog", "none")
        if self.fog not in FOG_LAWS:
            _fail("fog", f"must be one of {', '.join(sorted(FOG_LAWS))}", self.fog)
        self.fog_start = float(props.get("fog_start", 0.0))
        self.fog_end = float(props.get("fog_end", 1.0))
        self.fog_density = float(props.get("fog_density", 1.0))
        self.fog_color = self._spectrum(props, "fog_color")
        if not self.fog_start >= 0.0:
            _fail("fog_start", "must be >= 0", self.fog_start)
        if not self.fog_end > self.fog_start:
            _fail("fog_end", f"must be > fog_start = {self.fog_start}", self.fog_end)
        if not self.fog_density >= 0.0:
            _fail("fog_density", "must be >= 0", self.fog_density)

    @staticmethod
    def _spectrum(props, name):
        """Emission-type spectrum ``name``; None (black) when absent or all zero, since
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
                _fail(name, "must be >= 0", value)
            if max(values) == 0.0:
                return None
        return props.get_emissive_texture(name)

    # -- pieces of the model ---------------------------------------------------------

    def _light_samples(self, scene, it, samples, active):
        """(ds, incident radiance) of every emitter at the point ``it``."""
        return [
            emitter.sample_direction(it, sample, active)
            for emitter, sample in zip(scene.emitters(), samples, strict=True)
        ]

    def _visibility(self, scene, si, lights, active):
        """Whether each light sample is lit and unoccluded, the shadow ray starting at
        p + shadow_bias * n (n: geometric normal on the light's side), no extra offset."""
        visible = []
        for ds, radiance in lights:
            lit = active & dr.any(radiance != 0.0)
            if self.shadows:
                n = dr.mulsign(si.n, dr.dot(si.n, ds.d))
                origin = si.p + self.shadow_bias * n
                shadow_ray = mi.Ray3f(
                    origin, ds.d, ds.dist * (1.0 - mi.math.ShadowEpsilon), si.time, si.wavelengths
                )
                lit &= ~scene.ray_test(shadow_ray, lit)
            visible.append(lit)
        return visible

    def _model(self, bsdf, si, lights, visible, active):
        """sum_j V_j L_j f(l_j, v) (n . l_j) + rho/pi * ambient at ``si``."""
        ctx = mi.BSDFContext()
        L = dr.zeros(mi.Spectrum)
        for (ds, radiance), lit in zip(lights, visible, strict=True):
            f = bsdf.eval(ctx, si, si.to_local(ds.d), lit)
            L += dr.select(lit, f * radiance, 0.0)
        if self.ambient is not None:
            rho = bsdf.eval_diffuse_reflectance(si, active)
            L += dr.select(active, rho * dr.inv_pi * self.ambient.eval(si, active), 0.0)
        return L

    def fog_fraction(self, d):
        """f(d) of the configured fog law for camera distances ``d``."""
        return FOG_LAWS[self.fog](d, self.fog_start, self.fog_end, self.fog_density)

    # -- Mitsuba interface -----------------------------------------------------------

    def sample(self, scene, sampler, ray, medium=None, active=True):
        active = mi.Bool(active)
        if self.shading == "gouraud" and not all(
            shape.is_mesh() or shape.class_name() == "Instance" for shape in scene.shapes()
        ):
            mi.Log(
                mi.LogLevel.Warn,
                "local: shading 'gouraud' needs triangle meshes; "
                "hits on other shapes are shaded with 'phong'",
            )
        pi = scene.ray_intersect_preliminary(ray, coherent=True, active=active)
        si = pi.compute_surface_interaction(ray, mi.RayFlags.All, active)
        hit = active & si.is_valid()

        L = dr.zeros(mi.Spectrum)
        if not self.hide_emitters:
            L += si.emitter(scene, active).eval(si, active)
        samples = [sampler.next_2d(hit) for _ in scene.emitters()]
        bsdf = si.bsdf(ray)
        L += SHADING_MODELS[self.shading](self, scene, ray, pi, si, bsdf, samples, hit)

        valid = hit
        if self.fog != "none":
            d = dr.select(hit, si.t, dr.largest(mi.Float))
            f = self.fog_fraction(d)
            L = f * L
            if self.fog_color is not None:
                L += (1.0 - f) * self.fog_color.eval(si, active)
            valid = active
        return L, valid, []

    def to_string(self):
        return (
            f"Local[shading={self.shading!r}, shadows={self.shadows}, "
            f"shadow_bias={self.shadow_bias}, fog={self.fog!r}]"
        )


mi.register_integrator("local", lambda props: Local(props))
