"""spectrace.sweep: the grid of <default> values, its files, resuming, the DataArray.

Oracles: the Cartesian product by hand, the local pass loop (spectrace.passes.render_passes)
of each combination with its seed, and the files' modification times.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from spectrace import sweep
from spectrace.errors import ParameterError
from spectrace.passes import render_passes

ROOT = Path(__file__).resolve().parents[1]
SHOWCASE = ROOT / "scenes" / "showcase.xml"
VARIANT = "llvm_ad_rgb"
SPP = 4
#: The film accumulates samples with parallel atomic adds: equal seeds agree up to the
#: order of float additions.
SAME_SEED_ATOL = 1e-5
SAME_SEED_RTOL = 1e-5


def test_product_order_and_file_names():
    """-D a=1,2 -D b=x,y,z with two seeds: 2 * 3 * 2 images, first parameter slowest,
    every file name distinct (also for values that differ only in unsafe characters)."""
    grid = sweep.Grid.make(SHOWCASE, sweep.parse_sweep_defines(["res=8,16", "max_depth=1,2,3"]),
                           variants=VARIANT, seeds=[0, 1], spp=SPP)
    combos = grid.combinations()
    assert len(combos) == 12 and grid.dims == ["res", "max_depth", "seed"]
    assert [c.defines["res"] for c in combos] == ["8"] * 6 + ["16"] * 6
    assert [c.seed for c in combos[:4]] == [0, 1, 0, 1]
    assert len({c.stem() for c in combos}) == 12
    a = sweep.Combination((("res", "a/b"),), VARIANT, 0)
    b = sweep.Combination((("res", "a_b"),), VARIANT, 0)
    assert a.stem() != b.stem() and "/" not in a.stem()


@pytest.mark.parametrize(("defines", "word"), [
    (["res="], "no values"),
    (["res"], "expected name="),
    (["nosuch=1,2"], "nosuch"),
])
def test_bad_grid_is_a_user_error(defines, word):
    """No values, no '=', or a name that is not a <default> of the scene."""
    with pytest.raises(ParameterError, match=word):
        sweep.Grid.make(SHOWCASE, sweep.parse_sweep_defines(defines), variants=VARIANT)


def test_sweep_equals_local_renders_and_resumes(client, tmp_path):
    """Each image of the DataArray is the local render of its combination with its seed;
    results.csv has a row per image; a re-run renders nothing and touches no image."""
    import spectrace
    from spectrace.scene import load_scene

    params = {"res": 16, "max_depth": [2, 3]}
    da = spectrace.sweep(SHOWCASE, params=params, variants=VARIANT, seeds=[0, 5], spp=SPP,
                         client=client, outdir=tmp_path)
    assert da.dims == ("res", "max_depth", "seed", "y", "x", "channel")
    assert da.shape == (1, 2, 2, 16, 16, 3)
    assert da.attrs["spp"] == SPP and da.attrs["variant"] == VARIANT
    spectrace.set_variant(VARIANT)
    for depth in ("2", "3"):
        for seed in (0, 5):
            scene = load_scene(SHOWCASE, {"res": "16", "max_depth": depth})
            local = render_passes(scene, SPP, seed=seed).image[..., :3]
            np.testing.assert_allclose(da.sel(res="16", max_depth=depth, seed=seed).values,
                                       local, rtol=SAME_SEED_RTOL, atol=SAME_SEED_ATOL)
    with open(tmp_path / sweep.RESULTS) as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["res", "max_depth", "variant", "seed", "spp", "file", "seconds",
                             "mean_luminance"]
    assert len(rows) == 4 and all((tmp_path / r["file"]).is_file() for r in rows)
    assert (tmp_path / sweep.SHEET).is_file()
    images = sorted(tmp_path.glob("*.exr")) + sorted(tmp_path.glob("*.png"))
    before = {p: p.stat().st_mtime_ns for p in images if p.name != sweep.SHEET}
    grid = sweep.Grid.make(SHOWCASE, params, VARIANT, [0, 5], SPP)
    outcomes = sweep.run(grid, None, tmp_path)  # no client: it must not need one
    assert {o.status for o in outcomes} == {"skipped"}
    assert {p: p.stat().st_mtime_ns for p in before} == before


def test_a_bad_value_fails_alone(client, tmp_path):
    """res=abc cannot be parsed: that combination is reported, the other is written."""
    grid = sweep.Grid.make(SHOWCASE, {"res": ["16", "abc"]}, VARIANT, 0, SPP)
    outcomes = sweep.run(grid, client, tmp_path)
    assert [o.status for o in outcomes] == ["rendered", "failed"]
    assert "abc" in outcomes[1].error
    assert (tmp_path / outcomes[0].file).is_file() and not (tmp_path / outcomes[1].file).exists()
    with open(tmp_path / sweep.RESULTS) as f:
        assert len(list(csv.DictReader(f))) == 1
