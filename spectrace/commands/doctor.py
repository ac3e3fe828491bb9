"""``spectrace doctor``: versions, variants, the libLLVM found and whether the LLVM backend works.

The backend check runs in a child process, since a bad libLLVM aborts the whole process
(``LLVM ERROR: ...``) instead of raising. Exit status 1 when the LLVM backend cannot work.
"""

from __future__ import annotations

import os
import subprocess
import sys
from importlib import metadata
from pathlib import Path

from spectrace.errors import SetupError

# A tiny kernel plus a 4x4 render: exercises the JIT, including fminimum (LLVM 15 fails).
_PROBE = """
import spectrace
spectrace.set_variant("llvm_ad_rgb")
import drjit as dr, mitsuba as mi
x = dr.arange(mi.Float, 8)
assert dr.sum(dr.minimum(x, 3.0))[0] == 18.0
scene = mi.load_dict({"type": "scene", "s": {"type": "sphere"},
    "e": {"type": "constant"}, "i": {"type": "path"},
    "c": {"type": "perspective", "film": {"type": "hdrfilm", "width": 4, "height": 4}}})
assert dr.all(dr.isfinite(mi.render(scene, spp=1)).array)
print("ok")
"""


def add_arguments(parser) -> None:
    parser.add_argument("--timeout", type=float, default=120.0,
                        help="seconds allowed for the backend check (default 120)")


def kernel_cache_dir() -> Path:
    """Dr.Jit's on-disk kernel cache (``~/.drjit``)."""
    return Path.home() / ".drjit"


def _folder_summary(path: Path) -> str:
    if not path.is_dir():
        return f"{path} (not created yet)"
    files = [p for p in path.iterdir() if p.is_file()]
    size = sum(p.stat().st_size for p in files)
    return f"{path} ({len(files)} kernels, {size / 2**20:.1f} MiB)"


def _version(dist: str) -> str:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "not installed"


def check_backend(timeout: float) -> tuple[bool, str]:
    """Run the probe in a child process: (works, last line of its output)."""
    try:
        proc = subprocess.run([sys.executable, "-c", _PROBE], capture_output=True, text=True,
                              timeout=timeout, env=os.environ.copy())
    except subprocess.TimeoutExpired:
        return False, f"timed out after {timeout:.0f} s"
    out = (proc.stdout + proc.stderr).strip().splitlines()
    last = out[-1] if out else f"exit status {proc.returncode}"
    return proc.returncode == 0 and last == "ok", last


def _fix(user: str | None, candidates, install_hint) -> str:
    """The advice when no libLLVM can be used: unset the variable when it names a bad
    library while a good one is installed; otherwise install one."""
    from spectrace.llvm import ENV_VAR, MIN_LLVM_MAJOR

    good = [c for c in candidates if c.major is not None and c.major >= MIN_LLVM_MAJOR]
    if user and good:
        return (f"unset {ENV_VAR} (it names {user}; libLLVM {good[0].major} is installed at "
                f"{good[0].path} and is used when the variable is not set)")
    return install_hint()


def run(args) -> int:
    from spectrace.llvm import ENV_VAR, configure_libllvm, find_libllvm_candidates, install_hint

    rows = [(name, _version(name)) for name in ("spectrace", "mitsuba", "drjit",
                                                "colour-science", "OpenEXR", "numpy")]
    for name, version in rows:
        print(f"{name:16s} {version}")
    print(f"{'python':16s} {sys.version.split()[0]} ({sys.executable})")

    candidates = find_libllvm_candidates()
    print("libLLVM found:   " + (", ".join(f"{c.path} (LLVM {c.major})" for c in candidates)
                                 or "none"))
    user = os.environ.get(ENV_VAR)
    try:
        lib = configure_libllvm()
        origin = "from $" + ENV_VAR if user else "newest >= 16"
        print(f"libLLVM used:    {lib.path} (LLVM {lib.major}, {origin})")
    except SetupError as e:
        print(f"libLLVM used:    none: {e}")
        print(f"fix:             {_fix(user, candidates, install_hint)}")
        return 1

    import mitsuba as mi

    from spectrace import JIT_VARIANT_PREFIXES

    usable = [v for v in mi.variants() if v.startswith(JIT_VARIANT_PREFIXES)]
    others = [v for v in mi.variants() if v not in usable]
    print("variants:        " + ", ".join(usable))
    if others:
        print("not supported:   " + ", ".join(others) + " (scalar: the plugins are Dr.Jit code)")
    print("kernel cache:    " + _folder_summary(kernel_cache_dir()))
    works, detail = check_backend(args.timeout)
    print(f"LLVM backend:    {'works' if works else 'FAILS: ' + detail}")
    if not works:
        print(f"fix:             {install_hint()} (then set {ENV_VAR} if it is not found)")
        return 1
    return 0
