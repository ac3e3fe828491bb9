"""Tests of spectrace.studies, the helpers the study modules share.

Oracles: the environment variable contract, the scenes package, the depth AOV against the
camera geometry, and a hand-written table.
"""

from __future__ import annotations

import numpy as np
import pytest

from spectrace import studies
from spectrace.studies import spectral_vs_rgb


def test_budget_follows_the_quick_environment_variable(monkeypatch):
    """SPECTRACE_QUICK=1 selects the small size, anything else the normal one."""
    monkeypatch.setenv(studies.QUICK_ENV, "1")
    assert studies.budget(128, 16) == 16
    monkeypatch.setenv(studies.QUICK_ENV, "0")
    assert studies.budget(128, 16) == 128
    monkeypatch.delenv(studies.QUICK_ENV)
    assert studies.budget(128, 16) == 128


def test_scene_path_finds_the_study_scenes():
    """The scenes the notebooks render exist; an unknown name raises FileNotFoundError."""
    for name in ("phong_vs_energy", "falloff_laws", "spotlight_stage", "shading_models",
                 "shadow_acne", "fog", "fog_volpath"):
        assert studies.scene_path(name).is_file()
    with pytest.raises(FileNotFoundError):
        studies.scene_path("no_such_scene")


def test_every_study_has_its_module():
    """Each study notebook has a study module of the same name."""
    import importlib
    from pathlib import Path

    notebooks = Path(__file__).resolve().parents[2] / "notebooks"
    for name in ("spectral_vs_rgb", "phong_vs_energy", "light_falloff"):
        assert (notebooks / f"{name}.ipynb").is_file()
        importlib.import_module(f"spectrace.studies.{name}")


def test_luminance_is_the_y_row_of_the_srgb_matrix():
    """Y of linear sRGB white (1, 1, 1) is 1; of the primaries, the Rec. 709 weights."""
    np.testing.assert_allclose(studies.luminance(np.eye(3)), [0.2126, 0.7152, 0.0722],
                               atol=1e-4)
    assert studies.luminance(np.ones(3)) == pytest.approx(1.0, abs=1e-4)


def test_depth_aov_is_the_camera_distance(variant_rgb):
    """The depth AOV of the chart is the camera's height (2 m) minus the near clip distance
    (orthographic rays start on the near plane) on the patches, 0 in the gaps."""
    import mitsuba as mi

    study = spectral_vs_rgb
    layout = study.ChartLayout(2, cols=2, cell=8)
    scene = mi.load_dict(study.chart_scene(np.full((2, study.GRID.size), 0.5),
                                           study.light_spd("D65"), rgb=True, layout=layout))
    depth = studies.aov(scene, "depth")[..., 0]
    near_clip = float(mi.traverse(scene.sensors()[0])["near_clip"])
    assert depth[4, 4] == pytest.approx(2.0 - near_clip, rel=1e-6)
    assert depth[0, 0] == 0.0


def test_save_figure_writes_only_for_the_gallery(tmp_path, monkeypatch):
    """Without SPECTRACE_GALLERY nothing is written; with it, a PNG of the gallery width."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from PIL import Image

    fig, ax = plt.subplots(figsize=(4, 3))
    ax.plot([0, 1], [0, 1])
    monkeypatch.delenv(studies.GALLERY_ENV, raising=False)
    monkeypatch.chdir(tmp_path)
    assert studies.save_figure(fig, "line") is None
    assert list(tmp_path.iterdir()) == []
    monkeypatch.setenv(studies.GALLERY_ENV, str(tmp_path))
    path = studies.save_figure(fig, "line")
    plt.close(fig)
    assert path == tmp_path / "line.png"
    with Image.open(path) as image:
        assert image.width == studies.GALLERY_FIGURE_WIDTH
    assert sorted(p.name for p in tmp_path.iterdir()) == ["line.png"]  # no temporary left


def test_text_table_aligns_columns():
    """Columns are right-aligned under a rule as wide as each column."""
    text = studies.text_table(["a", "bb"], [("1", "2"), ("333", "4")])
    assert text.splitlines() == ["  a  bb", "---  --", "  1   2", "333   4"]
