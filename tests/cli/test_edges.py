"""Edges a new user hit (issue 18 B6, B7): messages that say what is wrong, negative numbers
as option values, a warning for an SPD that is no reflectance, an empty output refused."""

from __future__ import annotations

from pathlib import Path

import pytest
from error_checks import assert_one_line_error

from spectrace.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[2]
SHOWCASE = ROOT / "scenes" / "showcase.xml"
EXIT_USAGE = 2
SMALL = ["-D", "res=8", "--spp", "1", "-q", "--variant", "llvm_ad_rgb"]


def test_misspelt_parameter_is_named_not_the_plugin(capsys):
    """furnace phong -p exponet=2: the unknown parameter, not 'unknown plugin "phong"'."""
    assert main(["furnace", "phong", "-p", "exponet=2", "--variant", "llvm_ad_rgb"]) == 2
    err = assert_one_line_error(capsys, alone=True)
    assert "'exponet'" in err and "unknown plugin" not in err


def test_cuda_variant_without_a_gpu_says_so(tmp_path, capsys):
    """No Dr.Jit internals (jit_init(JitBackend::CUDA)) in the message."""
    import spectrace

    try:
        spectrace.set_variant("cuda_ad_rgb", lazy=True)
    except spectrace.errors.SetupError:
        pass
    else:
        spectrace.set_variant("llvm_ad_rgb")
        pytest.skip("this machine runs CUDA")
    code = main(["render", str(SHOWCASE), *SMALL[:-1], "cuda_ad_rgb",
                 "-o", str(tmp_path / "x.exr")])
    err = assert_one_line_error(capsys, alone=True)
    assert code == EXIT_USAGE and "cuda_ad_rgb" in err and "no CUDA GPU" in err
    assert "jit_" not in err and "JitBackend" not in err


def test_unknown_variant_lists_only_supported_ones(tmp_path, capsys):
    """The list after 'unknown variant' holds no scalar_* variant (which is refused)."""
    code = main(["render", str(SHOWCASE), *SMALL[:-1], "llvm_ad_nonsense",
                 "-o", str(tmp_path / "x.exr")])
    err = assert_one_line_error(capsys, alone=True)
    assert code == EXIT_USAGE and "llvm_ad_rgb" in err and "scalar_" not in err


def test_missing_ies_file_lists_each_folder_once(variant_rgb, tmp_path, monkeypatch):
    """'(looked in DIR, ...)' for a scene given by a relative path: each folder once, as an
    absolute path (it said '(looked in , DIR/bad, DIR/bad)')."""
    from spectrace.errors import FileAccessError
    from spectrace.scene import load_scene

    folder = tmp_path / "bad"
    folder.mkdir()
    scene = folder / "scene.xml"
    scene.write_text('<scene version="3.0.0"><integrator type="direct"/>'
                     '<sensor type="perspective"/><emitter type="ieslight">'
                     '<string name="filename" value="nothere.ies"/></emitter></scene>')
    monkeypatch.chdir(tmp_path)
    with pytest.raises(FileAccessError) as info:
        load_scene(Path("bad") / "scene.xml")
    message = str(info.value)
    looked = message.split("(looked in ", 1)[1].rstrip(")").split(", ")
    assert "no such file 'nothere.ies'" in message and str(folder.resolve()) in looked
    assert all(Path(f).is_absolute() for f in looked), message
    assert len(looked) == len(set(looked)), message


def test_output_below_a_file_says_which_file(tmp_path, capsys):
    """-o ok.xml/x.exr where ok.xml is a file: say so (it said 'File exists')."""
    (tmp_path / "ok.xml").write_text("")
    code = main(["render", str(SHOWCASE), *SMALL, "-o", str(tmp_path / "ok.xml" / "x.exr")])
    err = assert_one_line_error(capsys, alone=True)
    assert code == EXIT_USAGE and f"{tmp_path / 'ok.xml'} is a file, not a folder" in err


@pytest.mark.parametrize("command", [["render", str(SHOWCASE)], ["lux", str(SHOWCASE)],
                                     ["compare", "a.exr", "b.exr"]])
def test_empty_output_is_refused(tmp_path, capsys, command, monkeypatch):
    """-o '' wrote ./<scene>.exr: refused, nothing written."""
    monkeypatch.chdir(tmp_path)
    assert main([*command, "-o", ""]) == EXIT_USAGE
    assert "output path is empty" in assert_one_line_error(capsys, alone=True)
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("args", [["--range", "-5,10"], ["--range=-5,10"]])
def test_negative_numbers_are_option_values(args):
    """lux --range -5,10 reaches lux's own check (argparse took -5,10 for an option)."""
    parsed = build_parser("lux").parse_args(["lux", "s.xml", *args])
    assert parsed.value_range == "-5,10"
    parsed = build_parser("furnace").parse_args(["furnace", "phong", "--angles", "-1e1,0"])
    assert parsed.angles == [-10.0, 0.0]


def test_negative_range_is_lux_s_error_not_argparse_s(capsys, tmp_path):
    """The message is about the range (0 <= MIN), not 'expected one argument'."""
    assert main(["lux", str(SHOWCASE), "--range", "-5,10", "-o", str(tmp_path / "l.exr")]) == 2
    err = assert_one_line_error(capsys, alone=True)
    assert "--range" in err and "expected one argument" not in err


def test_spd_reflectance_beyond_one_warns(capsys):
    """spd FL11 --reflectance: a lamp's SPD is no reflectance (values up to 73): warned on
    stderr; a ColorChecker patch is not warned about."""
    assert main(["spd", "FL11", "--reflectance"]) == 0
    err = capsys.readouterr().err
    assert "warning: FL11 has values up to" in err and "not a reflectance" in err
    assert main(["spd", "dark skin"]) == 0
    assert "warning" not in capsys.readouterr().err


@pytest.mark.parametrize("item", ["res", "=8"])
def test_malformed_define_names_the_flag(tmp_path, capsys, item):
    """-D without '=' or without a name is the command line's mistake: one line naming -D,
    exit 2, nothing written (the scene is not even read)."""
    out = tmp_path / "out" / "x.exr"
    assert main(["render", str(SHOWCASE), "-D", item, "-o", str(out), "-q"]) == EXIT_USAGE
    err = assert_one_line_error(capsys, alone=True)
    assert f"-D {item!r}: expected name=value" in err, err
    assert not out.parent.exists()
