"""Every subcommand the CLI parser lists runs end to end at its smallest size (exit 0, its files written).

The list of subcommands comes from the parser itself: a new subcommand without a smallest size here fails
test_every_subcommand_has_a_smallest_size, so none goes untried.
"""

import argparse

import pytest

from elastoactive.cli import build_parser, main


def _subcommands() -> tuple[str, ...]:
    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return tuple(action.choices)


SMALLEST = {
    "run": ["run", "one-pinned", "--n", "2", "--duration", "2", "--out", "{tmp}/run", "--quiet"],
    "validate": ["validate", "two-pinned", "--quiet"],
    "sweep": [
        "sweep",
        "one-pinned",
        "--n",
        "2",
        "--grid",
        "sigma=1,2",
        "--duration",
        "4",
        "--engine",
        "reduced",
        "--out",
        "{tmp}/sweep.nc",
        "--workers",
        "1",
        "--quiet",
    ],
    "ramp": [
        "ramp",
        "trapped-unit",
        "--ramp",
        "Pi=0.5,2",
        "--duration",
        "10",
        "--out",
        "{tmp}/ramp.nc",
        "--workers",
        "1",
        "--quiet",
    ],
    "render": ["render", "{tmp}/run", "--still", "{tmp}/still.png", "--width", "64", "--height", "48"],
    "accuracy": ["accuracy", "--tiny", "--out", "{tmp}/accuracy", "--workers", "1", "--quiet"],
    "reproduce": [
        "reproduce",
        "--tiny",
        "--only",
        "stability",
        "--out",
        "{tmp}/reproduction",
        "--workers",
        "1",
        "--quiet",
    ],
    "stability": ["stability", "one-pinned", "--n", "3"],
    "filament": ["filament", "--S", "100", "--ns", "6,8", "--quiet"],
    "whirl": ["whirl", "--S", "100", "--ns", "5,6,7", "--quiet"],
}
"""Each subcommand at its smallest size (render draws the run's folder: it runs after run)."""

WRITES = {
    "run": "run/summary.json",
    "sweep": "sweep.nc",
    "ramp": "ramp.png",
    "render": "still.png",
    "accuracy": "accuracy/accuracy.md",
    "reproduce": "reproduction/report.md",
}
"""The file each subcommand that writes must leave."""


def test_every_subcommand_has_a_smallest_size():
    assert set(_subcommands()) == set(SMALLEST)


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("commands")


@pytest.mark.parametrize("command", list(SMALLEST))
def test_subcommand_runs_at_its_smallest_size(command, folder, capsys):
    if command == "render":
        from elastoactive.render import RenderError, gl_backend

        try:
            gl_backend()
        except RenderError as err:
            pytest.skip(f"no OpenGL back end here, nothing can be rendered: {err}")
        if not (folder / "run").exists():
            assert main([a.format(tmp=folder) for a in SMALLEST["run"]]) == 0
    argv = [a.format(tmp=folder) for a in SMALLEST[command]]
    assert main(argv) == 0, capsys.readouterr().err
    if command in WRITES:
        assert (folder / WRITES[command]).stat().st_size > 0
