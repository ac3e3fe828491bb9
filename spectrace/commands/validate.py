"""``spectrace validate``: the CIE 171:2006 case families, each against its closed form.

Prints one row per case, writes ``DIR/report.md`` with a figure per case, and exits 0 when
every modelled case passes, 1 otherwise (a case that cannot be modelled yet is listed with
its reason and does not count).
"""

from __future__ import annotations

import argparse
import sys

DEFAULT_FOLDER = "out/validation"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from spectrace import DEFAULT_VARIANT

    parser.add_argument("--quick", action="store_true",
                        help="small grids and few samples (what the test suite runs)")
    parser.add_argument("--case", action="append", default=[], metavar="NAME",
                        help="run this case only (repeatable; default: every case)")
    parser.add_argument("-o", "--output", default=DEFAULT_FOLDER, metavar="DIR",
                        help=f"folder of report.md and the figures (default {DEFAULT_FOLDER})")
    parser.add_argument("-m", "--variant", default=DEFAULT_VARIANT,
                        help=f"Mitsuba variant (default {DEFAULT_VARIANT})")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE",
                        help="override a parameter of the cases' scenes (never of their "
                        "references): a deliberately wrong setting, say")
    parser.add_argument("--list", action="store_true", help="list the cases and exit")


def run(args) -> int:
    from spectrace.errors import UsageError
    from spectrace.validation.cases import CASES

    if args.list:
        for name, case in CASES.items():
            print(f"{name:32s} {(case.__doc__ or '').strip().splitlines()[0]}")
        return 0
    unknown = [name for name in args.case if name not in CASES]
    if unknown:
        raise UsageError(f"--case {unknown[0]}: no such case (spectrace validate --list)")
    from spectrace.commands import parse_defines

    params = parse_defines(args.defines)
    import spectrace
    from spectrace import validation
    from spectrace.validation import report

    spectrace.set_variant(args.variant)

    def progress(name):
        if sys.stderr.isatty():
            print(f"\r\033[Kvalidating {name} ...", end="", file=sys.stderr, flush=True)

    results = validation.run(args.case or None, quick=args.quick, seed=args.seed,
                             params=params, progress=progress)
    if sys.stderr.isatty():
        print("\r\033[K", end="", file=sys.stderr)
    print(report.table(results))
    path = report.write_report(results, args.output, variant=args.variant, quick=args.quick,
                               seed=args.seed)
    modelled = [r for r in results if r.modelled]
    failed = [r.name for r in modelled if not r.passed]
    print(f"{len(modelled) - len(failed)} of {len(modelled)} modelled cases pass; "
          f"{len(results) - len(modelled)} not modelled; report: {path}")
    return 1 if failed else 0
