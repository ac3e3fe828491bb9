"""Calculation grids of EN 12464-1 on a horizontal plane: ``spectrace lux --grid``.

A grid is given in plan coordinates, ``"x0,y0 x1,y1 @ h"`` (metres): the rectangle of the
room (or task area) between the corners (x0, y0) and (x1, y1), on the horizontal plane at
height h. The plan is the view from above of a scene whose up axis is +Y (DESIGN.md), north
-Z and east +X: plan x is the scene's X (east), plan y is the scene's -Z (north), the height
is the scene's Y, so a plan point (x, y) at height h is the scene point (x, h, -y) and the
plan is drawn with x to the right and y up, as seen from above. A scene may name its grids:
``<default name="workplane" value="0,0 6,4 @ 0.8"/>``, and ``parse_grid("workplane",
scene_defaults(tree))`` reads it (``spectrace lux SCENE --grid workplane``).

Points (:func:`make_grid`): a band of ``border`` metres (0.5 m by default) is excluded at
each side of the rectangle, as EN 12464-1 allows for a room's walls ("a band of 0.5 m
from the walls is excluded from the calculation area, except when a task area is in or
extends into this border area"; give ``border`` 0 for a task area). The largest grid
spacing of EN 12464-1 is::

    p = 0.2 x 5^log10(d)   (m, at most 10 m)

with d the longer side of the calculation area (m); the longer side gets n = ceil(d / p)
points (so that the spacing d / n never exceeds p) and the shorter side the number that
keeps the cells nearest to square, ceil(d_short / (d / n)); the points are the centres of
the n x m equal cells. A ``spacing`` given instead replaces p. Source: EN 12464-1:2011,
4.4 (illuminance grid), kept in EN 12464-1:2021.

Results (:class:`GridResult`): maintained illuminance E = MF x E_new per point (MF the
maintenance factor, 0 < MF <= 1), E_m (mean), E_min, E_max, U0 = E_min / E_m and
E_min / E_max; :data:`TASKS` holds the requirements of a few common tasks (E_m, U0,
UGR_L) of EN 12464-1:2021, and :func:`GridResult.check` compares. :func:`plot_plan`
draws the plan view: false colour in lux with metre axes, the room outline (the scene's
bounds), the grid's rectangle, iso-lux lines and the points.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

from spectrace.errors import ParameterError

__all__ = ["GRID_FORMAT", "Grid", "GridResult", "TASKS", "Task", "grid_spacing",
           "grid_name", "make_grid", "parse_grid", "plan_to_scene", "plot_plan", "check_in_scene"]

#: How a grid is written.
GRID_FORMAT = "'x0,y0 x1,y1 @ h' (plan corners and height in metres, e.g. '0,0 6,4 @ 0.8')"
#: The band excluded at the walls (m), EN 12464-1.
BORDER = 0.5
#: EN 12464-1's largest spacing is at most this (m).
MAX_SPACING = 10.0
#: Slack (m) when checking that a grid lies inside the scene's bounds.
BOUNDS_SLACK = 1e-6


@dataclass(frozen=True)
class Task:
    """Requirements of a task of EN 12464-1:2021: maintained illuminance E_m (lx), its
    uniformity U0 and the unified glare rating limit UGR_L."""

    name: str
    description: str
    E_m: float
    U0: float
    UGR_L: float


#: A few common tasks of EN 12464-1:2021's schedule of lighting requirements (offices;
#: circulation areas), with the requirements E_m, U0 and UGR_L of the standard.
TASKS = {t.name: t for t in (
    Task("office", "offices: writing, typing, reading, data processing", 500.0, 0.60, 19.0),
    Task("technical_drawing", "offices: technical drawing", 750.0, 0.70, 16.0),
    Task("cad", "offices: CAD work stations", 500.0, 0.60, 19.0),
    Task("conference", "offices: conference and meeting rooms", 500.0, 0.60, 19.0),
    Task("reception", "offices: reception desk", 300.0, 0.60, 22.0),
    Task("filing", "offices: filing, copying", 300.0, 0.40, 19.0),
    Task("archive", "offices: archives", 200.0, 0.40, 25.0),
    Task("corridor", "circulation areas: corridors", 100.0, 0.40, 28.0),
)}


def grid_spacing(d: float) -> float:
    """EN 12464-1's largest grid spacing p = 0.2 x 5^log10(d) (m) for the longer side d
    (m), at most MAX_SPACING."""
    return min(MAX_SPACING, 0.2 * 5.0 ** math.log10(d))


@dataclass
class Grid:
    """A calculation grid: the given rectangle (plan m), its height, the excluded border,
    the spacing and the plan coordinates of the points' columns ``xs`` and rows ``ys``."""

    rectangle: tuple[float, float, float, float]  # x0, y0, x1, y1 with x0 < x1, y0 < y1
    height: float
    border: float
    spacing: float  # the largest spacing asked (EN 12464-1's p, or the one given)
    xs: np.ndarray
    ys: np.ndarray

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, columns) = (len(ys), len(xs))."""
        return len(self.ys), len(self.xs)

    def plan_points(self) -> np.ndarray:
        """(rows x columns, 2) plan (x, y) of the points, row by row (y, then x)."""
        x, y = np.meshgrid(self.xs, self.ys)
        return np.column_stack([x.ravel(), y.ravel()])

    def points(self) -> np.ndarray:
        """(N, 3) scene points of the grid (see :func:`plan_to_scene`)."""
        return plan_to_scene(self.plan_points(), self.height)

    def describe(self) -> str:
        rows, cols = self.shape
        dx = self.xs[1] - self.xs[0] if cols > 1 else float("nan")
        dy = self.ys[1] - self.ys[0] if rows > 1 else float("nan")
        x0, y0, x1, y1 = self.rectangle
        return (f"grid {x0:g},{y0:g} {x1:g},{y1:g} @ {self.height:g} m: {cols} x {rows} "
                f"points, spacing {dx:.3g} x {dy:.3g} m (p = {self.spacing:.3g} m), "
                f"border {self.border:g} m")


def plan_to_scene(plan: np.ndarray, height: float) -> np.ndarray:
    """Plan (x, y) at ``height`` -> scene (X, Y, Z) = (x, height, -y)."""
    plan = np.asarray(plan, dtype=np.float64).reshape(-1, 2)
    return np.column_stack([plan[:, 0], np.full(len(plan), float(height)), -plan[:, 1]])


_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_GRID = re.compile(rf"^\s*({_NUMBER})\s*,\s*({_NUMBER})\s+({_NUMBER})\s*,\s*({_NUMBER})"
                   rf"\s*@\s*({_NUMBER})\s*$")
#: A grid given by the name of a scene parameter (``<default>``) that holds it.
_NAME = re.compile(r"^\s*([A-Za-z_]\w*)\s*$")


def parse_grid(text: str, defaults: dict[str, str] | None = None
               ) -> tuple[tuple[float, float, float, float], float]:
    """``"x0,y0 x1,y1 @ h"`` -> ((x0, y0, x1, y1) sorted, h); or ``text`` is a name, and
    ``defaults`` (the scene's parameters, name -> value: its ``<default>``s, see
    :func:`spectrace.scene.scene_defaults`) holds the grid under it, as in
    ``<default name="workplane" value="0,0 6,4 @ 0.8"/>``. ParameterError when malformed,
    when the rectangle has no area or when no parameter has the name."""
    key = grid_name(text)
    if key is not None:
        values = defaults or {}
        if key not in values:
            grids = [k for k, v in values.items() if _GRID.match(str(v))]
            have = (f"its grids: {', '.join(grids)}" if grids else
                    "none of its <default>s holds a grid")
            raise ParameterError(f"grid {key!r}: the scene has no <default name={key!r}> "
                                 f"({have})")
        try:
            return _parse_rectangle(values[key])
        except ParameterError as e:
            raise ParameterError(f"<default name={key!r}>: {e}") from None
    return _parse_rectangle(text)


def grid_name(text: str) -> str | None:
    """The scene parameter's name when ``text`` names a grid rather than writing it out."""
    match = _NAME.match(str(text))
    return None if match is None else match.group(1)


