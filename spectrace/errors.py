"""The library's exceptions: mistakes a user can make (a bad parameter, a malformed or
missing file), each message naming the function parameter, plugin parameter or file.

They subclass the built-in types a Python caller expects (:class:`ValueError` for values,
:class:`OSError` for files), so ``except ValueError`` works as it does with numpy or
colour-science. The command line (``spectrace.cli``) turns every :class:`SpectraceError`
into a one-line ``error: ...`` on stderr and exit status 2; flag names and exit codes
live only in ``spectrace/commands/`` and ``spectrace/cli.py``.
"""

from __future__ import annotations

import re

#: The source location that Mitsuba puts before its messages: ``[properties.cpp:693] ``.
_SOURCE_LOCATION = re.compile(r"^\[[\w./-]+:\d+\]\s*")


class SpectraceError(Exception):
    """Base of every mistake in the user's input; the message names what is wrong."""


class ParameterError(SpectraceError, ValueError):
    """A function or plugin parameter has a value it cannot take (named in the message)."""


class FileFormatError(SpectraceError, ValueError):
    """A file's content is malformed or unsupported (the file is named in the message)."""


class FileAccessError(SpectraceError, OSError):
    """A file is missing, unreadable or unwritable (the file is named in the message)."""


class SetupError(SpectraceError):
    """The machine lacks something spectrace needs (a libLLVM >= 16, the GPU of a CUDA
    variant); the message says what to install or choose instead."""


class UsageError(SpectraceError):
    """A command-line mistake (a flag's value, a missing argument): raised only by
    ``spectrace/commands/`` and ``spectrace/cli.py``."""


def first_line(error: BaseException | str) -> str:
    """The first non-empty line of an error message (the exception's type name when the
    message is empty), without the ``[file.cpp:123]`` source location that Mitsuba puts
    first: what a one-line ``error: ...`` shows."""
    text = str(error).strip()
    if not text:
        return type(error).__name__ if isinstance(error, BaseException) else ""
    line = text.splitlines()[0].strip()
    return _SOURCE_LOCATION.sub("", line, count=1) or line
