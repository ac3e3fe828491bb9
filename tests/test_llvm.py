"""The libLLVM finder: picks the newest LLVM >= 16, never 14 or 15, and explains how to fix."""

from __future__ import annotations

import pytest

from spectrace import llvm
from spectrace.errors import SetupError


def make_libs(folder, names):
    folder.mkdir(parents=True, exist_ok=True)
    for name in names:
        (folder / name).write_bytes(b"\x7fELF")
    return folder


@pytest.mark.parametrize(
    ("name", "major"),
    [
        ("libLLVM-19.so", 19),
        ("libLLVM-19.so.1", 19),
        ("libLLVM.so.19.1", 19),
        ("libLLVM-14.0.6.so.1", 14),
        ("libLLVM-17.dylib", 17),
        ("libLLVM-15.so", 15),
        ("libLTO.so.19", None),
    ],
)
def test_major_from_file_name(name, major):
    """Debian, Fedora and Homebrew spell the version in the file name in different ways."""
    assert llvm.llvm_major_from_path(f"/usr/lib/{name}") == major


def test_major_from_folder_of_unversioned_library():
    """An unversioned libLLVM.so inside llvm-18/lib takes its version from the folder."""
    assert llvm.llvm_major_from_path("/usr/lib/llvm-18/lib/libLLVM.so") == 18


def test_newest_usable_is_chosen(tmp_path):
    """With 14, 15, 17 and 19 installed the finder picks 19, and never an old one."""
    a = make_libs(tmp_path / "a", ["libLLVM-14.0.6.so.1", "libLLVM-15.so"])
    b = make_libs(tmp_path / "b", ["libLLVM-17.so.1", "libLLVM.so.19.1"])
    lib = llvm.find_libllvm([str(a), str(b)])
    assert lib is not None and lib.major == 19 and lib.path.endswith("libLLVM.so.19.1")


def test_only_old_versions_give_a_clear_error(tmp_path):
    """With only LLVM 14 and 15 present, configuring fails with the install command."""
    a = make_libs(tmp_path / "a", ["libLLVM-14.0.6.so.1", "libLLVM-15.so"])
    env = {}
    with pytest.raises(SetupError, match=r"no libLLVM >= 16.*found only LLVM 15, LLVM 14.*install"):
        llvm.configure_libllvm(env, [str(a)])
    assert llvm.ENV_VAR not in env


def test_configure_sets_environment(tmp_path):
    """The chosen library is exported in DRJIT_LIBLLVM_PATH for Dr.Jit to load."""
    a = make_libs(tmp_path / "a", ["libLLVM-16.so", "libLLVM-15.so"])
    env = {}
    lib = llvm.configure_libllvm(env, [str(a)])
    assert env[llvm.ENV_VAR] == lib.path == str(a / "libLLVM-16.so")


def test_user_choice_is_kept_unless_too_old(tmp_path):
    """A user's DRJIT_LIBLLVM_PATH wins when it is new enough, and is refused when it is 15."""
    a = make_libs(tmp_path / "a", ["libLLVM-18.so", "libLLVM-15.so", "libLLVM-19.so"])
    env = {llvm.ENV_VAR: str(a / "libLLVM-18.so")}
    assert llvm.configure_libllvm(env, [str(a)]).major == 18
    assert env[llvm.ENV_VAR] == str(a / "libLLVM-18.so")
    with pytest.raises(SetupError, match="LLVM 15"):
        llvm.configure_libllvm({llvm.ENV_VAR: str(a / "libLLVM-15.so")}, [str(a)])
    with pytest.raises(SetupError, match="no such file"):
        llvm.configure_libllvm({llvm.ENV_VAR: str(a / "missing.so")}, [str(a)])


def test_ensure_installs_when_missing(tmp_path, monkeypatch):
    """As root with apt-get, a missing libLLVM is installed (the first package that works)."""
    folder = make_libs(tmp_path / "lib", ["libLLVM-15.so"])
    calls = []

    def fake_apt(cmd):
        calls.append(cmd)
        if cmd[-1] == "libllvm19":
            make_libs(folder, ["libLLVM-19.so"])
        return 0

    monkeypatch.setattr(llvm.os, "geteuid", lambda: 0)
    monkeypatch.setattr("shutil.which", lambda name: "/usr/bin/" + name)
    lib = llvm.ensure_libllvm(search_dirs=[str(folder)], runner=fake_apt)
    assert lib.major == 19
    assert calls[0][:2] == ["apt-get", "update"] and calls[1][-1] == "libllvm19"


def test_ensure_without_root_prints_the_command(tmp_path, monkeypatch):
    """Not root: no install attempt, an error with the exact sudo command."""
    folder = make_libs(tmp_path / "lib", ["libLLVM-15.so"])
    monkeypatch.setattr(llvm.os, "geteuid", lambda: 1000)

    def no_runner(cmd):
        raise AssertionError("must not run apt-get")

    with pytest.raises(SetupError, match=r"sudo apt-get install -y libllvm19"):
        llvm.ensure_libllvm(search_dirs=[str(folder)], runner=no_runner)
