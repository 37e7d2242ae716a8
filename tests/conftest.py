"""Fixtures shared by several test files."""

import pytest


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
    from elastoactive import claims  # the studies load both engines: only the tests that use them pay
    from elastoactive.studies import SUMMARIES, load_study, registry

    def check(runs, name):
        out, done = runs
        back = load_study(out, name)
        assert isinstance(back.summary, SUMMARIES[name])
        assert back.summary.as_dict() == done[name].summary.as_dict()  # nan-safe comparison
        paths = registry.get(name).draw(back, tmp_path)
        assert paths and all(p.stat().st_size > 5000 for p in paths)
        rows = claims.build_claims({name: back})
        assert rows and all(r.agree in ("yes", "no", "partly") for r in rows)
        return claims.claims_table(rows)

    return check
