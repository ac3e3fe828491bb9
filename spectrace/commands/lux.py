"""``spectrace lux``: an illuminance map in lux of a scene's view (EXR, false-colour PNG);
with ``--grid`` an EN 12464-1 calculation grid, with ``--points`` sensor points, with
``--luminance`` the view's luminance (and ``--ugr`` its glare rating), with ``--report``
a Markdown report of what was computed."""

from __future__ import annotations

import argparse
import os
import re
import sys
from pathlib import Path

from spectrace.commands import (
    EXIT_INTERRUPTED,
    add_render_options,
    check_render_options,
    parse_defines,
    progress_bar,
)
from spectrace.errors import ParameterError, SpectraceError, UsageError
from spectrace.passes import scene_spp


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
    parser.add_argument("--daylight-factor", nargs="?", const=0.0, type=float, default=None,
                        metavar="E_MED", help="print daylight factors against the ciesky's "
                        "unobstructed horizontal illuminance (and EN 17037 levels for a site "
                        "median diffuse illuminance E_MED in lux, if given)")
    design = parser.add_argument_group("lighting design")
    design.add_argument("--grid", metavar="'x0,y0 x1,y1 @ h'|NAME",
                        help="calculation grid on the horizontal plane at height h (plan x = "
                        "scene X, plan y = scene -Z, metres), or the name of a <default> of "
                        "the scene that holds one: OUT.csv (x,y,z,lux,stderr) and a "
                        "plan-view PNG; prints Em, Emin, Emax, U0")
    design.add_argument("--spacing", type=float, metavar="P",
                        help="grid spacing in m (default: EN 12464-1's 0.2 x 5^log10(d))")
    design.add_argument("--border", type=float, default=0.5, metavar="B",
                        help="band excluded at the grid's edges in m (default 0.5, "
                        "EN 12464-1's band at the walls; 0 for a task area)")
    design.add_argument("--points", metavar="FILE.csv",
                        help="sensor points, one x,y,z,nx,ny,nz per line: OUT.csv with "
                        "x,y,z,nx,ny,nz,lux,stderr (with --luminance: view directions, "
                        "x,y,z,dx,dy,dz,luminance,stderr)")
    design.add_argument("--kind", default="planar",
                        choices=("planar", "cylindrical", "semicylindrical"),
                        help="illuminance at points and grids: on the plane of the normal "
                        "(default), cylindrical Ez, or semi-cylindrical facing the normal")
    design.add_argument("--maintenance-factor", type=float, default=1.0, metavar="MF",
                        help="maintained illuminance = MF x the new installation's "
                        "(0 < MF <= 1, default 1)")
    design.add_argument("--task", help="EN 12464-1:2021 task whose Em, U0 (and UGR) the grid "
                        "must meet: " + ", ".join(_task_names()))
    design.add_argument("--luminance", action="store_true",
                        help="the view's luminance in cd/m^2: OUT.luminance.exr (Y) and a "
                        "false-colour PNG (log scale)")
    design.add_argument("--ugr", action="store_true",
                        help="the unified glare rating (CIE 117) seen from the camera (implies "
                        "--luminance)")
    design.add_argument("--report", metavar="OUT.md",
                        help="a Markdown report of the results, the figures beside it")


def _task_names():
    from spectrace.lighting.grids import TASKS

    return list(TASKS)


def output_paths(scene: Path, output: str | None) -> dict[str, Path]:
    """OUT.exr (default out/<scene>.lux.exr) and OUT.png beside it."""
    exr = Path(output) if output else Path("out") / f"{scene.stem}.lux.exr"
    if exr.suffix.lower() != ".exr":
        raise UsageError(f"output {exr}: must end in .exr (the PNG is written beside it)")
    return {"exr": exr, "png": exr.with_suffix(".png")}


def run(args) -> int:
    if args.grid is not None or args.points is not None or args.luminance or args.ugr or \
            args.report is not None:
        return run_design(args)
    return run_map(args)


