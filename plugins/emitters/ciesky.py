"""``ciesky``: the CIE standard general skies, the CIE overcast sky and the uniform sky, in cd/m^2.

An environment emitter (it surrounds the scene at infinity) whose luminance depends on the
direction d as one of the sky luminance distributions of lighting design: the 15 CIE
standard general skies of ISO 15469:2004 / CIE S 011/E:2003, from overcast (types 1-5) to
cloudless (types 11-15), the traditional CIE overcast sky of Moon and Spencer (1942) and a
uniform sky. Its absolute scale is a zenith luminance in cd/m^2 or the diffuse horizontal
illuminance in lux the unobstructed sky gives, so that a daylight scene and its electric
lights are computed together in lux. Below the horizon it is black, or a uniform ground
of luminance rho E_h / pi (``ground_reflectance`` rho, E_h the sky's horizontal
illuminance). Evaluated analytically; directions are importance sampled from a
tabulation of the same function (piecewise constant on 256 x 256 cells, equal in
solid angle, in azimuth and cos(zenith)).

Parameters
----------

==========================  ===============  ============  =======  ==========================
parameter                   type             default       unit     description
==========================  ===============  ============  =======  ==========================
``sky_type``                integer/string   cie_overcast  --       1 to 15 (ISO 15469 types),
                                                                    ``cie_overcast`` or
                                                                    ``uniform``
``zenith_luminance``        float            --            cd/m^2   luminance L_z of the
                                                                    zenith; > 0
``horizontal_illuminance``  float            10000         lux      instead: the diffuse
                                                                    illuminance E_h of an
                                                                    unobstructed horizontal
                                                                    plane; > 0
``ground_reflectance``      float            0             --       rho in [0, 1] of a uniform
                                                                    ground lit by the sky
``sun_azimuth``             float            180           degree   azimuth of the sun,
                                                                    clockwise from north
``sun_elevation``           float            45            degree   elevation of the sun; >= 0
                                                                    for sun-dependent skies
``latitude``                float            --            degree   with ``longitude`` and
                                                                    ``datetime``: the sun by
                                                                    NREL's SPA (``spectrace
                                                                    help solar``)
``longitude``               float            --            degree   east positive
``datetime``                string           --            --       ISO 8601 with UTC offset
``up``                      vector           (0, 1, 0)     --       the zenith direction;
                                                                    north = up x east, -Z by
                                                                    default
``spectrum``                spectrum         d65           --       spectral shape (scale
                                                                    irrelevant)
``cct``                     float            --            K        instead: CIE daylight of
                                                                    this CCT
==========================  ===============  ============  =======  ==========================

Give at most one of ``zenith_luminance`` and ``horizontal_illuminance``. A sky that depends
on the sun (every type but 1, 3 and 5, which have no indicatrix) refuses a sun below the
horizon. Azimuths run clockwise from north (east 90 degrees); north is -Z and east +X in
a +Y-up scene.

Formula
-------

With Z the zenith angle of the direction, Z_s that of the sun and chi the angle between the
direction and the sun (ISO 15469:2004, CIE S 011/E:2003, eq. 1-3)::

    L / L_z = f(chi) phi(Z) / (f(Z_s) phi(0))
    phi(Z)  = 1 + a exp(b / cos Z)           (gradation; phi(90 deg) = 1)
    f(chi)  = 1 + c (exp(d chi) - exp(d pi / 2)) + e cos^2 chi     (indicatrix)
    CIE overcast (Moon and Spencer 1942):  L / L_z = (1 + 2 cos Z) / 3
    uniform:                               L / L_z = 1

with a, b, c, d, e per type (CIE S 011/E:2003, table 1; Darula and Kittler 2002, table 1)::

    type   a      b      c    d     e       type   a      b      c    d     e
      1    4.0  -0.70    0  -1.0  0.00        9   -1.0  -0.55    2  -1.5  0.15
      2    4.0  -0.70    2  -1.5  0.15       10   -1.0  -0.55    5  -2.5  0.30
      3    1.1  -0.80    0  -1.0  0.00       11   -1.0  -0.55   10  -3.0  0.45
      4    1.1  -0.80    2  -1.5  0.15       12   -1.0  -0.32   10  -3.0  0.45
      5    0.0  -1.00    0  -1.0  0.00       13   -1.0  -0.32   16  -3.0  0.30
      6    0.0  -1.00    2  -1.5  0.15       14   -1.0  -0.15   16  -3.0  0.30
      7    0.0  -1.00    5  -2.5  0.30       15   -1.0  -0.15   24  -2.8  0.15
      8    0.0  -1.00   10  -3.0  0.45

The horizontal illuminance of the unobstructed sky is E_h = L_z integral (L / L_z) cos Z
d omega over the upper hemisphere: 7 pi L_z / 9 for the CIE overcast sky, pi L_z for the
uniform sky, a numerical integral (2048 x 1024 midpoint rule) otherwise. Luminance
becomes spectral radiance as for spectrace's other photometric lights (``spectrace help
luminous``): L_e = L s / (683 integral V s dlambda).

Light tracing (``ptracer``) cannot start rays from this sky (``spectrace help distant``);
every integrator that samples emitters from surfaces (``direct``, ``path``, ``volpath``,
``prb``, ``local``, ``illuminance``) sees it.

Sources
-------

ISO 15469:2004 / CIE S 011/E:2003, *Spatial distribution of daylight - CIE standard general
sky* (table 1); Darula, Kittler (2002), "CIE general sky standard defining luminance
distributions", Proc. eSim 2002, Montreal; Moon, Spencer (1942), "Illumination from a
non-uniform sky", Illuminating Engineering 37, 707-726; Tregenza, Wilson (2011), *Daylighting:
Architecture and Lighting Design*, ch. 6.

Example
-------

A CIE clear sky (type 12) of 8000 lux diffuse horizontal illuminance, the sun in the
south-west 35 degrees high::

    <emitter type="ciesky">
        <integer name="sky_type" value="12"/>
        <float name="horizontal_illuminance" value="8000"/>
        <float name="sun_azimuth" value="225"/>
        <float name="sun_elevation" value="35"/>
    </emitter>
"""

