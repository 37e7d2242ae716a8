"""The tutorial notebook (examples/tutorial.ipynb) runs from top to bottom, so it never goes stale.

It is executed with nbclient in a python3 kernel of this interpreter, in an empty temporary working
directory, and must raise in no cell and leave that directory empty (it writes only to tempfile
folders, never into the repository). The render cell catches RenderError itself; its picture is
checked only where an OpenGL back end works, as in test_render.py.

To refresh the outputs stored in the notebook after changing it:
    ELASTOACTIVE_UPDATE_NOTEBOOK=1 .venv/bin/python -m pytest -q tests/docs/test_notebook.py
"""

import sys
from pathlib import Path

import pytest
from notebooks import code_cells, execute  # shared with test_python_api_notebook.py

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")

NOTEBOOK = Path(__file__).resolve().parents[2] / "examples" / "tutorial.ipynb"
CELL_TIMEOUT = 300  # s; the whole notebook takes about 15 s on 2 cores


def _read():
    return nbformat.read(NOTEBOOK, as_version=4)


def _render_cell(nb):
    tagged = [c for c in code_cells(nb) if "render" in c.metadata.get("tags", [])]
    assert len(tagged) == 1, "the notebook should have exactly one code cell tagged 'render'"
    return tagged[0]


@pytest.fixture(scope="module")
def executed(tmp_path_factory):
    """The notebook executed in an empty temporary directory: (notebook, that directory)."""
    cwd = tmp_path_factory.mktemp("tutorial-cwd")
    out, _ = execute(NOTEBOOK, cwd, CELL_TIMEOUT)
    return out, cwd


def test_notebook_runs_without_error(executed):
    nb, _ = executed
    for cell in code_cells(nb):
        errors = [o for o in cell.outputs if o.output_type == "error"]
        assert not errors, f"cell failed:\n{cell.source}\n{errors[0].ename}: {errors[0].evalue}"
        assert cell.execution_count is not None


def test_notebook_writes_nothing_in_its_working_directory(executed):
    _, cwd = executed
    assert sorted(p.name for p in Path(cwd).iterdir()) == []


def test_notebook_plots_limit_cycle_and_sweep(executed):
    nb, _ = executed
    figures = [
        c
        for c in code_cells(nb)
        if any("image/png" in o.get("data", {}) for o in c.outputs) and "render" not in c.metadata.get("tags", [])
    ]
    assert len(figures) >= 2, "expected the limit-cycle and the sweep figures"


def test_render_cell_shows_a_still(executed):
    from elastoactive import render

    nb, _ = executed
    cell = _render_cell(nb)
    if any("image/png" in o.get("data", {}) for o in cell.outputs):
        return
    text = "".join(o.get("text", "") for o in cell.outputs)
    assert "Rendering skipped" in text, "the render cell neither showed a still nor said why not"
    try:  # no still: fine only if this machine cannot render (the back end chosen fails its probe)
        backend = render.gl_backend()
        reason = render.probe_backend(backend)
        reason = reason and f"MUJOCO_GL={backend}: {reason}"
    except render.RenderError as err:
        reason = str(err)
    if reason:
        pytest.skip(f"no OpenGL back end can be made to work on this machine, so nothing can be rendered: {reason}")
    pytest.fail(f"the {backend} back end renders here, yet the render cell showed no image:\n{text}")


def test_stored_notebook_has_outputs():
    """The committed notebook is executed (readable on a code host without running it) and modest in size."""
    nb = _read()
    nbformat.validate(nb)
    cells = code_cells(nb)
    assert cells and all(c.execution_count is not None for c in cells), "the stored notebook is not executed"
    assert sum("image/png" in o.get("data", {}) for c in cells for o in c.outputs) >= 2
    assert not any(o.output_type == "error" for c in cells for o in c.outputs)
    assert NOTEBOOK.stat().st_size < 400_000, "keep the stored outputs modest (figures at dpi ~80)"
    assert nb.metadata.get("kernelspec", {}).get("name") == "python3"


def test_kernel_is_this_interpreter():
    """nbclient starts the 'python3' kernel with sys.executable (so the notebook sees this install)."""
    from jupyter_client.kernelspec import KernelSpecManager

    spec = KernelSpecManager().get_kernel_spec("python3")
    assert spec.argv[0] in {"python", "python3", sys.executable}, spec.argv
