"""Mitsuba's log through Python's :mod:`logging`, once per message kind.

Mitsuba writes its warnings (``[LowDiscrepancySampler] Sample count should be a power of
two -- rounding to 64``, ``[HDRFilm] Monochrome mode enabled``, ``Received interrupt
signal, winding down..``) to stderr through its own global logger, once per plugin that
says it: forty times in a notebook whose cells build forty samplers. :func:`route` replaces
Mitsuba's default appender (its ``StreamAppender``) with one that forwards each message to
the logger :data:`LOGGER` (``logging.getLogger("spectrace.mitsuba")``), each kind of message
once (the digits of a message do not make a new kind). It does so once per process, and
only while Mitsuba's logger still has its default appender alone: appenders that a user
added or replaced are left as they are, and so is whatever the user does after.

Python's logging then decides what is shown: in a script or notebook without logging
configured, warnings reach stderr (Python's last-resort handler); the command line shows
only errors, and warnings too with ``-v`` (:func:`configure_cli`).
"""

from __future__ import annotations

import logging
import re

#: The name of the Python logger that receives Mitsuba's messages.
LOGGER = "spectrace.mitsuba"
#: Digits do not make a message a new kind ("rounding to 64" and "rounding to 16").
_NUMBER = re.compile(r"\d+(?:\.\d+)?")
#: Mitsuba's log line: "2025-01-01 12:00:00 WARN  [Class] message" (the time and level are
#: Mitsuba's formatting; logging adds its own).
_PREFIX = re.compile(r"^\d{4}-\d\d-\d\d \d\d:\d\d:\d\d\s+[A-Z]+\s+")

_appender = None  # the installed appender (the logger keeps no Python reference)
_seen: set[str] = set()


def python_level(level) -> int:
    """The :mod:`logging` level of a Mitsuba ``LogLevel``."""
    import mitsuba as mi

    return {mi.LogLevel.Trace: logging.DEBUG, mi.LogLevel.Debug: logging.DEBUG,
            mi.LogLevel.Info: logging.INFO, mi.LogLevel.Warn: logging.WARNING,
            mi.LogLevel.Error: logging.ERROR}.get(level, logging.WARNING)


def message_kind(text: str) -> str:
    """The kind of a message: the message with its numbers left out."""
    return _NUMBER.sub("#", text)


def forward(level: int, text: str) -> bool:
    """Log ``text`` at ``level`` on :data:`LOGGER` unless a message of its kind was logged
    before; whether it was logged."""
    text = _PREFIX.sub("", text.strip())
    kind = message_kind(text)
    if not text or kind in _seen:
        return False
    _seen.add(kind)
    logging.getLogger(LOGGER).log(level, "%s", text)
    return True


def route(mi) -> bool:
    """Send Mitsuba's log to :data:`LOGGER` (module docstring) when Mitsuba's logger still
    has its default appender alone and this process has not done so before; whether it did
    so now."""
    global _appender
    logger = mi.logger()
    if _appender is not None or logger is None:
        return False
    appenders = [logger.appender(i) for i in range(logger.appender_count())]
    if len(appenders) != 1 or type(appenders[0]) is not mi.StreamAppender:
        return False  # the user's own set-up

    class LoggingAppender(mi.Appender):
        """Mitsuba's messages to Python's logging, once per kind; no progress bars."""

        def append(self, level, text):
            forward(python_level(level), text)

        def log_progress(self, progress, name, formatted, eta, ptr=None):
            pass

    _appender = LoggingAppender()
    logger.clear_appenders()
    logger.add_appender(_appender)
    return True


class _Stderr(logging.Handler):
    """Each record as one line on the ``sys.stderr`` of the moment (pytest swaps it)."""

    def emit(self, record):
        import sys

        try:
            sys.stderr.write(self.format(record) + "\n")
        except Exception:  # noqa: BLE001 - logging's own rule: a handler never raises
            self.handleError(record)


def configure_cli(verbose: bool) -> None:
    """The command line's choice: Mitsuba's errors on stderr, its warnings too with
    ``verbose``, each as ``mitsuba: ...`` on one line."""
    log = logging.getLogger(LOGGER)
    if not any(isinstance(h, _Stderr) for h in log.handlers):
        handler = _Stderr()
        handler.setFormatter(logging.Formatter("mitsuba: %(message)s"))
        log.addHandler(handler)
    log.setLevel(logging.WARNING if verbose else logging.ERROR)
    log.propagate = False