def run_map(args) -> int:
    from spectrace import lux
    from spectrace.images import check_writable
    from spectrace.scene import read_scene_xml

    scene_path = Path(args.scene)
    check_render_options(args)  # before loading anything
    if args.max_depth == 0 or args.max_depth < -1:
        raise UsageError(f"--max-depth must be >= 1, or -1 for no limit (got {args.max_depth})")
    try:  # the library's messages call them plane, value_range, log: here, by their flags
        plane = None if args.plane is None else lux.parse_plane(args.plane, "--plane")
        value_range = None if args.value_range is None else \
            lux.parse_range(args.value_range, args.log, ("--range", "--log"))
    except ParameterError as e:
        raise UsageError(str(e)) from None
    paths = output_paths(scene_path, args.output)
    params = parse_defines(args.defines)
    root = read_scene_xml(scene_path)
    params = lux.true_units(root, params)  # a display exposure of the scene set to 1
    try:
        lux.lux_scene_tree(root)
    except SpectraceError as e:
        raise type(e)(f"scene {scene_path}: {e}") from None

    import spectrace

    spectrace.set_variant(args.variant, lazy=True)  # plugins registered as scenes load
    scene = _load(scene_path, params, root)
    if plane is not None:  # before check_writable makes the output's folder
        try:
            lux.check_plane_visible(scene, plane, name="--plane")
        except ParameterError as e:
            raise UsageError(str(e)) from None
    if args.daylight_factor is not None:  # a scene without a ciesky fails before rendering
        from spectrace import daylight

        daylight.sky_horizontal_illuminance(scene)
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
    if args.daylight_factor is not None:  # daylight factors of the pixels with data
        for line in daylight.report_lines(scene, luxmap.lux[luxmap.valid],
                                          args.daylight_factor or None):
            print(line)
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
    except SpectraceError as e:
        raise type(e)(re.sub(r"At string \(line \d+, col \d+\): ", "", str(e))) from None


def _render_with_progress(scene, spp, plane, args):
    from spectrace.lux import render_lux

    with progress_bar(spp, "spp", args.quiet) as on_pass:
        try:
            return render_lux(scene, spp, seed=args.seed, plane=plane,
                              max_depth=args.max_depth, spp_per_pass=args.spp_per_pass,
                              on_pass=on_pass)
        except ParameterError as e:
            if plane is None:
                raise
            raise UsageError(f"--plane: {e}") from None  # surfaces hide the plane


# -- lighting design: grids, points, luminance, glare, report ---------------------------------

def _check_design_options(args, defaults: dict[str, str]):
    """Every option checked before anything is loaded or written (UsageError);
    ``defaults``: the scene's parameters, where ``--grid NAME`` finds its grid."""
    import math

    from spectrace.lighting import grids

    if args.grid is not None and args.points is not None:
        raise UsageError("--grid and --points: give one of them")
    if not (math.isfinite(args.maintenance_factor) and 0.0 < args.maintenance_factor <= 1.0):
        raise UsageError(f"--maintenance-factor must be > 0 and <= 1 (got "
                         f"{args.maintenance_factor:g})")
    if args.task is not None and args.task not in grids.TASKS:
        raise UsageError(f"--task {args.task!r}: expected one of {', '.join(grids.TASKS)}")
    if args.task is not None and args.grid is None:
        raise UsageError("--task needs --grid (the requirements are checked on a grid)")
    if args.spacing is not None and not (math.isfinite(args.spacing) and args.spacing > 0.0):
        raise UsageError(f"--spacing must be > 0 m (got {args.spacing:g})")
    if not (math.isfinite(args.border) and args.border >= 0.0):
        raise UsageError(f"--border must be >= 0 m (got {args.border:g})")
    if args.max_depth == 0 or args.max_depth < -1:
        raise UsageError(f"--max-depth must be >= 1, or -1 for no limit (got {args.max_depth})")
    if args.kind == "semicylindrical" and args.grid is not None:
        raise UsageError("--kind semicylindrical needs a facing direction per point: use "
                         "--points (a grid's points face up)")
    if args.kind != "planar" and args.max_depth != 1:
        raise UsageError(f"--kind {args.kind}: direct light only (--max-depth 1)")
    if args.report is not None and Path(args.report).suffix.lower() != ".md":
        raise UsageError(f"--report {args.report}: must end in .md")
    if args.grid is None and args.points is None and args.report is not None and \
            not (args.luminance or args.ugr):
        raise UsageError("--report needs --grid, --points or --luminance (something to report)")
    grid = None
    if args.grid is not None:
        try:
            rectangle, height = grids.parse_grid(args.grid, defaults)
            grid = grids.make_grid(rectangle, height, args.border, args.spacing)
        except ValueError as e:
            raise UsageError(f"--grid: {e}") from None
    return grid


