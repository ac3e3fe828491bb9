"""Ctrl-C (SIGINT) while C extensions run Python code: deferred to a safe point.

Importing Mitsuba, setting its variant and loading a scene run Python code from C++ (Dr.Jit's
source transformations, plugin constructors on Mitsuba's own threads). A KeyboardInterrupt
raised in the middle of that surfaces as an unrelated error (``SystemError``, "error while
initializing the extension", a plugin error) or a chained traceback. :class:`defer_sigint`
notes the signal and raises KeyboardInterrupt once the block is over, so the command line
ends with "interrupted" and exit status 130.
"""

from __future__ import annotations


class defer_sigint:
    """Context manager that defers a SIGINT (Ctrl-C) on the main thread: it is noted
    (``seen``) and raised as KeyboardInterrupt when the block ends, since Mitsuba builds
    plugins on its own threads, where a KeyboardInterrupt would only become a plugin
    error. Nothing where SIGINT is ignored.

    ``stop_only=True`` is the pass loop's form: the block reads ``seen`` and stops by
    itself (after the current pass), so nothing is raised at the end, and SIGINT is caught
    even where it was ignored."""

    def __init__(self, stop_only: bool = False):
        self.stop_only = stop_only
        self.seen = False
        self._previous = None

    def __enter__(self):
        import signal
        import threading

        if threading.current_thread() is threading.main_thread():
            previous = signal.getsignal(signal.SIGINT)
            if self.stop_only or previous is not signal.SIG_IGN:
                self._previous = previous
                signal.signal(signal.SIGINT, self._handle)
        return self

    def _handle(self, signum, frame):
        self.seen = True

    def __exit__(self, exc_type, exc, tb):
        if self._previous is not None:
            import signal

            signal.signal(signal.SIGINT, self._previous)
        if self.seen and exc_type is None and not self.stop_only:
            raise KeyboardInterrupt
        return False
