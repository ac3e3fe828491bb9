"""Distance falloff laws shared by the ``pointlight`` and ``spotlight`` emitters.

Not a plugin: a helper module executed before the two lights (see
``spectrace.plugins.PLUGIN_MODULES``). It holds the one mapping from the value of the
lights' ``falloff`` parameter to a law, the parsing and validation of the laws'
parameters, and the parsing of the lights' ``intensity`` / ``power`` pair.

A law maps the squared distance r^2 between the light and the lit point to the factor
that multiplies the radiant intensity I (W/sr) to give the irradiance on a surface facing
the light, E = I * falloff(r) (W/m^2 for ``inverse_square``):

| ``falloff``              | falloff(r)                                 | parameters (default)  |
|--------------------------|--------------------------------------------|-----------------------|
| ``inverse_square``       | 1 / r^2 (the physical law; the default)    |                       |
| ``inverse_square_epsilon``| 1 / (r + epsilon)^2                       | ``epsilon`` (0.01),   |
|                          |                                            | >= 0                  |
| ``polynomial``           | 1 / (kc + kl r + kq r^2)                   | ``kc`` (0), ``kl``    |
|                          |                                            | (0), ``kq`` (1): all  |
|                          |                                            | >= 0, not all 0       |
| ``windowed``             | clamp(1 - (r/R)^4, 0, 1)^2/max(r^2, eps^2) | ``radius`` R > 0      |
|                          |                                            | (required), epsilon   |
|                          |                                            | (0.01) > 0            |
| ``none``                 | 1 (no distance falloff)                    |                       |

r is in scene units; with r in metres and I in W/sr, E is in W/m^2 for ``inverse_square``.

Sources: ``polynomial`` is the constant/linear/quadratic attenuation of fixed-function
OpenGL (``GL_CONSTANT_ATTENUATION`` ...); ``windowed`` is the windowed inverse square of
B. Karis, "Real Shading in Unreal Engine 4" (SIGGRAPH 2013 course), which reaches exactly
zero at r = R so that far lights can be culled; ``inverse_square_epsilon`` is the usual
singularity-free variant of 1/r^2. All parameters are in scene units.

Only ``inverse_square`` is physically consistent: light tracing (``ptracer``, which starts
paths with ``sample_ray``) produces 1/r^2 through the density of the rays it traces and
cannot apply another law; integrators that connect to the light (``direct``, ``path``,
``prb``, ``local``) apply every law.

XML example (the law's parameters sit beside ``falloff`` on the light)::

    <emitter type="pointlight">
        <point name="position" x="0" y="2" z="0"/>
        <float name="intensity" value="10"/>
        <string name="falloff" value="windowed"/>
        <float name="radius" value="8"/>
    </emitter>
"""

from __future__ import annotations

import math

import drjit as dr
import mitsuba as mi

DEFAULT_LAW = "inverse_square"


def _param(props, plugin: str, name: str, default: float | None) -> float:
    """Read the float parameter ``name`` (``default`` when absent; required when None)."""
    if name in props:
        return float(props.get(name))
    if default is None:
        raise ValueError(
            f"{plugin}: falloff '{props.get('falloff')}' needs parameter '{name}'"
        )
    return default


def _require(ok: bool, plugin: str, name: str, rule: str, value) -> None:
    if not ok:
        raise ValueError(f"{plugin}: parameter '{name}' must be {rule} (got {value})")


class InverseSquare:
    """1 / r^2: the physical law of a point source."""

    def __init__(self, props, plugin: str):
        pass

    def __call__(self, dist2):
        return dr.rcp(dist2)

    def __repr__(self):
        return "inverse_square"


class InverseSquareEpsilon:
    """1 / (r + epsilon)^2: finite (1/epsilon^2) at the light."""

    def __init__(self, props, plugin: str):
        self.epsilon = _param(props, plugin, "epsilon", 0.01)
        _require(self.epsilon >= 0, plugin, "epsilon", ">= 0", self.epsilon)

    def __call__(self, dist2):
        return dr.rcp(dr.square(dr.sqrt(dist2) + self.epsilon))

    def __repr__(self):
        return f"inverse_square_epsilon(epsilon={self.epsilon})"


class Polynomial:
    """1 / (kc + kl r + kq r^2): OpenGL's constant, linear and quadratic attenuation."""

    def __init__(self, props, plugin: str):
        self.kc = _param(props, plugin, "kc", 0.0)
        self.kl = _param(props, plugin, "kl", 0.0)
        self.kq = _param(props, plugin, "kq", 1.0)
        for name in ("kc", "kl", "kq"):
            value = getattr(self, name)
            _require(value >= 0, plugin, name, ">= 0", value)
        if self.kc == self.kl == self.kq == 0:
            raise ValueError(
                f"{plugin}: parameters 'kc', 'kl', 'kq' of the polynomial falloff must not "
                "all be 0 (the attenuation 1/(kc + kl r + kq r^2) would be infinite)"
            )

    def __call__(self, dist2):
        denominator = self.kq * dist2
        if self.kl != 0:
            denominator = denominator + self.kl * dr.sqrt(dist2)
        if self.kc != 0:
            denominator = denominator + self.kc
        return dr.rcp(denominator)

    def __repr__(self):
        return f"polynomial(kc={self.kc}, kl={self.kl}, kq={self.kq})"


