"""Phong BSDF (``phong``): Lambertian diffuse plus Phong's cosine-power lobe.

.. list-table::
   :header-rows: 1

   * - Parameter
     - Type
     - Default
     - Meaning
   * - ``diffuse_reflectance``
     - spectrum or texture, in [0, 1]
     - 0.5
     - rho, the diffuse reflectance (albedo of the diffuse part)
   * - ``specular_reflectance``
     - spectrum or texture, in [0, 1]
     - 0.2
     - rho_s, the specular coefficient (the lecture's gamma * rho_white)
   * - ``exponent``
     - float, > 0 (unitless)
     - 32
     - m, the Phong exponent (larger: sharper highlight)
   * - ``normalized``
     - boolean
     - false
     - false: the classic lobe; true: the energy-normalized lobe

Formula (wi towards the light, wo towards the viewer, local frame with n = +Z,
r = mirror of wi about n, so r.wo = cos of the angle between wo and the mirror
direction; symmetric in wi and wo, hence reciprocal)::

    f(wi, wo) = rho / pi + rho_s * k * max(r . wo, 0)^m
    k = 1                   (normalized = false: Phong 1975, the lecture's model)
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

Sources: B. T. Phong, "Illumination for computer generated pictures", CACM 18(6), 1975;
R. R. Lewis, "Making shaders more physically plausible", Computer Graphics Forum
13(2), 1994; E. Lafortune and Y. Willems, "Using the modified Phong reflectance model
for physically based rendering", KU Leuven CW197, 1994 (sampling).

XML example::

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
