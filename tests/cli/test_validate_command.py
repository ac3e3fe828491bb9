"""`spectrace validate`: the table, report.md with its figures, the exit status."""

from __future__ import annotations

from spectrace.cli import main
from spectrace.validation.cases import CASES


def test_quick_run_passes_and_writes_the_report(capsys, tmp_path):
    """--quick runs every case in the default variant, prints one row per case, writes
    report.md with a figure per modelled case and exits 0."""
    rc = main(["validate", "--quick", "-o", str(tmp_path)])
    out, err = capsys.readouterr()
    assert rc == 0, out
    rows = out.splitlines()[1:-1]
    assert [row.split()[next(i for i, w in enumerate(row.split()) if w in CASES)]
            for row in rows] == list(CASES)
    report = (tmp_path / "report.md").read_text()
    assert "| family | case |" in report and "## Versions" in report
    modelled = [line for line in out.splitlines() if line.rstrip().endswith(" yes")]
    assert len(modelled) == len(list(tmp_path.glob("*.png"))) == len(CASES)


def test_a_wrong_setting_exits_1(capsys, tmp_path):
    """-D intensity=1050 (the scene 5 % brighter than its reference): exit 1, row NO."""
    rc = main(["validate", "--quick", "--case", "point_horizontal", "-D", "intensity=1050",
               "-o", str(tmp_path)])
    out, _ = capsys.readouterr()
    assert rc == 1 and out.splitlines()[1].rstrip().endswith("NO")


def test_unknown_case_one_line_and_nothing_written(capsys, tmp_path):
    rc = main(["validate", "--case", "nope", "-o", str(tmp_path / "r")])
    out, err = capsys.readouterr()
    assert rc == 2 and err.count("\n") == 1 and "--case nope" in err
    assert not (tmp_path / "r").exists()


def test_list(capsys):
    assert main(["validate", "--list"]) == 0
    out, _ = capsys.readouterr()
    assert len(out.splitlines()) == len(CASES)
