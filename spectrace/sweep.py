"""Parameter sweeps: the Cartesian product of a scene's ``<default>`` values, on Dask.

A :class:`Grid` is a scene, the values of some of its ``<default>`` parameters (``-D
name=v1,v2``), variants, seeds and a sample count; its :meth:`Grid.combinations` are the
product in the order: parameters as given (the first varies slowest), then variant, then
seed. Each combination is rendered on a worker by :func:`spectrace.cluster.render_image`,
the pass loop of ``spectrace render``, so an image equals ``spectrace render SCENE -D ...``
of its combination with the same seed (up to the order of the film's float additions).

:func:`run` renders a grid into a folder: one EXR + PNG per combination (named after its
values), ``results.csv`` (a row per image) and ``sheet.png`` (a contact sheet). Images
travel back to the client, which writes every file atomically. A re-run skips every image
whose EXR (and PNG) are there with the same combination in the EXR header, without touching
them. A combination that fails for a user reason (a bad value) is reported in its
:class:`Outcome` while the others finish.

The module is callable: ``spectrace.sweep(scene, params={...})`` is :func:`sweep`, which
returns an ``xarray.DataArray`` for notebooks.
"""

from __future__ import annotations

import csv
import io
import itertools
import json
import re
import sys
import types
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from spectrace.errors import ParameterError, SpectraceError, first_line
from spectrace.passes import check_seed

RESULTS = "results.csv"
SHEET = "sheet.png"
#: Size in pixels of an image's cell in the contact sheet (larger images are shrunk).
SHEET_CELL = 160
_PAD = 4
#: Longest file name stem (characters, all ASCII) of an image; longer ones are shortened
#: with a hash of the combination (".spectral.exr" and temporary prefixes must still fit).
MAX_STEM = 200
_UNSAFE = re.compile(r"[^A-Za-z0-9._+-]+")


def parse_sweep_defines(defines: Iterable[str]) -> dict[str, list[str]]:
    """``["name=v1,v2", ...]`` (``-D`` options) -> ``{name: [v1, v2]}``, in order.

    ParameterError for an item without ``=``, an empty name or no values (``-D name=``).
    A name given twice collects the values of both. ``\\,`` is a comma inside a value
    (``-D color=0.2\\,0.5\\,0.9,1\\,1\\,1``: two RGB values).
    """
    params: dict[str, list[str]] = {}
    for item in defines or []:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise ParameterError(f"-D {item!r}: expected name=v1,v2,...")
        values = [v.strip() for v in split_values(text) if v.strip()]
        if not values:
            raise ParameterError(f"-D {name}=: no values (give name=v1,v2,...)")
        params.setdefault(name, []).extend(v for v in values if v not in params.get(name, []))
    return params


def split_values(text: str) -> list[str]:
    """``text`` split at its commas, except those escaped as ``\\,`` (kept as commas)."""
    return [v.replace("\0", ",") for v in text.replace("\\,", "\0").split(",")]


def parse_list(text: str | None, option: str, kind=str) -> list | None:
    """A comma-separated option (``--seeds 0,1``) as a list of ``kind``; None if not given."""
    if text is None:
        return None
    items = [t.strip() for t in text.split(",") if t.strip()]
    if not items:
        raise ParameterError(f"{option}: no values")
    try:
        return [kind(t) for t in items]
    except ValueError:
        raise ParameterError(f"{option} {text!r}: expected {kind.__name__} values separated by "
                        "commas") from None


@dataclass(frozen=True)
class Combination:
    """One image of a sweep: its parameter values, variant and seed."""

    values: tuple[tuple[str, str], ...]
    variant: str
    seed: int

    @property
    def defines(self) -> dict[str, str]:
        return dict(self.values)

    def stem(self) -> str:
        """File name (no suffix): ``name-value_..._variant_seedS``, safe characters only."""
        parts = [f"{k}-{_safe(v)}" for k, v in self.values]
        stem = "_".join([*parts, self.variant, f"seed{self.seed}"])
        if len(stem) > MAX_STEM:  # file names have at most 255 bytes; keep it unique
            import hashlib

            digest = hashlib.sha1(self.header().encode()).hexdigest()[:10]
            tail = f"~{digest}_{self.variant}_seed{self.seed}"
            stem = stem[: MAX_STEM - len(tail)].rstrip("_") + tail
        return stem

    def label(self) -> str:
        return " ".join([*(f"{k}={v}" for k, v in self.values), self.variant,
                         f"seed {self.seed}"])

    def header(self) -> str:
        """The combination as stored in the EXR header (for resuming)."""
        return json.dumps({"params": dict(self.values), "variant": self.variant,
                           "seed": self.seed}, sort_keys=True)


