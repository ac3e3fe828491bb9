"""``sun``: the sun as a distant disk of 0.533 degrees, in lux normal to its direction.

A directional light of finite angular size: a disk of uniform luminance L at infinity,
seen under the angular diameter delta, so that shadows have the penumbra of real sunlight
(an edge at height h above the floor casts a penumbra of width h delta, h x 0.0093 for the
default 0.533 degrees, the sun straight above). The light is given by its illuminance
E_n in lux on a plane normal to the sun; its position by azimuth and elevation or by a
place and a time, as ``ciesky`` (``spectrace help solar``). Directions are sampled
uniformly in solid angle over the disk.

Parameters
----------

====================  ========  =========  ======  ===========================================
parameter             type      default    unit    description
====================  ========  =========  ======  ===========================================
``illuminance``       float     100000     lux     E_n, illuminance on a plane normal to the
                                                   sun; >= 0
``angular_diameter``  float     0.533      degree  delta, in (0, 20]
``sun_azimuth``       float     180        degree  azimuth, clockwise from north (east 90)
``sun_elevation``     float     45         degree  elevation above the horizon, in [0, 90]
``latitude``          float     --         degree  with ``longitude`` and ``datetime``: the sun
                                                   by NREL's SPA
``longitude``         float     --         degree  east positive
``datetime``          string    --         --      ISO 8601 with its UTC offset
``up``                vector    (0, 1, 0)  --      the zenith direction; north = up x east, -Z
                                                   by default
``spectrum``          spectrum  d65        --      spectral shape (scale irrelevant)
``cct``               float     --         K       instead: CIE daylight of this CCT
====================  ========  =========  ======  ===========================================

A sun below the horizon is refused.

Formula
-------

With alpha = delta / 2 the disk's angular radius, its solid angle is Omega = 2 pi (1 - cos
alpha) and a uniform disk of luminance L gives the normal illuminance E_n = L pi sin^2
alpha, so::

    L = E_n / (pi sin^2 alpha),    L_e(lambda) = L s(lambda) / (683 integral V s dlambda)

A direction sample is uniform over the cone (pdf 1 / Omega) with weight L Omega. Like
Mitsuba's ``directional`` emitter the sun is flagged as a delta light: integrators reach it
only by sampling it (``direct``, ``path``, ``volpath``, ``local``, ``illuminance``), not by
rays that happen to hit the disk, so the disk is not seen by the camera or in a mirror;
light tracing (``ptracer``) is not supported (``spectrace help distant``).

Sources
-------

Pharr, Jakob, Humphreys (2023), *Physically Based Rendering* 4th ed., sec. 12.4 (distant
lights) and A.5 (uniform cone sampling); Tregenza, Wilson (2011), *Daylighting:
Architecture and Lighting Design*, ch. 5 (the sun's 0.53 degree disk); Reda, Andreas (2004),
NREL's SPA (solar position).

Example
-------

The sun of 20 June 2026, 15:00 in Berlin, 90 klx normal to it::

    <emitter type="sun">
        <float name="illuminance" value="90000"/>
        <float name="latitude" value="52.52"/>
        <float name="longitude" value="13.405"/>
        <string name="datetime" value="2026-06-20T15:00:00+02:00"/>
    </emitter>
"""

from __future__ import annotations

import math

import drjit as dr
import mitsuba as mi
from spectrace.plugins import params
from spectrace.plugins.emitters import distant, solar

from spectrace.errors import ParameterError

PLUGIN = "sun"
DEFAULT_ILLUMINANCE = 100000.0
DEFAULT_ANGULAR_DIAMETER = 0.533
MAX_ANGULAR_DIAMETER = 20.0


def disk_luminance(illuminance: float, angular_diameter: float) -> float:
    """L = E_n / (pi sin^2 alpha) of a uniform disk of angular diameter 2 alpha (degrees)."""
    alpha = math.radians(angular_diameter) / 2.0
    return illuminance / (math.pi * math.sin(alpha) ** 2)


class Sun(distant.DistantLight):
    """A uniform disk at infinity of angular diameter delta, E_n lux normal to it."""

    def __init__(self, props):
        mi.Emitter.__init__(self, props)
        frame = solar.read_frame(props, PLUGIN)
        self.azimuth, self.elevation = solar.read_sun_position(props, PLUGIN)
        if self.elevation < 0.0:
            raise ParameterError(f"{PLUGIN}: the sun is below the horizon (elevation "
                                 f"{self.elevation:.3g} degrees)")
        self.illuminance = params.read_float(props, PLUGIN, "illuminance", DEFAULT_ILLUMINANCE,
                                             minimum=0.0, finite=True)
        self.angular_diameter = params.read_float(
            props, PLUGIN, "angular_diameter", DEFAULT_ANGULAR_DIAMETER, minimum=0.0,
            strict_minimum=True, maximum=MAX_ANGULAR_DIAMETER)
        self.texture, watts_per_lumen = solar.read_daylight_spectrum(props, PLUGIN)
        alpha = math.radians(self.angular_diameter) / 2.0
        self.cos_alpha = math.cos(alpha)
        self.solid_angle = 2.0 * math.pi * (1.0 - self.cos_alpha)
        self.luminance = disk_luminance(self.illuminance, self.angular_diameter)
        #: radiance per unit spectrum times the disk's solid angle: the sample weight
        self.weight = self.luminance * watts_per_lumen * self.solid_angle
        self.direction = mi.ScalarVector3f(solar.direction(self.azimuth, self.elevation, frame))
        self.frame = mi.Frame3f(mi.Vector3f(self.direction))
        self.m_flags = mi.EmitterFlags.Infinite | mi.EmitterFlags.DeltaDirection
        self.m_needs_sample_2 = True

    def _radiance_scale(self, d):
        inside = dr.dot(d, mi.Vector3f(self.direction)) >= self.cos_alpha
        return dr.select(inside, self.weight / self.solid_angle, 0.0)

    def sample_direction(self, it, sample, active=True):
        d = self.frame.to_world(mi.warp.square_to_uniform_cone(sample, self.cos_alpha))
        ds = self._direction_sample(it, d, mi.Float(1.0 / self.solid_angle), True)
        value = self.texture.eval(self._spectral_si(it.wavelengths), active) * self.weight
        return ds, mi.depolarizer(dr.select(active, value, 0.0))

    def pdf_direction(self, it, ds, active=True):
        return mi.Float(0.0)

    def eval(self, si, active=True):
        return dr.zeros(mi.Spectrum)

    def to_string(self):
        return (f"Sun[illuminance={self.illuminance:g} lx, angular_diameter="
                f"{self.angular_diameter:g} deg, azimuth={self.azimuth:.2f} deg, "
                f"elevation={self.elevation:.2f} deg]")


mi.register_emitter(PLUGIN, lambda props: Sun(props))
