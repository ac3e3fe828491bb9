"""``spectrace sweep`` end to end: files, equality with ``spectrace render``, bad input."""

from __future__ import annotations

import csv
import time
from pathlib import Path

import numpy as np
import pytest
from error_checks import assert_one_line_error

from spectrace.cli import main
from spectrace.images import read_exr

ROOT = Path(__file__).resolve().parents[2]
SHOWCASE = ROOT / "scenes" / "showcase.xml"
VARIANT = "llvm_ad_rgb"
EXIT_USAGE = 2
EXIT_FAILED = 1
#: Equal seeds agree up to the order of the film's float additions.
SAME_SEED_RTOL = 1e-5
SAME_SEED_ATOL = 1e-6
#: An unreachable scheduler must be answered within this many seconds (issue 13).
UNREACHABLE_LIMIT_S = 30


@pytest.fixture(scope="module")
def scheduler():
    """The address of a LocalCluster of two worker processes."""
    from spectrace import cluster

    local = cluster.start_local(2)
    yield local.scheduler_address
    local.close()


@pytest.mark.parametrize(("defines", "word"), [
    (["-D", "res="], "no values"),
    (["-D", "nosuch=1,2"], "nosuch"),
])
def test_bad_grid_exits_2_and_writes_nothing(tmp_path, capsys, defines, word):
    """No values, or a name that is not a <default>: exit 2, one line, no folder."""
    out = tmp_path / "sweep"
    code = main(["sweep", str(SHOWCASE), *defines, "-o", str(out), "-q"])
    assert code == EXIT_USAGE
    assert_one_line_error(capsys, word, alone=True)
    assert not out.exists()


def test_unreachable_scheduler_exits_2_quickly(tmp_path, capsys, monkeypatch):
    """Nothing listens on port 1: exit 2 within the limit, one line, nothing written
    (the connect timeout shortened here; its default is within the limit too)."""
    from spectrace import cluster

    assert cluster.CONNECT_TIMEOUT_S < UNREACHABLE_LIMIT_S
    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT_S", 2)
    out = tmp_path / "sweep"
    start = time.perf_counter()
    code = main(["sweep", str(SHOWCASE), "-D", "res=16", "-o", str(out), "-q",
                 "--scheduler", "tcp://127.0.0.1:1"])
    assert time.perf_counter() - start < UNREACHABLE_LIMIT_S
    assert code == EXIT_USAGE
    assert_one_line_error(capsys, "tcp://127.0.0.1:1", alone=True)
    assert not out.exists()


