"""docs/teaching/lab.ipynb runs end to end, and its certify cells say what the lab says they say.

The notebook is executed with nbclient in a kernel of this very interpreter (CTest's
/usr/bin/python3) whose environment is this process's (PYTHONPATH=build/python, OCT_SOURCE_DIR),
from the repository root. The kernel is named by a kernel spec written to a temporary folder,
so neither a user's nor the system's `python3` spec (nor ipykernel's fallback to whichever
interpreter runs Jupyter) decides which Python and which octrace the lab sees; a first cell
added here checks both. By hand:
    PYTHONPATH=build/python /usr/bin/python3 -m pytest -q tests/python/test_notebook.py
"""
import json
import os
import pathlib
import re
import sys
import time

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")
from jupyter_client.kernelspec import KernelSpecManager  # noqa: E402 (after the skips)
from jupyter_client.manager import KernelManager  # noqa: E402

import octrace  # noqa: E402

ROOT = pathlib.Path(os.environ.get("OCT_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
NOTEBOOK = ROOT / "docs" / "teaching" / "lab.ipynb"
KERNEL = "octrace-lab"
CELL_TIMEOUT_S = 120  # the slowest cell takes about a second on 2 cores

# Prepended to the notebook: which interpreter the kernel runs and where it found octrace
# (a plain import: the lab's own first cell falls back to build/python when PYTHONPATH is unset,
# which would hide a kernel that did not inherit it).
PROBE = """
import sys, octrace
print("KERNEL", sys.executable)
print("OCTRACE", octrace.__file__)
"""


def kernel_spec_dir(tmp):
    spec = tmp / "kernels" / KERNEL
    spec.mkdir(parents=True)
    (spec / "kernel.json").write_text(json.dumps({
        # -Xfrozen_modules=off: no debugger warning about frozen modules on stderr.
        "argv": [sys.executable, "-Xfrozen_modules=off", "-m", "ipykernel_launcher",
                 "-f", "{connection_file}"],
        "display_name": "octrace lab (test)",
        "language": "python",
        "env": {"PYTHONPATH": os.environ.get("PYTHONPATH", ""),
                "OCT_SOURCE_DIR": str(ROOT),
                "PYDEVD_DISABLE_FILE_VALIDATION": "1"},
        "metadata": {"debugger": False},
    }))
    return tmp / "kernels"


def stdout_of(cell):
    return "".join(o.get("text", "") for o in cell.get("outputs", [])
                   if o.output_type == "stream" and o.name == "stdout")


@pytest.fixture(scope="module")
def executed(tmp_path_factory):
    """The notebook after execution, and how long it took."""
    nb = nbformat.read(NOTEBOOK, as_version=4)
    nb.cells.insert(0, nbformat.v4.new_code_cell(PROBE.strip()))
    km = KernelManager(kernel_name=KERNEL, kernel_spec_manager=KernelSpecManager(
        kernel_dirs=[str(kernel_spec_dir(tmp_path_factory.mktemp("jupyter")))]))
    client = nbclient.NotebookClient(nb, km=km, timeout=CELL_TIMEOUT_S, kernel_name=KERNEL,
                                     resources={"metadata": {"path": str(ROOT)}})
    start = time.perf_counter()
    try:
        client.execute()
    except nbclient.exceptions.CellExecutionError as e:
        pytest.fail(f"{NOTEBOOK} failed in a cell:\n{e}")
    finally:  # a kernel manager given to nbclient is the caller's to shut down
        if km.has_kernel:
            km.shutdown_kernel(now=True)
    return nb, time.perf_counter() - start


def tagged(nb, tag):
    cells = [c for c in nb.cells if tag in c.get("metadata", {}).get("tags", [])]
    assert len(cells) == 1, f"one cell tagged {tag!r} in {NOTEBOOK}, found {len(cells)}"
    return stdout_of(cells[0])


def test_the_kernel_is_this_python_with_this_octrace(executed):
    nb, _ = executed
    out = stdout_of(nb.cells[0])
    kernel = re.search(r"^KERNEL (.+)$", out, re.M).group(1)
    module = re.search(r"^OCTRACE (.+)$", out, re.M).group(1)
    assert os.path.realpath(kernel) == os.path.realpath(sys.executable)
    assert os.path.realpath(module) == os.path.realpath(octrace.__file__)


def test_every_code_cell_ran_without_an_error(executed):
    nb, seconds = executed
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert all(c.get("execution_count") for c in code)
    errors = [o for c in code for o in c.outputs if o.output_type == "error"]
    assert not errors, errors
    print(f"{NOTEBOOK.name}: {len(code) - 1} code cells in {seconds:.1f} s")


def test_the_textbook_tracer_is_certified_correct(executed):
    out = tagged(executed[0], "certify-correct")
    assert re.search(r"^outcome: PASS$", out, re.M), out
    assert re.search(r"^wrong rays: 0$", out, re.M), out


def test_the_broken_tracer_fails_with_its_wrong_rays_selected(executed):
    out = tagged(executed[0], "certify-broken")
    assert re.search(r"^outcome: FAIL$", out, re.M), out
    wrong = re.search(r"^wrong rays: (\d+)$", out, re.M)
    assert wrong and int(wrong.group(1)) > 0, out
    # The rows it names are judged t_outside_range: the bug is the forgotten segment.
    assert "t_outside_range" in out, out


def test_the_notebook_is_stored_without_outputs():
    nb = nbformat.read(NOTEBOOK, as_version=4)
    nbformat.validate(nb)
    for cell in nb.cells:
        if cell.cell_type == "code":
            assert cell.outputs == [] and cell.execution_count is None, cell.source[:60]
