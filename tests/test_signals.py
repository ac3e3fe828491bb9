"""``spectrace/signals.py``: a Ctrl-C while Mitsuba imports, sets its variant or loads a
scene is deferred to the end of that step and becomes exit 130 "interrupted"."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from spectrace.signals import defer_sigint

ROOT = Path(__file__).resolve().parents[1]
#: When the SIGINT is sent: the command is then importing Mitsuba or setting its variant.
EARLY_SIGINT_S = 0.3


def test_sigint_in_the_block_is_raised_at_its_end():
    """The signal is noted, the block runs to its end, then KeyboardInterrupt; the previous
    handler is back."""
    finished = False
    with pytest.raises(KeyboardInterrupt):
        with defer_sigint() as sigint:
            signal.raise_signal(signal.SIGINT)
            finished = True
    assert finished and sigint.seen
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_ignored_sigint_stays_ignored():
    """Where SIGINT is ignored (Dask workers), the block neither installs a handler nor
    raises."""
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with defer_sigint() as sigint:
            signal.raise_signal(signal.SIGINT)
        assert not sigint.seen and signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, previous)


def test_ctrl_c_during_start_up_is_exit_130(tmp_path):
    """Ctrl-C while `spectrace render` imports Mitsuba: exit 130 and the one line
    'interrupted' (it was a chained traceback from Dr.Jit's extension), nothing written."""
    out = tmp_path / "x.exr"
    process = subprocess.Popen(
        [sys.executable, "-m", "spectrace.cli", "render", str(ROOT / "scenes" / "showcase.xml"),
         "-o", str(out), "-D", "res=16", "--spp", "4", "-q"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path)
    time.sleep(EARLY_SIGINT_S)
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=120)
    assert process.returncode == 130, err[-2000:]
    assert err.strip().splitlines()[-1] == "interrupted"
    assert not out.exists()
