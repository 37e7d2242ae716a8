"""What the notebook tests share (test_notebook.py, test_python_api_notebook.py): a notebook executed with nbclient in
a python3 kernel of this interpreter, in a working directory of the test's, its outputs written back into the file
when ELASTOACTIVE_UPDATE_NOTEBOOK=1."""

import copy
import os
import time
from pathlib import Path

import pytest

UPDATE = os.environ.get("ELASTOACTIVE_UPDATE_NOTEBOOK") == "1"


def code_cells(nb):
    return [c for c in nb.cells if c.cell_type == "code"]


def execute(path: Path, cwd: Path, timeout: float):
    """(the executed notebook, its wall time): the test fails, naming the notebook, when a cell raises or takes more
    than `timeout` seconds."""
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    client = nbclient.NotebookClient(
        copy.deepcopy(nbformat.read(path, as_version=4)),
        timeout=timeout,
        kernel_name="python3",
        record_timing=False,
        resources={"metadata": {"path": str(cwd)}},
    )
    began = time.perf_counter()
    try:
        out = client.execute()
    except nbclient.exceptions.CellExecutionError as err:
        pytest.fail(f"a cell of {path.name} raised:\n{err}", pytrace=False)
    except TimeoutError as err:
        pytest.fail(f"a cell of {path.name} took more than {timeout:g} s: {err}", pytrace=False)
    wall = time.perf_counter() - began
    if UPDATE:
        nbformat.validate(out)
        nbformat.write(out, path)
    return out, wall
