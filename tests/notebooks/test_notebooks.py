"""Execute every study notebook (notebooks/*.ipynb) so that none can rot.

Each notebook runs top to bottom in a fresh IPython kernel started with this very Python
(the project's .venv), at test size (SPECTRACE_QUICK=1, see spectrace.studies.budget), in
the notebooks folder. The kernel is described by a kernelspec written to a temporary
folder for this run only (nothing is installed), and Jupyter's runtime and IPython's
profile folders are temporary too, so the test needs nothing but the virtual environment.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import ipykernel  # noqa: F401  (the notebooks' kernel: a test dependency, never skipped)
import nbclient
import nbformat
import pytest
from jupyter_client.kernelspec import KernelSpecManager
from jupyter_client.manager import KernelManager

NOTEBOOKS_DIR = Path(__file__).resolve().parents[2] / "notebooks"
NOTEBOOKS = sorted(NOTEBOOKS_DIR.glob("*.ipynb"))
EXPECTED = {"spectral_vs_rgb.ipynb", "phong_vs_energy.ipynb", "light_falloff.ipynb"}
#: Seconds a single cell may run before the test fails (test size runs in seconds).
CELL_TIMEOUT = 600
KERNEL_NAME = "spectrace-test"
PROBE = "import sys\nprint(sys.prefix)"


def test_every_study_notebook_is_present():
    """The three studies of the issue exist as notebooks (and are thus executed below)."""
    assert EXPECTED <= {p.name for p in NOTEBOOKS}


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_is_committed_without_outputs(path):
    """Notebooks are stored without outputs, so no stale figure can contradict the code."""
    nb = nbformat.read(path, as_version=4)
    for cell in nb.cells:
        if cell.cell_type == "code":
            assert cell.outputs == [], f"{path.name}: a code cell has stored outputs"
            assert cell.execution_count is None, f"{path.name}: a code cell has an execution count"


@pytest.fixture
def kernel_manager(tmp_path, monkeypatch):
    """A kernel manager for this interpreter, with every Jupyter/IPython folder in tmp_path."""
    spec_dir = tmp_path / "kernels" / KERNEL_NAME
    spec_dir.mkdir(parents=True)
    (spec_dir / "kernel.json").write_text(json.dumps({
        "argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
        "display_name": "spectrace test kernel",
        "language": "python",
    }))
    monkeypatch.setenv("SPECTRACE_QUICK", "1")
    monkeypatch.setenv("JUPYTER_RUNTIME_DIR", str(tmp_path / "runtime"))
    monkeypatch.setenv("IPYTHONDIR", str(tmp_path / "ipython"))
    monkeypatch.setenv("MPLBACKEND", "module://matplotlib_inline.backend_inline")
    ksm = KernelSpecManager(kernel_dirs=[str(tmp_path / "kernels")], ensure_native_kernel=False)
    return KernelManager(kernel_name=KERNEL_NAME, kernel_spec_manager=ksm)


@pytest.mark.slow
@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_runs(path, kernel_manager):
    """The notebook executes without error, in a kernel running the project's Python."""
    nb = nbformat.read(path, as_version=4)
    nb.cells.insert(0, nbformat.v4.new_code_cell(PROBE))
    client = nbclient.NotebookClient(
        nb,
        km=kernel_manager,
        timeout=CELL_TIMEOUT,
        resources={"metadata": {"path": str(path.parent)}},
    )
    client.execute()  # raises CellExecutionError, with the traceback, on any error
    probe = "".join(o.get("text", "") for o in nb.cells[0].outputs).strip()
    assert probe == sys.prefix, "the kernel does not run in the project's environment"
    figures = sum(
        "image/png" in output.get("data", {})
        for cell in nb.cells
        if cell.cell_type == "code"
        for output in cell.outputs
    )
    assert figures > 0, f"{path.name} produced no figure"
