"""The scenes travel with the package: every asset under scenes/ is package data.

The studies and ``make gallery`` find scenes through ``spectrace.scenes`` (installed as
package data), so that they work in a wheel install as in a checkout. A scene asset that no
``[tool.setuptools.package-data]`` pattern matches would be missing from the wheel.
"""

from __future__ import annotations

import fnmatch
from pathlib import Path

import tomllib

from spectrace import scenes

ROOT = Path(__file__).resolve().parents[1]
#: Files under scenes/ that are not data: the package's code and the generators of assets.
NOT_DATA = ("*.py", "*.pyc")


def test_every_scene_asset_is_package_data():
    """Each file under scenes/ (but the generator scripts) matches a package-data pattern."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    patterns = config["tool"]["setuptools"]["package-data"]["spectrace.scenes"]
    folder = ROOT / "scenes"
    missing = [
        str(rel) for rel in (p.relative_to(folder) for p in folder.rglob("*") if p.is_file())
        if "__pycache__" not in rel.parts
        and not any(fnmatch.fnmatch(rel.name, g) for g in NOT_DATA)
        and not any(fnmatch.fnmatch(str(rel), g) for g in patterns)
    ]
    assert missing == []


def test_scene_paths_resolve_through_the_package():
    """spectrace.scenes.path names the installed scene files; names() lists the showcase."""
    assert "showcase" in scenes.names()
    assert scenes.path("showcase").is_file()
    assert scenes.path("showcase.xml") == scenes.path("showcase")
