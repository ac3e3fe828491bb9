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
    beam = 2 * np.degrees(np.arccos(0.5 ** (1 / N)))
    field = 2 * np.degrees(np.arccos(0.1 ** (1 / N)))
    # "C0-C180 X deg, C90-C270 Y deg": the numbers 0, 180, X, 90, 270, Y
    assert numbers(out, "beam")[2::3][:2] == pytest.approx([beam] * 2, abs=ANGLE_ATOL)
    assert numbers(out, "field")[2::3][:2] == pytest.approx([field] * 2, abs=ANGLE_ATOL)
    assert "opening    point" in out


def test_wide_beam_is_not_defined(capsys, tmp_path):
    """An isotropic source has no beam or field angle in either plane: "not defined", not a
    number wider than a half-plane."""
    path = G.write_ies_function(tmp_path / "iso.ies", G.isotropic(50.0))
    rc, out, err = run(capsys, str(path))
    assert rc == 0, err
    beam = next(line for line in out.splitlines() if line.startswith("beam"))
    assert beam.count("not defined") == 2 and "deg" not in beam


def test_opening_and_photometric_distance(capsys, tmp_path):
    """A 2002 file with width = length = -0.2 m (a disk of 0.2 m) and one in feet with a
    box of 2 x 4 x 0.5 ft: the shape, the size in metres, the photometric distance 5x the
    largest dimension (1 m; 5 x 1.2192 m); an opening no edition knows is said so."""
    disk = G.write_ies_function(tmp_path / "disk.ies", G.cos_power(100.0, 2),
                                opening=(-0.2, -0.2, 0.0))
    rc, out, err = run(capsys, str(disk))
    assert rc == 0, err
    line = next(line for line in out.splitlines() if line.startswith("opening"))
    assert "disk" in line and "photometric distance 1 m" in line
    box = G.write_ies_function(tmp_path / "box.ies", G.cos_power(100.0, 2), units=1,
                               opening=(2.0, 4.0, 0.5))
    rc, out, err = run(capsys, str(box))
    line = next(line for line in out.splitlines() if line.startswith("opening"))
    assert "box, width 0.61 m, length 1.22 m, height 0.152 m" in line
    assert "photometric distance 6.1 m" in line
    bad = G.write_ies_function(tmp_path / "bad.ies", G.cos_power(100.0, 2),
                               opening=(0.3, -0.2, 0.0))
    rc, out, err = run(capsys, str(bad))
    assert rc == 0, err
    assert "is no shape of LM-63-2002" in out


def test_near_field_error_at_the_photometric_distance(capsys, tmp_path):
    """A Lambertian (cos gamma) disk of radius r: the near-field line gives the error of
    the point law at 5 x 2r on the axis, h^2 / (r^2 + h^2) - 1 = -1/101 = -0.99%
    (Howell B-13); a point opening has no such line."""
    disk = G.write_ies_function(tmp_path / "disk.ies", G.cos_power(100.0, 1),
                                opening=(-0.2, -0.2, 0.0),
                                vertical_angles=np.arange(0.0, 180.01, 0.5))
    rc, out, err = run(capsys, str(disk))
    assert rc == 0, err
    line = next(line for line in out.splitlines() if line.startswith("near field"))
    assert "-0.99%" in line and "1 m" in line
    point = G.write_ies_function(tmp_path / "point.ies", G.cos_power(100.0, 1))
    rc, out, err = run(capsys, str(point))
    assert "near field" not in out


def test_plot_is_written(capsys, downlight, tmp_path):
    """--plot writes a PNG (and nothing else beside it)."""
    out_png = tmp_path / "plots" / "polar.png"
    rc, out, err = run(capsys, str(downlight), "--plot", str(out_png))
    assert rc == 0, err
    assert out_png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in out_png.parent.iterdir()] == ["polar.png"]


def test_long_luminaire_name_stays_inside_the_plot(capsys, tmp_path, monkeypatch):
    """A [LUMINAIRE] text of 300 characters: the polar plot's title is wrapped and cut so
    that it lies inside the figure (it ran off both sides)."""
    import matplotlib.pyplot as plt

    name = "Linear LED luminaire with opal diffuser " * 8
    path = G.write_ies_function(tmp_path / "long.ies", G.cos_power(100.0, 2),
                                keywords={"LUMINAIRE": name})
    seen = []
    close = plt.close

    def measure_then_close(fig):  # the title's extent in the saved figure, in pixels
        title = fig.axes[0].title
        seen.append((title.get_window_extent(fig.canvas.get_renderer()), fig.bbox,
                     title.get_text()))
        close(fig)

    monkeypatch.setattr(plt, "close", measure_then_close)
    rc, out, err = run(capsys, str(path), "--plot", str(tmp_path / "p.png"))
    assert rc == 0, err
    box, frame, text = seen[0]
    assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0
    assert box.y1 <= frame.y1
    assert text.endswith(" lm, peak 100 cd") and "..." in text


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
