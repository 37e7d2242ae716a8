"""Options a network scene cannot use are refused, not dropped: an ODE method beside noise on the units (as a chain's
beside its noise), and `elastoactive stability` describes a network file by what shapes it, not by the generator's
settings it does not read."""

from __future__ import annotations

import json

import pytest
from conftest import HAND_WRITTEN, refused

import elastoactive as ea
from elastoactive.cli import main

NOISY = ea.Physics("lattice", rings=1, alignment_length=0.1, rotational_diffusion=0.01)


def test_a_method_beside_unit_noise_is_refused():
    with pytest.raises(ea.ParameterError, match=r"^method = DOP853: with noise on the units .* leave --method out$"):
        ea.simulate(NOISY, duration=1, engine="reduced", method="DOP853")


def test_a_method_beside_unit_noise_is_refused_on_the_command_line(capsys):
    argv = ["run", "lattice", "--rings", "1", "--alignment-length", "0.1", "--rotational-diffusion", "0.01"]
    refused(capsys, [*argv, "--engine", "reduced", "--method", "DOP853", "--duration", "1"], "method = DOP853")


def test_stability_of_a_file_prints_what_shapes_it(tmp_path, capsys):
    path = tmp_path / "hand.json"
    path.write_text(json.dumps(HAND_WRITTEN))
    assert main(["stability", "network", "--geometry", str(path), "--alignment-length", "0.1"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first == f"network, geometry = {path}, l_a = 0.1:"
    assert main(["stability", "network", "--geometry", "kagome", "--alignment-length", "0.1"]) == 0
    assert "size = 2, boundary = pinned" in capsys.readouterr().out.splitlines()[0]
