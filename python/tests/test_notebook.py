# examples/python/inverse_design.ipynb runs headless from top to bottom (nbclient with an
# ipykernel of this interpreter, in a scratch folder): a cell that raises, or one of its own
# asserts (Taylor test passed, SciPy at least as low as `tailor run`, the designed beam's tip
# moving 0.8), fails the test. Skipped where nbclient, nbformat or ipykernel is not installed
# (Debian: python3-nbclient, python3-nbformat, python3-ipykernel).
import os

import pytest

import tailor
from conftest import SOURCE_DIR

NOTEBOOK = SOURCE_DIR / "examples" / "python" / "inverse_design.ipynb"


def test_inverse_design_notebook_runs(tmp_path, monkeypatch):
    nbclient = pytest.importorskip("nbclient", reason="nbclient is not installed (Debian: python3-nbclient)")
    nbformat = pytest.importorskip("nbformat", reason="nbformat is not installed (Debian: python3-nbformat)")
    pytest.importorskip("ipykernel", reason="ipykernel is not installed (Debian: python3-ipykernel)")
    pytest.importorskip("matplotlib", reason="matplotlib is not installed (Debian: python3-matplotlib)")
    # The kernel inherits the environment: the package these tests import, the source tree for
    # the scenes, and no byte code written next to the sources.
    monkeypatch.setenv("PYTHONPATH", os.path.dirname(os.path.dirname(os.path.abspath(tailor.__file__))))
    monkeypatch.setenv("TAILOR_SOURCE_DIR", str(SOURCE_DIR))
    monkeypatch.setenv("PYTHONDONTWRITEBYTECODE", "1")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.setenv("PYDEVD_DISABLE_FILE_VALIDATION", "1")
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    assert all(not cell.get("outputs") for cell in notebook.cells if cell.cell_type == "code"), \
        "the notebook is stored without outputs"
    client = nbclient.NotebookClient(notebook, timeout=300, kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})
    client.execute()  # CellExecutionError names the cell and its traceback
    outputs = "".join(o.get("text", "") for cell in notebook.cells if cell.cell_type == "code"
                      for o in cell.outputs)
    assert "tip displacement with the design" in outputs
    assert not any(tmp_path.iterdir()), "the notebook wrote into its working folder"


def test_a_failing_cell_fails_the_run(tmp_path):
    nbclient = pytest.importorskip("nbclient", reason="nbclient is not installed (Debian: python3-nbclient)")
    nbformat = pytest.importorskip("nbformat", reason="nbformat is not installed (Debian: python3-nbformat)")
    pytest.importorskip("ipykernel", reason="ipykernel is not installed (Debian: python3-ipykernel)")
    notebook = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("x = 1"),
                                               nbformat.v4.new_code_cell("assert x == 2, 'seen'")])
    client = nbclient.NotebookClient(notebook, timeout=60, kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})
    with pytest.raises(nbclient.exceptions.CellExecutionError, match="seen"):
        client.execute()