class Windowed:
    """clamp(1 - (r/R)^4, 0, 1)^2 / max(r^2, eps^2): Karis' windowed inverse square."""

    def __init__(self, props, plugin: str):
        self.radius = _param(props, plugin, "radius", None)
        self.epsilon = _param(props, plugin, "epsilon", 0.01)
        _require(self.radius > 0, plugin, "radius", "> 0", self.radius)
        _require(self.epsilon > 0, plugin, "epsilon", "> 0", self.epsilon)
        self.inv_radius4 = 1.0 / self.radius**4
        self.epsilon2 = self.epsilon**2

    def __call__(self, dist2):
        window = dr.clip(1.0 - dr.square(dist2) * self.inv_radius4, 0.0, 1.0)
        return dr.square(window) / dr.maximum(dist2, self.epsilon2)

    def __repr__(self):
        return f"windowed(radius={self.radius}, epsilon={self.epsilon})"


class NoFalloff:
    """1: the light does not fade with distance."""

    def __init__(self, props, plugin: str):
        pass

    def __call__(self, dist2):
        return 1.0

    def __repr__(self):
        return "none"


#: The one mapping from the lights' ``falloff`` value to its law.
FALLOFF_LAWS = {
    "inverse_square": InverseSquare,
    "inverse_square_epsilon": InverseSquareEpsilon,
    "polynomial": Polynomial,
    "windowed": Windowed,
    "none": NoFalloff,
}


def parse_falloff(props, plugin: str):
    """The distance law named by ``props['falloff']``, its parameters read and validated.

    The returned object is called with the squared distance (a Dr.Jit Float) and gives
    the attenuation factor. Raises ``ValueError`` naming the parameter on a bad value.
    """
    name = props.get("falloff", DEFAULT_LAW)
    law = FALLOFF_LAWS.get(name)
    if law is None:
        raise ValueError(
            f"{plugin}: parameter 'falloff' must be one of {', '.join(FALLOFF_LAWS)} "
            f"(got {name!r})"
        )
    return law(props, plugin)


def _spectrum_minimum(texture) -> float:
    """The smallest value of a (spatially uniform) spectrum texture.

    Evaluated on a 1 nm grid over the visible range in spectral variants; RGB variants
    ignore the wavelengths and give the three channels.
    """
    wavelengths = dr.arange(mi.Float, 360, 831)
    si = dr.zeros(mi.SurfaceInteraction3f, dr.width(wavelengths))
    if mi.is_spectral:
        si.wavelengths = mi.Spectrum(wavelengths, wavelengths, wavelengths, wavelengths)
    value = texture.eval(si)
    return float(dr.min(value, axis=None)[0])


def parse_emission(props, plugin: str, default: float = 1.0):
    """Read a light's ``intensity`` (W/sr) or ``power`` (W), validated.

    Returns ``(texture, from_power)``: the emissive spectrum texture given (intensity or
    power) and whether it is a power, which the light then divides by the solid angle it
    emits into. Both given, or a negative value anywhere in the spectrum, raise
    ``ValueError`` naming the parameter.
    """
    has_intensity = "intensity" in props
    has_power = "power" in props
    if has_intensity and has_power:
        raise ValueError(
            f"{plugin}: give either parameter 'intensity' or parameter 'power', not both"
        )
    name = "power" if has_power else "intensity"
    texture = props.get_emissive_texture(name, default)
    if texture.is_spatially_varying():
        raise ValueError(
            f"{plugin}: parameter '{name}' must be a spectrum, not a spatially varying texture"
        )
    minimum = _spectrum_minimum(texture)
    if not minimum >= 0:
        raise ValueError(f"{plugin}: parameter '{name}' must be >= 0 (got minimum {minimum})")
    return texture, has_power


def parse_angle(props, plugin: str, name: str, default: float) -> float:
    """A half-angle in degrees from ``props``, in (0, 90]."""
    value = float(props.get(name, default))
    _require(0 < value <= 90, plugin, name, "in (0, 90] degrees", value)
    return value


FOUR_PI = 4.0 * math.pi


def parse_to_world(props) -> mi.Transform4f:
    """The light's ``to_world`` transform (identity when absent), in single precision
    with the inverse computed by the parser (as the built-in emitters get it)."""
    if "to_world" not in props:
        return mi.Transform4f()
    to_world = props.get("to_world")
    return mi.Transform4f(
        mi.Matrix4f(mi.ScalarMatrix4f(to_world.matrix)),
        mi.Matrix4f(mi.ScalarMatrix4f(to_world.inverse_transpose)),
    )


def shifted_wavelength_samples(sample):
    """The wavelength samples of ``sample`` shifted over the spectral channels
    (``mi.sample_shifted``, stratified hero wavelengths); an empty array in RGB variants."""
    return mi.sample_shifted(sample) if mi.is_spectral else mi.Color0f()
