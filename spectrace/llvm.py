"""Find a libLLVM that Dr.Jit's LLVM backend can use (LLVM >= 16).

Dr.Jit loads the system's libLLVM at run time. LLVM 15 makes a render abort the whole
process (``LLVM ERROR: Cannot select ... fminimum``) and LLVM 14 is refused, so spectrace
points Dr.Jit at the newest libLLVM >= 16 through ``DRJIT_LIBLLVM_PATH`` before mitsuba is
imported. A path the user set in ``DRJIT_LIBLLVM_PATH`` is kept when its version is good.
"""

from __future__ import annotations

import glob
import os
import re
from dataclasses import dataclass
from pathlib import Path

from spectrace.errors import SetupError

MIN_LLVM_MAJOR = 16
ENV_VAR = "DRJIT_LIBLLVM_PATH"

#: Folders searched for libLLVM, in order; globs are expanded.
SEARCH_DIRS = (
    "/usr/lib/x86_64-linux-gnu",
    "/usr/lib/aarch64-linux-gnu",
    "/usr/lib/llvm-*/lib",
    "/usr/lib64",
    "/usr/lib",
    "/usr/local/lib",
    "/usr/local/opt/llvm/lib",
    "/opt/homebrew/opt/llvm/lib",
    "/opt/homebrew/opt/llvm@*/lib",
)

# libLLVM-19.so, libLLVM-19.so.1, libLLVM-14.0.6.so.1, libLLVM.so.19.1, libLLVM-17.dylib
_VERSIONED = (
    re.compile(r"^libLLVM-(\d+)(?:\.\d+)*(?:git)?\.(?:so|dylib)(?:\.\d+)*$"),
    re.compile(r"^libLLVM\.so\.(\d+)(?:\.\d+)*$"),
)
# unversioned libLLVM.so / libLLVM.dylib inside llvm-19/lib or llvm@19/lib
_PLAIN = re.compile(r"^libLLVM\.(?:so|dylib)$")
_DIR_VERSION = re.compile(r"llvm[-@](\d+)")


@dataclass(frozen=True)
class LibLLVM:
    path: str
    major: int

    @property
    def usable(self) -> bool:
        return self.major >= MIN_LLVM_MAJOR


def llvm_major_from_path(path: str | os.PathLike) -> int | None:
    """The LLVM major version read from a library's file name (or its folder)."""
    p = Path(path)
    for pattern in _VERSIONED:
        m = pattern.match(p.name)
        if m:
            return int(m.group(1))
    if _PLAIN.match(p.name):
        for part in reversed(p.parts[:-1]):
            m = _DIR_VERSION.search(part)
            if m:
                return int(m.group(1))
    return None


def find_libllvm_candidates(search_dirs=SEARCH_DIRS) -> list[LibLLVM]:
    """Every libLLVM found in ``search_dirs``, newest first (duplicates of one file merged)."""
    found: dict[str, LibLLVM] = {}
    for pattern in search_dirs:
        for folder in sorted(glob.glob(str(pattern))):
            for lib in sorted(glob.glob(os.path.join(folder, "libLLVM*"))):
                major = llvm_major_from_path(lib)
                if major is None or not os.path.isfile(lib):
                    continue
                key = os.path.realpath(lib)
                if key not in found:
                    found[key] = LibLLVM(lib, major)
    return sorted(found.values(), key=lambda c: c.major, reverse=True)


def find_libllvm(search_dirs=SEARCH_DIRS) -> LibLLVM | None:
    """The newest libLLVM >= 16 in ``search_dirs``, or None."""
    for candidate in find_libllvm_candidates(search_dirs):
        if candidate.usable:
            return candidate
    return None


def install_hint() -> str:
    """The command that installs a good libLLVM on this system."""
    import platform

    if platform.system() == "Darwin":
        return "brew install llvm"
    prefix = "" if hasattr(os, "geteuid") and os.geteuid() == 0 else "sudo "
    return f"{prefix}apt-get install -y libllvm19"


def configure_libllvm(environ=os.environ, search_dirs=SEARCH_DIRS) -> LibLLVM:
    """Point Dr.Jit at a libLLVM >= 16 (sets ``DRJIT_LIBLLVM_PATH`` unless the user did).

    Raises SetupError with the fixing command when no usable library exists.
    """
    user_path = environ.get(ENV_VAR)
    if user_path:
        major = llvm_major_from_path(user_path)
        if not os.path.isfile(user_path):
            raise SetupError(f"{ENV_VAR}={user_path}: no such file")
        if major is not None and major < MIN_LLVM_MAJOR:
            good = find_libllvm(search_dirs)
            fix = (f"unset {ENV_VAR} to use the installed {good.path} (LLVM {good.major})"
                   if good is not None else f"install one: {install_hint()}")
            raise SetupError(
                f"{ENV_VAR}={user_path} is LLVM {major}; Dr.Jit needs LLVM >= {MIN_LLVM_MAJOR}"
                f" ({fix})"
            )
        return LibLLVM(user_path, major if major is not None else MIN_LLVM_MAJOR)
    lib = find_libllvm(search_dirs)
    if lib is None:
        olds = ", ".join(f"LLVM {c.major}" for c in find_libllvm_candidates(search_dirs))
        seen = f" (found only {olds})" if olds else ""
        raise SetupError(
            f"no libLLVM >= {MIN_LLVM_MAJOR} found for Dr.Jit's LLVM backend{seen}; "
            f"install one with: {install_hint()}, or set {ENV_VAR}"
        )
    environ[ENV_VAR] = lib.path
    return lib


#: Debian packages tried by :func:`ensure_libllvm`, newest first.
DEBIAN_PACKAGES = ("libllvm19", "libllvm18", "libllvm17", "libllvm16")


def _run(cmd: list[str]) -> int:
    import subprocess

    print("+ " + " ".join(cmd), flush=True)
    return subprocess.call(cmd)


def ensure_libllvm(install: bool = True, search_dirs=SEARCH_DIRS, runner=_run) -> LibLLVM:
    """Find a libLLVM >= 16; when none exists and we run as root on Debian, install one.

    Raises SetupError with the command to run when it cannot install one itself.
    """
    lib = find_libllvm(search_dirs)
    if lib is not None:
        return lib
    import shutil

    can_install = (install and shutil.which("apt-get") is not None
                   and hasattr(os, "geteuid") and os.geteuid() == 0)
    if not can_install:
        raise SetupError(f"no libLLVM >= {MIN_LLVM_MAJOR} found; install one with: "
                         f"{install_hint()}")
    runner(["apt-get", "update", "-qq"])
    for package in DEBIAN_PACKAGES:
        if runner(["apt-get", "install", "-y", "-qq", package]) == 0:
            lib = find_libllvm(search_dirs)
            if lib is not None:
                return lib
    raise SetupError(f"could not install any of {', '.join(DEBIAN_PACKAGES)} with apt-get")


def main(argv: list[str] | None = None) -> int:
    """``python -m spectrace.llvm [--no-install]``: make sure a libLLVM >= 16 is present."""
    import sys

    args = sys.argv[1:] if argv is None else argv
    try:
        lib = ensure_libllvm(install="--no-install" not in args)
    except SetupError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    print(f"libLLVM {lib.major}: {lib.path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
