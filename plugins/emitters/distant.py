"""``distant``: what the lights at infinity share, ciesky and sun (helper page, not a plugin).

A helper module executed before the daylight emitters (see
``spectrace.plugins.PLUGIN_MODULES``). Both emit, in the direction d towards them, the
radiance L_e(lambda, d) = k(d) s(lambda), with s their spectrum texture and k(d) a
radiance scale (W/(m^2 sr) per unit of s) that each light supplies; both stand at infinity.

Parameters
----------

============  ========  =======  ====  =====================================================
parameter     type      default  unit  description
============  ========  =======  ====  =====================================================
``spectrum``  spectrum  d65      --    spectral shape s (see ``spectrace help solar``)
============  ========  =======  ====  =====================================================

Formula
-------

A direction sample from a point p towards d stands for the light by the point p + D d with
D = 1e6 scene units (10^6 m: a scene in metres fits well inside): Mitsuba does not pass a
Python emitter the scene's bounds (``Emitter::set_scene`` cannot be overridden from
Python). The same is why these lights cannot start light paths: ``sample_ray`` returns
zero weight, so ``ptracer`` sees nothing of them. Their shadow rays, unlike those of
Mitsuba's own ``constant`` and ``envmap`` (as long as the scene's bounding sphere), do not
depend on the scene's bounding box, which Mitsuba 3.9.1 gets wrong when it merges shapes.

Sources
-------

Pharr, Jakob, Humphreys (2023), *Physically Based Rendering* 4th ed., sec. 12.4-12.5
(distant and infinite area lights); Jakob, Speierer, Roussel et al. (2022), Mitsuba 3,
``src/emitters/envmap.cpp`` (the direction-sample convention reproduced here).

Example
-------

See ``ciesky`` and ``sun``::

    <emitter type="sun"/>
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi

#: Distance (scene units) of the point that stands for a light at infinity.
DISTANCE = 1e6


class DistantLight(mi.Emitter):
    """Base of the lights at infinity: a subclass sets ``texture`` (spectrum) and
    implements ``_radiance_scale(d)`` (Dr.Jit Float), ``sample_direction``,
    ``pdf_direction`` and ``eval``."""

    def _radiance_scale(self, d):
        raise NotImplementedError

    @staticmethod
    def _spectral_si(wavelengths):
        si = dr.zeros(mi.SurfaceInteraction3f)
        si.wavelengths = wavelengths
        return si

    def _radiance(self, d, wavelengths, active=True):
        """L_e(lambda, d) as an emitted ``mi.Spectrum`` (depolarized in polarized variants)."""
        value = self.texture.eval(self._spectral_si(wavelengths), active)
        return mi.depolarizer(value * self._radiance_scale(d))

    def _direction_sample(self, it, d, pdf, delta: bool):
        ds = dr.zeros(mi.DirectionSample3f)
        ds.d = d
        ds.dist = mi.Float(DISTANCE)
        ds.p = it.p + d * DISTANCE
        ds.n = -d
        ds.time = it.time
        ds.pdf = pdf
        ds.delta = delta
        ds.emitter = mi.EmitterPtr(self)
        return ds

    def eval_direction(self, it, ds, active=True):
        return self._radiance(ds.d, it.wavelengths, active)

    def sample_wavelengths(self, si, sample, active=True):
        from spectrace.plugins.emitters import falloff

        wavelengths, weight = self.texture.sample_spectrum(
            si, falloff.shifted_wavelength_samples(sample), active)
        return wavelengths, weight * self._radiance_scale(-si.wi)

    def sample_ray(self, time, wavelength_sample, sample2, sample3, active=True):
        ray = dr.zeros(mi.Ray3f)  # no scene bounds: no rays from infinity (module page)
        ray.time = time
        return ray, dr.zeros(mi.Spectrum)

    def sample_position(self, time, sample, active=True):
        ps = dr.zeros(mi.PositionSample3f)
        ps.time = time
        return ps, mi.Float(0.0)

    def pdf_position(self, ps, active=True):
        return mi.Float(0.0)

    def bbox(self):
        return mi.ScalarBoundingBox3f()