def _safe(value: str) -> str:
    safe = _UNSAFE.sub("_", value).strip("_") or "_"
    if safe != value:  # keep distinct values distinct
        import hashlib

        safe += "~" + hashlib.sha1(value.encode()).hexdigest()[:6]
    return safe


@dataclass
class Grid:
    """A sweep: scene, swept ``<default>`` values, variants, seeds, sample counts."""

    scene: Path
    params: dict[str, list[str]]
    variants: list[str] = field(default_factory=lambda: ["llvm_ad_spectral"])
    seeds: list[int] = field(default_factory=lambda: [0])
    spp: int | None = None  # None: each scene's own sample count
    spp_per_pass: int | None = None  # None: the pass loop's default for each image

    @classmethod
    def make(cls, scene, params: Mapping[str, Sequence | str | float], variants=None,
             seeds=None, spp: int | None = None, spp_per_pass: int | None = None) -> Grid:
        """Check everything that can be checked before rendering (ParameterError otherwise).

        ``params`` values may be one value or a sequence; each name must be a ``<default>``
        of the scene; ``variants`` and ``seeds`` one value or a sequence.
        """
        import spectrace
        from spectrace.passes import check_sample_counts
        from spectrace.scene import read_scene_xml, scene_defaults

        scene = Path(scene)
        check_sample_counts(spp, spp_per_pass)
        root = read_scene_xml(scene)
        defaults = scene_defaults(root)
        grid_params: dict[str, list[str]] = {}
        for name, values in params.items():
            if name not in defaults:
                known = ", ".join(defaults) or "none"
                raise ParameterError(
                    f"-D {name}: not a <default> of scene {scene} (it has: {known})")
            values = [values] if isinstance(values, str | int | float) else list(values)
            values = [_format(v) for v in values]
            if not values or any(v == "" for v in values):
                raise ParameterError(f"-D {name}=: no values (give name=v1,v2,...)")
            grid_params[name] = list(dict.fromkeys(values))
        variants = _as_list(variants, spectrace.DEFAULT_VARIANT)
        _check_variants(variants)
        seeds = [int(s) for s in _as_list(seeds, 0)]
        for seed in seeds:
            check_seed(seed, "--seeds")
        return cls(scene, grid_params, list(dict.fromkeys(variants)),
                   list(dict.fromkeys(seeds)), spp, spp_per_pass)

    @property
    def dims(self) -> list[str]:
        """The grid's dimensions: the parameters, then variant and seed when several."""
        dims = list(self.params)
        if len(self.variants) > 1:
            dims.append("variant")
        if len(self.seeds) > 1:
            dims.append("seed")
        return dims

    def coords(self) -> dict[str, list]:
        coords: dict[str, list] = dict(self.params)
        if len(self.variants) > 1:
            coords["variant"] = self.variants
        if len(self.seeds) > 1:
            coords["seed"] = self.seeds
        return coords

    def combinations(self) -> list[Combination]:
        """The Cartesian product, first parameter slowest, then variant, then seed."""
        names = list(self.params)
        out = []
        for values in itertools.product(*self.params.values(), self.variants, self.seeds):
            *vals, variant, seed = values
            out.append(Combination(tuple(zip(names, vals, strict=True)), variant, seed))
        return out

    def index(self, combo: Combination) -> tuple[int, ...]:
        """The combination's position along :attr:`dims`."""
        idx = [self.params[k].index(v) for k, v in combo.values]
        if len(self.variants) > 1:
            idx.append(self.variants.index(combo.variant))
        if len(self.seeds) > 1:
            idx.append(self.seeds.index(combo.seed))
        return tuple(idx)

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(v) for v in self.coords().values())


def _format(value) -> str:
    return str(value).strip()


def _as_list(value, default) -> list:
    if value is None:
        return [default]
    if isinstance(value, str | int):
        return [value]
    return list(value)


def _check_variants(variants: list[str]) -> None:
    from spectrace.llvm import configure_libllvm

    if "mitsuba" not in sys.modules:
        try:
            configure_libllvm()
        except SpectraceError:
            pass
    import mitsuba as mi

    for v in variants:
        if v not in mi.variants():
            raise ParameterError(f"unknown variant {v!r}; available: {', '.join(mi.variants())}")


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


def mean_luminance(rgb: np.ndarray) -> float:
    """Mean of Y = 0.2126 R + 0.7152 G + 0.0722 B over the image (linear sRGB)."""
    from spectrace.comparison import LUMINANCE_WEIGHTS

    return float(np.mean(np.asarray(rgb[..., :3], np.float64) @ LUMINANCE_WEIGHTS))