def _without_grid(root, params: dict[str, str], grid: str | None) -> dict[str, str]:
    """``params`` without ``-D NAME=...`` of ``--grid NAME`` when the scene itself does not
    use ``$NAME`` (the grid is this command's, and Mitsuba refuses an unused parameter)."""
    from spectrace.lighting.grids import grid_name
    from spectrace.scene import uses_parameter

    name = None if grid is None else grid_name(grid)
    if name is None or name not in params or uses_parameter(root, name):
        return params
    return {k: v for k, v in params.items() if k != name}


def design_paths(args, scene_path: Path) -> dict[str, Path]:
    """The output files: the primary one is -o (points/grid: .csv; luminance alone:
    .exr), the others beside it (OUT.png for the plan, OUT.luminance.exr/.png)."""
    primary = ".csv" if (args.grid or args.points) else ".exr"
    kind = "points" if args.points else "grid" if args.grid else "luminance"
    if args.output:
        out = Path(args.output)
        if out.suffix.lower() != primary:
            raise UsageError(f"output {out}: must end in {primary}")
        stem = out.with_suffix("")
    else:
        stem = Path("out") / f"{scene_path.stem}.{kind}"
    paths = {}
    if args.points:
        paths["points"] = stem.with_suffix(".csv")
    if args.grid:
        paths["grid"] = stem.with_suffix(".csv")
        paths["plan"] = stem.with_suffix(".png")
    if args.luminance or args.ugr:
        if kind == "luminance":
            paths["luminance"], paths["luminance_png"] = Path(f"{stem}.exr"), Path(f"{stem}.png")
        else:
            paths["luminance"] = Path(f"{stem}.luminance.exr")
            paths["luminance_png"] = Path(f"{stem}.luminance.png")
    if args.report:
        paths["report"] = Path(args.report)
    return paths


def run_design(args) -> int:
    import spectrace
    from spectrace import lux
    from spectrace.images import check_writable
    from spectrace.lighting import grids, points, report
    from spectrace.scene import read_scene_xml, scene_defaults

    scene_path = Path(args.scene)
    check_render_options(args)  # before loading anything
    params = parse_defines(args.defines)
    root = read_scene_xml(scene_path)  # --grid NAME: a <default> of the scene (or -D)
    grid = _check_design_options(args, {**scene_defaults(root), **params})
    paths = design_paths(args, scene_path)
    point_data = None
    if args.points is not None:
        point_data = points.read_points_table(args.points)
    params = lux.true_units(root, _without_grid(root, params, args.grid))
    try:
        lux.lux_scene_tree(root)
    except SpectraceError as e:
        raise type(e)(f"scene {scene_path}: {e}") from None
    spectrace.set_variant(args.variant, lazy=True)
    scene = _load(scene_path, params, root)
    checks = []
    if grid is not None:
        checks.append(("--grid", lambda: grids.check_in_scene(grid, scene)))
    if point_data is not None and not args.luminance:
        checks.append(("--points", lambda: points.check_vectors(
            point_data[1], args.kind, f"points file {args.points}")))
    if args.ugr:
        from spectrace.lighting import glare, luminance

        checks.append(("--ugr", lambda: glare.check_line_of_sight(
            luminance.line_of_sight(scene.sensors()[0]))))
    for flag, check in checks:
        try:
            check()
        except ParameterError as e:
            raise UsageError(f"{flag}: {e}") from None
    for p in paths.values():  # nothing is written before every check has passed
        check_writable(p)
    spp = args.spp or scene_spp(scene)
    study = report.Study(scene_path.name, args.variant, report.luminaires(scene),
                         args.maintenance_factor)
    mf = args.maintenance_factor
    if grid is not None:
        result = grids.measure_grid(scene, grid, maintenance_factor=mf, spp=spp,
                                    seed=args.seed, max_depth=args.max_depth, kind=args.kind)
        grids.write_grid_csv(paths["grid"], result)
        grids.plot_plan(paths["plan"], result, grids.room_outline(scene),
                        title=f"{scene_path.name}: {result.summary()}",
                        lights=grids.light_positions(scene))
        print(grid.describe(), f"({result.samples} sample(s) per point)")
        print(result.summary(), f"-> {paths['grid']}")
        study.grid, study.plan_png = result, paths["plan"]
        if args.task is not None:
            study.task = grids.TASKS[args.task]
    if point_data is not None:
        _measure_points(args, scene, point_data, spp, paths["points"])
        study.points = (len(point_data[0]), paths["points"])
    if args.luminance or args.ugr:
        _luminance(args, scene, spp, paths, study)
    if study.task is not None:
        _print_task(study)
    if args.report is not None:
        report.write_report(paths["report"], study)
        print(f"report -> {paths['report']}")
    return 0