def _parse_rectangle(text: str) -> tuple[tuple[float, float, float, float], float]:
    match = _GRID.match(str(text))
    if match is None:
        raise ParameterError(f"grid {text!r}: expected {GRID_FORMAT}")
    x0, y0, x1, y1, h = (float(v) for v in match.groups())
    if not all(math.isfinite(v) for v in (x0, y0, x1, y1, h)):
        raise ParameterError(f"grid {text!r}: the numbers must be finite")
    if x0 == x1 or y0 == y1:
        raise ParameterError(f"grid {text!r}: the rectangle has no area (x0 = x1 or y0 = y1)")
    return (min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1)), h


def make_grid(rectangle, height: float, border: float = BORDER,
              spacing: float | None = None) -> Grid:
    """The grid of points over ``rectangle`` (x0, y0, x1, y1) at ``height`` (see the
    module docstring). ParameterError for a negative border, a border that leaves no
    area, or a spacing that is not positive."""
    x0, y0, x1, y1 = (float(v) for v in rectangle)
    if not (math.isfinite(border) and border >= 0.0):
        raise ParameterError(f"border must be >= 0 m (got {border!r})")
    if spacing is not None and not (math.isfinite(spacing) and spacing > 0.0):
        raise ParameterError(f"spacing must be > 0 m (got {spacing!r})")
    ax0, ay0, ax1, ay1 = x0 + border, y0 + border, x1 - border, y1 - border
    if not (ax1 > ax0 and ay1 > ay0):
        raise ParameterError(f"border {border:g} m leaves no calculation area in the "
                             f"{x1 - x0:g} x {y1 - y0:g} m rectangle")
    w, h = ax1 - ax0, ay1 - ay0
    d, short = max(w, h), min(w, h)
    p = grid_spacing(d) if spacing is None else float(spacing)
    n_long = max(1, math.ceil(d / p - 1e-9))
    n_short = max(1, math.ceil(short / (d / n_long) - 1e-9))
    nx, ny = (n_long, n_short) if w >= h else (n_short, n_long)
    xs = ax0 + (np.arange(nx) + 0.5) * (w / nx)
    ys = ay0 + (np.arange(ny) + 0.5) * (h / ny)
    return Grid((x0, y0, x1, y1), float(height), float(border), p, xs, ys)