def test_sweep_writes_images_equal_to_render_and_names_failures(tmp_path, capsys, scheduler):
    """On a cluster: res=16 is written as `spectrace render -D res=16 -D max_depth=2` writes
    it (same seed), res=abc fails alone and is named; exit status 1."""
    out = tmp_path / "sweep"
    code = main(["sweep", str(SHOWCASE), "-D", "res=16,abc", "-D", "max_depth=2",
                 "--variants", VARIANT, "--seeds", "3", "--spp", "4", "-o", str(out), "-q",
                 "--scheduler", scheduler])
    assert code == EXIT_FAILED
    err = capsys.readouterr().err
    assert "error: res=abc" in err and "Traceback" not in err
    with open(out / "results.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 1 and rows[0]["res"] == "16" and rows[0]["seed"] == "3"
    assert (out / "sheet.png").is_file() and (out / rows[0]["file"]).with_suffix(".png").is_file()
    ref = tmp_path / "ref.exr"
    assert main(["render", str(SHOWCASE), "-D", "res=16", "-D", "max_depth=2", "--seed", "3",
                 "--spp", "4", "--variant", VARIANT, "-o", str(ref), "-q"]) == 0
    np.testing.assert_allclose(read_exr(out / rows[0]["file"])[0], read_exr(ref)[0],
                               rtol=SAME_SEED_RTOL, atol=SAME_SEED_ATOL)


def test_outdir_that_is_a_file_exits_2_before_any_cluster(tmp_path, capsys, monkeypatch):
    """OUTDIR is a file, or lies under one: exit 2 with one line saying so, before a cluster
    is started (the message was 'File exists', after the workers had started)."""
    from spectrace import cluster

    def no_cluster(*args, **kwargs):
        raise AssertionError("a cluster was started")

    monkeypatch.setattr(cluster, "connect", no_cluster)
    a_file = tmp_path / "taken"
    a_file.write_text("not a folder")
    for out, words in ((a_file, ("is a file",)), (a_file / "sub", ("inside", "is a file"))):
        code = main(["sweep", str(SHOWCASE), "-D", "res=16", "-o", str(out), "-q"])
        assert code == EXIT_USAGE
        assert_one_line_error(capsys, str(out), *words, alone=True)
    assert a_file.read_text() == "not a folder"


def test_escaped_comma_long_values_and_seed_range(tmp_path, capsys):
    """`\\,` keeps a comma inside a value (an RGB triple); a value too long for a file name
    gets a short unique stem (it raised 'File name too long'); seeds must fit 32 bits."""
    from spectrace import sweeps
    from spectrace.commands.sweep import parse_sweep_defines

    params = parse_sweep_defines([r"color=0.9\,0.1\,0.1,1\,1\,1", "res=8,8,16"])
    assert params == {"color": ["0.9,0.1,0.1", "1,1,1"], "res": ["8", "16"]}
    long_a, long_b = "a" * 400, "a" * 399 + "b"
    stems = [sweeps.stem(sweeps.Combination((("name", v),), "llvm_ad_rgb", 0))
             for v in (long_a, long_b)]
    assert len(set(stems)) == 2
    assert all(len(s.encode()) <= sweeps.files.MAX_STEM for s in stems)
    assert all(s.endswith("_llvm_ad_rgb_seed0") for s in stems)
    out = tmp_path / "sweep"
    code = main(["sweep", str(SHOWCASE), "-D", "res=8", "--seeds", "99999999999", "-o",
                 str(out), "-q"])
    assert code == EXIT_USAGE
    assert_one_line_error(capsys, "seeds must be between", "(got 99999999999)", alone=True)
    assert not out.exists()


def test_ctrl_c_says_how_many_images_are_kept(tmp_path, capsys, monkeypatch):
    """Ctrl-C during a sweep: exit 130 and one line saying how many images are in OUTDIR
    for a re-run to skip (it printed only 'interrupted')."""
    import contextlib

    from spectrace import cluster
    from spectrace.commands import sweep as sweep_command

    class Client:
        def scheduler_info(self, n_workers=-1):
            return {"workers": {"tcp://127.0.0.1:1": {}}}

    def interrupted_run(sweep, grid, client, outdir, outcomes, quiet, display=None):
        outcomes[0].status = "rendered"  # one image written, then Ctrl-C
        raise KeyboardInterrupt

    monkeypatch.setattr(cluster, "connect", lambda *a, **k: contextlib.nullcontext(Client()))
    monkeypatch.setattr(sweep_command, "_run_with_progress", interrupted_run)
    code = main(["sweep", str(SHOWCASE), "-D", "res=8,16", "-o", str(tmp_path / "s"), "-q"])
    assert code == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1] == f"interrupted: 1 of 2 images are in {tmp_path / 's'} (a re-run skips them)"


def test_sweep_display_options_change_the_pngs_only(tmp_path, capsys, scheduler):
    """--exposure/--view: each image's EXR is bit-identical to the sweep's without them
    (same seed), its PNG made by the display pipeline differs."""
    runs = {}
    for name, extra in (("plain", []), ("shown", ["--exposure", "2", "--view", "neutral"])):
        out = tmp_path / name
        assert main(["sweep", str(SHOWCASE), "-D", "res=16", "-D", "max_depth=2,3",
                     "--variants", VARIANT, "--spp", "4", "-o", str(out), "-q",
                     "--scheduler", scheduler, *extra]) == 0
        runs[name] = sorted(out.glob("*.exr"))
    assert len(runs["plain"]) == 2
    for plain, shown in zip(runs["plain"], runs["shown"], strict=True):
        np.testing.assert_array_equal(read_exr(plain)[0], read_exr(shown)[0])
        assert plain.with_suffix(".png").read_bytes() != shown.with_suffix(".png").read_bytes()


def test_sweep_bad_display_option_exits_2_and_writes_nothing(tmp_path, capsys):
    """--exposure nan: one line naming the flag, exit 2, no folder, no cluster."""
    out = tmp_path / "sweep"
    code = main(["sweep", str(SHOWCASE), "-D", "res=16", "-o", str(out), "-q",
                 "--exposure", "nan"])
    assert code == EXIT_USAGE
    assert_one_line_error(capsys, "--exposure")
    assert not out.exists()
