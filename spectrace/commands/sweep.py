"""``spectrace sweep``: render the Cartesian product of a scene's ``<default>`` values.

A thin command over :mod:`spectrace.sweeps` (the grid, the files) and
:mod:`spectrace.cluster` (the Dask cluster): parse the options (``-D name=v1,v2``,
``--variants``, ``--seeds``), check, render with a progress bar over the images, print a
summary. Exit status: 0 when every image is there, 1 when some
combinations failed (each is named on stderr; the others are written), 2 for a user's
mistake found before rendering (nothing written), 130 on Ctrl-C (finished images are kept;
a re-run skips them).
"""

from __future__ import annotations

import argparse
import itertools
import sys
from pathlib import Path

from spectrace import DEFAULT_VARIANT
from spectrace.commands import add_display_options, add_spp_per_pass, display_settings
from spectrace.errors import UsageError

EXIT_FAILED = 1
EXIT_INTERRUPTED = 130


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scene", help="Mitsuba XML scene file")
    parser.add_argument("-D", dest="defines", action="append", default=[],
                        metavar="NAME=V1,V2,...",
                        help="values of the scene parameter $NAME (an XML <default>), "
                        "repeatable: the sweep is the Cartesian product; write a comma "
                        "inside a value as \\, (-D color=1\\,0\\,0,0\\,0\\,1)")
    parser.add_argument("--variants", help=f"Mitsuba variants, comma-separated "
                        f"(default {DEFAULT_VARIANT})")
    parser.add_argument("--seeds", help="random seeds, comma-separated (default 0)")
    parser.add_argument("--spp", type=int, help="samples per pixel (default: the scene's)")
    add_spp_per_pass(parser)
    parser.add_argument("-o", "--output", metavar="OUTDIR",
                        help="output folder (default out/sweep-<scene>)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N",
                       help="worker processes of the local Dask cluster (default: "
                       "spectrace.cluster.DEFAULT_WORKERS)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="use the Dask cluster of this scheduler (tcp://host:8786); its "
                       "workers must read the scene and its assets at the same path")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    add_display_options(parser)


def parse_sweep_defines(defines: list[str]) -> dict[str, list[str]]:
    """``["name=v1,v2", ...]`` (``-D`` options) -> ``{name: [v1, v2]}``, in order.

    UsageError for an item without ``=``, an empty name or no values (``-D name=``).
    A name given twice collects the values of both. ``\\,`` is a comma inside a value
    (``-D color=0.2\\,0.5\\,0.9,1\\,1\\,1``: two RGB values).
    """
    params: dict[str, list[str]] = {}
    for item in defines or []:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise UsageError(f"-D {item!r}: expected name=v1,v2,...")
        values = [v.strip() for v in split_values(text) if v.strip()]
        if not values:
            raise UsageError(f"-D {name}=: no values (give name=v1,v2,...)")
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
        raise UsageError(f"{option}: no values")
    try:
        return [kind(t) for t in items]
    except ValueError:
        raise UsageError(f"{option} {text!r}: expected {kind.__name__} values separated by "
                         "commas") from None


def run(args) -> int:
    from spectrace import sweeps
    from spectrace.cluster import connect

    params = parse_sweep_defines(args.defines)
    variants = parse_list(args.variants, "--variants")
    seeds = parse_list(args.seeds, "--seeds", int)
    if args.workers is not None and args.workers < 1:
        raise UsageError(f"--workers must be a positive integer (got {args.workers})")
    display_settings(args)  # a bad display option: nothing rendered or written
    grid = sweeps.Grid.make(args.scene, params, variants, seeds, args.spp, args.spp_per_pass)
    display = {"display": display_settings(args, _photometric(grid.scene)),
               "display_exr": args.display_exr}
    outdir = Path(args.output) if args.output else Path("out") / f"sweep-{grid.scene.stem}"
    sweeps.check_outdir(outdir, create=False)  # before starting a cluster
    outcomes = sweeps.plan(grid, outdir)
    todo = sum(o.status != "skipped" for o in outcomes)
    shape = " x ".join(str(n) for n in grid.shape) or "1"
    heading = (f"sweeping {grid.scene.name}: {len(outcomes)} images ({shape}), {todo} to "
               f"render -> {outdir}")
    dimming = sweeps.dimming_plan(grid) if todo else None
    if dimming:
        lights = ", ".join(f"{k} ({n} light{'' if n == 1 else 's'})"
                           for k, n in dimming.items())
        renders = len(grid.variants) * len(grid.seeds)
        print(f"{lights}: only scales lights; {renders} light-group "
              f"render{'' if renders == 1 else 's'} (one per variant and seed), relit for "
              f"each of the {len(outcomes)} images instead of rendering each", flush=True)
    if not todo:  # nothing to render: no cluster
        print(heading, file=sys.stderr, flush=True)
        outcomes = sweeps.run(grid, None, outdir, outcomes=outcomes, **display)
    else:
        try:
            with connect(args.workers, args.scheduler, variant=grid.variants[0]) as client:
                workers = len(client.scheduler_info(n_workers=-1)["workers"])
                print(f"{heading} on {workers} workers", file=sys.stderr, flush=True)
                outcomes = _run_with_progress(sweeps, grid, client, outdir, outcomes,
                                              args.quiet, display)
        except KeyboardInterrupt:
            done = sum(o.status in ("rendered", "skipped") for o in outcomes)
            kept = f"{done} of {len(outcomes)} images are in {outdir} (a re-run skips them)" \
                if done else "no image was finished"
            print(f"interrupted: {kept}", file=sys.stderr)
            return EXIT_INTERRUPTED
    counts = {s: sum(o.status == s for o in outcomes) for s in ("rendered", "skipped", "failed")}
    seconds = sum(o.seconds for o in outcomes if o.status == "rendered")
    print(f"{grid.scene.name}: {counts['rendered']} rendered ({seconds:.2f} s of renders), "
          f"{counts['skipped']} already done, {counts['failed']} failed -> "
          f"{outdir / sweeps.RESULTS}, {outdir / sweeps.SHEET}")
    for o in outcomes:
        if o.status == "failed":
            print(f"error: {o.combo.label()}: {o.error}", file=sys.stderr)
    return EXIT_FAILED if counts["failed"] else 0


def _photometric(scene) -> bool:
    from spectrace.display_options import photometric_scene
    from spectrace.scene import read_scene_xml

    return photometric_scene(read_scene_xml(scene))


def _run_with_progress(sweeps, grid, client, outdir, outcomes, quiet, display=None):
    from spectrace.commands import progress_bar

    finished = itertools.count(1)
    with progress_bar(len(outcomes), "images", quiet) as update:
        return sweeps.run(grid, client, outdir, keep_images=False, outcomes=outcomes,
                          on_image=lambda o: update(next(finished)), **(display or {}))
