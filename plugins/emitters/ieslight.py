"""``ieslight``: a real luminaire from its IES LM-63 or EULUMDAT photometric file, in candela.

A luminaire at the origin of ``to_world`` (a point, or the luminous opening that the file
or ``opening`` gives: see Opening below) that emits in each direction the luminous intensity
that a photometric file (``.ies``: IES LM-63-1986 to -2019; ``.ldt``: EULUMDAT) gives for
it, read by ``spectrace.photometry`` (``spectrace ies FILE`` shows what a file holds), with
the spectral shape of ``spectrum``. The file's candela values are absolute: the light emits
the file's luminous flux (or ``luminous_flux`` when given), and a surface at r metres whose
normal makes the angle theta with the direction to the light receives
E_v = I_v(gamma, C) cos(theta) / r^2 lux. Between the file's angles the intensity is
bilinear in (gamma, C), as ``Photometry.intensity``; it is zero outside the measured range.
Light tracing (``ptracer``) draws directions in proportion to the intensity.

Parameters
----------

===================  =========  ==============  ====  ==========================================
parameter            type       default         unit  description
===================  =========  ==============  ====  ==========================================
``filename``         string     (required)      --    the photometric file, ``.ies`` or
                                                      ``.ldt``; a relative path is resolved like
                                                      Mitsuba's other files (the scene's folder
                                                      first)
``to_world``         transform  identity        --    placement; the light points along local
                                                      +Z (gamma = 0), aim it with ``lookat``
                                                      (below) |exposed|
``spectrum``         spectrum   d65             --    spectral shape s of the lamp (value,
                                                      tabulated SPD, ``blackbody``, ``d65``,
                                                      RGB); its scale does not matter |exposed|
                                                      |differentiable|
``scale``            float      1               --    factor on the file's intensities (a
                                                      dimmer, a maintenance factor); >= 0
                                                      |exposed| |differentiable|
``luminous_flux``    float      --              lm    rescale the profile so that the light
                                                      emits this luminous flux (before
                                                      ``scale``); >= 0 |exposed|
                                                      |differentiable|
``falloff``          string     inverse_square  --    distance law and its parameters, as for
                                                      ``pointlight`` (see ``spectrace help
                                                      falloff``)
``sampling_weight``  float      1               --    relative chance that an integrator picks
                                                      this light to sample (Mitsuba's
                                                      emitters) |exposed|
``opening``          string     file            --    the luminous opening: ``file`` (the shape
                                                      and size the file gives; a point when its
                                                      dimensions are 0), ``point`` (the delta
                                                      light), ``rectangle``, ``disk``,
                                                      ``sphere``, ``box`` or ``cylinder``
                                                      (closed, vertical) with the sizes below
``width``            float      --              m     ``rectangle``, ``box``: the size along
                                                      C90-C270 (local y); > 0
``length``           float      --              m     ``rectangle``, ``box``: the size along
                                                      C0-C180 (local x); > 0
``height``           float      --              m     ``box``, ``cylinder``: the size along
                                                      gamma = 0 (local z); > 0
``diameter``         float      --              m     ``disk`` (facing gamma = 0), ``sphere``,
                                                      ``cylinder`` (about local z); > 0
===================  =========  ==============  ====  ==========================================

The emission parameters of the other lights (``intensity``, ``power``,
``luminous_intensity``) are refused: the file gives the intensity. Lengths are in metres for
the photometric units to hold (100 cd at 1 m give 100 lux).

Formula
-------

Frame. In the light's local frame the photometric zero (gamma = 0, nadir: where a downlight
shines) is local +Z; C = 0 is local +X; C grows counterclockwise seen from above the
luminaire (from local -Z, looking along the light), as IES LM-63 defines Type C, so C = 90
is local -Y::

     seen from above the luminaire         side view (C = 0 / 180 plane)
     (+Z, nadir, points into the page)

               C = 90                                 -Z (above)
              local -Y                                 |
                 |                               ------o------  luminaire
                 |                                    /|\\
      C = 180 ---o--- C = 0                  C = 180 / | \\ C = 0
      local -X   |    local +X                      /  |  \\
                 |                                     |
                 |                                    +Z  gamma = 0 (nadir)
               C = 270
              local +Y

A unit direction d = (x, y, z) in the local frame has the angles::

    d = (sin gamma cos C, -sin gamma sin C, cos gamma)
    gamma = atan2(sqrt(x^2 + y^2), z),    C = atan2(-y, x) mod 360

Aiming: ``<lookat origin="o" target="t" up="u"/>`` points local +Z (gamma = 0) from o to t,
local +Y along u (made perpendicular to the aim) and local +X along u x (t - o). So C = 0 is
``up x aim`` (to the left when seen from behind the light with u up), C = 90 points away
from u and C = 270 towards it: a downlight aimed at the floor (t below o) with ``up`` along
the world +X has C = 90 along the world -X.

Type B files (floodlights) follow the convention of ``spectrace.photometry`` (its module
``model`` derives it from LM-63 and compares it with Radiance's and Cycles' readings): the
Type B aiming axis (H = V = 0) is gamma = 0, local +Z, like a Type C file's nadir; V (the
tilt of the B-plane about the polar axis) > 0 turns towards C = 0 (local +X); the polar axis
(H = +-90, the luminaire's width, the axis the floodlight tilts about) is C = 270 / 90, local
+Y / -Y, and H > 0 (clockwise seen from above the floodlight, to the right seen from
behind it) turns towards C = 270, local +Y::

    seen from behind the floodlight (aim, local +Z, into the page)

                  V = +90, C = 0, local +X
                        |
      H = -90 ----------+---------- H = +90
      C = 90, local -Y  |           C = 270, local +Y
                        |
                  V = -90, C = 180

    d = (cos H sin V, sin H, cos H cos V)
    V = atan2(x, z),    H = atan2(y, sqrt(x^2 + z^2))

A Type B file is looked up in its own angles: bilinear in (H, V) as
``Photometry.intensity``, mirrored to H < 0 when its horizontal angles start at 0 and to
V < 0 when its vertical angles do, zero outside the measured range.

Emission. The file's intensity I_v(gamma, C) (cd) becomes the radiant intensity::

    I_e(omega, lambda) = scale * f * I_v(gamma, C) * s(lambda) / (K_m integral V s dlambda)

with K_m = 683 lm/W, V the CIE photopic efficiency, f = luminous_flux / Phi_file when
``luminous_flux`` is given (Phi_file: the file's flux, integrated over the sphere by
``spectrace.photometry``) and f = 1 otherwise, times the distance law (1/r^2 by default). In
RGB and mono variants the integral is Y(s) integral V dlambda, Y = 0.2126 R + 0.7152 G +
0.0722 B the luminance of the colour s (or its value): the same lux and the same image in
every variant (``spectrace help luminous``).

Opening. With an opening that is not a point, each point x of its surface emits the
luminance::

    L(x, omega) = I_e(omega) / A_proj(omega)

(W/(sr m^2); for the file's candela cd/m^2), A_proj the area the opening shows along omega:
4 hx hy |cos gamma| (rectangle), pi r^2 |cos gamma| (disk), pi r^2 (sphere),
y z |d_x| + x z |d_y| + x y |d_z| (box of edges x, y, z), 2 r h sin(gamma) + pi r^2
|cos(gamma)| (closed cylinder). Integrated over the opening,
sum L cos(theta_x) dA = I_e(omega): far away it is the file's intensity, and it emits the
file's flux; near it the lux differ from the point law (``spectrace ies FILE`` prints the
difference at the photometric distance). The flat openings (rectangle, disk) emit from
both faces, so that light above the horizon (gamma > 90) keeps its intensity too. The
opening lies centred on the photometric centre (the origin of ``to_world``, which must
then be rigid), the length along C0-C180 (local x) and the width along C90-C270 (local y),
as Radiance's ``ies2rad`` reads them. Of the file's shapes (``Photometry.opening``) the
light renders rectangle, disk, sphere, box and vertical cylinder; another one (an
ellipse, a horizontal cylinder, ...) is refused with ``opening`` ``file``: give ``point``
or one of those with its sizes.

As ``pointlight``'s ``source_radius`` (``spectrace help sized``), spectrace's scene loader
puts an ``ieslight`` with an opening on a black ``rectangle``, ``disk``, ``sphere`` or
``cube`` of that size (``mi.load_dict`` users: ``sized.expand_dict``; a cylinder: one
closed black mesh of 256 sides, side and caps, since Mitsuba's ``cylinder`` is open and
an emitter has one shape: a ``mi.Mesh`` made by ``sized.expand_dict``, or in an XML
scene the unit-cylinder PLY file ``sized.unit_cylinder_ply`` writes once to the user's
cache folder, scaled): one element in the XML, a
luminaire the camera sees with its luminance L and that BSDF-sampled rays hit
(multiple importance sampling in ``path``, ``volpath``, ``direct``). Next-event estimation
samples the sphere and the rectangle by the solid angle they subtend, the disk by solid
angle near it (``opening``'s ``auto``), the box by area over the faces the point sees
(each in proportion to its area times the cosine towards the point), the cylinder
uniformly by area over the part the point sees (the lit arc of its side, the cap on its
side); the distance law must be ``inverse_square``. ``opening`` ``point`` keeps the delta
light exactly.

Light tracing. ``sample_ray`` picks a cell [C_i, C_i+1] x [gamma_j, gamma_j+1] of the
profile's grid (``Photometry.angle_grid``; with Mitsuba's ``DiscreteDistribution``) with
probability proportional to
w_ij = Omega_ij * (mean of the cell's four corner intensities), Omega_ij = (C_i+1 - C_i)
(cos gamma_j - cos gamma_j+1) its solid angle, then a direction in the cell from the
bilinear interpolant of the corners in (C, cos gamma), uniform in solid angle for a constant
cell (Type B: cells [V_i, V_i+1] x [H_j, H_j+1], Omega_ij = (V_i+1 - V_i) (sin H_j+1 -
sin H_j), bilinear in (V, sin H)). The ray's weight is I_e(omega) / pdf(omega) with the
exact profile, so ``ptracer`` converges to ``direct`` and a constant profile gives every ray
the weight 4 pi I_e (as ``pointlight``). With an opening: a point uniform on its surface
(area A, both faces of a flat one) and a cosine-distributed direction about its normal,
of weight pi A L(omega).

From Python. The plugin reads a file; the light itself takes a ``Photometry`` (its
``angle_grid``: the table in its own angles, symmetry expanded), a spectrum and a scale. A
table built or changed in memory (``Photometry(...)``,
``read_photometry(path).replace(candela=...)``) becomes a light with ``from_photometry``,
after ``spectrace.set_variant``::

    from spectrace.plugins.emitters import ieslight
    light = ieslight.from_photometry(photometry, {"luminous_flux": 1200.0,
                                                  "to_world": mi.ScalarTransform4f()})
    scene = mi.load_dict({"type": "scene", "light": light, ...})

The parameters are the plugin's, but for ``filename``; a dict value (a spectrum) is loaded
with ``mi.load_dict`` first.

Sources
-------

IES (2019), ANSI/IES LM-63-19 *Approved Method: IES Standard File Format for the Electronic
Transfer of Photometric Data and Related Information* (Type C angles, Type B); A. Stockmar
(1990), EULUMDAT (the ``.ldt`` format); CIE (2019), CIE 018:2019 (K_m = 683 lm/W,
V(lambda)); Pharr, Jakob, Humphreys (2023), *Physically Based Rendering* 4th ed.,
sec. 12.2.3 (goniophotometric diagram lights: a factory reads the file, the light takes
the distribution, the spectrum and the scale; sampled by a 2D distribution).

Example
-------

A downlight 2.8 m above the floor, of a warm-white LED spectrum, rescaled to 1200 lm::

    <emitter type="ieslight">
        <string name="filename" value="luminaires/downlight.ies"/>
        <transform name="to_world">
            <lookat origin="1, 2.8, 0" target="1, 0, 0" up="0, 0, 1"/>
        </transform>
        <spectrum name="spectrum" filename="luminaires/led_3000k.spd"/>
        <float name="luminous_flux" value="1200"/>
    </emitter>

The same downlight as a 15 cm disk, whatever opening its file gives::

    <emitter type="ieslight">
        <string name="filename" value="luminaires/downlight.ies"/>
        <string name="opening" value="disk"/>
        <float name="diameter" value="0.15"/>
    </emitter>
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import drjit as dr
import mitsuba as mi
from spectrace.plugins import params
from spectrace.plugins.emitters import delta, falloff, luminous, opening, sized

from spectrace.errors import FileAccessError, ParameterError, SpectraceError, first_line

if TYPE_CHECKING:
    import numpy as np

PLUGIN = "ieslight"
#: The other lights' emission parameters, refused here, and what to use instead.
REFUSED = {
    "intensity": "the file gives the intensity; use 'scale' or 'luminous_flux' to change it",
    "power": "the file gives the flux; use 'luminous_flux' to rescale it",
    "luminous_intensity": "the file gives the intensity; use 'scale' or 'luminous_flux'",
    "position": "place the light with 'to_world' (its translation) and aim it with lookat",
}
#: A grid of the profile whose steps agree to this relative tolerance is looked up by
#: division instead of binary search.
REGULAR_RTOL = 1e-6


def read_profile(filename: str):
    """The path and ``Photometry`` of ``filename``, resolved through Mitsuba's file resolver;
    a missing file raises ``FileAccessError``, a bad one ``FileFormatError``, with one line
    naming the file (and the field)."""
    from spectrace.photometry import read_photometry


    resolver = mi.file_resolver()
    path = Path(str(resolver.resolve(filename)))
    if not path.is_file():
        what = (f"{filename!r} is a folder, not a file" if path.is_dir()
                else f"{filename!r} is not a regular file" if path.exists()
                else f"no such file {filename!r}")
        where = ""
        if not Path(filename).is_absolute():  # say where a relative name was looked up
            folders = [str(resolver[i]) for i in range(len(resolver))]
            folders = [f for f in folders if Path(f).name != "mitsuba"] or folders
            folders = dict.fromkeys(str(Path(f or ".").resolve()) for f in folders)
            where = f" (looked in {', '.join(folders)})"
        raise FileAccessError(f"{PLUGIN}: parameter 'filename': {what}{where}")
    try:
        return path, read_photometry(path)
    except SpectraceError as error:
        raise type(error)(f"{PLUGIN}: {first_line(error)}") from None
    except (OSError, UnicodeError) as error:
        raise FileAccessError(f"{PLUGIN}: {path}: cannot read ({error})") from None


class TypeC:
    """Type C angles: outer angle C (0..360), inner angle gamma (0..180); the solid angle is
    dC d(1 - cos gamma); the table covers the whole sphere."""

    bounded = False

    @staticmethod
    def angles(d):
        """(C, gamma) in degrees of a local direction (any length)."""
        rho = dr.sqrt(dr.square(d.x) + dr.square(d.y))
        gamma = dr.atan2(rho, d.z) * (180.0 / math.pi)
        c = dr.atan2(-d.y, d.x) * (180.0 / math.pi)
        return dr.select(c < 0.0, c + 360.0, c), gamma

    @staticmethod
    def measure(gamma_deg: np.ndarray) -> np.ndarray:
        """1 - cos(gamma) = 2 sin^2(gamma / 2) (exact near the axis)."""
        import numpy as np

        return 2.0 * np.sin(np.radians(gamma_deg) / 2.0) ** 2

    @staticmethod
    def measure_of(d):
        return 1.0 - d.z / dr.norm(d)

    @staticmethod
    def direction(c_rad, m):
        """The unit local direction at C (radians) and 1 - cos(gamma) = m, and gamma in
        degrees."""
        sin_gamma = dr.sqrt(dr.maximum(m * (2.0 - m), 0.0))
        sin_c, cos_c = dr.sincos(c_rad)
        d = mi.Vector3f(sin_gamma * cos_c, -sin_gamma * sin_c, 1.0 - m)
        return d, dr.atan2(sin_gamma, 1.0 - m) * (180.0 / math.pi)


class TypeB:
    """Type B angles: outer angle V (tilt about the polar axis, local Y), inner angle H
    (towards the polar axis, H > 0 towards local +Y); aim local +Z, V > 0 towards local +X;
    the solid angle is dV d(sin H); the table covers the file's measured range (and its
    mirror images), zero outside."""

    bounded = True

    @staticmethod
    def angles(d):
        """(V, H) in degrees of a local direction (any length)."""
        V = dr.atan2(d.x, d.z) * (180.0 / math.pi)
        H = dr.atan2(d.y, dr.sqrt(dr.square(d.x) + dr.square(d.z))) * (180.0 / math.pi)
        return V, H

    @staticmethod
    def measure(h_deg: np.ndarray) -> np.ndarray:
        import numpy as np

        return np.sin(np.radians(h_deg))

    @staticmethod
    def measure_of(d):
        return d.y / dr.norm(d)

    @staticmethod
    def direction(v_rad, m):
        """The unit local direction at V (radians) and sin(H) = m, and H in degrees."""
        cos_h = dr.sqrt(dr.maximum(1.0 - dr.square(m), 0.0))
        sin_v, cos_v = dr.sincos(v_rad)
        return mi.Vector3f(cos_h * sin_v, m, cos_h * cos_v), \
            dr.atan2(m, cos_h) * (180.0 / math.pi)


#: ``AngleGrid.system`` -> the Dr.Jit angle functions of that system.
SYSTEMS = {"C": TypeC, "B": TypeB}


def cell_weights(outer_deg, inner_deg, candela, system):
    """Solid angle Omega_ij and sampling weight w_ij = Omega_ij * mean of the four corners of
    each cell [outer_i, outer_i+1] x [inner_j, inner_j+1], shape (n_o - 1, n_i - 1)."""
    import numpy as np

    m = system.measure(inner_deg)
    omega = np.radians(np.diff(outer_deg))[:, None] * np.diff(m)[None, :]
    corners = candela[:-1, :-1] + candela[1:, :-1] + candela[:-1, 1:] + candela[1:, 1:]
    return omega, omega * 0.25 * corners


class Axis:
    """One angle axis of the table (degrees, increasing): the cell that holds an angle by
    binary search, or by division when the angles are evenly spaced."""

    def __init__(self, angles: np.ndarray):
        import numpy as np

        self.n = int(angles.size)
        self.angles = mi.Float(angles.astype(np.float32))
        steps = np.diff(angles)
        self.regular = bool(np.all(np.abs(steps - steps[0]) <= REGULAR_RTOL * steps[0]))
        self.first = float(angles[0])
        self.inv_step = float(1.0 / steps[0]) if self.regular else 0.0

    def cell(self, x):
        """Index i in [0, n - 2] with angles[i] <= x < angles[i + 1] (clamped at the ends),
        and the fraction (x - angles[i]) / (angles[i + 1] - angles[i]) in [0, 1]."""
        if self.regular:
            u = (x - self.first) * self.inv_step
            i = dr.clip(dr.floor(u), 0.0, self.n - 2.0)
            return mi.UInt32(i), dr.clip(u - i, 0.0, 1.0)
        angles = self.angles
        i = dr.binary_search(1, self.n - 1, lambda k: dr.gather(mi.Float, angles, k) <= x) - 1
        return i, self.fraction(i, x)

    def fraction(self, i, x):
        """(x - angles[i]) / (angles[i + 1] - angles[i]) clamped to [0, 1] (0 in an empty
        cell)."""
        if self.regular:
            return dr.clip((x - self.first) * self.inv_step - mi.Float(i), 0.0, 1.0)
        a0 = dr.gather(mi.Float, self.angles, i)
        a1 = dr.gather(mi.Float, self.angles, i + 1)
        width = a1 - a0
        t = dr.select(width > 0.0, (x - a0) / dr.maximum(width, 1e-30), 0.0)
        return dr.clip(t, 0.0, 1.0)


class IESLight(delta.DeltaLight):
    """A luminaire of a photometric file: I_v(gamma, C) times the lamp's spectrum."""

    def __init__(self, props, photometry=None):
        """The plugin's factory: ``props`` are the XML parameters; ``photometry`` (a
        ``spectrace.photometry.Photometry``, see ``from_photometry``) replaces ``filename``."""
        from spectrace.errors import ParameterError

        mi.Emitter.__init__(self, props)
        for name, advice in REFUSED.items():
            if name in props:
                raise ParameterError(f"{PLUGIN}: parameter '{name}' does not apply ({advice})")
        self.plugin_name = PLUGIN
        if photometry is not None:
            if "filename" in props:
                raise ParameterError(f"{PLUGIN}: parameter 'filename' does not apply to a "
                                     "light built from a Photometry")
            self.filename, self.path, self.photometry = None, photometry.path, photometry
        elif "filename" not in props:
            raise ParameterError(f"{PLUGIN}: parameter 'filename' is required (an .ies or "
                                 ".ldt photometric file)")
        else:
            self.filename = params.read_string(props, PLUGIN, "filename", params.REQUIRED)
            self.path, self.photometry = read_profile(self.filename)
        self.to_world = falloff.parse_to_world(props)
        self.intensity = params.read_spectrum(props, PLUGIN, "spectrum", 1.0)
        luminous.check_luminous_content(self.intensity, PLUGIN, "spectrum")
        self.scale_value = mi.Float(params.read_float(props, PLUGIN, "scale", 1.0,
                                                      minimum=0.0, finite=True))
        self.file_flux = float(self.photometry.flux)
        self.luminous_flux = None
        if "luminous_flux" in props:
            value = params.read_float(props, PLUGIN, "luminous_flux", None, minimum=0.0,
                                      finite=True)
            if not self.file_flux > 0.0:
                raise ParameterError(
                    f"{PLUGIN}: parameter 'luminous_flux' cannot rescale {self.path}: its "
                    f"profile emits no light (flux {self.file_flux:g} lm)"
                )
            self.luminous_flux = mi.Float(value)
        self.law = falloff.parse_falloff(props, PLUGIN)
        self._init_profile()
        self.luminous = None
        self.opening_kind, self.half = self._read_opening(props)
        if self.opening_kind == "point":
            self.m_flags = mi.EmitterFlags.DeltaPosition
            self.m_needs_sample_3 = False
        else:
            sized.check_sized(PLUGIN, self.law, props.get("to_world", None))
            # Not Surface: Mitsuba's scene drops top-level Surface emitters (see sized).
            self.m_flags = mi.EmitterFlags.Empty
        self._update()

    def _read_opening(self, props):
        """The opening's kind and half-extents (``sized.resolve_opening``)."""
        values = {"opening": params.read_string(props, PLUGIN, "opening", None)}
        for name in sized.IES_SIZES:
            values[name] = params.read_float(props, PLUGIN, name, None)
        photometry = self.photometry

        def file_opening():
            try:
                return photometry.opening
            except SpectraceError as error:
                raise type(error)(f"{PLUGIN}: {first_line(error)}") from None

        return sized.resolve_opening(values, file_opening, PLUGIN)

    # -- profile ------------------------------------------------------------------------

    def _init_profile(self):
        """The profile's table, its axes and the distribution of ``sample_ray`` over cells."""
        import numpy as np

        from spectrace.errors import FileFormatError

        try:
            grid = self.photometry.angle_grid()
        except ValueError as error:
            raise FileFormatError(f"{PLUGIN}: {error}") from None
        system, outer, inner, candela = SYSTEMS[grid.system], grid.outer, grid.inner, \
            grid.candela
        if not (np.all(np.isfinite(candela)) and np.all(candela >= 0.0)
                and candela.max() <= np.finfo(np.float32).max):
            raise FileFormatError(f"{PLUGIN}: {self.path}: candela values must be finite, "
                                  ">= 0 and within single precision")
        self.system = system
        self.n_inner = inner.size
        self.outer_axis, self.inner_axis = Axis(outer), Axis(inner)
        self.bounds = (float(outer[0]), float(outer[-1]), float(inner[0]), float(inner[-1]))
        self.table = mi.Float(candela.astype(np.float32).ravel())  # index: i_o * n_i + i_i
        #: Type C with every C plane the same: the lookup needs gamma only (its first row)
        self.rotational = system is TypeC and bool(np.all(candela == candela[:1]))
        self.inner_measure = mi.Float(system.measure(inner).astype(np.float32))
        self.outer_rad = mi.Float(np.radians(outer).astype(np.float32))
        omega, weights = cell_weights(outer, inner, candela, system)
        if not float(weights.sum()) > 0.0:
            raise FileFormatError(f"{PLUGIN}: {self.path}: the profile emits no light (every "
                                  "candela value is 0)")
        self.cell_omega = mi.Float(omega.astype(np.float32).ravel())  # i_o * (n_i - 1) + i_i
        # the cell distribution; its CDF is summed in double precision by Mitsuba
        self.cells = mi.DiscreteDistribution(weights.astype(np.float32).ravel())

    def _corners(self, io, ii):
        """The candela values at the four corners of cell (io, ii): (outer_i, inner_j),
        (outer_i+1, inner_j), (outer_i, inner_j+1), (outer_i+1, inner_j+1)."""
        n = self.n_inner
        k = io * n + ii
        table = self.table
        return (dr.gather(mi.Float, table, k), dr.gather(mi.Float, table, k + n),
                dr.gather(mi.Float, table, k + 1), dr.gather(mi.Float, table, k + n + 1))

    def _inside(self, outer, inner):
        """Whether the angles lie in the measured range (always, for Type C)."""
        o0, o1, i0, i1 = self.bounds
        return (outer >= o0) & (outer <= o1) & (inner >= i0) & (inner <= i1)

    def candela(self, local_d):
        """I_v (cd) of the file in the local direction ``local_d`` (any length): bilinear in
        the file's angles, as ``Photometry.intensity`` ((gamma, C) for Type C, linear in
        gamma alone for a rotationally symmetric profile; (H, V) for Type B, zero outside
        the measured range)."""
        if self.rotational:
            rho = dr.sqrt(dr.square(local_d.x) + dr.square(local_d.y))
            gamma = dr.atan2(rho, local_d.z) * (180.0 / math.pi)
            ii, ti = self.inner_axis.cell(gamma)
            v0 = dr.gather(mi.Float, self.table, ii)
            return dr.lerp(v0, dr.gather(mi.Float, self.table, ii + 1), ti)
        outer, inner = self.system.angles(local_d)
        (io, to), (ii, ti) = self.outer_axis.cell(outer), self.inner_axis.cell(inner)
        v00, v10, v01, v11 = self._corners(io, ii)
        value = dr.lerp(dr.lerp(v00, v10, to), dr.lerp(v01, v11, to), ti)
        if self.system.bounded:
            value = dr.select(self._inside(outer, inner), value, 0.0)
        return value

    def ray_direction_pdf(self, local_d):
        """The density (per steradian) of the local directions that ``sample_ray`` draws:
        the cell's probability times the bilinear density in (C, 1 - cos gamma) (Type B:
        (V, sin H)) over its solid angle."""
        outer, inner = self.system.angles(local_d)
        (io, to), (ii, _) = self.outer_axis.cell(outer), self.inner_axis.cell(inner)
        m = self.system.measure_of(local_d)
        m0 = dr.gather(mi.Float, self.inner_measure, ii)
        m1 = dr.gather(mi.Float, self.inner_measure, ii + 1)
        y = dr.clip((m - m0) / dr.maximum(m1 - m0, 1e-30), 0.0, 1.0)
        cell = io * (self.n_inner - 1) + ii
        v00, v10, v01, v11 = self._corners(io, ii)
        mean = 0.25 * (v00 + v10 + v01 + v11)
        inv_mean = dr.select(mean > 0.0, dr.rcp(mean), 0.0)
        bilinear = dr.lerp(dr.lerp(v00, v10, to), dr.lerp(v01, v11, to), y) * inv_mean
        omega = dr.gather(mi.Float, self.cell_omega, cell)
        pmf = self.cells.eval_pmf_normalized(cell)
        valid = omega > 0.0
        if self.system.bounded:
            valid &= self._inside(outer, inner)
        return dr.select(valid, pmf * bilinear / dr.maximum(omega, 1e-30), 0.0)

    def _sample_cell(self, u):
        """A cell drawn from the uniform ``u`` (Mitsuba's ``DiscreteDistribution``): its flat
        index, ``u`` made uniform again for reuse, and the cell's probability."""
        index, reused, pmf = self.cells.sample_reuse_pmf(u)
        return index, dr.clip(reused, 0.0, dr.one_minus_epsilon(mi.Float)), pmf

    def _sample_local_direction(self, sample):
        """A local direction drawn from the cell distribution, and I_v / pdf (cd sr)."""
        index, u, pmf = self._sample_cell(sample.x)
        io = index // (self.n_inner - 1)
        ii = index - io * (self.n_inner - 1)
        v00, v10, v01, v11 = self._corners(io, ii)
        inv_mean = dr.rcp(dr.maximum(0.25 * (v00 + v10 + v01 + v11), 1e-30))
        p, pdf_cell = mi.warp.square_to_bilinear(v00 * inv_mean, v10 * inv_mean,
                                                 v01 * inv_mean, v11 * inv_mean,
                                                 mi.Point2f(u, sample.y))
        o0 = dr.gather(mi.Float, self.outer_rad, io)
        o1 = dr.gather(mi.Float, self.outer_rad, io + 1)
        m0 = dr.gather(mi.Float, self.inner_measure, ii)
        m1 = dr.gather(mi.Float, self.inner_measure, ii + 1)
        local_d, inner = self.system.direction(dr.fma(p.x, o1 - o0, o0),
                                               dr.fma(p.y, m1 - m0, m0))
        # the exact profile at the drawn direction (bilinear in the angle, not its measure)
        ti = self.inner_axis.fraction(ii, inner)
        candela = dr.lerp(dr.lerp(v00, v10, p.x), dr.lerp(v01, v11, p.x), ti)
        omega = dr.gather(mi.Float, self.cell_omega, index)
        pdf = pmf * pdf_cell / omega
        return local_d, dr.select(pdf > 0.0, candela / dr.maximum(pdf, 1e-30), 0.0)

    # -- parameters ---------------------------------------------------------------------

    def _update(self):
        """Recompute the transforms and the emission scale (W/sr per cd of the file) from
        the traversed parameters, which are never rebound (mi.traverse holds references)."""
        self.to_local = self.to_world.inverse()
        self.position = self.to_world.translation()
        # the flat openings' back face: the frame turned by 180 degrees about local x
        flip = mi.Transform4f(mi.Matrix4f(mi.ScalarTransform4f().scale([1.0, -1.0, -1.0]).matrix))
        self.to_world_back = self.to_world @ flip
        self.to_local_back = self.to_world_back.inverse()
        dr.make_opaque(self.to_world_back, self.to_local_back)
        scale = self.scale_value * luminous.watts_per_lumen_dr(self.intensity)
        if self.luminous_flux is not None:
            scale = scale * self.luminous_flux * (1.0 / self.file_flux)
        self.scale = scale
        dr.make_opaque(self.to_world, self.to_local, self.position, self.scale)

    def traverse(self, callback):
        callback.put("scale", self.scale_value, mi.ParamFlags.Differentiable)
        if self.luminous_flux is not None:
            callback.put("luminous_flux", self.luminous_flux, mi.ParamFlags.Differentiable)
        callback.put("spectrum", self.intensity, mi.ParamFlags.Differentiable)
        callback.put("to_world", self.to_world, mi.ParamFlags.NonDifferentiable)

    def parameters_changed(self, keys):
        values = [("scale", self.scale_value)]
        if self.luminous_flux is not None:
            values.append(("luminous_flux", self.luminous_flux))
        for name, array in values:
            value = float(dr.slice(dr.detach(array)))
            if not value >= 0.0:
                raise ParameterError(f"{PLUGIN}: parameter '{name}' must be >= 0 (got {value:g})")
        luminous.check_luminous_content(self.intensity, PLUGIN, "spectrum")
        self._update()

    # -- sampling and evaluation --------------------------------------------------------

    def _emitted(self, local_d, wavelengths, active):
        """I_e in the local direction ``local_d`` (any length), without the distance law."""
        value = self.intensity.eval(self._spectral_si(wavelengths), active)
        return value * (self.candela(local_d) * self.scale)

    def sample_ray(self, time, wavelength_sample, sample2, sample3, active=True):
        wavelengths, weight = delta.DeltaLight.sample_wavelengths(
            self, dr.zeros(mi.SurfaceInteraction3f), wavelength_sample, active
        )
        if self.opening_kind != "point":
            # A point uniform on the opening's surface, a cosine-distributed direction
            # about its normal: weight L(omega) pi A.
            p, n, area = self._surface_point(sample2)
            d = mi.Frame3f(n).to_world(mi.warp.square_to_cosine_hemisphere(sample3))
            ray = sized.spawn_ray(p, n, d, time, wavelengths)
            ratio = self._candela_per_area(self.to_local @ d) * (dr.pi * area)
            return ray, self._out(weight * ratio)
        local_d, ratio = self._sample_local_direction(sample2)
        ray = mi.Ray3f(self.position, self.to_world @ local_d, time, wavelengths)
        return ray, self._out(weight * ratio)

    def sample_direction(self, it, sample, active=True):
        if self.opening_kind != "point":
            p, n, pdf = self._sample_opening(it.p, sample)
            ds = sized.direction_sample(self, it, p, n, pdf)
            lit = active & (pdf > 0.0)
            value = self._radiance(self.to_local @ (-ds.d), it.wavelengths, lit)
            return ds, dr.select(lit, value * dr.rcp(pdf), 0.0)
        ds, dist2 = self._direction_sample(it)
        local_d = self.to_local @ (-ds.d)
        value = self._emitted(local_d, it.wavelengths, active) * self.law(dist2)
        return ds, self._out(value)

    def eval_direction(self, it, ds, active=True):
        if self.opening_kind != "point":
            return self._radiance(self.to_local @ (-ds.d), it.wavelengths, active)
        d = mi.Vector3f(it.p - ds.p)
        local_d = self.to_local @ d
        value = self._emitted(local_d, it.wavelengths, active)
        return self._out(value * self.law(dr.squared_norm(d)))

    def sample_position(self, time, sample, active=True):
        if self.opening_kind != "point":
            p, n, area = self._surface_point(sample)
            ps, weight = sized.position_sample(time, p, n, area)
            return ps, weight if self.get_shape() is not None else weight * 0.0
        return self._position_sample(time), mi.Float(1.0)

    # -- the opening --------------------------------------------------------------------

    def _flat_frame(self, back):
        """The flat opening's frame facing the side ``back`` (local -Z) or the front."""
        to_world = mi.Transform4f(dr.select(back, self.to_world_back.matrix,
                                            self.to_world.matrix))
        to_local = mi.Transform4f(dr.select(back, self.to_local_back.matrix,
                                            self.to_local.matrix))
        return to_world, to_local

    def _sample_opening(self, ref_p, sample):
        """``(p, n, pdf)``: a point of the opening seen from ``ref_p`` (by solid angle for
        the sphere, the rectangle and near the disk; by area over the faces seen for the
        box), its normal on the side seen and the density in solid angle."""
        hx, hy, hz = self.half
        if self.opening_kind == "sphere":
            return opening.sphere_sample_direction(self.position, hx, ref_p, sample)
        if self.opening_kind == "box":
            return opening.box_sample_direction(self.to_world, self.to_local, self.half,
                                                ref_p, sample)
        if self.opening_kind == "cylinder":
            return opening.cylinder_sample_direction(self.to_world, self.to_local, hx, hz,
                                                     ref_p, sample)
        to_world, to_local = self._flat_frame((self.to_local @ ref_p).z < 0.0)
        if self.opening_kind == "rectangle":
            return opening.rectangle_solid_angle_sample(to_world, hx, hy, ref_p, sample)
        return opening.disk_sample_direction(to_world, to_local, hx, ref_p, sample)

    def pdf_direction(self, it, ds, active=True):
        if self.opening_kind == "point":
            return super().pdf_direction(it, ds, active)
        hx, hy, hz = self.half
        outward = dr.dot(ds.d, ds.n) < 0.0
        if self.opening_kind == "sphere":
            pdf = dr.select(outward, opening.sphere_pdf_direction(
                self.position, hx, it.p, ds.p, ds.n), 0.0)
        elif self.opening_kind == "box":
            pdf = dr.select(outward, opening.box_pdf_direction(
                self.to_local, self.half, it.p, ds.p, ds.n), 0.0)
        elif self.opening_kind == "cylinder":
            pdf = dr.select(outward, opening.cylinder_pdf_direction(
                self.to_local, hx, hz, it.p, ds.p, ds.n), 0.0)
        else:
            to_world, to_local = self._flat_frame((self.to_local @ it.p).z < 0.0)
            if self.opening_kind == "rectangle":
                pdf = opening.rectangle_solid_angle_pdf(to_world, hx, hy, it.p, ds.p)
            else:
                n = mi.Normal3f(dr.normalize(to_world @ mi.Normal3f(0.0, 0.0, 1.0)))
                pdf = opening.disk_pdf_direction(to_world, to_local, hx, it.p, ds.p, n)
        return dr.select(active, pdf, 0.0)

    def pdf_position(self, ps, active=True):
        if self.opening_kind == "point":
            return super().pdf_position(ps, active)
        return dr.select(active, dr.rcp(self._area()), 0.0)

    def _area(self):
        """The emitting area (both faces of a flat opening)."""
        hx, hy, hz = self.half
        if self.opening_kind == "sphere":
            return mi.Float(4.0 * math.pi * hx * hx)
        if self.opening_kind == "box":
            return mi.Float(8.0 * (hx * hy + hx * hz + hy * hz))
        if self.opening_kind == "cylinder":
            return mi.Float(2.0 * math.pi * hx * (2.0 * hz + hx))
        face = 4.0 * hx * hy if self.opening_kind == "rectangle" else math.pi * hx * hx
        return mi.Float(2.0 * face)

    def _surface_point(self, sample):
        """A point uniform by area on the opening's emitting surface, its outward normal
        and the area."""
        hx, hy, hz = self.half
        if self.opening_kind == "sphere":
            n = mi.Normal3f(mi.warp.square_to_uniform_sphere(sample))
            return mi.Point3f(self.position + hx * n), n, self._area()
        if self.opening_kind == "box":
            return opening.box_point(self.to_world, self.half, sample)
        if self.opening_kind == "cylinder":
            return opening.cylinder_point(self.to_world, hx, hz, sample)
        back = sample.x < 0.5  # the side, then the sample made uniform again
        sample = mi.Point2f(dr.select(back, 2.0 * sample.x, 2.0 * sample.x - 1.0), sample.y)
        to_world, _ = self._flat_frame(back)
        if self.opening_kind == "rectangle":
            p, n = opening.rectangle_point(to_world, hx, hy, sample)
        else:
            p, n = opening.disk_point(to_world, hx, sample)
        return p, n, self._area()

    def projected_area(self, local_d):
        """A_proj (m^2) of the opening seen along the unit local direction ``local_d``: a
        flat opening shows both faces, pi r^2 |cos gamma| (disk) or 4 hx hy |cos gamma|
        (rectangle)."""
        hx, hy, hz = self.half
        if self.opening_kind == "sphere":
            return opening.sphere_projected_area(hx)
        if self.opening_kind == "box":
            return opening.box_projected_area((2.0 * hx, 2.0 * hy, 2.0 * hz), local_d)
        if self.opening_kind == "cylinder":
            return opening.cylinder_projected_area(hx, 2.0 * hz, local_d.z)
        cos_gamma = dr.abs(local_d.z)
        if self.opening_kind == "rectangle":
            return opening.rectangle_projected_area(hx, hy, cos_gamma)
        return opening.disk_projected_area(hx, cos_gamma)

    def _candela_per_area(self, local_d):
        """I_v(omega) / A_proj(omega) (cd/m^2, the luminance of the file's candela) in the
        local direction ``local_d`` (any length; 0 where A_proj is 0)."""
        unit = dr.normalize(local_d)
        area = self.projected_area(unit)
        return dr.select(area > 0.0, self.candela(unit) * dr.rcp(dr.maximum(area, 1e-30)),
                         0.0)

    def _radiance(self, local_d, wavelengths, active):
        """L = I_e(omega) / A_proj(omega) in the local direction ``local_d``."""
        value = self.intensity.eval(self._spectral_si(wavelengths), active)
        return self._out(dr.select(active, value * (self._candela_per_area(local_d)
                                                    * self.scale), 0.0))

    def eval(self, si, active=True):
        if self.opening_kind == "point":
            return super().eval(si, active)
        return self._radiance(self.to_local @ si.to_world(si.wi), si.wavelengths, active)

    def sample_wavelengths(self, si, sample, active=True):
        """Wavelengths and weight of the emission; with an opening, at the point ``si`` of
        its surface towards the world direction ``si.wi`` (what ``ptracer`` asks when it
        connects a visible light to the camera): L(omega) / p(lambda), 0 from an opening
        that is not attached to a shape (invisible)."""
        wavelengths, weight = super().sample_wavelengths(si, sample, active)
        if self.opening_kind == "point":
            return wavelengths, weight
        factor = self._candela_per_area(self.to_local @ si.wi)
        if self.get_shape() is None:
            factor = factor * 0.0
        return wavelengths, weight * factor

    def bbox(self):
        if self.opening_kind == "point":
            return super().bbox()
        p = mi.ScalarPoint3f(dr.slice(self.position, 0))
        reach = math.sqrt(sum(h * h for h in self.half))
        return mi.ScalarBoundingBox3f(p - reach, p + reach)

    def to_string(self):
        flux = "" if self.luminous_flux is None else \
            f", luminous_flux={float(dr.slice(dr.detach(self.luminous_flux))):g} lm"
        return (
            f"IESLight[filename={self.path}, flux of the file={self.file_flux:g} lm, "
            f"to_world={self.to_world}, scale={float(dr.slice(dr.detach(self.scale_value))):g}"
            f"{flux}, spectrum={self.intensity}, falloff={self.law!r}]"
        )


def from_photometry(photometry, parameters: dict | None = None) -> IESLight:
    """An ``ieslight`` of an in-memory ``Photometry`` (for the active variant): the
    plugin's parameters but ``filename`` in ``parameters`` (a dict value, such as a
    spectrum, is loaded with ``mi.load_dict``)."""
    props = mi.Properties(PLUGIN)
    for name, value in (parameters or {}).items():
        props[name] = mi.load_dict(value) if isinstance(value, dict) else value
    return IESLight(props, photometry=photometry)


mi.register_emitter(PLUGIN, lambda props: IESLight(props))
