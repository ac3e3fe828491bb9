"""The user's cache folder of spectrace: data derived once from installed packages and kept
between runs (V(lambda) from colour-science, the cylinder mesh of ``ieslight`` openings)."""

from __future__ import annotations

import os
from pathlib import Path


def cache_folder() -> Path:
    """``$XDG_CACHE_HOME/spectrace``, or ``~/.cache/spectrace`` (not created here)."""
    root = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(root) / "spectrace"
