"""``spectrace envmap convert IN OUT --to latlong|cube|sphere``: environment-map layouts.

Reads a latitude-longitude (2:1), mirror-ball or angular (1:1; ``--from angular`` for a
light probe) or cube-cross (4:3 horizontal, 3:4 vertical) map from EXR, HDR or PNG and
writes it in another layout as EXR or HDR (six separate cube faces: a file name with
``{face}``, replaced by px, nx, py, ny, pz, nz, for the input or with ``--to faces``):
``latlong`` is what Mitsuba's ``envmap`` reads (with its importance sampling): its rows
run from the zenith (first) to the nadir (last), columns at their centres.
``--illuminance LUX`` scales the map so that a horizontal plane receives LUX from its
upper hemisphere; ``--scale S`` multiplies it. Prints the
layouts and the illuminance before and after. The projectors are
:mod:`spectrace.envmaps`.
"""

from __future__ import annotations

from spectrace.errors import UsageError


def add_arguments(parser) -> None:
    sub = parser.add_subparsers(dest="action", required=True)
    convert = sub.add_parser("convert", help="convert a map to another layout")
    convert.add_argument("input", help="map to read (.exr, .hdr, .png); six separate cube "
                                       "faces as one name with {face} (px, nx, py, ny, pz, nz)")
    convert.add_argument("output", help="map to write (.exr or .hdr)")
    convert.add_argument("--to", required=True,
                         choices=["latlong", "cube", "sphere", "angular", "cross_vertical",
                                  "faces"],
                         help="layout to write (cube: a horizontal cross; faces: six files, "
                              "OUTPUT names them with {face})")
    convert.add_argument("--from", dest="source", default=None,
                         choices=["latlong", "sphere", "angular", "cube"],
                         help="layout of the input (default: from its aspect ratio; a square "
                              "image is a mirror ball unless this says angular)")
    convert.add_argument("--size", type=int, default=None,
                         help="height of the output in pixels (default: the input's)")
    scale = convert.add_mutually_exclusive_group()
    scale.add_argument("--illuminance", type=float, default=None,
                       help="scale to this many lux on a horizontal plane (upper hemisphere)")
    scale.add_argument("--scale", type=float, default=None, help="multiply the map by this")


def run(args) -> int:
    from spectrace import envmaps

    if args.size is not None and args.size < 1:
        raise UsageError(f"--size must be >= 1 (got {args.size})")
    if args.illuminance is not None and not args.illuminance > 0:
        raise UsageError(f"--illuminance must be > 0 (got {args.illuminance:g})")
    if args.scale is not None and not args.scale >= 0:
        raise UsageError(f"--scale must be >= 0 (got {args.scale:g})")
    summary = envmaps.convert_file(args.input, args.output, args.to, args.source, args.size,
                                   args.illuminance, args.scale)
    height, width = summary["shape"]
    print(f"{args.input} ({summary['from']}) -> {args.output} ({summary['to']}, "
          f"{width} x {height})")
    print(f"horizontal illuminance: {summary['lux_in']:.6g} lx -> {summary['lux_out']:.6g} lx "
          f"(scale {summary['scale']:.6g})")
    return 0