def scene_bounds(scene) -> tuple[np.ndarray, np.ndarray] | None:
    """(min, max) of the scene's shapes' bounding box, or None when it has no shape."""
    box = scene.bbox()
    if not box.valid():
        return None
    return (np.array([box.min.x, box.min.y, box.min.z], dtype=np.float64),
            np.array([box.max.x, box.max.y, box.max.z], dtype=np.float64))


def check_in_scene(grid: Grid, scene) -> None:
    """ParameterError unless the grid's points lie inside the scene's bounding box."""
    bounds = scene_bounds(scene)
    if bounds is None:
        raise ParameterError("grid: the scene has no shapes, so no room to put a grid in")
    low, high = bounds
    p = grid.points()
    inside = np.all((p >= low - BOUNDS_SLACK) & (p <= high + BOUNDS_SLACK), axis=1)
    if not inside.all():
        x0, y0, x1, y1 = grid.rectangle
        room = (f"x {low[0]:g} to {high[0]:g}, y {-high[2]:g} to {-low[2]:g}, "
                f"height {low[1]:g} to {high[1]:g} m")
        raise ParameterError(f"grid {x0:g},{y0:g} {x1:g},{y1:g} @ {grid.height:g}: "
                             f"{int((~inside).sum())} of {len(p)} points lie outside the "
                             f"scene (its bounds in plan: {room})")