def _finished(outdir: Path, grid: Grid, outcome: Outcome) -> bool:
    """Whether an earlier run left this combination's image (same combination, same spp)."""
    from spectrace.images import read_exr

    exr = outdir / outcome.file
    if not (exr.is_file() and exr.with_suffix(".png").is_file()):
        return False
    try:
        rgb, header = read_exr(exr)
    except SpectraceError:
        return False
    if header.get("sweep") != outcome.combo.header():
        return False
    if grid.spp is not None and header.get("spp") != grid.spp:
        return False
    outcome.image, outcome.spp = rgb, int(header.get("spp", 0))
    outcome.seconds = float(header.get("seconds", float("nan")))
    outcome.mean_luminance = mean_luminance(rgb)
    outcome.status = "skipped"
    return True


def check_outdir(outdir, create: bool = True) -> Path:
    """SpectraceError when the output folder, or a folder above it, is a file, or when nothing
    can be written there; ``create``: make the folder (else only check, making nothing)."""
    import os

    from spectrace.images import check_writable

    outdir = Path(outdir)
    for folder in (outdir, *outdir.parents):
        if folder.exists() and not folder.is_dir():
            what = "is" if folder == outdir else f"is inside {folder}, which is"
            raise ParameterError(f"output folder {outdir} {what} a file, not a folder")
        if folder.is_dir():  # the nearest folder that exists
            if not os.access(folder, os.W_OK | os.X_OK):
                raise ParameterError(f"cannot write output folder {outdir}: {folder} is not "
                                "writable")
            break
    if create:
        check_writable(outdir / RESULTS)
    return outdir


def plan(grid: Grid, outdir) -> list[Outcome]:
    """The outcomes of ``grid`` in grid order, those an earlier run finished ``skipped``."""
    outdir = Path(outdir)
    outcomes = [Outcome(c, c.stem() + ".exr") for c in grid.combinations()]
    for o in outcomes:
        _finished(outdir, grid, o)
    return outcomes


def run(grid: Grid, client, outdir, *, on_image: Callable[[Outcome], None] | None = None,
        keep_images: bool = True, outcomes: list[Outcome] | None = None) -> list[Outcome]:
    """Render ``grid`` on ``client``'s workers into ``outdir``; outcomes in grid order.

    Skips finished images (``outcomes``: a :func:`plan` already made; ``client`` may be None
    when it has nothing left to render); writes each new EXR + PNG as it arrives, and
    ``results.csv`` and ``sheet.png`` at the end (after a crash, a re-run rebuilds them from
    the EXR headers). ``on_image(outcome)``
    is called for each image (skipped ones first). A KeyboardInterrupt cancels the
    outstanding renders, writes ``results.csv`` and ``sheet.png`` of the images done and
    propagates. ``keep_images=False`` keeps only a contact-sheet-sized copy of each new
    image in its outcome (memory stays small for large sweeps).
    """
    from spectrace.cluster import RETRIES, SceneSpec, render_image

    outdir = check_outdir(outdir)
    outcomes = plan(grid, outdir) if outcomes is None else outcomes
    todo = [o for o in outcomes if o.status != "skipped"]
    if on_image:
        for o in outcomes:
            if o.status == "skipped":
                on_image(o)
    if todo and client is None:
        raise ValueError("sweep.run: images left to render and no client")
    futures = {}
    # grouped by variant, so that a worker switches variants as rarely as possible
    for o in sorted(todo, key=lambda o: grid.variants.index(o.combo.variant)):
        spec = SceneSpec.make(grid.scene, o.combo.defines, o.combo.variant)
        f = client.submit(render_image, spec, grid.spp, o.combo.seed, grid.spp_per_pass,
                          pure=False, retries=RETRIES)
        futures[f] = o
    try:
        for future in _as_completed(client, futures):
            o = futures[future]
            try:
                answer = future.result()
            except Exception as e:  # noqa: BLE001 - e.g. KilledWorker after the retries
                answer = {"error": f"{type(e).__name__}: {first_line(e)}"}
            _take(outdir, grid, o, answer)
            if not keep_images and o.status == "rendered":
                o.image = _thumbnail(o.image)
            if on_image:
                on_image(o)
    except KeyboardInterrupt:
        client.cancel(list(futures))
        write_results(outdir, grid, outcomes)
        write_sheet(outdir / SHEET, grid, outcomes)
        raise
    write_results(outdir, grid, outcomes)
    write_sheet(outdir / SHEET, grid, outcomes)
    return outcomes


def _as_completed(client, futures):
    if not futures:
        return []
    from distributed import as_completed

    return as_completed(futures, loop=client.loop)


