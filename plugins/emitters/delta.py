"""``delta``: what every light at a single point shares (helper page, not a plugin).

The base of ``pointlight``, ``spotlight`` and ``ieslight``. These lights sit at one point
(``mi.EmitterFlags.DeltaPosition``), so no ray can hit them and integrators reach them only
by connecting to them (``sample_direction``, a delta direction of density 1) or by tracing
from them (``sample_ray``). They emit a spectrum given in one of four units, scaled by a
constant and attenuated by a distance law of ``falloff``. The light's own page says in
which directions it emits (its directional profile p(omega), 1 on the light's axis).

Parameters
----------

======================  ========  ==============  ====  =========================================
parameter               type      default         unit  description
======================  ========  ==============  ====  =========================================
``intensity``           spectrum  1               W/sr  radiant intensity I (on the axis for a
                                                        light with a profile); any Mitsuba
                                                        spectrum: value, tabulated SPD,
                                                        ``blackbody``, ``d65``, RGB; >= 0
                                                        |exposed| |differentiable|
``power``               spectrum  --              W     radiant flux Phi instead: I = Phi /
                                                        Omega |exposed| |differentiable|
``luminous_intensity``  float     --              cd    luminous intensity I_v instead, with
                                                        ``spectrum`` |exposed| |differentiable|
``luminous_flux``       float     --              lm    luminous flux Phi_v instead: I_v =
                                                        Phi_v / Omega |exposed| |differentiable|
``spectrum``            spectrum  d65             --    spectral shape s of a light in cd or lm
                                                        (its scale does not matter); only with
                                                        ``luminous_intensity`` or
                                                        ``luminous_flux`` |exposed|
                                                        |differentiable|
``falloff``             string    inverse_square  --    distance law, see ``spectrace help
                                                        falloff``
======================  ========  ==============  ====  =========================================

At most one of the four emission parameters may be given (none: ``intensity`` 1).

Formula
-------

The emitted radiant intensity in the direction omega at the distance r is::

    I(omega, r) = I p(omega) falloff(r)

with Omega = integral of p over the sphere (4 pi for ``pointlight``), so that a ``power``
Phi gives I = Phi / Omega and the light emits exactly Phi into the sphere (with
``inverse_square``). A luminous quantity becomes a radiant one through the ``luminous``
page: I = I_v * s / (K_m integral V s dlambda), K_m = 683 lm/W (spectral variants; RGB
and mono variants use Y(s) integral V dlambda, Y the luminance of the colour s).

Sources
-------

Pharr, Jakob, Humphreys (2023), *Physically Based Rendering* 4th ed., sec. 12.1 (point
lights, delta distributions) and 4.4 (photometric quantities); Jakob, Speierer, Roussel et
al. (2022), Mitsuba 3, ``src/emitters/point.cpp`` (the delta-position interface that the
lights reproduce).

Example
-------

A 100 cd light of a tabulated spectral shape::

    <emitter type="pointlight">
        <point name="position" x="0" y="3" z="0"/>
        <float name="luminous_intensity" value="100"/>
        <spectrum name="spectrum" value="400:1, 550:3, 700:2"/>
    </emitter>
"""

from __future__ import annotations

import drjit as dr
import mitsuba as mi
from spectrace.plugins import params
from spectrace.plugins.emitters import falloff, luminous

from spectrace.errors import ParameterError

#: The four ways to give a light's emission, and their units.
EMISSION_UNITS = {"intensity": "W/sr", "power": "W", "luminous_intensity": "cd",
                  "luminous_flux": "lm"}
LUMINOUS = ("luminous_intensity", "luminous_flux")
#: Of these, the ones that are a flux (divided by the solid angle Omega of the light).
FLUXES = ("power", "luminous_flux")


def _float_value(props, plugin: str, name: str) -> float:
    """A non-negative float parameter (no coercion from another XML type)."""
    if props.type(name) not in (mi.Properties.Type.Float, mi.Properties.Type.Integer):
        raise ParameterError(
            f"{plugin}: parameter '{name}' must be a float in {EMISSION_UNITS[name]} "
            f"(got a {params.xml_type(props, name)}); give the spectral shape as "
            "parameter 'spectrum'"
        )
    return params.read_float(props, plugin, name, params.REQUIRED, minimum=0.0, finite=True)


def _uniform_texture(props, plugin: str, name: str, default):
    """An emissive spectrum texture, spatially uniform and >= 0 everywhere."""
    return params.read_spectrum(props, plugin, name, default, minimum=0.0)