def check_maintenance_factor(mf: float) -> float:
    """``mf`` when 0 < mf <= 1, else ParameterError."""
    if not (isinstance(mf, (int, float)) and math.isfinite(mf) and 0.0 < mf <= 1.0):
        raise ParameterError(f"maintenance factor must be > 0 and <= 1 (got {mf!r})")
    return float(mf)


def task(name: str) -> Task:
    """The task ``name`` of :data:`TASKS`; ParameterError listing them otherwise."""
    if name not in TASKS:
        raise ParameterError(f"task {name!r}: expected one of {', '.join(TASKS)}")
    return TASKS[name]


@dataclass
class GridResult:
    """Maintained illuminance at a grid's points and its statistics."""

    grid: Grid
    lux: np.ndarray  # (rows, columns), maintained (MF applied)
    stderr: np.ndarray  # (rows, columns)
    maintenance_factor: float = 1.0
    samples: int = 1
    stats: dict = field(init=False)

    def __post_init__(self):
        values = self.lux.ravel().astype(np.float64)
        mean, low, high = float(values.mean()), float(values.min()), float(values.max())
        self.stats = {"E_m": mean, "E_min": low, "E_max": high,
                      "U0": low / mean if mean > 0.0 else float("nan"),
                      "E_min/E_max": low / high if high > 0.0 else float("nan")}

    def summary(self) -> str:
        s = self.stats
        return (f"Em {s['E_m']:.4g} lx, Emin {s['E_min']:.4g} lx, Emax {s['E_max']:.4g} lx, "
                f"U0 = Emin/Em {s['U0']:.3f}, Emin/Emax {s['E_min/E_max']:.3f} "
                f"(MF {self.maintenance_factor:g})")

    def check(self, required: Task) -> dict[str, bool]:
        """Pass (True) or fail per requirement: E_m >= the task's E_m, U0 >= its U0."""
        return {"E_m": self.stats["E_m"] >= required.E_m, "U0": self.stats["U0"] >= required.U0}

    def scene_points(self) -> np.ndarray:
        return self.grid.points()


def measure_grid(scene, grid: Grid, *, maintenance_factor: float = 1.0, spp: int = 64,
                 seed: int = 0, max_depth: int = 1, kind: str = "planar") -> GridResult:
    """Maintained illuminance at the grid's points (horizontal illuminance for ``planar``,
    or another kind of :mod:`~spectrace.lighting.points`), measured at the points."""
    from spectrace.lighting.points import measure_points

    check_in_scene(grid, scene)
    mf = check_maintenance_factor(maintenance_factor)
    points = grid.points()
    up = np.tile([0.0, 1.0, 0.0], (len(points), 1))
    lux, stderr, samples = measure_points(scene, points, up, kind=kind, spp=spp, seed=seed,
                                          max_depth=max_depth)
    shape = grid.shape
    return GridResult(grid, (mf * lux).reshape(shape), (mf * stderr).reshape(shape), mf,
                      samples)


def write_grid_csv(path, result: GridResult) -> None:
    """``x,y,z,lux,stderr`` per point (scene coordinates, maintained lux); atomic."""
    from spectrace.lighting.points import write_csv

    data = np.column_stack([result.scene_points(), result.lux.ravel(), result.stderr.ravel()])
    write_csv(path, ("x", "y", "z", "lux", "stderr"), data)


