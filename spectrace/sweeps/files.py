"""A sweep's folder: file names, the images' EXR + PNG, and what a re-run may skip.

Each combination has one EXR + PNG named after its values (:func:`stem`). The EXR header
holds the combination (:func:`identity`: the parameters as the scene saw them, variant,
seed), so a re-run skips every image whose pair is there with the same combination and
sample count, without touching it (:func:`plan`). The PNG is written before the EXR: an
EXR means the pair is complete.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from pathlib import Path

from spectrace.errors import FileAccessError, SpectraceError
from spectrace.sweeps.grid import Combination, Grid, Outcome

RESULTS = "results.csv"
SHEET = "sheet.png"
#: Longest file name stem (characters, all ASCII) of an image; longer ones are shortened
#: with a hash of the combination (".spectral.exr" and temporary prefixes must still fit).
MAX_STEM = 200
_UNSAFE = re.compile(r"[^A-Za-z0-9._+-]+")


def identity(combo: Combination) -> str:
    """The combination as stored in the EXR header (for resuming)."""
    return json.dumps({"params": combo.defines, "variant": combo.variant,
                       "seed": int(combo.seed)}, sort_keys=True)


def stem(combo: Combination) -> str:
    """File name (no suffix): ``name-value_..._variant_seedS``, safe characters only."""
    parts = [f"{k}-{_safe(v)}" for k, v in combo.defines.items()]
    name = "_".join([*parts, combo.variant, f"seed{combo.seed}"])
    if len(name) > MAX_STEM:  # file names have at most 255 bytes; keep it unique
        tail = f"~{_digest(identity(combo), 10)}_{combo.variant}_seed{combo.seed}"
        name = name[: MAX_STEM - len(tail)].rstrip("_") + tail
    return name


def _digest(text: str, n: int) -> str:
    return hashlib.sha1(text.encode()).hexdigest()[:n]


def _safe(value: str) -> str:
    safe = _UNSAFE.sub("_", value).strip("_") or "_"
    if safe != value:  # keep distinct values distinct
        safe += "~" + _digest(value, 6)
    return safe


def check_outdir(outdir, create: bool = True) -> Path:
    """FileAccessError when the output folder, or a folder above it, is a file, or when
    nothing can be written there; ``create``: make the folder (else only check)."""
    from spectrace.images import check_writable

    outdir = Path(outdir)
    for folder in (outdir, *outdir.parents):
        if folder.exists() and not folder.is_dir():
            what = "is" if folder == outdir else f"is inside {folder}, which is"
            raise FileAccessError(f"output folder {outdir} {what} a file, not a folder")
        if folder.is_dir():  # the nearest folder that exists
            if not os.access(folder, os.W_OK | os.X_OK):
                raise FileAccessError(f"cannot write output folder {outdir}: {folder} is "
                                      "not writable")
            break
    if create:
        check_writable(outdir / RESULTS)
    return outdir


def plan(grid: Grid, outdir) -> list[Outcome]:
    """The outcomes of ``grid`` in grid order, those an earlier run finished ``skipped``."""
    outdir = Path(outdir)
    outcomes = [Outcome(c, stem(c) + ".exr") for c in grid.combinations()]
    for o in outcomes:
        _resume(outdir, grid, o)
    return outcomes


def _resume(outdir: Path, grid: Grid, outcome: Outcome) -> None:
    """Mark ``outcome`` skipped, with its image, if an earlier run left it (same
    combination, same spp)."""
    from spectrace.images import read_exr
    from spectrace.sweeps.results import mean_luminance

    exr = outdir / outcome.file
    if not (exr.is_file() and exr.with_suffix(".png").is_file()):
        return
    try:
        rgb, header = read_exr(exr)
    except (SpectraceError, ValueError, OSError):
        return  # unreadable: rendered again
    if header.get("sweep") != identity(outcome.combo):
        return
    if grid.spp is not None and header.get("spp") != grid.spp:
        return
    outcome.image, outcome.spp = rgb, int(header.get("spp", 0))
    outcome.seconds = float(header.get("seconds", float("nan")))
    outcome.mean_luminance = mean_luminance(rgb)
    outcome.status = "skipped"


def write_image(outdir: Path, grid: Grid, outcome: Outcome, display=None,
                display_exr: bool = False) -> None:
    """The outcome's PNG, then its EXR (header: spp, variant, seed, scene, the combination,
    seconds). ``display``: :class:`spectrace.display.DisplaySettings` of the PNG (None or
    the defaults: the plain sRGB PNG); ``display_exr``: also ``<stem>.display.exr``. The
    EXR is the same with any of them."""
    from spectrace.images import write_exr, write_png

    header = {"spp": outcome.spp, "variant": outcome.combo.variant,
              "seed": int(outcome.combo.seed), "scene": str(grid.scene.resolve()),
              "film": "rgb", "sweep": identity(outcome.combo), "seconds": outcome.seconds}
    exr = outdir / outcome.file
    if (display is None or display.is_default) and not display_exr:
        write_png(exr.with_suffix(".png"), outcome.image)
    else:
        from spectrace.display import write_display_png

        write_display_png(exr.with_suffix(".png"), outcome.image, display,
                          exr.with_suffix(".display.exr") if display_exr else None)
    write_exr(exr, outcome.image, header)
