"""``spectrace doctor`` reports what it found and fails when the LLVM backend cannot work."""

from __future__ import annotations

from spectrace import llvm
from spectrace.cli import main
from spectrace.llvm import ENV_VAR


def test_doctor_reports_a_working_backend(capsys):
    """On a set-up machine: versions, variants, the libLLVM used, a working backend, exit 0."""
    assert main(["doctor"]) == 0
    out = capsys.readouterr().out
    for word in ("mitsuba", "drjit", "llvm_ad_spectral", "libLLVM used", "kernel cache",
                 "LLVM backend:    works"):
        assert word in out, word


def _fake_llvm15(tmp_path, monkeypatch):
    fake = tmp_path / "libLLVM-15.so"
    fake.write_bytes(b"\x7fELF")
    monkeypatch.setenv(ENV_VAR, str(fake))


def test_doctor_refuses_llvm_15_and_says_unset_when_a_good_one_is_installed(
        tmp_path, monkeypatch, capsys):
    """DRJIT_LIBLLVM_PATH naming LLVM 15 while LLVM 19 is installed: the fix is to unset the
    variable (not to install what is there), and the exit is 1."""
    good = llvm.LibLLVM("/usr/lib/x86_64-linux-gnu/libLLVM-19.so", 19)
    monkeypatch.setattr(llvm, "find_libllvm", lambda *a, **k: good)
    monkeypatch.setattr(llvm, "find_libllvm_candidates", lambda *a, **k: [good])
    _fake_llvm15(tmp_path, monkeypatch)
    assert main(["doctor"]) == 1
    out = capsys.readouterr().out
    assert "LLVM 15" in out and f"unset {ENV_VAR}" in out and good.path in out
    assert "apt-get" not in out


def test_doctor_refuses_llvm_15_and_says_install_when_none_is_good(tmp_path, monkeypatch, capsys):
    """DRJIT_LIBLLVM_PATH naming LLVM 15 and no LLVM >= 16 installed: the fix installs one."""
    monkeypatch.setattr(llvm, "find_libllvm", lambda *a, **k: None)
    monkeypatch.setattr(llvm, "find_libllvm_candidates", lambda *a, **k: [])
    _fake_llvm15(tmp_path, monkeypatch)
    assert main(["doctor"]) == 1
    out = capsys.readouterr().out
    assert "LLVM 15" in out and "apt-get install -y libllvm19" in out
