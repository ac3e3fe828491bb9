"""The :class:`Photometry` record: a luminaire's intensity table and what follows from it.

Angles are in degrees and intensities in candela throughout.

Type C (the C-gamma system of LM-63 and EULUMDAT): gamma is the angle from the photometric
zero (nadir, the direction the light points), C the azimuth of the half-plane around the
gamma = 0 axis, C = 0 along the luminaire's local +X, C growing counterclockwise seen from
above the luminaire (from the side opposite to nadir), so C = 90 is local -Y.

Type B (floodlights, LM-63 photometric type 2): the polar axis is horizontal, through the
luminaire and perpendicular to its aiming axis. The vertical angle V is the tilt of a
B-plane about that polar axis; the horizontal angle H is measured inside the B-plane from
the plane's aiming line towards the polar axis (-90 <= H <= 90). (H, V) = (0, 0) is the
aiming axis. A direction is ``cos H cos V * aim + cos H sin V * up + sin H * side``, and
in the Type C frame we put ``aim`` at gamma = 0 (local +Z of ``ieslight``), ``up`` (V > 0)
at C = 0 (local +X) and ``side`` (H > 0) at C = 90 (local -Y):

* B -> C: ``cos gamma = cos H cos V``, ``C = atan2(sin H, cos H sin V)``;
* C -> B: ``sin H = sin gamma sin C``, ``tan V = sin gamma cos C / cos gamma``

(the relations tan B = cos C tan gamma, sin beta = sin C sin gamma used by EULUMDAT
converters, with B = V and beta = H). So H = V = 0 is gamma = 0; (H, V) = (0, 30) is
(gamma, C) = (30, 0); (H, V) = (30, 0) is (30, 90).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

#: The angular width (degrees) of the step from the last measured intensity to zero in
#: :meth:`Photometry.type_c_grid` (outside the measured gamma range the intensity is 0).
GRID_EDGE_STEP_DEG = 1e-3
#: The regular grid step (degrees) of :meth:`Photometry.type_c_grid` for Type B files.
TYPE_B_GRID_STEP_DEG = 1.0
#: Sampling of a plane (degrees) when locating the beam and field angles.
SPREAD_STEP_DEG = 0.05

SYMMETRIES = ("rotational", "quadrant", "bilateral_0_180", "bilateral_90_270", "none")


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
    symmetric, I(H, V) = I(-H, V): a mirror about the C0-C180 plane, "bilateral_0_180".
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
    #: luminous opening (width, length, height) in metres, as LM-63 defines their signs
    opening_m: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self):
        self.path = Path(self.path)
        self.vertical_angles = np.asarray(self.vertical_angles, dtype=np.float64)
        self.horizontal_angles = np.asarray(self.horizontal_angles, dtype=np.float64)
        self.candela = np.asarray(self.candela, dtype=np.float64).reshape(
            self.horizontal_angles.size, self.vertical_angles.size
        )
        if self.photometric_type not in ("C", "B"):
            raise ValueError(f"photometric_type must be 'C' or 'B' (got {self.photometric_type!r})")
        if self.symmetry not in SYMMETRIES:
            raise ValueError(f"symmetry must be one of {SYMMETRIES} (got {self.symmetry!r})")

    def replace(self, **changes) -> Photometry:
        """A copy with some fields changed (e.g. ``candela`` scaled)."""
        return dataclasses.replace(self, **changes)

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
        if self.symmetry == "bilateral_0_180":
            H = np.abs(H)
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
            raise ValueError(f"type_c_grid: step must be > 0 (got {step})")
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
            wc = _trapezoid_weights(np.radians(cgrid))
            wg = _linear_weights(np.radians(self.vertical_angles), "sin")
            return float(wc @ table @ wg)
        wh = _linear_weights(np.radians(self.horizontal_angles), "cos")
        wv = _trapezoid_weights(np.radians(self.vertical_angles))
        total = float(wh @ self.candela @ wv)
        if self.symmetry == "bilateral_0_180":  # H from 0: the mirrored half H < 0
            total *= 2.0
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
        wc = _trapezoid_weights(np.radians(cgrid))
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
        through nadir and zenith). NaN if the plane is dark or never falls that far."""
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
        return spread if spread <= 360.0 else float("nan")

    @property
    def beam_angle(self) -> float:
        """Beam angle (degrees): full angle to 50% of the peak (CIE/IES), the mean of the
        C0-C180 and C90-C270 planes (each plane relative to its own peak)."""
        return 0.5 * (self.plane_spread(0.5, 0.0) + self.plane_spread(0.5, 90.0))

    @property
    def field_angle(self) -> float:
        """Field angle (degrees): as :attr:`beam_angle` at 10% of the peak."""
        return 0.5 * (self.plane_spread(0.1, 0.0) + self.plane_spread(0.1, 90.0))


# -------------------------------------------------------------------- angle conversion
def type_c_to_b(gamma, c):
    """Type C (gamma, C) -> Type B (H, V), degrees (see the module docstring)."""
    g, c = np.radians(gamma), np.radians(c)
    aim, up, side = np.cos(g), np.sin(g) * np.cos(c), np.sin(g) * np.sin(c)
    H = np.degrees(np.arcsin(np.clip(side, -1.0, 1.0)))
    V = np.degrees(np.arctan2(up, aim))
    return H, V


def type_b_to_c(H, V):
    """Type B (H, V) -> Type C (gamma, C), degrees, C in [0, 360)."""
    h, v = np.radians(H), np.radians(V)
    aim, up, side = np.cos(h) * np.cos(v), np.cos(h) * np.sin(v), np.sin(h)
    gamma = np.degrees(np.arccos(np.clip(aim, -1.0, 1.0)))
    c = np.mod(np.degrees(np.arctan2(side, up)), 360.0)
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


def _trapezoid_weights(x: np.ndarray) -> np.ndarray:
    """w with sum(w f) = integral of the piecewise-linear f over [x0, xN]."""
    w = np.zeros_like(x)
    h = np.diff(x)
    w[:-1] += h / 2
    w[1:] += h / 2
    return w


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
