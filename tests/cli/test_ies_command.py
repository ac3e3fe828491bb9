"""`spectrace ies`: the report of a photometric file, its polar plot, and bad files."""

from __future__ import annotations

import re

import numpy as np
import pytest
from spectrace.photometry import generate as G

from spectrace.cli import main

FLUX_RTOL = 2e-3  # printed with one decimal; the table integrates cos^n to 0.1%
ANGLE_ATOL = 0.15  # printed with one decimal; crossings between 0.5-degree samples
I0, N = 2000.0, 10


@pytest.fixture
def downlight(tmp_path):
    return G.write_ies_function(
        tmp_path / "down.ies", G.cos_power(I0, N), vertical_angles=np.arange(0.0, 90.001, 0.5),
        keywords={"TEST": "T1", "MANUFAC": "spectrace examples", "LUMINAIRE": "Spot\nnarrow",
                  "LAMP": "LED 3000 K"})


def run(capsys, *argv):
    rc = main(["ies", *argv])
    out, err = capsys.readouterr()
    return rc, out, err


def numbers(out, label):
    line = next(line for line in out.splitlines() if line.startswith(label))
    return [float(x) for x in re.findall(r"[-+]?\d+\.?\d*(?:[eE][-+]?\d+)?", line[len(label):])]


def test_report_of_a_cos_power_downlight(capsys, downlight):
    """I0 cos^10: flux 2 pi I0 / 11, peak I0 at gamma 0, beam 2 arccos(0.5^0.1) and field
    2 arccos(0.1^0.1) degrees; keywords, format and symmetry printed."""
    rc, out, err = run(capsys, str(downlight))
    assert rc == 0 and err == ""
    assert "spectrace examples" in out and "Spot narrow" in out and "LED 3000 K" in out
    assert "LM-63-2002, Type C, symmetry rotational" in out
    assert numbers(out, "angles")[:1] == [181]
    assert numbers(out, "flux")[0] == pytest.approx(2 * np.pi * I0 / (N + 1), rel=FLUX_RTOL)
    assert numbers(out, "peak")[:3] == pytest.approx([I0, 0.0, 0.0])
    beam, _, field = numbers(out, "beam")[:3]
    assert beam == pytest.approx(2 * np.degrees(np.arccos(0.5 ** (1 / N))), abs=ANGLE_ATOL)
    assert field == pytest.approx(2 * np.degrees(np.arccos(0.1 ** (1 / N))), abs=ANGLE_ATOL)


def test_plot_is_written(capsys, downlight, tmp_path):
    """--plot writes a PNG (and nothing else beside it)."""
    out_png = tmp_path / "plots" / "polar.png"
    rc, out, err = run(capsys, str(downlight), "--plot", str(out_png))
    assert rc == 0, err
    assert out_png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in out_png.parent.iterdir()] == ["polar.png"]


def test_bad_file_exits_2_with_one_line(capsys, tmp_path):
    """A truncated file and a missing file: exit status 2, one error line naming the file,
    no plot written."""
    bad = tmp_path / "cut.ies"
    good = G.write_ies_function(tmp_path / "good.ies", G.cos_power(100.0, 2))
    bad.write_bytes(good.read_bytes()[:-40])
    for path in (bad, tmp_path / "missing.ies"):
        rc, out, err = run(capsys, str(path), "--plot", str(tmp_path / "p.png"))
        assert rc == 2 and out == ""
        assert err.startswith("error: ") and err.count("\n") == 1 and str(path) in err
    assert not (tmp_path / "p.png").exists()


def test_bad_file_makes_no_plot_folder(capsys, tmp_path):
    """A file that cannot be read is refused before --plot's folder is made (an empty
    folder was left behind)."""
    plot = tmp_path / "plots" / "p.png"
    rc, out, err = run(capsys, str(tmp_path / "missing.ies"), "--plot", str(plot))
    assert rc == 2 and err.startswith("error: ")
    assert not plot.parent.exists()


def test_control_characters_of_keywords_are_not_printed(capsys, tmp_path):
    """A keyword holding terminal escape codes (ESC [2J clears the screen) is printed with
    its control characters shown as '?', never sent to the terminal."""
    path = G.write_ies_function(tmp_path / "esc.ies", G.cos_power(100.0, 2),
                                keywords={"LUMINAIRE": "Evil \x1b[2J\x07 spot"})
    rc, out, err = run(capsys, str(path))
    assert rc == 0, err
    assert "\x1b" not in out and "\x07" not in out
    assert "luminaire  Evil ?[2J? spot" in out
