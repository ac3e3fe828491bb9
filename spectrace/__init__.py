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

__all__ = ["DEFAULT_VARIANT", "RenderResult", "SpectraceError", "check_variant", "render",
           "set_variant", "sweep"]

from spectrace.errors import ParameterError, SetupError, SpectraceError  # noqa: E402


def set_variant(name: str = DEFAULT_VARIANT, *, lazy: bool = False) -> None:
    """Set the Mitsuba variant ``name`` and register every spectrace plugin for it.

    Before mitsuba is first imported, points Dr.Jit at a libLLVM >= 16 (see
    :mod:`spectrace.llvm`). Calling it again switches variants and re-registers the
    plugins, since a plugin class made under one variant does not work under another.
    Raises :class:`~spectrace.errors.ParameterError` for an unknown or unsupported variant,
    :class:`~spectrace.errors.SetupError` for a missing libLLVM or a variant this machine
    cannot run (a CUDA variant without a GPU).

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


def supported_variants() -> list[str]:
    """Mitsuba's variants that spectrace works in (the JIT ones)."""
    import mitsuba as mi

    return [v for v in mi.variants() if v.startswith(JIT_VARIANT_PREFIXES)]


def check_variant(name: str) -> None:
    """Raise :class:`~spectrace.errors.ParameterError` unless ``name`` is a variant
    spectrace can run (one of Mitsuba's JIT variants), :class:`~spectrace.errors.SetupError`
    when an LLVM variant finds no libLLVM >= 16 (set up here before mitsuba is first
    imported). Sets no variant: the one check :func:`set_variant` and the sweeps share."""
    if "mitsuba" not in sys.modules or name.startswith("llvm"):
        from spectrace.llvm import configure_libllvm

        try:
            configure_libllvm()
        except SpectraceError:
            if name.startswith("llvm"):
                raise
    from spectrace.signals import defer_sigint

    with defer_sigint():  # Ctrl-C inside Mitsuba's import is raised after it
        import mitsuba as mi

    if name not in mi.variants():
        raise ParameterError(f"unknown variant {name!r}; available: "
                             f"{', '.join(supported_variants())}")
    if not name.startswith(JIT_VARIANT_PREFIXES):
        raise ParameterError(
            f"variant {name!r} is not supported: spectrace's plugins are vectorized Dr.Jit "
            f"code for the JIT variants; use one of {', '.join(supported_variants())}"
        )


def _set_variant(name: str, lazy: bool) -> None:
    import mitsuba as mi

    from spectrace import registry

    if mi.variant() != name:
        try:
            registry.set_variant(name, lazy)
        except (ImportError, RuntimeError) as e:  # e.g. a CUDA variant without a GPU
            raise SetupError(f"variant {name!r} cannot run on this machine: "
                             f"{_backend_problem(name, e)}") from None
    from spectrace import mitsuba_log

    mitsuba_log.route(mi)
    if not lazy:
        registry.require_all()


def _backend_problem(name: str, error: BaseException) -> str:
    """What keeps a variant from starting, in words (Dr.Jit's own message names its C++
    functions, such as ``jit_init(JitBackend::CUDA)``)."""
    from spectrace.errors import first_line

    if name.startswith("cuda"):
        return "no CUDA GPU or driver found (use an llvm_ad_* variant)"
    return first_line(error)


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