def plot_plan(path, result: GridResult, room=None, title: str | None = None,
              lights=None) -> None:
    """The plan-view figure (PNG): false colour in lux over the grid's cells with metre
    axes, iso-lux lines, the points, the grid's rectangle (dashed), the room outline
    ``room`` = (x0, y0, x1, y1) in plan metres (the scene's bounds) and the ``lights``'
    plan positions (K, 2) as stars; atomic."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    from spectrace.images import atomic_path
    from spectrace.lux import COLOUR_MAP, contour_levels

    grid = result.grid
    rows, cols = grid.shape
    x0, y0, x1, y1 = grid.rectangle
    extent = room if room is not None else grid.rectangle
    span_x, span_y = extent[2] - extent[0], extent[3] - extent[1]
    fig = Figure(figsize=(7.0, max(3.0, 6.0 * span_y / max(span_x, 1e-9))), dpi=120)
    ax = fig.add_subplot()
    ax.set_aspect("equal")
    dx = grid.xs[1] - grid.xs[0] if cols > 1 else x1 - x0 - 2 * grid.border
    dy = grid.ys[1] - grid.ys[0] if rows > 1 else y1 - y0 - 2 * grid.border
    edges_x = np.concatenate([grid.xs - dx / 2, [grid.xs[-1] + dx / 2]])
    edges_y = np.concatenate([grid.ys - dy / 2, [grid.ys[-1] + dy / 2]])
    high = float(result.lux.max()) if result.lux.max() > 0 else 1.0
    mesh = ax.pcolormesh(edges_x, edges_y, result.lux, cmap=COLOUR_MAP, vmin=0.0, vmax=high,
                         shading="flat")
    bar = fig.colorbar(mesh, ax=ax)
    bar.set_label("maintained illuminance E (lx)")
    levels = contour_levels(float(result.lux.min()), high)
    if rows > 1 and cols > 1 and levels.size:
        lines = ax.contour(grid.xs, grid.ys, result.lux, levels=levels, colors="white",
                           linewidths=0.8)
        ax.clabel(lines, fmt=lambda v: f"{v:g}", fontsize=7)
        bar.add_lines(lines)
    px, py = np.meshgrid(grid.xs, grid.ys)
    ax.plot(px.ravel(), py.ravel(), "k.", markersize=2)
    ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, linestyle="--",
                           edgecolor="0.3", linewidth=0.8))
    if room is not None:
        ax.add_patch(Rectangle((room[0], room[1]), room[2] - room[0], room[3] - room[1],
                               fill=False, edgecolor="black", linewidth=1.5))
    if lights is not None and len(lights):
        lights = np.asarray(lights, dtype=np.float64).reshape(-1, 2)
        ax.plot(lights[:, 0], lights[:, 1], "*", color="orange", markeredgecolor="black",
                markersize=10, label="lights")
    margin = 0.03 * max(span_x, span_y)
    ax.set_xlim(extent[0] - margin, extent[2] + margin)
    ax.set_ylim(extent[1] - margin, extent[3] + margin)
    ax.set_xlabel("x (m, east = scene +X)")
    ax.set_ylabel("y (m, north = scene -Z)")
    ax.set_title(title if title is not None else result.summary(), fontsize=8)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")


def room_outline(scene) -> tuple[float, float, float, float] | None:
    """The plan rectangle (x0, y0, x1, y1) of the scene's bounds (the room), or None."""
    bounds = scene_bounds(scene)
    if bounds is None:
        return None
    low, high = bounds
    return float(low[0]), float(-high[2]), float(high[0]), float(-low[2])


def light_positions(scene) -> np.ndarray:
    """Plan (x, y) of the scene's lights at a point (delta-position lights), (K, 2)."""
    import mitsuba as mi

    found = []
    for emitter in scene.emitters():
        if mi.has_flag(emitter.flags(), mi.EmitterFlags.DeltaPosition):
            ps, _ = emitter.sample_position(0.0, mi.Point2f(0.5))
            p = np.asarray(ps.p, dtype=np.float64).ravel()
            found.append((p[0], -p[2]))
    return np.asarray(found, dtype=np.float64).reshape(-1, 2)
