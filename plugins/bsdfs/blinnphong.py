"""``blinnphong``: Lambertian diffuse plus Blinn's half-vector lobe (a BSDF).

Parameters
----------

========================  =========  =======  ====  ==============================================
parameter                 type       default  unit  description
========================  =========  =======  ====  ==============================================
``diffuse_reflectance``   spectrum   0.5      --    rho, the diffuse reflectance (albedo of the
                          or                        diffuse part); in [0, 1] everywhere |exposed|
                          texture                   |differentiable|
``specular_reflectance``  spectrum   0.2      --    rho_s, the specular coefficient (the
                          or                        textbooks' k_s); in [0, 1] everywhere
                          texture                   |exposed| |differentiable|
``exponent``              float      32       --    m, the Blinn-Phong exponent (larger: sharper
                                                    highlight); > 0 |exposed| |differentiable|
                                                    |discontinuous|
``normalized``            boolean    false    --    false: the classic lobe; true: the
                                                    energy-normalized lobe (below)
========================  =========  =======  ====  ==============================================

A reflectance texture is checked at load (values in [0, 1], evaluated on a grid when it is
spatially varying); one that cannot be evaluated for the check is refused.

Formula
-------

With wi towards the light, wo towards the viewer, local frame with n = +Z,
h = (wi + wo)/|wi + wo| the half vector; symmetric in wi and wo, hence reciprocal::

    f(wi, wo) = rho / pi + rho_s * k * (n . h)^m
    k = 1                                              (normalized = false: Blinn 1977)
    k = (m + 2)(m + 4) / (8 pi (2^(-m/2) + m))         (normalized = true)

The normalization is exact: at normal incidence (wi = n, so theta_h = theta_o / 2)
the integral of (n.h)^m cos(theta_o) over the hemisphere is
8 pi (2^(-m/2) + m) / ((m + 2)(m + 4)), so the normalized lobe's albedo there is 1
(Giesen 2009). The popular approximation (m + 8)/(8 pi)
overshoots it by up to about 7.5% (maximum near m = 8.8; 4.2% at m = 2, 4.6% at
m = 32): it reflects more energy than it receives for rho_s = 1.

``eval`` returns f * cos(theta_o), as Mitsuba expects. Only the front side reflects
(zero when wi or wo is below the surface), like ``diffuse``.

Energy: the classic lobe's albedo at normal incidence is
rho_s * 8 pi (2^(-m/2) + m) / ((m + 2)(m + 4)), above 1 for rho_s = 1 and m below
about 18.7 (m = 2: 5 pi / 6, about 2.62).

Sampling: a mixture of cosine-weighted hemisphere sampling and half vectors drawn with
density (m + 1)/(2 pi) (n.h)^m, reflected about h (density
(m + 1)/(2 pi) (n.h)^m / (4 wo.h) in wo; directions below the surface are rejected,
weight 0); mixture weights as for ``phong`` (see :mod:`spectrace.plugins.bsdfs.lobes`).

Sources
-------

Blinn (1977), "Models of light reflection for computer synthesized pictures",
*SIGGRAPH 1977*; Giesen (2009), "The Blinn-Phong normalization zoo" (the exact
normalization).

Example
-------

A blue normalized Blinn-Phong plastic::

    <bsdf type="blinnphong">
        <rgb name="diffuse_reflectance" value="0.1, 0.2, 0.5"/>
        <float name="specular_reflectance" value="0.4"/>
        <float name="exponent" value="100"/>
        <boolean name="normalized" value="true"/>
    </bsdf>
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi
from spectrace.plugins.bsdfs.lobes import LobeBSDF, power_cosine, sample_power_cosine


class BlinnPhong(LobeBSDF):
    """f = rho/pi + rho_s k (n.h)^m; see the module docstring."""

    name = "blinnphong"

    @staticmethod
    def normalization(m):
        return (m + 2.0) * (m + 4.0) / (8.0 * dr.pi * (dr.exp2(-0.5 * m) + m))

    def lobe(self, wi, wo):
        h = dr.normalize(wi + wo)
        lobe = power_cosine(h.z, self.m_exponent)
        wo_dot_h = dr.dot(wo, h)
        valid = wo_dot_h > 0
        lobe_pdf = dr.select(
            valid, self.m_pdf_scale * lobe / (4.0 * dr.select(valid, wo_dot_h, 1.0)), 0.0
        )
        return lobe, lobe_pdf

    def sample_lobe(self, wi, sample2):
        return mi.reflect(wi, sample_power_cosine(sample2, self.m_inv_m1))


mi.register_bsdf("blinnphong", lambda props: BlinnPhong(props))
