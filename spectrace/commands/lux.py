"""``spectrace lux``: an illuminance map in lux of a scene's view (EXR, false-colour PNG)."""

from __future__ import annotations

import argparse
import os
import re
import sys
from pathlib import Path

from spectrace.commands import EXIT_INTERRUPTED, add_render_options, progress_bar
from spectrace.errors import UserError
from spectrace.passes import check_sample_counts, check_seed, scene_spp


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scene", help="Mitsuba XML scene file (its sensor is kept, its "
                        "integrator replaced by illuminance)")
    parser.add_argument("-o", "--output", help="output EXR, one channel Y in lux (default: "
                        "out/<scene>.lux.exr); the false-colour PNG is written beside it")
    add_render_options(parser)
    parser.add_argument("--max-depth", type=int, default=1, metavar="K",
                        help="1: direct light (default); K > 1 adds light reflected up to "
                        "K - 1 times; -1: no limit")
    parser.add_argument("--plane", metavar="'x,y,z nx,ny,nz'",
                        help="measure on this virtual work plane (point and normal, metres), "
                        "where the camera rays cross it, e.g. '0,0.85,0 0,1,0'")
    parser.add_argument("--range", dest="value_range", metavar="MIN,MAX",
                        help="colour scale of the PNG in lux (default 0 to the maximum)")
    parser.add_argument("--log", action="store_true", help="logarithmic colour scale")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bar")


def output_paths(scene: Path, output: str | None) -> dict[str, Path]:
    """OUT.exr (default out/<scene>.lux.exr) and OUT.png beside it."""
    exr = Path(output) if output else Path("out") / f"{scene.stem}.lux.exr"
    if exr.suffix.lower() != ".exr":
        raise UserError(f"output {exr}: must end in .exr (the PNG is written beside it)")
    return {"exr": exr, "png": exr.with_suffix(".png")}


def run(args) -> int:
    from spectrace import lux
    from spectrace.images import check_writable
    from spectrace.scene import parse_defines, read_scene_xml

    scene_path = Path(args.scene)
    check_sample_counts(args.spp, args.spp_per_pass)  # before loading anything
    check_seed(args.seed)
    if args.max_depth == 0 or args.max_depth < -1:
        raise UserError(f"--max-depth must be >= 1, or -1 for no limit (got {args.max_depth})")
    plane = None if args.plane is None else lux.parse_plane(args.plane)
    value_range = None if args.value_range is None else \
        lux.parse_range(args.value_range, args.log)
    paths = output_paths(scene_path, args.output)
    params = parse_defines(args.defines)
    root = read_scene_xml(scene_path)
    params = lux.true_units(root, params)  # a display exposure of the scene set to 1
    try:
        lux.lux_scene_tree(root)
    except UserError as e:
        raise UserError(f"scene {scene_path}: {e}") from None

    import spectrace

    spectrace.set_variant(args.variant, lazy=True)  # plugins registered as scenes load
    scene = _load(scene_path, params, root)
    if plane is not None:  # before check_writable makes the output's folder
        lux.check_plane_visible(scene, plane)
    for p in paths.values():  # before rendering: a bad output path costs no render time
        check_writable(p)
    spp = args.spp or scene_spp(scene)
    where = "first surfaces" if plane is None else f"plane {lux.plane_string(plane)}"
    print(f"measuring {scene_path.name}: {spp} spp, {args.variant}, seed {args.seed}, "
          f"max depth {args.max_depth}, on the {where}", file=sys.stderr, flush=True)
    luxmap = _render_with_progress(scene, spp, plane, args)
    if luxmap.nonfinite:
        print(f"warning: {luxmap.nonfinite} pixel values were NaN or infinite and were set "
              "to 0", file=sys.stderr)
    header = {"variant": args.variant, "seed": int(args.seed),
              "scene": os.path.abspath(scene_path)}
    lux.write_lux_exr(paths["exr"], luxmap, header)
    lux.plot_lux(paths["png"], luxmap, value_range, args.log,
                 title=f"{scene_path.name}: {luxmap.summary()}")
    print(f"{scene_path.name}: {luxmap.spp} spp, {luxmap.seconds:.2f} s -> {paths['exr']}")
    pixels = luxmap.valid.size
    print(f"{luxmap.summary()} ({pixels - luxmap.no_data} of {pixels} pixels with data)")
    if luxmap.interrupted:
        print(f"interrupted: saved {luxmap.spp} of {spp} spp", file=sys.stderr)
        return EXIT_INTERRUPTED
    return 0


def _load(scene_path, params, root):
    """``load_scene`` of the rewritten tree, whose line numbers are not the file's: they are
    dropped from the messages."""
    from spectrace.scene import load_scene

    try:
        return load_scene(scene_path, params, root=root)
    except UserError as e:
        raise UserError(re.sub(r"At string \(line \d+, col \d+\): ", "", str(e))) from None


def _render_with_progress(scene, spp, plane, args):
    from spectrace.lux import render_lux

    with progress_bar(spp, "spp", args.quiet) as on_pass:
        return render_lux(scene, spp, seed=args.seed, plane=plane, max_depth=args.max_depth,
                          spp_per_pass=args.spp_per_pass, on_pass=on_pass)
