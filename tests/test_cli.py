"""The ``spectrace`` executable (spectrace.cli.console): the process ends right after the
command, without Python's teardown, and nothing is lost by it."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from spectrace import cli

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "showcase.xml"


class _Exited(Exception):
    def __init__(self, code):
        self.code = code


@pytest.fixture
def fake_exit(monkeypatch):
    """os._exit raising _Exited(code) instead of ending the test process."""
    def exit_now(code):
        raise _Exited(code)

    monkeypatch.setattr(os, "_exit", exit_now)


def test_console_skips_the_teardown_with_the_command_status(monkeypatch, fake_exit):
    """The command's exit status is the process's (os._exit after flushing)."""
    monkeypatch.setattr(cli, "main", lambda: 3)
    monkeypatch.delitem(sys.modules, "distributed", raising=False)
    monkeypatch.delitem(sys.modules, "coverage", raising=False)
    monkeypatch.setattr(sys, "gettrace", lambda: None)
    monkeypatch.setattr(sys, "getprofile", lambda: None)
    with pytest.raises(_Exited) as ended:
        cli.console()
    assert ended.value.code == 3


@pytest.mark.parametrize("watcher", ["distributed", "coverage", "trace", "profile"])
def test_console_keeps_the_teardown_for_dask_and_tracers(monkeypatch, fake_exit, watcher):
    """After Dask (its exit handlers close what is left) or under a tracer or profiler
    (coverage writes its data at exit), the process ends normally: SystemExit."""
    monkeypatch.setattr(cli, "main", lambda: 4)
    monkeypatch.delitem(sys.modules, "distributed", raising=False)
    monkeypatch.setattr(sys, "gettrace", lambda: None)
    monkeypatch.setattr(sys, "getprofile", lambda: None)
    monkeypatch.delitem(sys.modules, "coverage", raising=False)
    if watcher in ("distributed", "coverage"):
        monkeypatch.setitem(sys.modules, watcher, object())
    else:
        monkeypatch.setattr(sys, f"get{watcher}", lambda: print)
    with pytest.raises(SystemExit) as ended:
        cli.console()
    assert ended.value.code == 4


def test_executable_output_is_complete(tmp_path):
    """``python -m spectrace.cli render`` (the console path) with stdout and stderr piped:
    every line arrives, the EXR and PNG are whole, the status is 0; and a user error still
    gives its one line and status 2."""
    out = tmp_path / "x.exr"
    done = subprocess.run([sys.executable, "-m", "spectrace.cli", "render", str(SCENE), "-o",
                           str(out), "--variant", "llvm_ad_rgb", "--spp", "4", "-D", "res=16",
                           "-q"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.startswith("showcase.xml: 4 spp in 1 pass") and done.stdout.endswith("\n")
    assert "rendering showcase.xml" in done.stderr
    from spectrace.images import read_exr

    image, header = read_exr(out)
    assert image.shape == (16, 16, 3) and header["spp"] == 4
    assert out.with_suffix(".png").read_bytes().endswith(b"IEND\xaeB`\x82")  # the PNG's end
    bad = subprocess.run([sys.executable, "-m", "spectrace.cli", "render", str(SCENE),
                          "--spp", "0"], capture_output=True, text=True, timeout=300)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "--spp" in bad.stderr