from __future__ import annotations

import math

import drjit as dr
import mitsuba as mi
from spectrace.plugins import params
from spectrace.plugins.emitters import distant, solar

from spectrace.errors import ParameterError

PLUGIN = "ciesky"

#: (a, b, c, d, e) of the 15 CIE standard general skies, ISO 15469:2004 / CIE S 011/E:2003
#: table 1 (checked against Darula and Kittler 2002, table 1).
CIE_STANDARD_SKIES: dict[int, tuple[float, float, float, float, float]] = {
    1: (4.0, -0.70, 0.0, -1.0, 0.00),
    2: (4.0, -0.70, 2.0, -1.5, 0.15),
    3: (1.1, -0.80, 0.0, -1.0, 0.00),
    4: (1.1, -0.80, 2.0, -1.5, 0.15),
    5: (0.0, -1.00, 0.0, -1.0, 0.00),
    6: (0.0, -1.00, 2.0, -1.5, 0.15),
    7: (0.0, -1.00, 5.0, -2.5, 0.30),
    8: (0.0, -1.00, 10.0, -3.0, 0.45),
    9: (-1.0, -0.55, 2.0, -1.5, 0.15),
    10: (-1.0, -0.55, 5.0, -2.5, 0.30),
    11: (-1.0, -0.55, 10.0, -3.0, 0.45),
    12: (-1.0, -0.32, 10.0, -3.0, 0.45),
    13: (-1.0, -0.32, 16.0, -3.0, 0.30),
    14: (-1.0, -0.15, 16.0, -3.0, 0.30),
    15: (-1.0, -0.15, 24.0, -2.8, 0.15),
}
#: The named skies beside the 15 types.
NAMED_SKIES = ("cie_overcast", "uniform")
DEFAULT_SKY = "cie_overcast"
DEFAULT_HORIZONTAL_ILLUMINANCE = 10000.0
#: Cells of the sampling table: azimuth x cos(zenith) over the whole sphere.
TABLE_PHI, TABLE_MU = 256, 256
#: Midpoint grid (azimuth x cos(zenith) over the upper hemisphere) of the E_h integral.
NORMALIZATION_PHI, NORMALIZATION_MU = 2048, 1024
#: cos(zenith) floor of the gradation's b / cos Z (exp of it is 0 in float32 anyway).
COS_FLOOR = 1e-20


