"""The Python API notebook (examples/python_api.ipynb) runs from top to bottom within its budget, without the command
line, so it never goes stale.

It is executed with nbclient in a python3 kernel of this interpreter, in an empty temporary working directory, and
must raise in no cell, leave that directory empty (it writes only to a tempfile folder), take at most CELL_SECONDS
per cell and NOTEBOOK_SECONDS in all.

To refresh the outputs stored in the notebook after changing it:
    ELASTOACTIVE_UPDATE_NOTEBOOK=1 .venv/bin/python -m pytest -q tests/docs/test_python_api_notebook.py
"""

from pathlib import Path

import pytest
from notebooks import code_cells, execute  # shared with test_notebook.py

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")

NOTEBOOK = Path(__file__).resolve().parents[2] / "examples" / "python_api.ipynb"
CELL_SECONDS = 30
"""Most wall time one cell may take (its first run compiles the reduced engine's kernels; a few seconds on 2 cores)."""
NOTEBOOK_SECONDS = 60
"""Most wall time the whole notebook may take, its kernel's start included."""


@pytest.fixture(scope="module")
def executed(tmp_path_factory):
    """The notebook executed in an empty temporary directory: (notebook, that directory, wall time)."""
    cwd = tmp_path_factory.mktemp("python-api-cwd")
    out, wall = execute(NOTEBOOK, cwd, CELL_SECONDS)
    return out, cwd, wall


def test_notebook_runs_within_its_budget(executed):
    nb, _, wall = executed
    for cell in code_cells(nb):
        errors = [o for o in cell.outputs if o.output_type == "error"]
        assert not errors, f"cell failed:\n{cell.source}\n{errors[0].ename}: {errors[0].evalue}"
    assert wall < NOTEBOOK_SECONDS, f"{NOTEBOOK.name} took {wall:.0f} s (budget {NOTEBOOK_SECONDS} s)"


def test_notebook_writes_nothing_in_its_working_directory(executed):
    _, cwd, _ = executed
    assert sorted(p.name for p in Path(cwd).iterdir()) == []


def test_notebook_does_without_the_command_line():
    """Run, save, load, sweep (also on Dask), ramp, stability and the two figures, through the front door only."""
    source = "\n".join(c.source for c in code_cells(nbformat.read(NOTEBOOK, as_version=4)))
    assert "elastoactive.cli" not in source and "!elastoactive" not in source and "subprocess" not in source
    for call in ("ea.simulate(", "ea.save(", "ea.load(", "ea.sweep(", "Client(", "ea.ramp(", "ea.stability("):
        assert call in source, call
    assert '"clamped-3d"' in source and '"lattice"' in source


def test_stored_notebook_has_outputs():
    """The committed notebook is executed (readable on a code host without running it), with its figures."""
    nb = nbformat.read(NOTEBOOK, as_version=4)
    nbformat.validate(nb)
    cells = code_cells(nb)
    assert cells and all(c.execution_count is not None for c in cells), "the stored notebook is not executed"
    assert sum("image/png" in o.get("data", {}) for c in cells for o in c.outputs) >= 4
    assert not any(o.output_type == "error" for c in cells for o in c.outputs)
    assert NOTEBOOK.stat().st_size < 400_000, "keep the stored outputs modest (figures at dpi ~80)"