def parse_emission(props, plugin: str, default: float = 1.0):
    """Read a light's emission: exactly one of ``intensity`` (W/sr), ``power`` (W),
    ``luminous_intensity`` (cd), ``luminous_flux`` (lm), with ``spectrum`` for the
    luminous ones.

    Returns ``(name, texture, value)``: the parameter given (``intensity`` when none),
    the emissive spectrum texture (the given one, or ``spectrum``, default ``d65``) and
    the luminous value in cd or lm (None for a radiometric one). Raises ``ValueError``
    with one line naming the parameters on any misuse.
    """
    given = [name for name in EMISSION_UNITS if name in props]
    if len(given) > 1:
        named = " and ".join(f"'{name}'" for name in given)
        raise ParameterError(
            f"{plugin}: give only one of parameters 'intensity', 'power', "
            f"'luminous_intensity', 'luminous_flux' (got {named})"
        )
    name = given[0] if given else "intensity"
    if name in LUMINOUS:
        value = _float_value(props, plugin, name)
        texture = _uniform_texture(props, plugin, "spectrum", 1.0)  # d65 in spectral variants
        luminous.check_luminous_content(texture, plugin, "spectrum")
        return name, texture, value
    if "spectrum" in props:
        raise ParameterError(
            f"{plugin}: parameter 'spectrum' only applies to 'luminous_intensity' and "
            f"'luminous_flux' (the spectrum of '{name}' is its own value)"
        )
    return name, _uniform_texture(props, plugin, name, default), None


class DeltaLight(mi.Emitter):
    """What ``pointlight``, ``spotlight`` and ``ieslight`` share: a light at a point.

    A subclass sets, in its constructor, ``position`` (a ``mi.Point3f``), ``law`` (from
    ``falloff.parse_falloff``) and calls ``self._init_emission(props, plugin)``, which
    sets ``emission_name``, ``intensity`` (the spectrum texture: the given intensity or
    power, or the luminous ``spectrum``), ``luminous`` (the cd or lm value as a
    ``mi.Float``, None for a radiometric light) and ``from_power``; then ``self.scale =
    self._emission_scale(Omega)`` (None when 1). It supplies ``sample_direction`` /
    ``eval_direction``, ``sample_position`` and ``sample_ray``, and may override
    ``_sample_spectrum`` and ``pdf_wavelengths`` (the spectrum whose wavelength
    distribution ``sample_wavelengths`` draws from). Emitted values pass through
    ``_out`` (a depolarizing Mueller matrix in polarized variants, as Mitsuba's own
    lights). Executed by :func:`spectrace.plugins.register` after ``falloff`` and
    ``luminous`` and before the lights, so that they subclass the base built for the
    active variant.
    """

    # -- emission -----------------------------------------------------------------------

    def _init_emission(self, props, plugin: str, default: float = 1.0):
        """Parse the emission parameters (see :func:`parse_emission`)."""
        self.plugin_name = plugin
        self.emission_name, self.intensity, value = parse_emission(props, plugin, default)
        self.luminous = None if value is None else mi.Float(value)
        self.from_power = self.emission_name in FLUXES

    def _emission_scale(self, solid_angle=None):
        """The constant factor of the emitted spectrum: W per lumen times the luminous
        value for a luminous light, over ``solid_angle`` for a flux; None when it is 1.
        Differentiable with respect to the luminous value and the spectrum."""
        scale = None
        if self.luminous is not None:
            scale = self.luminous * luminous.watts_per_lumen_dr(self.intensity)
        if self.from_power:
            inverse = dr.rcp(solid_angle)
            scale = inverse if scale is None else scale * inverse
        return scale

    def _traverse_emission(self, callback):
        if self.luminous is None:
            callback.put(self.emission_name, self.intensity, mi.ParamFlags.Differentiable)
        else:
            callback.put(self.emission_name, self.luminous, mi.ParamFlags.Differentiable)
            callback.put("spectrum", self.intensity, mi.ParamFlags.Differentiable)

    def _check_emission(self):
        """After a parameter change: the luminous value and the spectrum still valid."""
        if self.luminous is not None:
            value = float(dr.slice(dr.detach(self.luminous)))
            if not value >= 0.0:
                raise ParameterError(
                    f"{self.plugin_name}: parameter '{self.emission_name}' must be >= 0 "
                    f"(got {value:g})"
                )
            luminous.check_luminous_content(self.intensity, self.plugin_name, "spectrum")

    def _emission_string(self) -> str:
        if self.luminous is None:
            return f"{self.emission_name}={self.intensity}"
        value = float(dr.slice(dr.detach(self.luminous)))
        return f"{self.emission_name}={value:g} {EMISSION_UNITS[self.emission_name]}, " \
               f"spectrum={self.intensity}"

    # -- helpers ------------------------------------------------------------------------

    def _scaled(self, value):
        """``value`` times the constant ``scale`` (unchanged when there is none)."""
        return value if self.scale is None else value * self.scale

    @staticmethod
    def _out(value):
        """An unpolarized emitted value as a ``mi.Spectrum``: a depolarizing Mueller
        matrix in polarized variants (as Mitsuba's ``point``), unchanged otherwise."""
        return mi.depolarizer(value)

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
