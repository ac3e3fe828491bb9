"""``spectrace doctor`` reports what it found and fails when the LLVM backend cannot work."""

from __future__ import annotations

from spectrace.cli import main
from spectrace.llvm import ENV_VAR


def test_doctor_reports_a_working_backend(capsys):
    """On a set-up machine: versions, variants, the libLLVM used, a working backend, exit 0."""
    assert main(["doctor"]) == 0
    out = capsys.readouterr().out
    for word in ("mitsuba", "drjit", "llvm_ad_spectral", "libLLVM used", "kernel cache",
                 "LLVM backend:    works"):
        assert word in out, word


def test_doctor_refuses_llvm_15(tmp_path, monkeypatch, capsys):
    """A DRJIT_LIBLLVM_PATH naming LLVM 15 is reported with the fix, and the exit is 1."""
    fake = tmp_path / "libLLVM-15.so"
    fake.write_bytes(b"\x7fELF")
    monkeypatch.setenv(ENV_VAR, str(fake))
    assert main(["doctor"]) == 1
    out = capsys.readouterr().out
    assert "LLVM 15" in out and "apt-get install -y libllvm19" in out
