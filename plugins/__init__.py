"""spectrace's Mitsuba plugins (import name ``spectrace.plugins``).

Each plugin lives in its own module, named after its XML type, and the module ends by
registering it with Mitsuba for the active variant. :func:`register` (re)executes the
modules in order, so that the classes are rebuilt for the variant that is active now: all
of them, or only those of the plugins a scene names (what the command line does, see
:mod:`spectrace.registry`).
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
    "emitters.opening",
    "emitters.sized",
    "emitters.pointlight",
    "emitters.spotlight",
    "emitters.ieslight",
    "emitters.solar",
    "emitters.distant",
    "emitters.ciesky",
    "emitters.sun",
    "integrators.fog",
    "integrators.local",
    "integrators.illuminance",
    "integrators.lightgroups",
)
#: The modules that register no plugin of their own: the shared helpers, executed before any
#: plugin module (the classes they define are rebuilt for the variant like the plugins).
HELPER_MODULES: frozenset[str] = frozenset(
    {"bsdfs.lobes", "emitters.falloff", "emitters.luminous", "emitters.delta", "emitters.solar",
     "emitters.distant", "emitters.opening", "emitters.sized", "integrators.fog"}
)
#: XML type name -> the module that registers it (a plugin module is named after its type).
PLUGINS: dict[str, str] = {
    module.rpartition(".")[2]: module for module in PLUGIN_MODULES if module not in HELPER_MODULES
}

#: module -> the variant it was last executed for.
_executed: dict[str, str] = {}


def register(names=None, force: bool = False) -> list[str]:
    """Register spectrace's plugins for the active Mitsuba variant: every plugin, or those
    among ``names`` (XML type names; other names are ignored), with the helpers they use.

    A plugin already registered for this variant is left as it is, unless ``force`` is true.
    Returns the names of the plugins this call registered.
    """
    import mitsuba as mi

    variant = mi.variant()
    if variant is None:
        raise RuntimeError("set a Mitsuba variant first (spectrace.set_variant)")
    wanted = set(PLUGINS) if names is None else set(names) & set(PLUGINS)
    todo = [PLUGINS[name] for name in wanted
            if force or _executed.get(PLUGINS[name]) != variant]
    if not todo:
        return []
    for module in PLUGIN_MODULES:  # in order: the helpers before the plugins using them
        if module in todo or (module in HELPER_MODULES
                              and (force or _executed.get(module) != variant)):
            full = f"{__name__}.{module}"
            if full in sys.modules:
                importlib.reload(sys.modules[full])
            else:
                importlib.import_module(full)
            _executed[module] = variant
    return sorted(name for name in wanted if PLUGINS[name] in todo)
