"""`elastoactive whirl --S S` on a tiny ladder: the table and the JSON carry the continuum rate, tip radius and bend
with their error bars, the rungs are Newton's whirls (stable), and bad input gets one line naming the parameter."""

from __future__ import annotations

import json

import pytest

from elastoactive.cli import main


def test_whirl_json_on_a_tiny_ladder(capsys):
    assert main(["whirl", "--S", "100", "--ns", "5,6,7", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert [r["n"] for r in out["rungs"]] == [5, 6, 7]
    assert all(r["residual"] < 1e-10 and r["growth"] < 0 for r in out["rungs"])
    assert [r["sigma"] for r in out["rungs"]] == pytest.approx([100 / n**3 for n in (5, 6, 7)])
    omega = out["omega"]
    # the limit from N = 10..56 is 277.813 +- 5e-4 (docs/model3d.md): a ladder this coarse lands within its error bar
    assert abs(abs(omega["value"]) - 277.813) < 2 * omega["error"] < 0.15 * 277.813
    assert omega["converging"] and 0.25 < out["radius"]["value"] < 0.35 and out["bend"]["error"] > 0


def test_whirl_table(capsys):
    assert main(["whirl", "--S", "100", "--ns", "5,6,7", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "N^4 |Omega| = 266." in out and "R / L" in out and "every rung's whirl stable" in out
    assert "wall time" not in out


@pytest.mark.parametrize(
    "argv, words",
    [
        (["--S", "50"], "onset"),
        (["--S", "100", "--drag-ratio", "0"], "--drag-ratio"),
        (["--S", "100", "--ns", "3,4,5"], "--S 100"),  # N = 3 does not resolve the bending length
    ],
)
def test_whirl_refuses_bad_input(argv, words, capsys):
    assert main(["whirl", *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("elastoactive: error: ") and words in err and err.count("\n") == 1


@pytest.mark.parametrize(
    "straight, advice",
    [(True, "try a larger --S (it is 100) or a --drag-ratio nearer 1 (it is 1e+06)"), (False, "(--ns)")],
)
def test_no_whirl_says_what_happened_and_advises_the_commands_options(straight, advice, capsys, monkeypatch):
    from elastoactive.analysis import whirl

    what = "Newton's method converged to the straight chain" if straight else "Newton's method did not converge"

    def missed(*args, **kwargs):
        raise whirl.NoWhirl(f"{what} at N = 10", straight)

    monkeypatch.setattr(whirl, "continuum_whirl", missed)
    assert main(["whirl", "--S", "100", "--drag-ratio", "1e6"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"elastoactive: error: no whirl found: {what} at N = 10; ") and err.count("\n") == 1
    assert advice in err and "simulation" not in err
