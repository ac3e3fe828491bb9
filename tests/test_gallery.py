"""The README gallery's composed thumbnails (issue 18 B8): shadow_acne at bias 0 beside
bias 0.01, phong_vs_energy's grid with its rows and columns labelled."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
from PIL import Image

ROOT = Path(__file__).resolve().parents[1]


def gallery():
    spec = importlib.util.spec_from_file_location("make_gallery", ROOT / "docs" / "make_gallery.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_pair_is_shown_side_by_side_and_grid_labelled(tmp_path):
    """Two renders (black, white) become one thumbnail: the left half from the first, the
    right from the second, under a label strip; a labelled grid gains a margin and a strip
    with dark label pixels in them."""
    g = gallery()
    renders = tmp_path / "renders"
    renders.mkdir()
    Image.new("RGB", (64, 64), "black").save(renders / "shadow_acne.png")
    Image.new("RGB", (64, 64), "white").save(renders / "shadow_acne_biased.png")
    Image.new("RGB", (64, 64), (128, 128, 128)).save(renders / "phong_vs_energy.png")
    assert g.main(["--renders", str(renders), "--out", str(tmp_path / "out"), "--width", "64",
                   "--no-notebooks"]) == 0
    scenes = tmp_path / "out" / "scenes"
    assert sorted(p.name for p in scenes.iterdir()) == ["phong_vs_energy.png", "shadow_acne.png"]
    pair = np.asarray(Image.open(scenes / "shadow_acne.png").convert("L"), np.float64)
    assert pair.shape == (32 + g.LABEL_PX, 64)
    assert pair[g.LABEL_PX:, :32].max() == 0 and pair[g.LABEL_PX:, 32:].min() == 255
    grid = np.asarray(Image.open(scenes / "phong_vs_energy.png").convert("L"), np.float64)
    assert grid.shape[0] == 64 + g.LABEL_PX and grid.shape[1] > 64
    margin = grid.shape[1] - 64
    assert grid[:g.LABEL_PX].min() < 100 and grid[g.LABEL_PX:, :margin].min() < 100