def read_sky_type(props) -> str | int:
    """``sky_type``: an integer 1-15 (or its digits as a string), ``cie_overcast`` or
    ``uniform``."""
    listed = "an integer 1 to 15, 'cie_overcast' or 'uniform'"
    if "sky_type" not in props:
        return DEFAULT_SKY
    kind = props.type("sky_type")
    if kind == mi.Properties.Type.Integer:
        value = int(props.get("sky_type"))
    elif kind == mi.Properties.Type.String:
        text = str(props.get("sky_type")).strip()
        if text in NAMED_SKIES:
            return text
        if not text.isdigit():
            raise ParameterError(f"{PLUGIN}: parameter 'sky_type' must be {listed} (got {text!r})")
        value = int(text)
    else:
        raise ParameterError(f"{PLUGIN}: parameter 'sky_type' must be {listed} "
                             f"(got a {params.xml_type(props, 'sky_type')})")
    if value not in CIE_STANDARD_SKIES:
        raise ParameterError(f"{PLUGIN}: parameter 'sky_type' must be {listed} (got {value})")
    return value


def sun_dependent(sky) -> bool:
    """Whether the sky's luminance depends on the sun's position (an indicatrix)."""
    if sky in NAMED_SKIES:
        return False
    _, _, c, _, e = CIE_STANDARD_SKIES[sky]
    return c != 0.0 or e != 0.0


def indicatrix(chi, cos_chi, c, d, e):
    """f(chi) = 1 + c (exp(d chi) - exp(d pi/2)) + e cos^2 chi (Dr.Jit or float)."""
    exp = dr.exp if not isinstance(chi, float) else math.exp
    return 1.0 + c * (exp(d * chi) - math.exp(d * math.pi / 2.0)) + e * cos_chi * cos_chi


def gradation(cos_z, a, b):
    """phi(Z) = 1 + a exp(b / cos Z), for cos Z > 0 (Dr.Jit or float)."""
    if isinstance(cos_z, float):
        return 1.0 + a * math.exp(b / cos_z)
    return 1.0 + a * dr.exp(b / dr.maximum(cos_z, COS_FLOOR))


def _general(cos_z, cos_chi, coefficients, norm):
    a, b, c, d, e = coefficients
    cos_chi = dr.clip(cos_chi, -1.0, 1.0)
    return indicatrix(dr.acos(cos_chi), cos_chi, c, d, e) * gradation(cos_z, a, b) / norm


#: Relative luminance L / L_z of a sky above the horizon: name -> f(cos Z, cos chi,
#: coefficients, normalisation) (colour-science's *_METHODS style).
SKY_MODELS = {
    "cie_general": _general,
    "cie_overcast": lambda cos_z, cos_chi, coefficients, norm: (1.0 + 2.0 * cos_z) / 3.0,
    "uniform": lambda cos_z, cos_chi, coefficients, norm: dr.full(mi.Float, 1.0,
                                                                   dr.width(cos_z)),
}
#: E_h / L_z of the skies with a closed form (Moon and Spencer: 7 pi / 9; uniform: pi).
HORIZONTAL_FACTORS = {"cie_overcast": 7.0 * math.pi / 9.0, "uniform": math.pi}


