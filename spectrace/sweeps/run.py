"""Rendering a grid on Dask: one task per image, each written as it arrives.

Each combination is rendered on a worker by :func:`spectrace.cluster.render_image`, the pass
loop of ``spectrace render``, so an image equals ``spectrace render SCENE -D ...`` of its
combination with the same seed (up to the order of the film's float additions). Images
travel back to the client, which writes every file atomically. A sweep of dimming
parameters only is one light-group render per variant and seed, relit for every value
(:mod:`spectrace.sweeps.dimming`).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

from spectrace.errors import first_line
from spectrace.sweeps.dimming import dimming_plan, relit_image, render_dimming_layers
from spectrace.sweeps.files import SHEET, check_outdir, plan, write_image
from spectrace.sweeps.grid import Grid, Outcome
from spectrace.sweeps.results import mean_luminance, write_results
from spectrace.sweeps.sheet import thumbnail, write_sheet


def run(grid: Grid, client, outdir, *, on_image: Callable[[Outcome], None] | None = None,
        keep_images: bool = True, outcomes: list[Outcome] | None = None,
        display=None, display_exr: bool = False, relight: bool = True) -> list[Outcome]:
    """Render ``grid`` on ``client``'s workers into ``outdir``; outcomes in grid order.

    Skips finished images (``outcomes``: a :func:`~spectrace.sweeps.files.plan` already
    made; ``client`` may be None when it has nothing left to render); writes each new EXR +
    PNG as it arrives, and ``results.csv`` and ``sheet.png`` at the end (after a crash, a
    re-run rebuilds them from the EXR headers). ``on_image(outcome)`` is called for each
    image (skipped ones first). A KeyboardInterrupt cancels the outstanding renders, writes
    ``results.csv`` and ``sheet.png`` of the images done and propagates.
    ``keep_images=False`` keeps only a contact-sheet-sized copy of each new image in its
    outcome (memory stays small for large sweeps). A combination that fails for a user
    reason (a bad value) is reported in its :class:`Outcome` while the others finish.
    ``display``, ``display_exr``: how each PNG is made (:func:`write_image`).
    ``relight``: a sweep of dimming parameters only (:func:`~spectrace.sweeps.dimming.
    dimming_plan`) renders one light-group render per variant and seed and relights it for
    every value (False: renders every combination).
    """
    outdir = check_outdir(outdir)
    outcomes = plan(grid, outdir) if outcomes is None else outcomes
    todo = [o for o in outcomes if o.status != "skipped"]
    if on_image:
        for o in outcomes:
            if o.status == "skipped":
                on_image(o)
    if todo and client is None:
        raise ValueError("sweeps.run: images left to render and no client")
    layered = bool(todo) and relight and dimming_plan(grid) is not None
    futures = _submit_layers(grid, client, todo) if layered else _submit(grid, client, todo)
    try:
        for future in _as_completed(client, futures):
            group = futures[future]
            try:
                answer = future.result()
            except Exception as e:  # noqa: BLE001 - e.g. KilledWorker after the retries
                answer = {"error": f"{type(e).__name__}: {first_line(e)}"}
            for o in group:
                _take(outdir, grid, o, _relit(answer, o, len(group)) if layered else answer,
                      display, display_exr)
                if not keep_images and o.status == "rendered":
                    o.image = thumbnail(o.image)
                if on_image:
                    on_image(o)
    except KeyboardInterrupt:
        client.cancel(list(futures))
        _summaries(outdir, grid, outcomes)
        raise
    _summaries(outdir, grid, outcomes)
    return outcomes


def _submit(grid: Grid, client, todo: list[Outcome]) -> dict:
    """One task per image: future -> [its outcome]."""
    from spectrace.cluster import RETRIES, SceneSpec, render_image

    futures = {}
    # grouped by variant, so that a worker switches variants as rarely as possible
    for o in sorted(todo, key=lambda o: grid.variants.index(o.combo.variant)):
        spec = SceneSpec.make(grid.scene, o.combo.defines, o.combo.variant)
        f = client.submit(render_image, spec, grid.spp, o.combo.seed, grid.spp_per_pass,
                          pure=False, retries=RETRIES)
        futures[f] = [o]
    return futures


def _submit_layers(grid: Grid, client, todo: list[Outcome]) -> dict:
    """A dimming sweep: one light-group render per variant and seed: future -> the
    outcomes relit from it."""
    from spectrace.cluster import RETRIES

    groups: dict[tuple[str, int], list[Outcome]] = {}
    for o in todo:
        groups.setdefault((o.combo.variant, o.combo.seed), []).append(o)
    futures = {}
    for (variant, seed), group in groups.items():
        f = client.submit(render_dimming_layers, str(grid.scene.resolve()), list(grid.params),
                          variant, grid.spp, seed, grid.spp_per_pass, pure=False,
                          retries=RETRIES)
        futures[f] = group
    return futures


def _relit(answer: dict, o: Outcome, images: int) -> dict:
    """The answer of one image relit from the layers of a dimming render; its seconds are
    the relight's plus its share of the render's."""
    if "error" in answer:
        return answer
    start = time.perf_counter()
    image = relit_image(answer["layers"], o.combo)
    return {"image": image, "spp": answer["spp"],
            "seconds": answer["seconds"] / images + time.perf_counter() - start}


def _summaries(outdir: Path, grid: Grid, outcomes: list[Outcome]) -> None:
    write_results(outdir, grid, outcomes)
    write_sheet(outdir / SHEET, grid, outcomes)


def _as_completed(client, futures):
    if not futures:
        return []
    from distributed import as_completed

    return as_completed(futures, loop=client.loop)


def _take(outdir: Path, grid: Grid, o: Outcome, answer: dict, display=None,
          display_exr: bool = False) -> None:
    if "error" in answer:
        o.status, o.error = "failed", answer["error"]
        return
    o.image, o.spp, o.seconds = answer["image"], int(answer["spp"]), float(answer["seconds"])
    o.mean_luminance = mean_luminance(o.image)
    write_image(outdir, grid, o, display, display_exr)
    o.status = "rendered"
