"""Films and passes too large for Dr.Jit's 32-bit arrays or for the memory are refused before
anything is allocated (issue 18 B2: -D res=100000 was a traceback, res=30000 a floating-point
exception, res=20000 the OOM killer; furnace --samples 1e12 a 65 TiB allocation)."""

from __future__ import annotations

from pathlib import Path

import pytest

from spectrace import memory
from spectrace.cli import main
from spectrace.errors import ParameterError

ROOT = Path(__file__).resolve().parents[1]
SHOWCASE = ROOT / "scenes" / "showcase.xml"
EXIT_USAGE = 2


def load(res: int):
    from spectrace.scene import load_scene

    return load_scene(SHOWCASE, {"res": str(res)})


def test_film_beyond_a_dr_jit_array_is_refused(variant_rgb):
    """A 30000^2 RGB film stores 5 x 9e8 values (RGB, alpha, weight): more than 2^32."""
    with pytest.raises(ParameterError, match=r"30000x30000 film .* Dr\.Jit array"):
        memory.check_pass(load(30000), 1)
    memory.check_pass(load(29000), 1, available=2**62)  # 4.2e9 values: still fits


def test_pass_of_too_many_samples_names_the_largest_pass(variant_rgb):
    """pixels x spp_per_pass beyond 2^32: the message gives the largest spp_per_pass."""
    scene = load(1024)
    most = memory.MAX_ARRAY_WIDTH // 1024**2
    memory.check_pass(scene, most, available=2**62)
    with pytest.raises(ParameterError, match=f"spp_per_pass <= {most}"):
        memory.check_pass(scene, most + 1)


def test_memory_estimate(variant_rgb):
    """A pass needs the film's storage and the pass loop's buffers: refused when that is
    more than the memory available, which the message names."""
    scene = load(100)
    need = 100 * 100 * ((3 + memory.STORAGE_EXTRA_CHANNELS) * 4 + 3 * memory.PIXEL_BUFFERS)
    memory.check_pass(scene, 4, available=need)
    with pytest.raises(ParameterError, match="needs about .* of memory"):
        memory.check_pass(scene, 4, available=need - 1)
    assert memory.available_bytes() > 0


def test_render_refuses_before_rendering(variant_rgb):
    """spectrace.render checks before its first pass."""
    import spectrace

    with pytest.raises(ParameterError, match="Dr.Jit array"):
        spectrace.render(load(100000), spp=1)


@pytest.mark.parametrize("res", [100000, 30000])
def test_command_line_refuses_huge_films_in_one_line(tmp_path, capsys, res):
    """-D res=100000 and res=30000: exit 2, one line, nothing written (no folder either)."""
    out = tmp_path / "out" / "x.exr"
    code = main(["render", str(SHOWCASE), "-D", f"res={res}", "--spp", "1", "-q",
                 "--variant", "llvm_ad_rgb", "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == EXIT_USAGE and len(err) == 1 and err[0].startswith("error: ")
    assert f"{res}x{res}" in err[0] and not out.parent.exists()


def test_furnace_refuses_too_many_samples(capsys):
    """furnace --samples 10^12: one line naming the largest sample count, no allocation."""
    code = main(["furnace", "phong", "--samples", str(10**12), "--variant", "llvm_ad_rgb"])
    err = capsys.readouterr().err.strip()
    assert code == EXIT_USAGE and "\n" not in err and "use samples <=" in err
    with pytest.raises(ParameterError, match="of memory"):
        memory.check_furnace(10**6, 9, available=10**6)
