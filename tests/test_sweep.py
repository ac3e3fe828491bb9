"""spectrace.sweeps: the grid of <default> values, its files, resuming, the DataArray.

Oracles: the Cartesian product by hand, the local pass loop (spectrace.passes.render_passes)
of each combination with its seed, and the files' modification times.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from spectrace import sweeps
from spectrace.commands.sweep import parse_sweep_defines
from spectrace.errors import ParameterError, UsageError
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
    grid = sweeps.Grid.make(SHOWCASE, parse_sweep_defines(["res=8,16", "max_depth=1,2,3"]),
                            variants=VARIANT, seeds=[0, 1], spp=SPP)
    combos = grid.combinations()
    assert len(combos) == 12 and grid.dims == ["res", "max_depth", "seed"]
    assert grid.shape == (2, 3, 2)
    assert [c.defines["res"] for c in combos] == ["8"] * 6 + ["16"] * 6
    assert [c.seed for c in combos[:4]] == [0, 1, 0, 1]
    assert len({sweeps.stem(c) for c in combos}) == 12
    a = sweeps.Combination((("res", "a/b"),), VARIANT, 0)
    b = sweeps.Combination((("res", "a_b"),), VARIANT, 0)
    assert sweeps.stem(a) != sweeps.stem(b) and "/" not in sweeps.stem(a)


def test_axes_keep_their_types_and_one_value_is_a_scalar_coordinate():
    """Numbers stay numbers (the scene sees their text); a parameter, a variant and a seed
    of one value are all scalar coordinates, not dimensions."""
    grid = sweeps.Grid.make(SHOWCASE, {"res": 16, "max_depth": [2, 4, 4.5]}, VARIANT, 3)
    assert grid.dims == ["max_depth"]
    assert grid.coords() == {"res": 16, "max_depth": [2, 4, 4.5], "variant": VARIANT,
                             "seed": 3}
    assert [c.defines for c in grid.combinations()][1] == {"res": "16", "max_depth": "4"}


@pytest.mark.parametrize(("defines", "word"), [
    (["res="], "no values"),
    (["res"], "expected name="),
])
def test_bad_defines_are_a_usage_error(defines, word):
    """-D with no values or no '=' (the command line's parsing)."""
    with pytest.raises(UsageError, match=word):
        parse_sweep_defines(defines)


@pytest.mark.parametrize(("params", "word"), [
    ({"res": []}, "no values"),
    ({"nosuch": [1, 2]}, "nosuch"),
])
def test_bad_grid_is_a_parameter_error(params, word):
    """No values, or a name that is not a <default> of the scene: a ValueError naming it."""
    with pytest.raises(ParameterError, match=word):
        sweeps.Grid.make(SHOWCASE, params, variants=VARIANT)


def test_sweep_equals_local_renders_and_resumes(client, tmp_path):
    """Each image of the DataArray is the local render of its combination with its seed;
    results.csv has a row per image; a re-run renders nothing and touches no image."""
    import spectrace
    from spectrace.scene import load_scene

    params = {"res": 16, "max_depth": [2, 4]}
    da = spectrace.sweep(SHOWCASE, params=params, variants=VARIANT, seeds=[0, 5], spp=SPP,
                         client=client, outdir=tmp_path)
    assert da.dims == ("max_depth", "seed", "y", "x", "channel")
    assert da.shape == (2, 2, 16, 16, 3)
    assert da.attrs["spp"] == SPP and da.variant == VARIANT and da.res == 16
    spectrace.set_variant(VARIANT)
    for depth in (2, 4):
        for seed in (0, 5):
            scene = load_scene(SHOWCASE, {"res": "16", "max_depth": str(depth)})
            local = render_passes(scene, SPP, seed=seed).image[..., :3]
            np.testing.assert_allclose(da.sel(max_depth=depth, seed=seed).values,
                                       local, rtol=SAME_SEED_RTOL, atol=SAME_SEED_ATOL)
    with open(tmp_path / sweeps.RESULTS) as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["res", "max_depth", "variant", "seed", "spp", "file", "seconds",
                             "mean_luminance"]
    assert [(r["max_depth"], r["seed"], r["res"]) for r in rows] == [
        ("2", "0", "16"), ("2", "5", "16"), ("4", "0", "16"), ("4", "5", "16")]
    assert len(rows) == 4 and all((tmp_path / r["file"]).is_file() for r in rows)
    assert (tmp_path / sweeps.SHEET).is_file()
    images = sorted(tmp_path.glob("*.exr")) + sorted(tmp_path.glob("*.png"))
    before = {p: p.stat().st_mtime_ns for p in images if p.name != sweeps.SHEET}
    # the command line's text values name the same images: nothing to render again
    grid = sweeps.Grid.make(SHOWCASE, {"res": "16", "max_depth": ["2", "4"]}, VARIANT,
                            [0, 5], SPP)
    outcomes = sweeps.run(grid, None, tmp_path)  # no client: it must not need one
    assert {o.status for o in outcomes} == {"skipped"}
    assert {p: p.stat().st_mtime_ns for p in before} == before


def test_numeric_coordinates_select_by_number(client, tmp_path):
    """``da.sel(max_depth=4)`` finds the max_depth=4 image (the coordinates were strings,
    and this raised KeyError); a one-value seed is a scalar coordinate like a one-value
    parameter."""
    import spectrace

    da = spectrace.sweep(SHOWCASE, params={"res": 8, "max_depth": [1, 4]}, variants=VARIANT,
                         seeds=2, spp=SPP, client=client, outdir=tmp_path)
    assert da.max_depth.values.tolist() == [1, 4] and da.max_depth.dtype.kind == "i"
    four = da.sel(max_depth=4)
    assert four.shape == (8, 8, 3) and int(four.seed) == 2 and int(four.res) == 8
    assert float(four.mean()) > float(da.sel(max_depth=1).mean())  # more bounces, more light


def test_a_bad_value_fails_alone(client, tmp_path):
    """res=abc cannot be parsed: that combination is reported, the other is written."""
    grid = sweeps.Grid.make(SHOWCASE, {"res": ["16", "abc"]}, VARIANT, 0, SPP)
    outcomes = sweeps.run(grid, client, tmp_path)
    assert [o.status for o in outcomes] == ["rendered", "failed"]
    assert "abc" in outcomes[1].error
    assert (tmp_path / outcomes[0].file).is_file() and not (tmp_path / outcomes[1].file).exists()
    with open(tmp_path / sweeps.RESULTS) as f:
        assert len(list(csv.DictReader(f))) == 1
