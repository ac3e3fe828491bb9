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
    not a terminal. ``update.describe(text)`` shows ``text`` beside the unit (the render's
    noise estimate)."""
    if quiet or not sys.stderr.isatty():
        def update(done, total=None):
            return None

        update.describe = lambda text: None
        yield update
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

        def update(done, total=None):
            progress.update(task, completed=done)

        update.describe = lambda text: progress.update(task, description=f"{unit}, {text}")
        yield update


def add_spp_per_pass(parser) -> None:
    """``--spp-per-pass K`` (default: :func:`spectrace.passes.default_spp_per_pass`)."""
    parser.add_argument("--spp-per-pass", type=int, default=None, metavar="K",
                        help="samples per pixel in one pass (default: the largest power of 4 "
                        "up to 64 that keeps a pass within about 4 million samples)")


def add_render_options(parser) -> None:
    """The options of every command that renders a scene: ``-m/--variant``, ``--spp``,
    ``--spp-per-pass``, ``--seed`` and ``-D name=value``."""
    from spectrace import DEFAULT_VARIANT
    parser.add_argument("-m", "--variant", default=DEFAULT_VARIANT,
                        help=f"Mitsuba variant (default {DEFAULT_VARIANT})")
    parser.add_argument("--spp", type=int, help="samples per pixel (default: the scene's)")
    add_spp_per_pass(parser)
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE",
                        help="set the scene parameter $NAME (XML <default>), repeatable")
    add_verbose(parser)


def add_verbose(parser) -> None:
    """``-v/--verbose``: Mitsuba's warnings on stderr (once each; errors are always shown)."""
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="show Mitsuba's warnings (once each)")


def parse_defines(defines: list[str] | None) -> dict[str, str]:
    """``["name=value", ...]`` of ``-D`` options -> the scene parameters (a dict); UsageError
    for an item without ``=`` or a name."""
    from spectrace.errors import UsageError

    params = {}
    for item in defines or []:
        name, sep, value = item.partition("=")
        if not sep or not name.strip():
            raise UsageError(f"-D {item!r}: expected name=value")
        params[name.strip()] = value
    return params


#: The flags of the render options, by the library parameter they set.
RENDER_FLAGS = {"spp": "--spp", "spp_per_pass": "--spp-per-pass", "seed": "--seed"}


def check_render_options(args) -> None:
    """The sample counts and seed of :func:`add_render_options` checked before anything
    loads, the messages naming the flags."""
    from spectrace.passes import check_sample_counts, check_seed

    check_sample_counts(args.spp, getattr(args, "spp_per_pass", None),
                        names=(RENDER_FLAGS["spp"], RENDER_FLAGS["spp_per_pass"]))
    check_seed(args.seed, RENDER_FLAGS["seed"])


def add_display_options(parser, views: bool = True) -> None:
    """The display pipeline's options (:mod:`spectrace.display`): ``--exposure``,
    ``--ev100``, ``--white-balance``, and with ``views`` also ``--view``, ``--display``,
    ``--png-bits``. They change the PNG only, never the EXR."""
    group = parser.add_argument_group("display (the PNG only; the EXR never changes)")
    group.add_argument("--exposure", metavar="EV|auto",
                       help="exposure in stops relative to the scene's scale, or 'auto' (the "
                       "log-average luminance to middle grey 0.18, Reinhard et al. 2002); "
                       "default 0, or auto for a scene with photometric lights")
    group.add_argument("--ev100", type=float, metavar="N",
                       help="absolute camera exposure at ISO 100 (saturation-based, ISO 12232): "
                       "a 500 lux office looks right at about 8-9")
    group.add_argument("--white-balance", default="none", metavar="none|D65|CCTK|auto",
                       help="adapt this white to D65 (Bradford, in XYZ), e.g. 3000K; auto: "
                       "grey world (default none)")
    if views:
        from spectrace.display_options import DISPLAYS, PNG_BITS, VIEW_NAMES

        group.add_argument("--view", default="standard", metavar="|".join(VIEW_NAMES),
                           help="view transform: standard (clip), aces (ACES 2.0 SDR through "
                           "OpenColorIO), neutral (Khronos PBR Neutral), false-colour "
                           "(luminance in cd/m^2, log scale)")
        group.add_argument("--display", default="srgb", metavar="|".join(DISPLAYS),
                           help="the PNG's colour space (default srgb)")
        group.add_argument("--png-bits", type=int, default=8, metavar="|".join(map(str, PNG_BITS)),
                           help="bits per channel of the PNG (default 8)")
        group.add_argument("--display-exr", action="store_true",
                           help="also write OUT.display.exr: the PNG's picture as linear "
                           "display values in [0, 1] (the scene-referred EXR stays as it is)")


def display_settings(args, photometric: bool = False):
    """The :class:`spectrace.display.DisplaySettings` of the parsed display options (a
    photometric scene with no exposure given: ``auto``); UsageError naming the flag of a
    bad value."""
    from spectrace.display_options import DisplaySettings, parse_exposure
    from spectrace.errors import ParameterError, UsageError

    exposure = args.exposure
    if exposure is None and args.ev100 is None and photometric:
        exposure = "auto"
    values = {"exposure": exposure, "ev100": args.ev100, "white_balance": args.white_balance,
              "view": getattr(args, "view", "standard"),
              "display": getattr(args, "display", "srgb"),
              "png_bits": getattr(args, "png_bits", 8)}
    for field, value in values.items():  # one at a time: the message names the flag
        try:
            DisplaySettings(**{field: value})
        except ParameterError as e:
            raise UsageError(f"--{field.replace('_', '-')}: {e}") from None

    values["exposure"] = parse_exposure(values["exposure"])
    try:
        return DisplaySettings(**values)
    except ParameterError as e:
        raise UsageError(f"--exposure, --ev100: {e}") from None


def write_picture(png, rgb, settings, display_exr=None) -> tuple[str, ...]:
    """The PNG of the linear sRGB image ``rgb``: plain sRGB with the default settings (and
    no ``display_exr``), else through the display pipeline
    (:func:`spectrace.display.write_display_png`); returns the pipeline's notes."""
    if settings.is_default and display_exr is None:
        from spectrace.images import write_png

        write_png(png, rgb)
        return ()
    import numpy as np

    from spectrace.display import write_display_png

    return write_display_png(png, np.asarray(rgb, np.float32), settings, display_exr).notes
