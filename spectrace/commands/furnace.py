"""``spectrace furnace BSDF [-p name=value ...] [--angles 0,30,60]``: white-furnace table.

The measurement is :func:`spectrace.furnace.directional_albedo`; this module parses the
command line and prints its table.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from spectrace.errors import UsageError
from spectrace.furnace import DEFAULT_ANGLES, DEFAULT_SAMPLES


def _parse_value(text: str):
    lowered = text.strip().lower()
    if lowered in ("true", "false"):
        return lowered == "true"
    parts = [p for p in text.replace(",", " ").split()]
    try:
        numbers = [float(p) for p in parts]
    except ValueError:
        return text
    if len(numbers) == 1:
        return numbers[0]
    if len(numbers) == 3:
        return {"type": "rgb", "value": numbers}
    raise UsageError(f"expected one or three numbers, got {text!r}")


def bsdf_spec(name: str, params: list[str]):
    """The BSDF description for the command line's BSDF argument and ``-p`` options."""
    if name.lstrip().startswith("<") or Path(name).is_file():
        if params:
            raise UsageError("-p applies to a plugin name, not to an XML string or file")
        return name
    spec = {"type": name}
    for item in params:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise UsageError(f"-p expects name=value, got {item!r}")
        spec[key.strip()] = _parse_value(value)
    return spec


def _angles(text: str):
    try:
        return [float(a) for a in text.split(",") if a.strip()]
    except ValueError:
        message = f"not a comma-separated list of angles: {text!r}"
        raise argparse.ArgumentTypeError(message) from None


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("bsdf", help="plugin name (with -p), XML string '<bsdf ...>' or XML file")
    parser.add_argument("-p", "--param", action="append", default=[], metavar="NAME=VALUE",
                        help="BSDF parameter: a number, three numbers (RGB) or true/false")
    parser.add_argument("--angles", type=_angles, default=list(DEFAULT_ANGLES),
                        help="incident angles in degrees, comma-separated")
    parser.add_argument("--samples", type=int, default=DEFAULT_SAMPLES, help="samples per angle")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--variant", default=None, help="Mitsuba variant (default: spectrace's)")


def run(args) -> int:
    import spectrace

    spectrace.set_variant(args.variant or spectrace.DEFAULT_VARIANT)
    spec = bsdf_spec(args.bsdf, args.param)
    from spectrace.furnace import directional_albedo

    result = directional_albedo(spec, args.angles, args.samples, args.seed)
    print(f"white furnace: {args.bsdf} {' '.join(args.param)}".rstrip())
    print(result.table())
    return 0
