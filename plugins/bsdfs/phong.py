"""``phong``: Lambertian diffuse plus Phong's cosine-power lobe (a BSDF).

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
``exponent``              float      32       --    m, the Phong exponent (larger: sharper
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
r = mirror of wi about n, so r.wo = cos of the angle between wo and the mirror
direction; symmetric in wi and wo, hence reciprocal::

    f(wi, wo) = rho / pi + rho_s * k * max(r . wo, 0)^m
    k = 1                   (normalized = false: Phong 1975)
    k = (m + 2) / (2 pi)    (normalized = true: Lewis 1994)

``eval`` returns f * cos(theta_o), as Mitsuba expects. Only the front side reflects
(zero when wi or wo is below the surface), like ``diffuse``.

Energy: at normal incidence the lobe reflects rho_s * 2 pi / (m + 2) of the incident
energy when classic, so for m < 2 pi - 2 (about 4.28) and rho_s = 1 it reflects more
than it receives (m = 2: pi/2, about 1.57). The normalized lobe reflects exactly rho_s
at normal incidence and less at grazing angles (part of the lobe goes below the
horizon); rho + rho_s <= 1 then keeps the BSDF energy conserving. See
``spectrace furnace`` and ``scenes/phong_vs_energy.xml``.

Sampling: a mixture of cosine-weighted hemisphere sampling and the lobe itself, drawn
with density (m + 1)/(2 pi) cos^m around r (directions below the surface are rejected,
weight 0); the glossy lobe is picked with probability proportional to its albedo at
normal incidence times the mean of rho_s, the diffuse one in proportion to the mean of
rho (see :mod:`spectrace.plugins.bsdfs.lobes`). ``pdf`` is the density of ``sample``.

Sources
-------

Phong (1975), "Illumination for computer generated pictures", *Communications of the
ACM* 18(6); Lewis (1994), "Making shaders more physically plausible", *Computer Graphics
Forum* 13(2) (the normalization); Lafortune, Willems (1994), "Using the modified Phong
reflectance model for physically based rendering", KU Leuven report CW197 (sampling).

Example
-------

A red normalized Phong plastic::

    <bsdf type="phong">
        <rgb name="diffuse_reflectance" value="0.4, 0.1, 0.1"/>
        <float name="specular_reflectance" value="0.3"/>
        <float name="exponent" value="64"/>
        <boolean name="normalized" value="true"/>
    </bsdf>
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi
from spectrace.plugins.bsdfs.lobes import LobeBSDF, power_cosine, sample_power_cosine


class Phong(LobeBSDF):
    """f = rho/pi + rho_s k (r.wo)^m; see the module docstring."""

    name = "phong"

    @staticmethod
    def normalization(m):
        return (m + 2.0) * dr.inv_two_pi

    def lobe(self, wi, wo):
        lobe = power_cosine(dr.dot(mi.reflect(wi), wo), self.m_exponent)
        return lobe, self.m_pdf_scale * lobe

    def sample_lobe(self, wi, sample2):
        return mi.Frame3f(mi.reflect(wi)).to_world(sample_power_cosine(sample2, self.m_inv_m1))


mi.register_bsdf("phong", lambda props: Phong(props))
