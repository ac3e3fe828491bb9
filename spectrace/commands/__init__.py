"""The ``spectrace`` subcommands, one module per subcommand, imported only by :mod:`spectrace.cli`.

Each module has ``add_arguments(parser)`` and ``run(args) -> int``: it parses, calls the
library (``spectrace.*``, ``spectrace.spectral``, ``spectrace.photometry``) and prints.
Nothing else imports a command. This package's ``__init__`` holds what commands share.
"""

import contextlib
import sys

#: Exit statuses of the command line: bad input, and a render stopped by Ctrl-C (128 + SIGINT).
EXIT_USAGE = 2
EXIT_INTERRUPTED = 130


@contextlib.contextmanager
def progress_bar(total: int, unit: str, quiet: bool):
    """Yield ``update(done, total=None)`` for a transient progress bar over ``total``
    ``unit`` on stderr; a no-op (and rich not imported) with ``quiet`` or when stderr is
    not a terminal."""
    if quiet or not sys.stderr.isatty():
        yield lambda done, total=None: None
        return
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    with Progress("[progress.description]{task.description}", BarColumn(),
                  MofNCompleteColumn(), TimeElapsedColumn(), TimeRemainingColumn(),
                  transient=True) as progress:
        task = progress.add_task(unit, total=total)
        yield lambda done, total=None: progress.update(task, completed=done)


def add_spp_per_pass(parser) -> None:
    """``--spp-per-pass K`` (default: :func:`spectrace.passes.default_spp_per_pass`)."""
    parser.add_argument("--spp-per-pass", type=int, default=None, metavar="K",
                        help="samples per pixel in one pass (default: the largest power of 4 "
                        "up to 64 that keeps a pass within about 4 million samples)")


def add_render_options(parser) -> None:
    """The options of every command that renders a scene: ``--variant``, ``--spp``,
    ``--spp-per-pass``, ``--seed`` and ``-D name=value``."""
    from spectrace import DEFAULT_VARIANT
    parser.add_argument("--variant", default=DEFAULT_VARIANT,
                        help=f"Mitsuba variant (default {DEFAULT_VARIANT})")
    parser.add_argument("--spp", type=int, help="samples per pixel (default: the scene's)")
    add_spp_per_pass(parser)
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE",
                        help="set the scene parameter $NAME (XML <default>), repeatable")
