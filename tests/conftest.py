"""Fixtures shared by several test files."""

import pytest

HAND_WRITTEN = {
    "nodes": [[0, 0], [1, 0], [2, 0], [3, 0], [0.5, 0.9], [1.5, 0.85], [2.5, 0.9], [3.5, 0.9], [0, 1.75], [1, 1.7],
              [2, 1.8], [3, 1.75]],
    "bonds": [[0, 1], [1, 2], [2, 3], [4, 5], [5, 6], [6, 7], [8, 9], [9, 10], [10, 11], [0, 4], [1, 4], [1, 5],
              [2, 5], [2, 6], [3, 6], [3, 7], [4, 8], [4, 9], [5, 9], [5, 10], [6, 10], [6, 11], [7, 11]],
    "pinned": [0, 8, 3],
    "units": [5, 6, 9, 10, 1],
}  # fmt: skip
"""docs/network.md's network written by hand: 12 nodes, 3 pinned, 5 units, its rest lengths the initial distances
(the network tests import it: `from conftest import HAND_WRITTEN`)."""


def refused(capsys, argv, *words, code=2):
    """The command line `argv` exits `code` with one 'elastoactive: error:' line containing every word (the tests
    import this: `from conftest import refused`)."""
    from elastoactive.cli import main  # the CLI loads only in the tests that use it

    capsys.readouterr()  # what earlier calls printed
    assert main(argv) == code
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("elastoactive: error:"), err
    for word in words:
        assert word in err[0], (word, err[0])
    return err[0]


@pytest.fixture
def no_simulation(monkeypatch):
    """Fail the test if anything is simulated: the checks must come first."""
    from elastoactive import api  # the API loads only in the tests that use it

    def boom(*args, **kwargs):
        raise AssertionError("simulated before the options were checked")

    monkeypatch.setattr(api, "run_engine", boom)


@pytest.fixture(scope="module")
def tiny_studies(tmp_path_factory):
    """run(*names) -> (folder, {name: Study}): the named studies at the tiny size, saved into a fresh folder."""
    from elastoactive.studies import STUDIES  # the studies load both engines: only the tests that use them pay

    def run(*names):
        out = tmp_path_factory.mktemp("studies")
        done = {}
        for name in names:
            study = STUDIES[name]("tiny", workers=2, progress=False)
            study.save(out)
            done[name] = study
        return out, done

    return run


@pytest.fixture
def round_trip(tmp_path):
    """check(runs, name) -> the claims table: a study saved by tiny_studies reads back equal, draws its figures and
    renders claim rows with a verdict each."""
    from elastoactive.report import claims  # the studies load both engines: only the tests that use them pay
    from elastoactive.studies import SUMMARIES, load_study, registry
    from elastoactive.studies.claim_rows import VERDICTS

    def check(runs, name):
        out, done = runs
        back = load_study(out, name)
        assert isinstance(back.summary, SUMMARIES[name])
        assert back.summary.as_dict() == done[name].summary.as_dict()  # nan-safe comparison
        paths = registry.get(name).draw(back, tmp_path)
        assert paths and all(p.stat().st_size > 5000 for p in paths)
        rows = claims.build_claims({name: back})
        assert rows and all(r.agree in VERDICTS for r in rows)
        return claims.claims_table(rows)

    return check


@pytest.fixture(scope="module")
def backend():
    """The working OpenGL back end (the render tests); skips the test, saying why, where none can be made to work."""
    from elastoactive import render  # the renderer loads only in the tests that use it

    try:
        return render.gl_backend()
    except render.RenderError as err:
        pytest.skip(f"no OpenGL back end can be made to work on this machine, so nothing can be rendered: {err}")
