"""The :class:`Photometry` record: a luminaire's intensity table and what follows from it.

Angles are in degrees, intensities in candela and lengths in metres throughout.

Type C (the C-gamma system of LM-63 and EULUMDAT): gamma is the angle from the photometric
zero (nadir, the direction the light points), C the azimuth of the half-plane around the
gamma = 0 axis, C = 0 along the luminaire's local +X (its length, the "photometric
horizontal"), C growing counterclockwise seen from above the luminaire (from the side
opposite to nadir; LM-63-2002 sec. 3: "measured counterclockwise in a horizontal plane for
Type C photometry"), so C = 90 is local -Y.

Type B (floodlights, LM-63 photometric type 2; the B-beta system of CIE 121 and EN 13032-1).
The polar axis is horizontal: the luminaire's minor axis (its width, the C90-C270 line),
perpendicular to the aiming axis. A B-plane is a plane through the polar axis; the vertical
angle V is the tilt of the B-plane about the polar axis (V = 0: the plane through the aiming
axis; V > 0 upwards, towards the photometric horizontal, which LM-63 puts at (H, V) =
(0, 90) for Type B as for Type C); the horizontal angle H is measured *inside* the B-plane,
from the plane's aiming line towards the polar axis (-90 <= H <= 90). Both are rotation
angles, not projections. H is positive clockwise seen from above the floodlight in its
measuring position (LM-63-2002 sec. 3: horizontal angles are "measured ... clockwise for
Type A and B photometry"), that is to the right seen from behind the luminaire, as in
headlamp photometry (H right, V up). Seen from behind the floodlight, aimed away from the
viewer::

                 V = +90 (up: photometric horizontal, Type C C = 0, local +X)
                    |
                    |    B-plane V = v: the plane through the polar axis tilted by v
        H = -90 ----+---- H = +90    polar axis (luminaire width), C = 90 / 270
      (left, C 90)  |    (right, C 270, local +Y)
                    |
                 V = -90            aiming axis (H = V = 0) into the page: gamma = 0

A direction is ``cos H cos V * aim + cos H sin V * up + sin H * right``; in the Type C frame
``aim`` is gamma = 0 (local +Z of ``ieslight``), ``up`` C = 0 (local +X) and ``right``
C = 270 (local +Y), so that the record gives one direction for one physical direction
whatever the photometric type:

* B -> C: ``cos gamma = cos H cos V``, ``C = atan2(-sin H, cos H sin V)``;
* C -> B: ``sin H = -sin gamma sin C``, ``tan V = sin gamma cos C / cos gamma``.

So H = V = 0 is gamma = 0; (H, V) = (0, 30) is (gamma, C) = (30, 0); (H, V) = (30, 0) is
(30, 270) and (-30, 0) is (30, 90). (Converters that write the B-beta relations as
tan B = cos C tan gamma, sin beta = sin C sin gamma count beta the other way: beta = -H.)

Symmetry (LM-63-2002, the horizontal and vertical angle fields): horizontal angles from 0
to 90 mean a luminaire laterally symmetric about the vertical plane H = 0,
I(-H, V) = I(H, V) (the C0-C180 plane: "bilateral_0_180"); vertical angles from 0 to 90
one symmetric about the horizontal plane V = 0, I(H, -V) = I(H, V) (the C90-C270 plane:
"bilateral_90_270"); both, "quadrant".

The other readers. Radiance's ``source.cal`` (2008 onwards, used by ``ies2rad``) computes
``srcB_horiz = atan2(Dy, Dz)``, with D the ray direction towards the source: H positive
towards C = 270, as here, but H is the angle of the direction's projection on the V = 0
plane rather than the angle inside its own B-plane; the two agree in the planes H = 0 and
V = 0 and differ off them (by arctan(tan H / cos V) against H: 3.7 degrees at H = 30,
V = 30). We agree with Radiance on the sign and not on the projection: LM-63 and CIE 121
measure H within the B-plane. Blender Cycles (``src/util/ies.cpp``, Type B since 2024)
transposes the table into its own spherical grid, H + 90 as the polar angle and V + 90 as
the azimuth about the polar axis: rotation angles as here, and it mirrors both a horizontal
range from 0 and a vertical range from 0 as here, but it puts the polar axis along the
lamp's own axis and leaves the aiming to the user, so its directions are ours only after a
rotation the user must supply. spectrace before this reading put H > 0 at C = 90 (the
mirror image: asymmetric Type B files came out left for right) and did not mirror a
vertical range from 0.

The luminous opening (:class:`Opening`): LM-63's width, length and height fields with the
meaning of their signs in each edition (:data:`OPENING_SHAPES`), length along C0-C180 and
width along C90-C270 (as Radiance's ``ies2rad`` reads them), or EULUMDAT's luminous area
(fields 16-21).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

from spectrace.errors import FileFormatError, ParameterError
from spectrace.quadrature import trapezoid_weights

#: The angular width (degrees) of the step from the last measured intensity to zero in
#: :meth:`Photometry.type_c_grid` (outside the measured gamma range the intensity is 0).
GRID_EDGE_STEP_DEG = 1e-3
#: The regular grid step (degrees) of :meth:`Photometry.type_c_grid` for Type B files.
TYPE_B_GRID_STEP_DEG = 1.0
#: Sampling of a plane (degrees) when locating the beam and field angles.
SPREAD_STEP_DEG = 0.05
#: A beam or field angle wider than this (degrees) is not defined: the arc around the peak
#: would take in more than a half-plane (wide, batwing and wall-pack distributions).
MAX_SPREAD_DEG = 180.0
#: The fractions of a plane's peak that define the beam and the field angle (CIE 121, IES).
BEAM_FRACTION, FIELD_FRACTION = 0.5, 0.1
#: The two main plane pairs, named by their C angles.
MAIN_PLANES = {"C0-C180": 0.0, "C90-C270": 90.0}

SYMMETRIES = ("rotational", "quadrant", "bilateral_0_180", "bilateral_90_270", "none")
#: Relative tolerance within which two opening dimensions count as equal (a circle, not an
#: ellipse); files print them with a few digits.
OPENING_EQUAL_RTOL = 1e-3
#: The photometric distance is this many times the opening's largest dimension: beyond it
#: the point (far-field) law E = I cos / r^2 holds within about 1% (CIE 121-1996, sec. 4).
PHOTOMETRIC_DISTANCE_FACTOR = 5.0

#: LM-63 luminous openings by edition: the signs (-1, 0, +1) of (width, length, height) ->
#: shape. Length lies along C0-C180, width along C90-C270. 1986 and 1991 share a table, so
#: do 2002 and 2019; a name in a pair (circle, ellipse) is chosen by whether the two negative
#: dimensions are equal. The tables follow the editions as Radiance's ``ies2rad``
#: (``makeiesshape``, 2021) reads them, including its extension of a box with one zero
#: horizontal side (a vertical rectangle) and its reading of 1986's ellipse with a height as
#: an ellipsoid.
_BOX = {(1, 1, 1): "box", (0, 1, 1): "box", (1, 0, 1): "box"}
OPENING_SHAPES = {
    "1986": {(0, 0, 0): "point", (1, 1, 0): "rectangle", **_BOX,
             (-1, 0, 0): "disk", (-1, 0, 1): "vertical_cylinder", (-1, 1, 0): "ellipse",
             (-1, 1, 1): "ellipsoid"},
    "1995": {(0, 0, 0): "point", (1, 1, 0): "rectangle", **_BOX,
             (-1, 0, 0): "disk", (-1, 0, 1): "vertical_cylinder", (-1, 0, -1): "sphere",
             (0, 1, -1): "horizontal_cylinder_along", (1, 0, -1): "horizontal_cylinder_across",
             (1, -1, 1): "vertical_elliptical_cylinder",
             (-1, 1, 1): "vertical_elliptical_cylinder",
             (1, -1, -1): "ellipsoid", (-1, 1, -1): "ellipsoid"},
    "2002": {(0, 0, 0): "point", (1, 1, 0): "rectangle", **_BOX,
             (-1, -1, 0): ("disk", "ellipse"),
             (-1, -1, 1): ("vertical_cylinder", "vertical_elliptical_cylinder"),
             (-1, -1, -1): ("sphere", "ellipsoid"),
             (-1, 1, -1): ("horizontal_cylinder_along", "horizontal_elliptical_cylinder_along"),
             (1, -1, -1): ("horizontal_cylinder_across",
                           "horizontal_elliptical_cylinder_across"),
             (0, -1, -1): ("vertical_disk", "vertical_ellipse")},
}
_EDITION_TABLE = {"LM-63-1986": "1986", "LM-63-1991": "1986", "LM-63-1995": "1995",
                  "LM-63-2002": "2002", "LM-63-2019": "2002"}


@dataclass(frozen=True, eq=False)
class AngleGrid:
    """A photometric table in its own angles, symmetry expanded, for renderers that sample
    it (``ieslight``): bilinear interpolation on it is :meth:`Photometry.intensity`.

    ``system`` "C": ``outer`` the C angles over 0..360 and ``inner`` gamma over 0..180 (the
    whole sphere, :meth:`Photometry.type_c_grid`); "B": ``outer`` V and ``inner`` H in the
    file's measured range with their mirror images (zero outside). ``candela`` has shape
    (outer.size, inner.size); each axis has two angles or more.
    """

    system: str
    outer: np.ndarray
    inner: np.ndarray
    candela: np.ndarray


@dataclass(frozen=True)
class Opening:
    """A luminaire's luminous opening (LM-63) or luminous area (EULUMDAT), in metres.

    ``shape``: "point", "rectangle" (width x length, horizontal), "box" (width x length x
    height, luminous sides), "disk" / "ellipse" (horizontal, diameters width and length),
    "vertical_cylinder" / "vertical_elliptical_cylinder" (that disk or ellipse extruded by
    the height), "sphere" / "ellipsoid", "horizontal_cylinder_along" (axis along the
    length, C0-C180, diameter the width = height) / "..._across" (axis along the width,
    C90-C270, diameter the length = height) and their elliptical forms, "vertical_disk" /
    "vertical_ellipse" (in the vertical plane of the length, facing C90-C270; width 0).
    ``width`` lies along C90-C270 and ``length`` along C0-C180, both >= 0 (the file's signs
    give the shape, not the size); a circle's diameter is both. ``side_heights``: EULUMDAT's
    heights of the luminous area at C0, C90, C180, C270 (``height`` is their largest).
    """

    shape: str
    width: float = 0.0
    length: float = 0.0
    height: float = 0.0
    side_heights: tuple[float, float, float, float] | None = None

    @property
    def largest_dimension(self) -> float:
        """The largest of width, length and height (m)."""
        return max(self.width, self.length, self.height)

    @property
    def photometric_distance(self) -> float:
        """PHOTOMETRIC_DISTANCE_FACTOR times the largest dimension (m): from there on the
        luminaire may be taken as a point."""
        return PHOTOMETRIC_DISTANCE_FACTOR * self.largest_dimension


def ies_opening(edition: str, width: float, length: float, height: float) -> Opening:
    """The :class:`Opening` of LM-63 ``edition`` ("LM-63-1986" ... "LM-63-2019") from its
    signed width, length and height (m). Raises ``ValueError`` (no path: the caller names
    the file) when the signs are no shape of that edition."""
    dims = (float(width), float(length), float(height))
    signs = tuple(int(np.sign(x)) for x in dims)
    table = OPENING_SHAPES[_EDITION_TABLE[edition]]
    if signs not in table:
        raise ValueError(
            f"luminous opening: width {dims[0]:g}, length {dims[1]:g}, height {dims[2]:g} m "
            f"(signs {''.join('-0+'[s + 1] for s in signs)}) is no shape of {edition}")
    name = table[signs]
    w, l, h = (abs(x) for x in dims)
    if isinstance(name, tuple):  # circle or ellipse: are the negative dimensions equal?
        negative = [abs(x) for x, s in zip(dims, signs, strict=True) if s < 0]
        round_ = np.allclose(negative, negative[0], rtol=OPENING_EQUAL_RTOL, atol=0.0)
        name = name[0] if round_ else name[1]
    if signs[1] == 0 and name in ("disk", "vertical_cylinder", "sphere"):
        l = w  # 1986-1995: the diameter is the width alone
    if name == "horizontal_cylinder_along" and signs[0] == 0:
        w = h  # 1995: the diameter is the height
    if name == "horizontal_cylinder_across" and signs[1] == 0:
        l = h
    if name == "sphere":
        if not np.isclose(w, h, rtol=OPENING_EQUAL_RTOL, atol=0.0):
            raise ValueError(f"luminous opening: a sphere of {edition} has equal width and "
                             f"height (got {w:g} and {h:g} m)")
        h = w
    return Opening(name, w, l, h)


def ldt_opening(length: float, width: float, side_heights) -> Opening:
    """The :class:`Opening` of EULUMDAT's luminous area (m): ``length`` (field 16, the
    length or the diameter; along C0-C180 as LM-63's), ``width`` (field 17, along C90-C270;
    0 for a circular area) and the heights at C0, C90, C180, C270 (fields 18-21): a point
    (all 0), a disk or a rectangle, with luminous sides (any height > 0) a vertical cylinder
    or a box. Raises ``ValueError`` (no path) for a negative size or a width without a
    length."""
    heights = tuple(float(x) for x in side_heights)
    if min(length, width, *heights) < 0:
        raise ValueError("luminous area (lines 16-21): sizes must be >= 0 (got length "
                         f"{length:g}, width {width:g}, heights {heights} m)")
    if width > 0 and not length > 0:
        raise ValueError(f"luminous area (lines 16-17): a width ({width:g} m) needs a length "
                         "or diameter (line 16 is 0)")
    height = max(heights)
    if not length > 0:
        if height > 0:
            raise ValueError("luminous area (lines 18-21): heights without a length or "
                             "diameter (line 16 is 0)")
        return Opening("point", side_heights=heights)
    if width == 0:
        return Opening("vertical_cylinder" if height > 0 else "disk", length, length, height,
                       heights)
    return Opening("box" if height > 0 else "rectangle", width, length, height, heights)


@dataclass
class Tilt:
    """An LM-63 tilt table: multiplying factor against the luminaire's tilt angle.

    ``geometry`` is the lamp-to-luminaire geometry code (1: lamp vertical base up or down,
    2: horizontal, burning position constant as the luminaire tilts, 3: horizontal,
    burning position changing with the tilt).
    """

    geometry: int
    angles: np.ndarray
    factors: np.ndarray

    def factor(self, angle: float = 0.0) -> float:
        """The factor at ``angle`` (degrees), linear between entries, clamped at the ends."""
        return float(np.interp(angle, self.angles, self.factors))


@dataclass(eq=False)
class Photometry:
    """One photometric file.

    ``candela`` has shape (n_horizontal, n_vertical) in cd with every factor of the file
    applied (``applied_factor``: the candela multiplier, ballast factor, ballast-lamp
    photometric factor, tilt factor at 0 degrees; for EULUMDAT the lamp flux / 1000 and the
    conversion factor). ``horizontal_angles`` and ``vertical_angles`` are the file's (for
    EULUMDAT with Isym 3 the stored half C270-C0-C90 appears as its mirror image C90-C270,
    see :mod:`spectrace.photometry.eulumdat`). ``symmetry`` names how the table extends to
    the whole sphere: "rotational" (one plane), "quadrant" (C 0-90), "bilateral_0_180"
    (C 0-180, mirror about the C0-C180 plane), "bilateral_90_270" (C 90-270, mirror about
    the C90-C270 plane), "none" (C 0-360). A Type B table with H from 0 is laterally
    symmetric, I(H, V) = I(-H, V): a mirror about the C0-C180 plane, "bilateral_0_180"; one
    with V from 0 is symmetric about its horizontal plane, I(H, -V) = I(H, V): a mirror
    about the C90-C270 plane, "bilateral_90_270"; both: "quadrant".
    Treat the arrays as read-only (the expanded table and the flux are cached); use
    :meth:`replace` for a changed copy.
    """

    path: Path
    format: str
    photometric_type: str
    vertical_angles: np.ndarray
    horizontal_angles: np.ndarray
    candela: np.ndarray
    keywords: dict[str, str] = field(default_factory=dict)
    symmetry: str = "none"
    #: lumens of one lamp (None: absolute photometry, lumens = -1 in LM-63)
    lumens_per_lamp: float | None = None
    n_lamps: int = 1
    #: the product of the factors applied to the file's numbers to get ``candela``
    applied_factor: float = 1.0
    multiplier: float = 1.0
    ballast_factor: float = 1.0
    ballast_lamp_factor: float = 1.0
    tilt: Tilt | None = None
    tilt_factor: float = 1.0
    input_watts: float | None = None
    #: luminous opening (width, length, height) in metres with the file's signs (LM-63) or
    #: the luminous area (EULUMDAT, positive); see :attr:`opening`
    opening_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    #: EULUMDAT's heights of the luminous area at C0, C90, C180, C270 (m); None for LM-63
    opening_side_heights: tuple[float, float, float, float] | None = None

    def __post_init__(self):
        self.path = Path(self.path)
        self.vertical_angles = np.asarray(self.vertical_angles, dtype=np.float64)
        self.horizontal_angles = np.asarray(self.horizontal_angles, dtype=np.float64)
        self.candela = np.asarray(self.candela, dtype=np.float64).reshape(
            self.horizontal_angles.size, self.vertical_angles.size
        )
        if self.photometric_type not in ("C", "B"):
            raise ParameterError(f"photometric_type must be 'C' or 'B' (got "
                                 f"{self.photometric_type!r})")
        if self.symmetry not in SYMMETRIES:
            raise ParameterError(f"symmetry must be one of {SYMMETRIES} (got {self.symmetry!r})")

    def replace(self, **changes) -> Photometry:
        """A copy with some fields changed (e.g. ``candela`` scaled)."""
        return dataclasses.replace(self, **changes)

    # ---------------------------------------------------------------- the opening
    @cached_property
    def opening(self) -> Opening:
        """The luminous opening (:class:`Opening`, metres), read from the width, length and
        height of an LM-63 file by the signs of its edition, or from a EULUMDAT file's
        luminous area. Raises :class:`~spectrace.errors.FileFormatError` naming the file
        when the file's values are no shape (reading the file does not: the intensities
        stay usable)."""
        width, length, height = self.opening_m
        try:
            if self.format == "EULUMDAT":
                return ldt_opening(length, width, self.opening_side_heights or (0.0,) * 4)
            return ies_opening(self.format if self.format in _EDITION_TABLE else
                               "LM-63-2002", width, length, height)
        except ValueError as error:
            raise FileFormatError(f"{self.path}: {error}") from None

    # ---------------------------------------------------------------- Type B symmetry
    @property
    def _b_mirrors(self) -> tuple[bool, bool]:
        """Type B: (mirrored in H, mirrored in V) by the symmetry."""
        return (self.symmetry in ("bilateral_0_180", "quadrant"),
                self.symmetry in ("bilateral_90_270", "quadrant"))

    # ---------------------------------------------------------------- the whole sphere
    @cached_property
    def _c_table(self) -> tuple[np.ndarray, np.ndarray]:
        """Type C: (C grid over [0, 360], candela (n_c, n_vertical)) with symmetry expanded.

        The C grid holds every image of the file's planes under the symmetry, so linear
        interpolation on it equals folding C into the file's range and interpolating there.
        """
        h = self.horizontal_angles
        table = self.candela
        sym = self.symmetry
        if sym == "rotational":
            return np.array([0.0, 360.0]), np.repeat(table[:1], 2, axis=0)
        if sym == "quadrant":
            images = np.concatenate([h, 180 - h, 180 + h, 360 - h])
        elif sym == "bilateral_0_180":
            images = np.concatenate([h, 360 - h])
        elif sym == "bilateral_90_270":
            images = np.concatenate([h, np.mod(180 - h, 360), [0.0, 360.0]])
        else:  # none: periodic, 360 is 0
            images = np.concatenate([h, [0.0, 360.0]])
        c = np.unique(np.round(images, 9))
        c = c[(c >= 0) & (c <= 360)]
        return c, self._rows_at(c)

    def _fold(self, c: np.ndarray) -> np.ndarray:
        """Map C (in [0, 360]) into the file's horizontal range by the symmetry."""
        sym = self.symmetry
        if sym == "quadrant":
            c = np.where(c > 180, 360 - c, c)
            return np.where(c > 90, 180 - c, c)
        if sym == "bilateral_0_180":
            return np.where(c > 180, 360 - c, c)
        if sym == "bilateral_90_270":
            return np.where(c < 90, 180 - c, np.where(c > 270, 540 - c, c))
        return c

    def _rows_at(self, c: np.ndarray) -> np.ndarray:
        """Candela rows at the C angles ``c`` in [0, 360] (linear in C between planes)."""
        h, table = self.horizontal_angles, self.candela
        if self.symmetry == "none" and h[-1] < 360:  # close the circle: C = 360 is C = 0
            h = np.append(h, 360.0)
            table = np.vstack([table, table[:1]])
        f = self._fold(np.asarray(c, dtype=np.float64))
        i = np.clip(np.searchsorted(h, f, side="right") - 1, 0, h.size - 2)
        t = np.clip((f - h[i]) / (h[i + 1] - h[i]), 0.0, 1.0)[:, None]
        return table[i] * (1 - t) + table[i + 1] * t

    def angle_grid(self) -> AngleGrid:
        """The table in the file's own angles with its symmetry expanded (:class:`AngleGrid`):
        Type C on (C, gamma) over the whole sphere; Type B on (V, H) with the mirror images
        a horizontal or vertical range from 0 stands for."""
        if self.photometric_type == "C":
            gamma, c, table = self.type_c_grid()
            if gamma.size < 2:
                raise FileFormatError(f"{self.path}: a Type C table needs two vertical angles "
                                      "or more")
            return AngleGrid("C", c, gamma, table)
        h, v, table = self.horizontal_angles, self.vertical_angles, self.candela
        mirror_h, mirror_v = self._b_mirrors
        if mirror_h:  # I(-H, V) = I(H, V)
            h, table = np.concatenate([-h[:0:-1], h]), np.concatenate([table[:0:-1], table])
        if mirror_v:  # I(H, -V) = I(H, V)
            v = np.concatenate([-v[:0:-1], v])
            table = np.concatenate([table[:, :0:-1], table], axis=1)
        if h.size < 2 or v.size < 2:
            raise FileFormatError(f"{self.path}: a Type B table needs two angles or more in "
                                  "each direction (it covers no solid angle)")
        return AngleGrid("B", v.copy(), h.copy(), np.ascontiguousarray(table.T))

    # ---------------------------------------------------------------- evaluation
    def intensity(self, gamma, c) -> np.ndarray:
        """Intensity (cd) at Type C angles ``gamma``, ``c`` in degrees (numpy broadcast).

        Bilinear in the file's own angles (in (gamma, C) for Type C, in (H, V) for Type B
        after converting the direction), the symmetry expanded, zero outside the measured
        range. gamma outside [0, 180] is taken through the pole (gamma -> -gamma or
        360 - gamma with C + 180).
        """
        gamma, c = np.broadcast_arrays(np.asarray(gamma, np.float64), np.asarray(c, np.float64))
        g = np.mod(gamma, 360.0)
        over = g > 180
        g = np.where(over, 360.0 - g, g)
        c = np.mod(np.where(over, c + 180.0, c), 360.0)
        if self.photometric_type == "C":
            cgrid, table = self._c_table
            return _bilinear(cgrid, self.vertical_angles, table, c, g)
        H, V = type_c_to_b(g, c)
        mirror_h, mirror_v = self._b_mirrors
        H = np.abs(H) if mirror_h else H
        V = np.abs(V) if mirror_v else V
        return _bilinear(self.horizontal_angles, self.vertical_angles, self.candela, H, V)

    def type_c_grid(self, step: float | None = None):
        """The whole sphere on a Type C grid: ``(gamma_deg (n_g,), c_deg (n_c,), candela
        (n_c, n_g))``, gamma covering 0..180 and C 0..360 inclusive, symmetry expanded.

        Type C with ``step=None``: the file's own angles, plus the images of the planes under
        the symmetry, plus zero rows outside the measured gamma range (a step to zero within
        ``GRID_EDGE_STEP_DEG``), so that bilinear interpolation on this grid reproduces
        :meth:`intensity` (exactly, except within that step of the range's ends). Type B (or
        any ``step``): a regular grid of ``step`` degrees (default ``TYPE_B_GRID_STEP_DEG``
        for Type B) sampled with :meth:`intensity`; bilinear interpolation on it is then an
        approximation of :meth:`intensity` (its error shrinks as step squared).
        """
        if self.photometric_type == "C" and step is None:
            cgrid, table = self._c_table
            g = self.vertical_angles
            eps = GRID_EDGE_STEP_DEG
            gammas, cols = [g], [table]
            if g[0] > 0:
                lo = [0.0, g[0] - eps] if g[0] > eps else [0.0]
                gammas.insert(0, np.array(lo))
                cols.insert(0, np.zeros((cgrid.size, len(lo))))
            if g[-1] < 180:
                hi = [g[-1] + eps, 180.0] if g[-1] < 180 - eps else [180.0]
                gammas.append(np.array(hi))
                cols.append(np.zeros((cgrid.size, len(hi))))
            return np.concatenate(gammas), cgrid.copy(), np.concatenate(cols, axis=1)
        step = TYPE_B_GRID_STEP_DEG if step is None else float(step)
        if not step > 0:
            raise ParameterError(f"type_c_grid: step must be > 0 (got {step})")
        gamma = np.linspace(0.0, 180.0, int(round(180.0 / step)) + 1)
        c = np.linspace(0.0, 360.0, int(round(360.0 / step)) + 1)
        return gamma, c, self.intensity(gamma[None, :], c[:, None])

    # ---------------------------------------------------------------- derived numbers
    @cached_property
    def flux(self) -> float:
        """Luminous flux (lm): the bilinear-interpolated intensity integrated exactly over
        the sphere, symmetry expanded (integral of I sin(gamma) dgamma dC for Type C,
        I cos(H) dH dV for Type B)."""
        if self.photometric_type == "C":
            cgrid, table = self._c_table
            wc = trapezoid_weights(np.radians(cgrid))
            wg = _linear_weights(np.radians(self.vertical_angles), "sin")
            return float(wc @ table @ wg)
        wh = _linear_weights(np.radians(self.horizontal_angles), "cos")
        wv = trapezoid_weights(np.radians(self.vertical_angles))
        total = float(wh @ self.candela @ wv)
        for mirrored in self._b_mirrors:  # H (or V) from 0: the mirrored half below 0
            total *= 2.0 if mirrored else 1.0
        return total

    def flux_between(self, gamma_lo: float, gamma_hi: float) -> float:
        """Luminous flux (lm) into the zone gamma_lo <= gamma <= gamma_hi (degrees), e.g.
        (0, 90) the downward flux. Exact for Type C (the zone's ends are inserted into the
        gamma grid, along which the interpolation is linear); for Type B the integral of
        the 0.25-degree ``type_c_grid`` (within 0.1% on smooth tables)."""
        lo, hi = max(float(gamma_lo), 0.0), min(float(gamma_hi), 180.0)
        if self.photometric_type == "C":
            cgrid, table = self._c_table
            v = self.vertical_angles
            lo, hi = max(lo, v[0]), min(hi, v[-1])
            if not hi > lo:
                return 0.0
            g = np.unique(np.concatenate([[lo, hi], v[(v > lo) & (v < hi)]]))
            rows = np.stack([np.interp(g, v, row) for row in table])
        else:
            g_all, cgrid, table_all = self.type_c_grid(step=0.25)
            keep = (g_all >= lo) & (g_all <= hi)
            g, rows = g_all[keep], table_all[:, keep]
            if g.size < 2:
                return 0.0
        wc = trapezoid_weights(np.radians(cgrid))
        return float(wc @ rows @ _linear_weights(np.radians(g), "sin"))

    @property
    def max_candela(self) -> float:
        """The largest intensity (cd); bilinear interpolation never exceeds the table's."""
        return float(self.candela.max())

    @property
    def peak_direction(self) -> tuple[float, float]:
        """(gamma, C) in degrees of the largest tabulated intensity (first one found)."""
        i, j = np.unravel_index(np.argmax(self.candela), self.candela.shape)
        h, v = float(self.horizontal_angles[i]), float(self.vertical_angles[j])
        if self.photometric_type == "C":
            return v, h
        g, c = type_b_to_c(h, v)
        return float(g), float(c)

    def plane_spread(self, fraction: float, c_plane: float = 0.0) -> float:
        """Full angle (degrees) in the plane C = ``c_plane`` / C = ``c_plane`` + 180 between
        the two directions, either side of the plane's peak, where the intensity has fallen
        to ``fraction`` of that peak (linear between samples; the plane is a full circle,
        through nadir and zenith), as CIE 121 and the IES define beam (50%) and field (10%)
        angles. NaN, "not defined", if the plane is dark, if the intensity never falls that
        far on one side, or if the arc around the peak is wider than ``MAX_SPREAD_DEG``
        (a wide or batwing distribution has no beam in that plane)."""
        # signed angle along the circle: theta >= 0 is gamma = theta in C = c_plane,
        # theta < 0 is gamma = -theta in C = c_plane + 180; theta = -180 is the zenith
        theta = np.arange(-180.0, 180.0, SPREAD_STEP_DEG)
        if self.photometric_type == "C":  # the table's own gamma nodes: exact crossings
            v = self.vertical_angles
            theta = np.unique(np.concatenate([theta, v[v < 180], -v[v > 0]]))
        I = self.intensity(np.abs(theta), np.where(theta >= 0, c_plane, c_plane + 180.0))
        n = theta.size
        k = int(np.argmax(I))
        peak = I[k]
        if not peak > 0:
            return float("nan")
        threshold = fraction * peak
        ends = []
        for direction in (1, -1):
            steps = np.arange(1, n)
            idx = (k + direction * steps) % n
            below = np.nonzero(I[idx] < threshold)[0]
            if below.size == 0:
                return float("nan")
            m = int(below[0])
            j1 = int(idx[m])
            j0 = k if m == 0 else int(idx[m - 1])
            # unwrapped angles of the two samples, walking from the peak
            a0 = theta[k] + direction * np.mod(direction * (theta[j0] - theta[k]), 360.0)
            a1 = theta[k] + direction * np.mod(direction * (theta[j1] - theta[k]), 360.0)
            t = (I[j0] - threshold) / (I[j0] - I[j1])
            ends.append(a0 + t * (a1 - a0))
        spread = float(ends[0] - ends[1])
        return spread if spread <= MAX_SPREAD_DEG else float("nan")

    def spread_angles(self, fraction: float) -> dict[str, float]:
        """:meth:`plane_spread` in each main plane pair: {"C0-C180": ..., "C90-C270": ...}
        (degrees, NaN where not defined)."""
        return {name: self.plane_spread(fraction, c) for name, c in MAIN_PLANES.items()}

    @property
    def beam_angles(self) -> dict[str, float]:
        """Beam angle (degrees, full angle to 50% of the plane's own peak) per main plane."""
        return self.spread_angles(BEAM_FRACTION)

    @property
    def field_angles(self) -> dict[str, float]:
        """Field angle (degrees, full angle to 10% of the plane's own peak) per main plane."""
        return self.spread_angles(FIELD_FRACTION)

    @property
    def beam_angle(self) -> float:
        """Beam angle (degrees): the mean of :attr:`beam_angles` over the C0-C180 and
        C90-C270 planes; NaN when it is not defined in either."""
        return float(np.mean(list(self.beam_angles.values())))

    @property
    def field_angle(self) -> float:
        """Field angle (degrees): as :attr:`beam_angle` at 10% of each plane's peak."""
        return float(np.mean(list(self.field_angles.values())))


