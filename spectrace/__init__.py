"""spectrace: the classic shading and light models as Mitsuba 3 plugins, spectral and RGB.

Entry points: :func:`set_variant` (libLLVM set-up, Mitsuba variant, plugin registration)
and :func:`render` (the pass loop of the command line).
"""

from __future__ import annotations

import sys

__version__ = "0.1.0"
DEFAULT_VARIANT = "llvm_ad_spectral"

__all__ = ["DEFAULT_VARIANT", "RenderResult", "UserError", "render", "set_variant"]

from spectrace.errors import UserError  # noqa: E402


def set_variant(name: str = DEFAULT_VARIANT) -> None:
    """Set the Mitsuba variant ``name`` and register every spectrace plugin for it.

    Before mitsuba is first imported, points Dr.Jit at a libLLVM >= 16 (see
    :mod:`spectrace.llvm`). Calling it again switches variants and re-registers the
    plugins, since a plugin class made under one variant does not work under another.
    Raises :class:`UserError` for an unknown variant or a missing libLLVM.
    """
    if "mitsuba" not in sys.modules or name.startswith("llvm"):
        from spectrace.llvm import configure_libllvm

        try:
            configure_libllvm()
        except UserError:
            if name.startswith("llvm"):
                raise
    import mitsuba as mi

    if name not in mi.variants():
        raise UserError(f"unknown variant {name!r}; available: {', '.join(mi.variants())}")
    if mi.variant() != name:
        try:
            mi.set_variant(name)
        except (ImportError, RuntimeError) as e:  # e.g. a CUDA variant without a GPU
            first = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
            raise UserError(f"variant {name!r} cannot run on this machine: {first}") from None
    from spectrace import plugins

    plugins.register()


# The pass loop, as ``spectrace.render(scene, spp=..., seed=..., spp_per_pass=...)``.
# Bound after importing the submodule of the same name, so the name is the function.
from spectrace.passes import RenderResult, render_passes  # noqa: E402

render = render_passes
