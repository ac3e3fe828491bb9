"""The ``spectrace`` command line.

Each subcommand is a module with ``add_arguments(parser)`` and ``run(args) -> int``;
``COMMANDS`` maps the subcommand name to that module, imported only when used.
A :class:`~spectrace.errors.UserError` becomes one ``error: ...`` line on stderr and
exit status 2, never a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from spectrace.errors import UserError

#: subcommand -> (module, one-line help)
COMMANDS: dict[str, tuple[str, str]] = {
    "render": ("spectrace.commands.render", "render a Mitsuba XML scene in passes"),
    "doctor": ("spectrace.commands.doctor", "report variants, libLLVM and whether the backend works"),
    "compare": ("spectrace.commands.compare", "CIEDE2000 between two images, scenes or variants"),
    "furnace": ("spectrace.commands.furnace", "white furnace: directional albedo of a BSDF vs incident angle"),
    "spd": ("spectrace.commands.spd", "XYZ, xy, CCT, CRI and sRGB colour of an SPD file or dataset"),
}

EXIT_USAGE = 2
EXIT_INTERRUPTED = 130


class _Parser(argparse.ArgumentParser):
    """argparse with the project's one-line error format and exit status 2."""

    def error(self, message):
        self.exit(EXIT_USAGE, f"error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="spectrace", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=_version())
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name, (module, help_text) in COMMANDS.items():
        cmd = sub.add_parser(name, help=help_text, description=help_text)
        mod = importlib.import_module(module)
        mod.add_arguments(cmd)
        cmd.set_defaults(_module=mod)
    return parser


def _version() -> str:
    from spectrace import __version__

    return f"spectrace {__version__}"


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args._module.run(args) or 0)
    except UserError as e:
        print(f"error: {e}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED


if __name__ == "__main__":
    sys.exit(main())