# -------------------------------------------------------------------- angle conversion
def type_c_to_b(gamma, c):
    """Type C (gamma, C) -> Type B (H, V), degrees (see the module docstring)."""
    g, c = np.radians(gamma), np.radians(c)
    aim, up, right = np.cos(g), np.sin(g) * np.cos(c), -np.sin(g) * np.sin(c)
    H = np.degrees(np.arcsin(np.clip(right, -1.0, 1.0)))
    V = np.degrees(np.arctan2(up, aim))
    return H, V


def type_b_to_c(H, V):
    """Type B (H, V) -> Type C (gamma, C), degrees, C in [0, 360)."""
    h, v = np.radians(H), np.radians(V)
    aim, up, right = np.cos(h) * np.cos(v), np.cos(h) * np.sin(v), np.sin(h)
    gamma = np.degrees(np.arccos(np.clip(aim, -1.0, 1.0)))
    c = np.mod(np.degrees(np.arctan2(-right, up)), 360.0)
    return gamma, c


# -------------------------------------------------------------------- numerics
def _bilinear(xs, ys, table, x, y):
    """Bilinear interpolation of ``table`` (len(xs), len(ys)); 0 outside the grid."""
    inside = (x >= xs[0]) & (x <= xs[-1]) & (y >= ys[0]) & (y <= ys[-1])
    i = np.clip(np.searchsorted(xs, x, side="right") - 1, 0, xs.size - 2)
    j = np.clip(np.searchsorted(ys, y, side="right") - 1, 0, ys.size - 2)
    tx = np.clip((x - xs[i]) / (xs[i + 1] - xs[i]), 0.0, 1.0)
    ty = np.clip((y - ys[j]) / (ys[j + 1] - ys[j]), 0.0, 1.0)
    value = (
        table[i, j] * (1 - tx) * (1 - ty)
        + table[i + 1, j] * tx * (1 - ty)
        + table[i, j + 1] * (1 - tx) * ty
        + table[i + 1, j + 1] * tx * ty
    )
    return np.where(inside, value, 0.0)


def _linear_weights(x: np.ndarray, kind: str) -> np.ndarray:
    """w with sum(w f) = integral of the piecewise-linear f(x) * sin(x) (``kind`` "sin") or
    * cos(x) ("cos") over [x0, xN], exactly (x in radians, increasing).

    On a cell [a, b] of width h the hat t = (x - a) / h integrates to
    (sin b - sin a - h cos b) / h against sin and (h sin b + cos b - cos a) / h against cos;
    1 - t gets the rest of the cell's integral of the weight.
    """
    a, b = x[:-1], x[1:]
    h = b - a
    if kind == "sin":
        total = np.cos(a) - np.cos(b)
        w_hi = (np.sin(b) - np.sin(a) - h * np.cos(b)) / h
    else:
        total = np.sin(b) - np.sin(a)
        w_hi = (h * np.sin(b) + np.cos(b) - np.cos(a)) / h
    w = np.zeros_like(x)
    w[:-1] += total - w_hi
    w[1:] += w_hi
    return w