def _take(outdir: Path, grid: Grid, o: Outcome, answer: dict) -> None:
    from spectrace.images import write_exr, write_png

    if "error" in answer:
        o.status, o.error = "failed", answer["error"]
        return
    rgb = answer["image"]
    o.image, o.spp, o.seconds = rgb, int(answer["spp"]), float(answer["seconds"])
    o.mean_luminance = mean_luminance(rgb)
    header = {"spp": o.spp, "variant": o.combo.variant, "seed": int(o.combo.seed),
              "scene": str(grid.scene.resolve()), "film": "rgb", "sweep": o.combo.header(),
              "seconds": o.seconds}
    exr = outdir / o.file
    write_png(exr.with_suffix(".png"), rgb)  # PNG first: an EXR means the pair is complete
    write_exr(exr, rgb, header)
    o.status = "rendered"


def _thumbnail(rgb: np.ndarray, size: int = SHEET_CELL) -> np.ndarray:
    step = max(1, max(rgb.shape[:2]) // size)
    return rgb[::step, ::step]


def write_results(outdir: Path, grid: Grid, outcomes: Sequence[Outcome]) -> Path:
    """``results.csv``: a row per finished image, in grid order (atomically)."""
    from spectrace.images import atomic_path

    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow([*grid.params, "variant", "seed", "spp", "file", "seconds",
                     "mean_luminance"])
    for o in outcomes:
        if o.status in ("rendered", "skipped"):
            writer.writerow([*o.combo.defines.values(), o.combo.variant, o.combo.seed, o.spp,
                             o.file, f"{o.seconds:.4f}", f"{o.mean_luminance:.6g}"])
    path = outdir / RESULTS
    with atomic_path(path) as tmp:
        Path(tmp).write_text(buf.getvalue())
    return path


def _sheet_layout(grid: Grid) -> tuple[list[str], str | None]:
    """Row dimensions (all but the last dimension of more than one value) and the column."""
    varying = [d for d, c in grid.coords().items() if len(c) > 1]
    if not varying:
        return [], None
    return varying[:-1], varying[-1]


def write_sheet(path, grid: Grid, outcomes: Sequence[Outcome]) -> Path:
    """A contact sheet (PNG): a column per value of the last varying dimension, a row per
    combination of the others, labelled above and on the left; a failed image is a grey
    cell marked "failed". Images are shown at about :data:`SHEET_CELL` pixels (sRGB)."""
    from PIL import Image, ImageDraw

    from spectrace.images import atomic_path, encode_srgb_8bit

    row_dims, col_dim = _sheet_layout(grid)
    coords = grid.coords()
    col_values = coords[col_dim] if col_dim else [None]
    row_keys = list(itertools.product(*(coords[d] for d in row_dims))) or [()]
    cells = {}
    for o in outcomes:
        key = dict(zip(grid.dims, _coord_values(grid, o.combo), strict=True))
        cells.setdefault((tuple(key[d] for d in row_dims), key[col_dim] if col_dim else None), o)
    shapes = [o.image.shape[:2] for o in outcomes if o.image is not None] or [(1, 1)]
    h, w = max(s[0] for s in shapes), max(s[1] for s in shapes)
    scale = max(1, SHEET_CELL // max(h, w))  # tiny renders: whole-pixel enlargement
    if max(h, w) > SHEET_CELL:
        scale = SHEET_CELL / max(h, w)
    cw, ch = max(1, round(w * scale)), max(1, round(h * scale))
    draw_probe = ImageDraw.Draw(Image.new("RGB", (1, 1)))

    def text_size(text):
        box = draw_probe.multiline_textbbox((0, 0), text)
        return box[2] - box[0], box[3] - box[1]

    row_labels = ["\n".join(f"{d}={v}" for d, v in zip(row_dims, rk, strict=True))
                  for rk in row_keys]
    col_labels = [f"{col_dim}={v}" if col_dim else "" for v in col_values]
    left = max([text_size(t)[0] for t in row_labels] + [0]) + 2 * _PAD
    top = max([text_size(t)[1] for t in col_labels] + [0]) + 2 * _PAD
    sheet = Image.new("RGB", (left + len(col_values) * (cw + _PAD),
                              top + len(row_keys) * (ch + _PAD)), "white")
    draw = ImageDraw.Draw(sheet)
    for j, label in enumerate(col_labels):
        tw, _ = text_size(label)
        draw.text((left + j * (cw + _PAD) + (cw - tw) // 2, _PAD), label, fill="black")
    for i, rk in enumerate(row_keys):
        y = top + i * (ch + _PAD)
        draw.multiline_text((_PAD, y + ch // 2 - text_size(row_labels[i])[1] // 2),
                            row_labels[i], fill="black")
        for j, ck in enumerate(col_values):
            x = left + j * (cw + _PAD)
            o = cells.get((rk, ck))
            if o is not None and o.image is not None:
                im = Image.fromarray(encode_srgb_8bit(o.image), "RGB")
                resample = Image.NEAREST if scale >= 1 else Image.BILINEAR
                sheet.paste(im.resize((cw, ch), resample), (x, y))
            else:
                draw.rectangle((x, y, x + cw - 1, y + ch - 1), fill=(200, 200, 200))
                mark = "failed" if o is not None and o.status == "failed" else "-"
                tw, th = text_size(mark)
                draw.text((x + (cw - tw) // 2, y + (ch - th) // 2), mark, fill=(180, 0, 0))
    with atomic_path(path) as tmp:
        sheet.save(tmp, format="PNG")
    return Path(path)


def _coord_values(grid: Grid, combo: Combination) -> list:
    values = [v for _, v in combo.values]
    if len(grid.variants) > 1:
        values.append(combo.variant)
    if len(grid.seeds) > 1:
        values.append(combo.seed)
    return values


def to_dataarray(grid: Grid, outcomes: Sequence[Outcome]):
    """The images as an ``xarray.DataArray``: dims :attr:`Grid.dims` + y, x, channel.

    Attributes: ``spp`` (one value or a list per image, in grid order), ``seed`` and
    ``variant`` (when not dimensions), ``scene``, ``failed`` (labels of failed images,
    which are NaN).
    """
    import xarray as xr

    images = [o.image for o in outcomes if o.image is not None]
    if not images:
        raise ParameterError("sweep: no image was rendered: "
                        + "; ".join(f"{o.combo.label()}: {o.error}" for o in outcomes))
    h, w, c = images[0].shape
    data = np.full((*grid.shape, h, w, c), np.nan, np.float32)
    for o in outcomes:
        if o.image is not None:
            if o.image.shape != (h, w, c):
                raise ParameterError(f"sweep: image {o.combo.label()} is {o.image.shape[1]}x"
                                f"{o.image.shape[0]}, the first was {w}x{h}: a DataArray "
                                "needs equal sizes (write to a folder instead)")
            data[grid.index(o.combo)] = o.image
    coords = {**grid.coords(), "channel": ["R", "G", "B"][:c]}
    spps = sorted({o.spp for o in outcomes if o.spp is not None})
    attrs = {"spp": spps[0] if len(spps) == 1 else [o.spp for o in outcomes],
             "scene": str(grid.scene),
             "failed": [f"{o.combo.label()}: {o.error}" for o in outcomes
                        if o.status == "failed"]}
    if len(grid.variants) == 1:
        attrs["variant"] = grid.variants[0]
    if len(grid.seeds) == 1:
        attrs["seed"] = grid.seeds[0]
    return xr.DataArray(data, dims=[*grid.dims, "y", "x", "channel"], coords=coords,
                        attrs=attrs, name=grid.scene.stem)


def sweep(scene, params: Mapping[str, Sequence | str | float], variants=None, seeds=None,
          spp: int | None = None, client=None, *, outdir=None, spp_per_pass: int | None = None,
          workers: int | None = None, scheduler: str | None = None):
    """Render the Cartesian product of ``params`` (``<default>`` name -> values) of ``scene``.

    Returns an ``xarray.DataArray`` (see :func:`to_dataarray`): dims the swept parameters
    (then ``variant`` and ``seed`` when several are given), then y, x, channel (linear
    sRGB). ``client``: a ``distributed.Client`` to use; None starts a LocalCluster of
    ``workers`` processes (or joins ``scheduler``) for this call. ``outdir``: also keep the
    files of ``spectrace sweep`` there (resumable); default a temporary folder.
    A failed combination is NaN, its label and error in ``attrs["failed"]``.
    """
    import contextlib
    import tempfile

    from spectrace.cluster import connect

    grid = Grid.make(scene, params, variants, seeds, spp, spp_per_pass)
    with contextlib.ExitStack() as stack:
        if client is None:
            client = stack.enter_context(connect(workers, scheduler, variant=grid.variants[0]))
        if outdir is None:
            outdir = stack.enter_context(tempfile.TemporaryDirectory(prefix="spectrace-sweep-"))
        outcomes = run(grid, client, outdir)
    return to_dataarray(grid, outcomes)


class _CallableModule(types.ModuleType):
    """``spectrace.sweep`` is this module; calling it calls :func:`sweep`."""

    def __call__(self, *args, **kwargs):
        return sweep(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