class CIESky(distant.DistantLight):
    """A sky luminance distribution of ISO 15469 (or CIE overcast, uniform) at infinity."""

    def __init__(self, props):
        mi.Emitter.__init__(self, props)
        self.sky = read_sky_type(props)
        self.model = self.sky if self.sky in NAMED_SKIES else "cie_general"
        self.coefficients = CIE_STANDARD_SKIES.get(self.sky, (0.0,) * 5)
        east, north, up = solar.read_frame(props, PLUGIN)
        self.azimuth, self.elevation = solar.read_sun_position(props, PLUGIN)
        if sun_dependent(self.sky) and self.elevation < 0.0:
            raise ParameterError(
                f"{PLUGIN}: sky_type {self.sky} depends on the sun, which is below the horizon "
                f"(elevation {self.elevation:.3g} degrees): pick a sky without sun (1, 3, 5, "
                "cie_overcast, uniform) or another time")
        sun = solar.direction(self.azimuth, self.elevation, (east, north, up))
        self.east, self.north, self.up = (mi.ScalarVector3f(v) for v in (east, north, up))
        self.sun = mi.ScalarVector3f(sun)
        self.norm = 1.0
        if self.model == "cie_general":
            a, b, c, d, e = self.coefficients
            cos_zs = max(math.sin(math.radians(self.elevation)), 0.0)
            zs = math.acos(min(cos_zs, 1.0))
            self.norm = indicatrix(zs, cos_zs, c, d, e) * (1.0 + a * math.exp(b))
        self.ground_reflectance = params.read_float(props, PLUGIN, "ground_reflectance", 0.0,
                                                    minimum=0.0, maximum=1.0)
        self.texture, self.watts_per_lumen = solar.read_daylight_spectrum(props, PLUGIN)
        self.ground = 0.0  # the sky alone while E_h is integrated
        self.horizontal_factor = self._horizontal_factor()
        self.zenith_luminance = self._read_scale(props)
        self.horizontal_illuminance = self.zenith_luminance * self.horizontal_factor
        #: ground luminance / L_z
        self.ground = self.ground_reflectance * self.horizontal_factor / math.pi
        self.scale = self.zenith_luminance * self.watts_per_lumen
        self._build_table()
        self.m_flags = mi.EmitterFlags.Infinite | mi.EmitterFlags.SpatiallyVarying

    # -- parameters ---------------------------------------------------------------------

    def _read_scale(self, props) -> float:
        if "zenith_luminance" in props and "horizontal_illuminance" in props:
            raise ParameterError(f"{PLUGIN}: give either parameter 'zenith_luminance' or "
                                 "'horizontal_illuminance', not both")
        if "zenith_luminance" in props:
            return params.read_float(props, PLUGIN, "zenith_luminance", params.REQUIRED,
                                     strict_minimum=True, minimum=0.0, finite=True)
        illuminance = params.read_float(props, PLUGIN, "horizontal_illuminance",
                                        DEFAULT_HORIZONTAL_ILLUMINANCE, minimum=0.0,
                                        strict_minimum=True, finite=True)
        return illuminance / self.horizontal_factor

    def _horizontal_factor(self) -> float:
        """E_h / L_z: closed form where there is one, else the midpoint rule."""
        if self.model in HORIZONTAL_FACTORS:
            return HORIZONTAL_FACTORS[self.model]
        d_phi = 2.0 * math.pi / NORMALIZATION_PHI
        d_mu = 1.0 / NORMALIZATION_MU
        index = dr.arange(mi.UInt32, NORMALIZATION_PHI * NORMALIZATION_MU)
        mu = (mi.Float(index // NORMALIZATION_PHI) + 0.5) * d_mu
        phi = (mi.Float(index % NORMALIZATION_PHI) + 0.5) * d_phi
        value = self.relative_luminance(self._to_world(mu, phi)) * mu
        import numpy as np

        return float(np.sum(np.asarray(value, dtype=np.float64))) * d_phi * d_mu

    # -- the sky function ---------------------------------------------------------------

    def _to_world(self, mu, phi):
        """World direction of cos(zenith) ``mu`` and azimuth angle ``phi`` counted from
        east towards north (the table's angle, not the compass azimuth)."""
        sin_t = dr.safe_sqrt(1.0 - mu * mu)
        x, y = sin_t * dr.cos(phi), sin_t * dr.sin(phi)
        return x * mi.Vector3f(self.east) + y * mi.Vector3f(self.north) + \
            mu * mi.Vector3f(self.up)

    def _local(self, d):
        """(cos zenith, table angle in [0, 2 pi)) of world direction ``d``."""
        mu = dr.dot(d, mi.Vector3f(self.up))
        phi = dr.atan2(dr.dot(d, mi.Vector3f(self.north)), dr.dot(d, mi.Vector3f(self.east)))
        phi = dr.select(phi < 0.0, phi + 2.0 * math.pi, phi)
        return mu, phi

    def relative_luminance(self, d):
        """L / L_z in the unit world direction ``d`` (Dr.Jit): the sky above the horizon,
        the ground's rho E_h / (pi L_z) below it."""
        cos_z = dr.dot(d, mi.Vector3f(self.up))
        cos_chi = dr.dot(d, mi.Vector3f(self.sun))
        sky = SKY_MODELS[self.model](cos_z, cos_chi, self.coefficients, self.norm)
        return dr.select(cos_z > 0.0, sky, self.ground)

    def _radiance_scale(self, d):
        return self.scale * self.relative_luminance(d)

    # -- importance sampling ------------------------------------------------------------

    def _build_table(self):
        """Piecewise-constant density on TABLE_PHI x TABLE_MU cells of equal solid angle
        (azimuth x cos zenith on [-1, 1]), the sky function at the cell centres."""
        self.d_phi = 2.0 * math.pi / TABLE_PHI
        self.d_mu = 2.0 / TABLE_MU
        index = dr.arange(mi.UInt32, TABLE_PHI * TABLE_MU)
        mu = -1.0 + (mi.Float(index // TABLE_PHI) + 0.5) * self.d_mu
        phi = (mi.Float(index % TABLE_PHI) + 0.5) * self.d_phi
        values = self.relative_luminance(self._to_world(mu, phi))
        dr.eval(values)
        self.distribution = mi.DiscreteDistribution(dr.detach(values))

    def _cell(self, d):
        mu, phi = self._local(d)
        i_mu = mi.UInt32(dr.clip(mi.Int32((mu + 1.0) / self.d_mu), 0, TABLE_MU - 1))
        i_phi = mi.UInt32(dr.clip(mi.Int32(phi / self.d_phi), 0, TABLE_PHI - 1))
        return i_mu * TABLE_PHI + i_phi

    def _pdf(self, d, active=True):
        pmf = self.distribution.eval_pmf_normalized(self._cell(d), active)
        return pmf / (self.d_phi * self.d_mu)

    # -- the emitter interface ----------------------------------------------------------

    def eval(self, si, active=True):
        return self._radiance(-si.wi, si.wavelengths, active)

    def sample_direction(self, it, sample, active=True):
        index, u, pmf = self.distribution.sample_reuse_pmf(sample.x, active)
        i_mu, i_phi = index // TABLE_PHI, index % TABLE_PHI
        phi = (mi.Float(i_phi) + u) * self.d_phi
        mu = -1.0 + (mi.Float(i_mu) + sample.y) * self.d_mu
        d = self._to_world(mu, phi)
        ds = self._direction_sample(it, d, pmf / (self.d_phi * self.d_mu), False)
        value = self._radiance(d, it.wavelengths, active)
        return ds, dr.select(active & (ds.pdf > 0.0), value / ds.pdf, 0.0)

    def pdf_direction(self, it, ds, active=True):
        return self._pdf(ds.d, active)

    def to_string(self):
        return (f"CIESky[sky_type={self.sky}, zenith_luminance={self.zenith_luminance:g} "
                f"cd/m^2, horizontal_illuminance={self.horizontal_illuminance:g} lx, "
                f"sun=({self.azimuth:.2f}, {self.elevation:.2f}) deg]")


mi.register_emitter(PLUGIN, lambda props: CIESky(props))
