"""``spectrace/scene.py``: reading scene files, with one-line errors naming the file."""

from __future__ import annotations

import pytest

from spectrace.errors import FileAccessError
from spectrace.scene import read_scene_xml


def test_a_folder_is_not_a_scene_file(tmp_path):
    """A folder given as the scene is named as a folder, not as a missing file."""
    with pytest.raises(FileAccessError, match="is a folder, not a scene file"):
        read_scene_xml(tmp_path)


def test_a_missing_scene_is_named(tmp_path):
    """A path that does not exist is 'no such file', with the path."""
    missing = tmp_path / "none.xml"
    with pytest.raises(FileAccessError, match=f"{missing}: no such file"):
        read_scene_xml(missing)
