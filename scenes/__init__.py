"""The example scenes and their assets (import name ``spectrace.scenes``).

Installed with the package so that the studies and ``make gallery`` find them in a wheel
install as in the source tree: :func:`path` gives a scene file by name.
"""

from __future__ import annotations

from pathlib import Path

FOLDER = Path(__file__).resolve().parent


def path(name: str) -> Path:
    """The scene file ``name`` (with or without ``.xml``) of this folder."""
    return FOLDER / (name if name.endswith(".xml") else f"{name}.xml")


def names() -> list[str]:
    """Every scene of this folder, by name, sorted."""
    return sorted(p.stem for p in FOLDER.glob("*.xml"))
