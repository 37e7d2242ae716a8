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
