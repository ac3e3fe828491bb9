"""The ``spectrace`` command line.

Each subcommand is a module with ``add_arguments(parser)`` and ``run(args) -> int``;
``COMMANDS`` maps the subcommand name to that module, imported only when used.
A :class:`~spectrace.errors.SpectraceError` becomes one ``error: ...`` line on stderr and
exit status 2, never a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import re
import sys

from spectrace.commands import EXIT_INTERRUPTED, EXIT_USAGE
from spectrace.errors import SpectraceError, UsageError

#: subcommand -> (module, one-line help)
COMMANDS: dict[str, tuple[str, str]] = {
    "render": ("spectrace.commands.render", "render Mitsuba XML scenes in passes"),
    "doctor": ("spectrace.commands.doctor",
               "report variants, libLLVM and whether the backend works"),
    "compare": ("spectrace.commands.compare",
                "CIEDE2000 between two images, scenes or variants"),
    "furnace": ("spectrace.commands.furnace",
                "white furnace: directional albedo of a BSDF vs incident angle"),
    "spd": ("spectrace.commands.spd",
            "XYZ, xy, CCT, CRI and sRGB colour of an SPD file or dataset"),
    "ies": ("spectrace.commands.ies",
            "flux, peak, beam angle and polar plot of an IES or EULUMDAT file"),
    "help": ("spectrace.commands.help", "a plugin's reference page (help phong), or the list"),
    "lux": ("spectrace.commands.lux",
            "illuminance map in lux of a scene's view (EXR, false-colour PNG, U0)"),
    "view": ("spectrace.commands.view",
             "develop an EXR into a PNG: exposure, white balance, view transform"),
    "relight": ("spectrace.commands.relight",
                "new light intensities and lamp spectra from a render's light-group layers"),
    "sweep": ("spectrace.commands.sweep",
              "render the Cartesian product of scene parameters on Dask"),
    "validate": ("spectrace.commands.validate",
                 "the CIE 171:2006 case families against their closed forms"),
    "envmap": ("spectrace.commands.envmap",
               "convert environment maps between latlong, cube cross and mirror ball"),
}

#: A negative number, or a comma- or space-separated list that starts with one.
_NEGATIVE_NUMBERS = re.compile(r"^-(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?(?:[, ].*)?$")


class _Parser(argparse.ArgumentParser):
    """argparse with the project's one-line error format and exit status 2, and option values
    that are negative numbers or lists of them (``--range -5,10``, ``--angles -30,0``) taken
    as values, not as options."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        # argparse's own test takes "-5" and "-0.5" as numbers, not "-5,10" or "-1e3"
        self._negative_number_matcher = _NEGATIVE_NUMBERS

    def error(self, message):
        self.exit(EXIT_USAGE, f"error: {message}\n")


DESCRIPTION = ("spectrace: the classic shading and light models as Mitsuba 3 plugins, "
               "spectral and RGB. 'spectrace COMMAND --help' describes a command.")


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The parser of every subcommand; with ``only``, the module of that subcommand alone is
    imported and its arguments added (the others are listed by name and help), so a command
    starts without importing the others."""
    parser = _Parser(prog="spectrace", description=DESCRIPTION)
    parser.add_argument("--version", action="version", version=_version())
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name, (module, help_text) in COMMANDS.items():
        cmd = sub.add_parser(name, help=help_text, description=help_text)
        if only is None or name == only:
            mod = importlib.import_module(module)
            mod.add_arguments(cmd)
            cmd.set_defaults(_module=mod)
    return parser


def _command_in(argv: list[str]) -> str:
    """The subcommand named in ``argv`` ("" when there is none: nothing to import)."""
    return next((arg for arg in argv if not arg.startswith("-")), "")


def _version() -> str:
    from spectrace import __version__

    return f"spectrace {__version__}"


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        parser = build_parser(only=_command_in(argv))
        args = parser.parse_args(argv)
        from spectrace.mitsuba_log import configure_cli

        configure_cli(getattr(args, "verbose", False))
        output = getattr(args, "output", None)
        if isinstance(output, str) and not output.strip():  # -o '' would mean "./"
            raise UsageError("-o: the output path is empty")
        code = int(args._module.run(args) or 0)
        sys.stdout.flush()  # a closed pipe shows here, not in Python's flush at exit
        return code
    except SpectraceError as e:
        print(f"error: {e}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        # The reader of the output went away (spectrace ... | head): end quietly, with
        # stdout pointed at /dev/null so that Python's final flush does not complain.
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


def console() -> None:
    """The ``spectrace`` executable: :func:`main`, then the end of the process without
    Python's teardown.

    Every output file is written and closed by the time :func:`main` returns (Dr.Jit
    writes its kernel cache as it compiles), and unloading Dr.Jit, LLVM and the
    interpreter's modules takes 60 to 90 ms on these machines: longer than a small render.
    The teardown still runs when Dask was used (its exit handlers close what may be left
    open) or when a tracer or profiler watches (coverage writes its data at exit).
    """
    code = main()
    watched = sys.gettrace() is not None or sys.getprofile() is not None \
        or "coverage" in sys.modules  # coverage may watch through sys.monitoring
    if watched or "distributed" in sys.modules:
        sys.exit(code)
    import os

    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe: nothing more to say
            pass
    os._exit(code)


if __name__ == "__main__":
    console()
