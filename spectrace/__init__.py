"""spectrace: the classic shading and light models as Mitsuba 3 plugins, spectral and RGB.

Entry points: :func:`set_variant` (libLLVM set-up, Mitsuba variant, plugin registration)
and :func:`render` (the pass loop of the command line).
"""

from __future__ import annotations

import sys

__version__ = "0.1.0"
DEFAULT_VARIANT = "llvm_ad_spectral"
#: The variants spectrace works in (rgb, mono, spectral and their _polarized forms of each).
JIT_VARIANT_PREFIXES = ("llvm_ad_", "cuda_ad_")

__all__ = ["DEFAULT_VARIANT", "RenderResult", "UserError", "check_variant", "render",
           "set_variant", "sweep"]

from spectrace.errors import UserError  # noqa: E402


def set_variant(name: str = DEFAULT_VARIANT, *, lazy: bool = False) -> None:
    """Set the Mitsuba variant ``name`` and register every spectrace plugin for it.

    Before mitsuba is first imported, points Dr.Jit at a libLLVM >= 16 (see
    :mod:`spectrace.llvm`). Calling it again switches variants and re-registers the
    plugins, since a plugin class made under one variant does not work under another.
    Raises :class:`UserError` for an unknown variant or a missing libLLVM.

    ``lazy=True`` (the command line's choice) registers nothing yet, not even Mitsuba's
    own Python integrators: :func:`spectrace.scene.load_scene` registers the plugins a
    scene names as it loads it (:mod:`spectrace.registry`), so a scene of built-in plugins
    starts as fast as with Mitsuba's ``mitsuba`` executable. Code that then builds plugins
    itself (``mi.load_dict``) registers them first: ``spectrace.registry.require({"phong"})``.
    """
    check_variant(name)
    from spectrace.signals import defer_sigint

    with defer_sigint():
        _set_variant(name, lazy)


def check_variant(name: str) -> None:
    """Raise :class:`UserError` unless ``name`` is a variant spectrace can run: one of
    Mitsuba's JIT variants, with a libLLVM >= 16 for the LLVM ones (set up here before
    mitsuba is first imported). Sets no variant (the one check :func:`set_variant` and
    the sweeps share)."""
    if "mitsuba" not in sys.modules or name.startswith("llvm"):
        from spectrace.llvm import configure_libllvm

        try:
            configure_libllvm()
        except UserError:
            if name.startswith("llvm"):
                raise
    from spectrace.signals import defer_sigint

    with defer_sigint():  # Ctrl-C inside Mitsuba's import is raised after it
        import mitsuba as mi

    if name not in mi.variants():
        raise UserError(f"unknown variant {name!r}; available: {', '.join(mi.variants())}")
    if not name.startswith(JIT_VARIANT_PREFIXES):
        supported = [v for v in mi.variants() if v.startswith(JIT_VARIANT_PREFIXES)]
        raise UserError(
            f"variant {name!r} is not supported: spectrace's plugins are vectorized Dr.Jit "
            f"code for the JIT variants; use one of {', '.join(supported)}"
        )


def _set_variant(name: str, lazy: bool) -> None:
    import mitsuba as mi

    from spectrace import registry

    if mi.variant() != name:
        try:
            registry.set_variant(name, lazy)
        except (ImportError, RuntimeError) as e:  # e.g. a CUDA variant without a GPU
            first = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
            raise UserError(f"variant {name!r} cannot run on this machine: {first}") from None
    _plain_log_when_piped(mi)
    if not lazy:
        registry.require_all()


_plain_appender = None


def _plain_log_when_piped(mi) -> None:
    """When stderr is not a terminal, Mitsuba's log lines without their colour escape codes
    (its own appender writes them unconditionally): one plain appender to ``sys.stderr``."""
    global _plain_appender
    if _plain_appender is not None or sys.stderr.isatty():
        return

    class PlainAppender(mi.Appender):
        def append(self, level, text):
            sys.stderr.write(text.rstrip("\n") + "\n")

        def log_progress(self, progress, name, formatted, eta, ptr=None):
            pass

    _plain_appender = PlainAppender()  # kept: the logger holds no Python reference
    logger = mi.logger()
    logger.clear_appenders()
    logger.add_appender(_plain_appender)


def __getattr__(name):
    """The names imported on first use, so that ``import spectrace`` stays light.

    ``spectrace.render(scene, spp=..., seed=..., spp_per_pass=...)`` is the pass loop
    (:func:`spectrace.passes.render_passes`) and ``RenderResult`` its result;
    ``spectrace.sweep(scene, params={...})`` is :func:`spectrace.sweeps.sweep` (it imports
    Dask and xarray when called).
    """
    if name in ("render", "RenderResult"):
        from spectrace.passes import RenderResult, render_passes

        globals().update(render=render_passes, RenderResult=RenderResult)
        return globals()[name]
    if name == "sweep":
        from spectrace.sweeps import sweep

        globals()["sweep"] = sweep
        return sweep
    raise AttributeError(f"module 'spectrace' has no attribute {name!r}")
