"""The grid of a sweep: a scene, values of its ``<default>`` parameters, variants, seeds.

A :class:`Grid` is an ordered set of axes (the parameters as given, then ``variant``, then
``seed``), each a list of values that keep the type they were given (``max_depth=[2, 4]``
stays integers, so that ``da.sel(max_depth=4)`` works; the command line gives text). The
axes are the xarray coordinates of every view of a sweep (:mod:`spectrace.sweeps.results`,
:mod:`spectrace.sweeps.sheet`): an axis of several values is a dimension, an axis of one
value (a parameter, a variant or a seed alike) a scalar coordinate. A scene sees each value
as its text (``str(value)``), which also names the image's files.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from spectrace.errors import ParameterError

#: The per-image columns of ``results.csv`` (and variables of the results Dataset).
COLUMNS = ("spp", "file", "seconds", "mean_luminance")
#: Names a swept parameter cannot have: the other axes, image dimensions and columns.
RESERVED = ("variant", "seed", "y", "x", "channel", *COLUMNS)


def text(value) -> str:
    """A value as the scene's ``$name`` substitution sees it."""
    return str(value).strip()


@dataclass(frozen=True)
class Combination:
    """One image of a sweep: its parameter values (as given), variant and seed."""

    params: tuple[tuple[str, Any], ...]
    variant: str
    seed: int

    @property
    def defines(self) -> dict[str, str]:
        """The ``-D`` parameters of the scene: name -> text."""
        return {k: text(v) for k, v in self.params}

    @property
    def point(self) -> dict[str, Any]:
        """The image's coordinates on every axis of the grid."""
        return {**dict(self.params), "variant": self.variant, "seed": self.seed}

    def label(self) -> str:
        return " ".join([*(f"{k}={v}" for k, v in self.defines.items()), self.variant,
                         f"seed {self.seed}"])


@dataclass
class Outcome:
    """What became of one combination: rendered, skipped (already done) or failed."""

    combo: Combination
    file: str  # EXR path relative to the output folder
    status: str = "pending"  # "rendered", "skipped", "failed"
    image: np.ndarray | None = None  # (H, W, 3) linear sRGB float32
    spp: int | None = None
    seconds: float | None = None
    mean_luminance: float | None = None
    error: str | None = None

    @property
    def done(self) -> bool:
        return self.status in ("rendered", "skipped")


@dataclass
class Grid:
    """A sweep: scene, swept ``<default>`` values, variants, seeds, sample counts."""

    scene: Path
    params: dict[str, list]
    variants: list[str]
    seeds: list[int]
    spp: int | None = None  # None: each scene's own sample count
    spp_per_pass: int | None = None  # None: the pass loop's default for each image

    @classmethod
    def make(cls, scene, params: Mapping[str, Sequence | str | float], variants=None,
             seeds=None, spp: int | None = None, spp_per_pass: int | None = None) -> Grid:
        """Check everything that can be checked before rendering (ParameterError).

        ``params`` values may be one value or a sequence; each name must be a ``<default>``
        of the scene; ``variants`` and ``seeds`` one value or a sequence. Repeated values
        count once.
        """
        import spectrace
        from spectrace.passes import check_sample_counts, check_seed
        from spectrace.scene import read_scene_xml, scene_defaults

        scene = Path(scene)
        check_sample_counts(spp, spp_per_pass)
        defaults = scene_defaults(read_scene_xml(scene))
        axes: dict[str, list] = {}
        for name, values in params.items():
            if name not in defaults:
                known = ", ".join(defaults) or "none"
                raise ParameterError(f"scene {scene} has no <default> named {name!r} (it "
                                     f"has: {known}): the params of a sweep are <default>s")
            if name in RESERVED:
                raise ParameterError(f"<default> {name!r} of scene {scene} cannot be swept "
                                     f"(a sweep uses the names {', '.join(RESERVED)})")
            axes[name] = _values(name, values)
        variants = [str(v) for v in _values("variants", variants, spectrace.DEFAULT_VARIANT)]
        for variant in variants:
            spectrace.check_variant(variant)
        seeds = [check_seed(s, "seeds") for s in _values("seeds", seeds, 0)]
        return cls(scene, axes, variants, list(dict.fromkeys(seeds)), spp, spp_per_pass)

    @property
    def axes(self) -> dict[str, list]:
        """Every axis in product order: the parameters, then variant, then seed."""
        return {**self.params, "variant": self.variants, "seed": self.seeds}

    @property
    def dims(self) -> list[str]:
        """The axes of more than one value (the DataArray's leading dimensions)."""
        return [name for name, values in self.axes.items() if len(values) > 1]

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(self.axes[d]) for d in self.dims)

    def coords(self) -> dict[str, Any]:
        """xarray coordinates: a list per dimension, a scalar per axis of one value."""
        return {name: values if len(values) > 1 else values[0]
                for name, values in self.axes.items()}

    def combinations(self) -> list[Combination]:
        """The Cartesian product in grid order (C order of :attr:`shape`): first parameter
        slowest, then variant, then seed."""
        names = list(self.params)
        return [Combination(tuple(zip(names, vals, strict=True)), variant, seed)
                for *vals, variant, seed in itertools.product(*self.axes.values())]

    def array(self, items: Sequence, dtype=object) -> np.ndarray:
        """``items`` (one per combination, in grid order) as an array of :attr:`shape`."""
        out = np.empty(len(items), dtype)
        for i, item in enumerate(items):  # item by item: numpy would unpack arrays
            out[i] = item
        return out.reshape(self.shape)


def _values(name: str, values, default=None) -> list:
    """One value or a sequence as a list of distinct values (by their text); a sequence
    that is empty, or a value whose text is empty, is a ParameterError."""
    if values is None and default is not None:
        values = default
    if isinstance(values, str | bytes | int | float | np.generic) or values is None:
        values = [values]
    values = list(values)
    if not values or any(v is None or text(v) == "" for v in values):
        raise ParameterError(f"{name}: no values (give one value or a list)")
    seen: dict[str, Any] = {}
    for v in values:
        seen.setdefault(text(v), v.item() if isinstance(v, np.generic) else v)
    return list(seen.values())
