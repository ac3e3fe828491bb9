"""Shared machinery of the ``phong`` and ``blinnphong`` BSDFs (not a plugin itself).

Both models are f = rho/pi + rho_s * k(m) * lobe(wi, wo), front side only, with a
diffuse component (index 0, ``DiffuseReflection``) and a glossy one (index 1,
``GlossyReflection``). :class:`LobeBSDF` implements everything but the lobe: parameter
parsing and validation, ``eval``/``pdf``/``eval_pdf``/``sample`` as a two-component
mixture, ``traverse``/``parameters_changed``, ``eval_diffuse_reflectance`` and the
attributes. A subclass supplies four things:

- ``name``: the plugin's XML type (used in error messages and ``to_string``);
- ``normalization(m)``: the factor that makes the lobe's albedo 1 at normal incidence
  (so the classic lobe's albedo at normal incidence is ``1 / normalization(m)``);
- ``lobe(wi, wo)``: the unnormalized lobe value and the density of ``sample_lobe``
  at ``wo`` (solid angle, local frame);
- ``sample_lobe(wi, sample2)``: a direction drawn from that density.

Sampling: the glossy lobe is chosen with probability s / (d + s), where d is the mean
of rho over the colour channels (or sampled wavelengths) at the hit and s is the mean of
rho_s times the lobe's albedo at normal incidence (1 when normalized, 1/k(m) otherwise),
so each component is sampled in proportion to the energy it reflects. The mixture
weights are detached: gradients flow through ``eval`` only.

Every Mitsuba type is looked up when the module executes, so :func:`spectrace.plugins.register`
can re-execute it after a variant switch.
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi
from spectrace.plugins import params

from spectrace.errors import ParameterError

#: Parameters the two BSDFs accept; anything else is a load error (a typo, usually).
PARAMETERS = ("diffuse_reflectance", "specular_reflectance", "exponent", "normalized")


def power_cosine(c, m):
    """c^m for c > 0, else 0; safe for gradients with respect to m (no log(0))."""
    positive = c > 0
    return dr.select(positive, dr.power(dr.select(positive, c, 1.0), m), 0.0)


def sample_power_cosine(sample2, inv_m1):
    """Direction around +Z with density (m+1)/(2 pi) cos^m(theta); ``inv_m1`` = 1/(m+1)."""
    cos_theta = dr.power(sample2.x, inv_m1)
    sin_theta = dr.safe_sqrt(1.0 - cos_theta * cos_theta)
    sin_phi, cos_phi = dr.sincos(dr.two_pi * sample2.y)
    return mi.Vector3f(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta)


class LobeBSDF(mi.BSDF):
    """Diffuse + glossy lobe BSDF; subclasses define the lobe (see the module docstring)."""

    name = "lobe"

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        unknown = sorted(set(props.keys()) - set(PARAMETERS))
        if unknown:
            raise ParameterError(
                f"{self.name}: unknown parameter(s) {', '.join(map(repr, unknown))}; "
                f"expected {', '.join(PARAMETERS)}"
            )
        self.m_diffuse = params.read_reflectance(props, self.name, "diffuse_reflectance", 0.5)
        self.m_specular = params.read_reflectance(props, self.name, "specular_reflectance", 0.2)
        exponent = params.read_float(props, self.name, "exponent", 32.0, minimum=0.0,
                                     strict_minimum=True, finite=True)
        self.m_exponent = dr.opaque(mi.Float, exponent)
        self.m_normalized = params.read_bool(props, self.name, "normalized", False)
        diffuse = mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.FrontSide
        glossy = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
        self.m_components = [diffuse, glossy]
        self.m_flags = diffuse | glossy
        self.parameters_changed()

    # -- subclass interface --------------------------------------------------------
    @staticmethod
    def normalization(m):
        raise NotImplementedError

    def lobe(self, wi, wo):
        raise NotImplementedError

    def sample_lobe(self, wi, sample2):
        raise NotImplementedError

    # -- parameters ----------------------------------------------------------------
    def traverse(self, cb):
        cb.put("diffuse_reflectance", self.m_diffuse, mi.ParamFlags.Differentiable)
        cb.put("specular_reflectance", self.m_specular, mi.ParamFlags.Differentiable)
        cb.put(
            "exponent",
            self.m_exponent,
            mi.ParamFlags.Differentiable | mi.ParamFlags.Discontinuous,
        )

    def parameters_changed(self, keys=None):
        """Recompute the exponent's derived constants (opaque: no recompilation per value)."""
        m = self.m_exponent
        k = self.normalization(m)
        one = dr.opaque(mi.Float, 1.0)
        self.m_lobe_scale = k if self.m_normalized else one
        self.m_lobe_albedo = dr.detach(one if self.m_normalized else 1.0 / k)
        self.m_inv_m1 = 1.0 / (m + 1.0)
        self.m_pdf_scale = (m + 1.0) * dr.inv_two_pi
        dr.make_opaque(self.m_lobe_scale, self.m_lobe_albedo, self.m_inv_m1, self.m_pdf_scale)

    # -- evaluation ----------------------------------------------------------------
    @staticmethod
    def _enabled(ctx):
        return (
            ctx.is_enabled(mi.BSDFFlags.DiffuseReflection, 0),
            ctx.is_enabled(mi.BSDFFlags.GlossyReflection, 1),
        )

    def _glossy_probability(self, rho, rho_s, has_diffuse, has_glossy):
        if not has_glossy:
            return mi.Float(0.0)
        if not has_diffuse:
            return mi.Float(1.0)
        d = dr.detach(dr.mean(rho, axis=0))
        s = dr.detach(dr.mean(rho_s, axis=0)) * self.m_lobe_albedo
        total = d + s
        return dr.select(total > 0, s / total, 0.5)

    def _value_pdf(self, wi, wo, rho, rho_s, p_glossy, has_diffuse, has_glossy, active):
        """(f * cos_o, mixture density) at wo, given the reflectances at the hit."""
        cos_o = wo.z
        active = active & (cos_o > 0)
        lobe, lobe_pdf = self.lobe(wi, wo)
        f = dr.zeros(mi.UnpolarizedSpectrum)
        if has_diffuse:
            f += rho * dr.inv_pi
        if has_glossy:
            f += rho_s * (self.m_lobe_scale * lobe)
        pdf = (1.0 - p_glossy) * (cos_o * dr.inv_pi) + p_glossy * lobe_pdf
        return (
            dr.select(active, f * cos_o, 0.0),
            dr.select(active, pdf, 0.0),
        )

    def _reflectances(self, si, active):
        return self.m_diffuse.eval(si, active), self.m_specular.eval(si, active)

    def eval_pdf(self, ctx, si, wo, active=True):
        has_diffuse, has_glossy = self._enabled(ctx)
        if not (has_diffuse or has_glossy):
            return dr.zeros(mi.Spectrum), mi.Float(0.0)
        active = mi.Bool(active) & (si.wi.z > 0)
        rho, rho_s = self._reflectances(si, active)
        p_glossy = self._glossy_probability(rho, rho_s, has_diffuse, has_glossy)
        value, pdf = self._value_pdf(
            si.wi, wo, rho, rho_s, p_glossy, has_diffuse, has_glossy, active
        )
        return mi.Spectrum(value), pdf

    def eval(self, ctx, si, wo, active=True):
        return self.eval_pdf(ctx, si, wo, active)[0]

    def pdf(self, ctx, si, wo, active=True):
        return self.eval_pdf(ctx, si, wo, active)[1]

    def sample(self, ctx, si, sample1, sample2, active=True):
        has_diffuse, has_glossy = self._enabled(ctx)
        bs = dr.zeros(mi.BSDFSample3f)
        if not (has_diffuse or has_glossy):
            return bs, dr.zeros(mi.Spectrum)
        wi = si.wi
        active = mi.Bool(active) & (wi.z > 0)
        rho, rho_s = self._reflectances(si, active)
        p_glossy = self._glossy_probability(rho, rho_s, has_diffuse, has_glossy)
        pick_glossy = sample1 < p_glossy
        wo = dr.select(
            pick_glossy,
            self.sample_lobe(wi, sample2),
            mi.warp.square_to_cosine_hemisphere(sample2),
        )
        value, pdf = self._value_pdf(
            wi, wo, rho, rho_s, p_glossy, has_diffuse, has_glossy, active
        )
        active &= pdf > 0
        bs.wo = wo
        bs.pdf = pdf
        bs.eta = 1.0
        bs.sampled_type = dr.select(
            pick_glossy,
            mi.UInt32(+mi.BSDFFlags.GlossyReflection),
            mi.UInt32(+mi.BSDFFlags.DiffuseReflection),
        )
        bs.sampled_component = dr.select(pick_glossy, mi.UInt32(1), mi.UInt32(0))
        weight = dr.select(active, value / dr.select(active, pdf, 1.0), 0.0)
        return bs, mi.Spectrum(weight)

    def eval_diffuse_reflectance(self, si, active=True):
        return mi.Spectrum(self.m_diffuse.eval(si, active))

    # -- attributes ----------------------------------------------------------------
    def _attribute(self, name):
        return {"diffuse_reflectance": self.m_diffuse, "specular_reflectance": self.m_specular}.get(
            name
        )

    def has_attribute(self, name, active=True):
        return mi.Bool(self._attribute(name) is not None)

    def eval_attribute(self, name, si, active=True):
        texture = self._attribute(name)
        if texture is None:
            return dr.zeros(mi.UnpolarizedSpectrum)
        return texture.eval(si, active)

    def eval_attribute_1(self, name, si, active=True):
        texture = self._attribute(name)
        if texture is None:
            return mi.Float(0.0)
        return texture.eval_1(si, active)

    def eval_attribute_3(self, name, si, active=True):
        texture = self._attribute(name)
        if texture is None:
            return dr.zeros(mi.Color3f)
        return texture.eval_3(si, active)

    def to_string(self):
        def indent(obj):
            return str(obj).replace("\n", "\n  ")

        return (
            f"{type(self).__name__}[\n"
            f"  diffuse_reflectance = {indent(self.m_diffuse)},\n"
            f"  specular_reflectance = {indent(self.m_specular)},\n"
            f"  exponent = {dr.ravel(self.m_exponent)[0]},\n"
            f"  normalized = {str(self.m_normalized).lower()}\n"
            f"]"
        )
