"""Fixtures of the render tests."""

import pytest

from elastoactive import render


@pytest.fixture(scope="module")
def backend():
    """The working OpenGL back end; the test is skipped, saying why, where none can be made to work."""
    try:
        return render.gl_backend()
    except render.RenderError as err:
        pytest.skip(f"no OpenGL back end can be made to work on this machine, so nothing can be rendered: {err}")
