"""Shared base of the ``pointlight`` and ``spotlight`` emitters (not a plugin itself).

Both lights sit at one point (``mi.EmitterFlags.DeltaPosition``), emit an ``intensity``
(W/sr) or a ``power`` (W) spectrum scaled by a constant (``scale``: 1 / solid angle for a
power, None for an intensity) and attenuate it with a distance law of
:mod:`spectrace.plugins.emitters.falloff`. :class:`DeltaLight` implements what is the same
for every such light: the direction sample towards the light point, the zero densities of
delta positions and directions, the sampling and density of wavelengths, the zero
``eval`` (a point cannot be hit), the degenerate bounding box and the traversal key of the
emission. A subclass sets, in its constructor, the attributes

- ``position``: the light's position (a ``mi.Point3f``, or what ``to_world.translation()``
  gives);
- ``intensity``, ``from_power``: from :func:`falloff.parse_emission`;
- ``scale``: the factor applied to the emitted spectrum (None when there is none);
- ``law``: from :func:`falloff.parse_falloff`;

and supplies ``sample_direction`` / ``eval_direction`` (the emitted value),
``sample_position`` and ``sample_ray``. It may override ``_sample_spectrum`` (the spectrum
whose wavelength distribution ``sample_wavelengths`` draws from).

Executed by :func:`spectrace.plugins.register` before the lights, so that the lights
subclass the base built for the active variant (they reference it as ``delta.DeltaLight``
when they are executed).
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi

from spectrace.plugins.emitters import falloff


class DeltaLight(mi.Emitter):
    """What ``pointlight`` and ``spotlight`` share: a light at a single point."""

    # -- helpers ------------------------------------------------------------------------

    @property
    def emission_name(self) -> str:
        """The parameter the emission was given as: ``power`` or ``intensity``."""
        return "power" if self.from_power else "intensity"

    def _scaled(self, value):
        """``value`` times the constant ``scale`` (unchanged when there is none)."""
        return value if self.scale is None else value * self.scale

    @staticmethod
    def _spectral_si(wavelengths):
        """A zero surface interaction carrying ``wavelengths`` (to evaluate spectra)."""
        si = dr.zeros(mi.SurfaceInteraction3f)
        si.wavelengths = wavelengths
        return si

    def _direction_sample(self, it):
        """The (delta) direction sample from ``it`` towards the light, and the squared
        distance between them."""
        ds = dr.zeros(mi.DirectionSample3f)
        ds.p = mi.Point3f(self.position)
        ds.time = it.time
        ds.pdf = 1.0
        ds.delta = True
        ds.emitter = mi.EmitterPtr(self)
        d = mi.Vector3f(ds.p - it.p)
        dist2 = dr.squared_norm(d)
        ds.dist = dr.sqrt(dist2)
        ds.d = d * dr.rsqrt(dist2)
        return ds, dist2

    def _position_sample(self, time):
        """The (delta) position sample at the light."""
        ps = dr.zeros(mi.PositionSample3f)
        ps.p = mi.Point3f(self.position)
        ps.time = time
        ps.delta = True
        return ps

    def _sample_spectrum(self, si, samples, active):
        """Wavelengths drawn from the emitted spectrum and their weights."""
        return self.intensity.sample_spectrum(si, samples, active)

    # -- sampling and evaluation --------------------------------------------------------

    def pdf_direction(self, it, ds, active=True):
        return mi.Float(0.0)

    def pdf_position(self, ps, active=True):
        return mi.Float(0.0)

    def sample_wavelengths(self, si, sample, active=True):
        wavelengths, weight = self._sample_spectrum(
            si, falloff.shifted_wavelength_samples(sample), active
        )
        return wavelengths, self._scaled(weight)

    def pdf_wavelengths(self, wavelengths, active=True):
        return self.intensity.pdf_spectrum(self._spectral_si(wavelengths), active)

    def eval(self, si, active=True):
        return dr.zeros(mi.Spectrum)

    def bbox(self):
        p = mi.ScalarPoint3f(dr.slice(self.position, 0))
        return mi.ScalarBoundingBox3f(p, p)
