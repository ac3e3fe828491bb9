"""spectrace's Mitsuba plugins (import name ``spectrace.plugins``).

Each plugin lives in its own module, named after its XML type, and the module ends by
registering it with Mitsuba for the active variant. :func:`register` (re)executes the
modules in order, so that the classes are rebuilt for the variant that is active now.
"""

from __future__ import annotations

import importlib
import sys

#: Modules executed by :func:`register`, shared helpers before the plugins that use them.
PLUGIN_MODULES: tuple[str, ...] = (
    "bsdfs.lobes",
    "bsdfs.phong",
    "bsdfs.blinnphong",
    "emitters.falloff",
    "emitters.luminous",
    "emitters.delta",
    "emitters.pointlight",
    "emitters.spotlight",
    "emitters.ieslight",
    "integrators.fog",
    "integrators.local",
    "integrators.illuminance",
)

_registered_for: str | None = None


def register(force: bool = False) -> None:
    """Register every spectrace plugin for the active Mitsuba variant.

    Does nothing when the plugins are already registered for this variant, unless
    ``force`` is true.
    """
    global _registered_for
    import mitsuba as mi

    variant = mi.variant()
    if variant is None:
        raise RuntimeError("set a Mitsuba variant first (spectrace.set_variant)")
    if variant == _registered_for and not force:
        return
    for name in PLUGIN_MODULES:
        full = f"{__name__}.{name}"
        if full in sys.modules:
            importlib.reload(sys.modules[full])
        else:
            importlib.import_module(full)
    _registered_for = variant