def _measure_points(args, scene, point_data, spp, out):
    import numpy as np

    from spectrace.lighting import luminance, points

    where, vectors, rows = point_data
    if args.luminance:
        values, stderr = luminance.luminance_along(scene, where, vectors, spp=spp,
                                                   seed=args.seed, max_depth=args.max_depth)
        points.write_points_csv(out, where, vectors, values, stderr, points.LUMINANCE_COLUMNS,
                                rows)
        print(f"{len(where)} points: luminance {values.min():.4g} to {values.max():.4g} "
              f"cd/m^2 ({spp} spp) -> {out}")
        return
    values, stderr, samples = points.measure_points(
        scene, where, vectors, kind=args.kind, spp=spp, seed=args.seed,
        max_depth=args.max_depth)
    values, stderr = args.maintenance_factor * values, args.maintenance_factor * stderr
    points.write_points_csv(out, where, vectors, values, stderr, rows=rows)
    print(f"{len(where)} points: {args.kind} illuminance {values.min():.4g} to "
          f"{values.max():.4g} lx ({samples} sample(s) per point, MF "
          f"{args.maintenance_factor:g}) -> {out}")
    if np.isnan(stderr).any():  # one random sample: no spread to estimate it from
        print("note: the standard error is nan (unknown) with 1 random sample per point; "
              "--spp 2 or more estimates it", file=sys.stderr)


def _luminance(args, scene, spp, paths, study):
    from spectrace import lux
    from spectrace.lighting import glare, luminance

    image = luminance.luminance_image(scene, spp=spp, seed=args.seed, max_depth=args.max_depth)
    luminance.write_luminance_exr(paths["luminance"], image, {"variant": args.variant})
    as_map = luminance.as_map(image)
    positive = image.Y[image.Y > 0]
    value_range = None
    if positive.size:
        high = float(positive.max())
        value_range = (max(float(positive.min()), high / lux.LOG_DECADES), high)
        if not value_range[0] < value_range[1]:
            value_range = (high / lux.LOG_DECADES, high)
    lux.plot_lux(paths["luminance_png"], as_map, value_range, log=positive.size > 0,
                 title=f"luminance: {as_map.minimum:.4g} to {as_map.maximum:.4g} cd/m^2",
                 label="luminance L_v (cd/m^2)")
    print(f"luminance {as_map.minimum:.4g} to {as_map.maximum:.4g} cd/m^2, mean "
          f"{as_map.mean:.4g} ({spp} spp) -> {paths['luminance']}")
    study.luminance_png = paths["luminance_png"]
    if args.ugr:
        study.glare = glare.ugr(image.Y, image.directions, image.solid_angle, image.forward)
        print(study.glare.summary())
        if not glare.has_visible_lights(scene):
            study.glare_note = glare.NO_SIZE_NOTE
            print(f"note: {glare.NO_SIZE_NOTE}", file=sys.stderr)


def _print_task(study):
    task = study.task
    checks = study.grid.check(task)
    word = {True: "pass", False: "FAIL"}
    line = (f"{task.name} ({task.description}, EN 12464-1:2021): Em >= {task.E_m:g} lx "
            f"{word[checks['E_m']]}, U0 >= {task.U0:.2f} {word[checks['U0']]}")
    if study.glare is not None and study.glare.UGR is not None:
        line += f", UGR <= {task.UGR_L:g} {word[study.glare.UGR <= task.UGR_L]}"
    print(line)
