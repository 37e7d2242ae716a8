"""Each scene speaks its own units: what a user reads about a scene (its own `run SCENE --help` and `sweep SCENE
--help`, summary.json's units, a sweep's netCDF attributes, ea.plot's labels) names no quantity of another system of
units that the scene does not have (no l, C1, tau or Theta on a network; no gamma/k on a chain), and a beat's amplitude
is in its signal's units (no rad on a length). Over every registered scene and term. And the coupling Pi, given in
place of sigma where a scene has one."""

from __future__ import annotations

import contextlib
import io
import json
import re

import numpy as np
import pytest

import elastoactive as ea
from elastoactive import terms
from elastoactive.cli import main
from elastoactive.core import observables, registry
from elastoactive.core.errors import ParameterError
from elastoactive.core.params import has_coupling, scene_parameters
from elastoactive.core.units import CHAIN, NETWORK, SYSTEMS, beat_signal, scene_units
from elastoactive.plot import labels
from elastoactive.sweep import make_sweep, scene_variables
from elastoactive.sweep.netcdf import scene_coordinate_attrs, scene_variable_attrs
from elastoactive.wording import observable, summary_units

SCENES = registry.names()


def foreign(scene: str) -> set[str]:
    """The symbols other systems of units name and this scene's does not."""
    own = scene_units(registry.get(scene))
    return {s for system in SYSTEMS if system != own for s in system.symbols} - set(own.symbols)


def named(text: str, symbol: str) -> bool:
    """Whether `text` names `symbol` as a whole word (l_a does not name l; 'gamma/k' is one symbol)."""
    return re.search(rf"(?<![\w^/]){re.escape(symbol)}(?![\w^])", text) is not None


def _help(argv: list[str]) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), pytest.raises(SystemExit):
        main(argv)
    return out.getvalue()


def _observed(scene: str) -> tuple[str, ...]:
    """Every observable a scene reports: the beat's, its own, and those of the terms that can act on it."""
    definition = registry.get(scene)
    usable = set(scene_parameters(definition))
    names = [o.name for o in observables.BEAT] + list(definition.observable_names())
    for term in terms.terms():
        if all(p.name in usable for p in term.parameters):
            names += term.observable_names()
    return tuple(dict.fromkeys(names))


def labels_of(scene: str) -> dict[str, str]:
    """Everything a user reads about `scene`, by where it is read."""
    physics = ea.Physics(scene)
    out = {
        "run --help": _help(["run", scene, "--help"]),
        "sweep --help": _help(["sweep", scene, "--help"]),
    }
    for key, value in summary_units(physics, dict.fromkeys(_observed(scene))).items():
        out[f"summary units {key}"] = str(value)
    sweep_keys = [k for k in scene_parameters(physics.scene_def)] + ["dt", "perturbation", "sample_dt", "mass_ratio"]
    for key in sweep_keys:
        out[f"netCDF coordinate {key}"] = " ".join(map(str, scene_coordinate_attrs(key, physics).values()))
    for name in (*scene_variables(scene), "harmonics"):
        out[f"netCDF variable {name}"] = " ".join(map(str, scene_variable_attrs(name, physics).values()))
    for field, text in vars(labels(physics)).items():
        out[f"plot {field}"] = text
    return out


@pytest.mark.parametrize("scene", SCENES)
def test_no_label_names_another_systems_quantity(scene):
    symbols = foreign(scene)
    assert symbols, "the systems of units name some symbols of their own"
    bad = [
        f"{where}: {symbol!r} in {text[:200]!r}"
        for where, text in labels_of(scene).items()
        for symbol in symbols
        if named(text, symbol)
    ]
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize("scene", SCENES)
def test_the_beat_is_in_its_signals_units(scene):
    """amplitude in the beat signal's units (a length on a held network, not rad), frequency per the scene's time."""
    physics = ea.Physics(scene)
    units, signal = scene_units(physics.scene_def), beat_signal(physics)
    assert observable("amplitude", physics).units == units.of(signal.units)
    assert signal.symbol in observable("amplitude", physics).long_name
    assert observable("frequency", physics).units == units.rate_units
    if units is NETWORK:
        assert observable("amplitude", physics).units == "a"
        assert "rad" not in scene_coordinate_attrs("perturbation", physics)["long_name"]


@pytest.mark.parametrize("term", terms.names())
def test_every_terms_labels_in_every_scene_it_acts_on(term):
    """A term's parameters and observables, on every scene where they act, name nothing of another system."""
    definition = terms.get(term)
    for scene in SCENES:
        if not all(p.name in scene_parameters(registry.get(scene)) for p in definition.parameters):
            continue
        physics, units, symbols = ea.Physics(scene), scene_units(registry.get(scene)), foreign(scene)
        texts = [f"{p.help_in(units)} [{p.units_in(units)}]" for p in definition.parameters]
        texts += [
            f"{observable(n, physics).long_name} [{observable(n, physics).units}]"
            for n in definition.observable_names()
        ]
        bad = [(scene, s, t) for t in texts for s in symbols if named(t, s)]
        assert not bad, bad


def test_units_rewrite_chain_symbols():
    assert NETWORK.of("rad/tau") == "rad k/gamma"
    assert NETWORK.of("1/tau") == "k/gamma"
    assert NETWORK.of("tau") == "gamma/k"
    assert NETWORK.of("a/tau^2") == "a k^2/gamma^2"
    assert NETWORK.of("l") == "a"
    assert CHAIN.of("rad/tau") == "rad/tau"
    assert (
        NETWORK.words("MuJoCo timestep in tau, rates in rad/tau") == "MuJoCo timestep in gamma/k, rates in rad k/gamma"
    )


def test_the_general_help_names_both_systems():
    text = " ".join(_help(["run", "--help"]).split())
    assert CHAIN.sigma in text and NETWORK.sigma in text and "run SCENE --help" in text


# ------------------------------------------------------------------ the coupling Pi


@pytest.mark.parametrize("scene", [s for s in SCENES if has_coupling(registry.get(s))])
def test_pi_gives_the_sigma_that_has_it(scene):
    physics = ea.Physics(scene, Pi=1.5, alignment_length=0.2)
    assert physics.Pi == pytest.approx(1.5, rel=1e-12)
    assert physics.sigma == pytest.approx(1.5 / physics.scene_def.coupling(physics, 1.0), rel=1e-12)
    assert "Pi" not in physics.relevant()  # sigma is recorded: --from and old runs keep working
    assert physics.replace(Pi=3.0).sigma == pytest.approx(2 * physics.sigma)
    with pytest.raises(ParameterError, match="give sigma or Pi, not both"):
        ea.Physics(scene, Pi=1.0, sigma=0.1)


def test_pi_on_the_lattice_and_the_trap():
    assert ea.Physics("lattice", Pi=1.5, alignment_length=0.1).sigma == pytest.approx(0.15)
    assert ea.Physics("trapped-unit", Pi=8.0, trap=0.1, alignment_length=1.0).sigma == pytest.approx(0.8)


def test_pi_is_refused_where_there_is_no_coupling():
    with pytest.raises(ParameterError, match="Pi has no effect on scene one-pinned"):
        ea.Physics("one-pinned", Pi=1.0)
    assert ea.Physics("one-pinned").Pi is None


def test_pi_on_a_sweeps_grid():
    sweep = make_sweep("lattice", {"Pi": [1.0, 2.0]}, fixed={"alignment_length": 0.1, "rings": 1}, engine="reduced")
    sigmas = [sweep.case(k).physics.sigma for k in range(sweep.size)]
    assert np.allclose(sigmas, [0.1, 0.2])
    assert "sigma" not in sweep.fixed  # set by the grid's Pi, not a fixed value


def test_physics_help_names_each_system_and_its_scenes():
    """help(ea.Physics) says which scenes speak which units, and what the worded parameters are on a network."""
    text = " ".join(ea.Physics.__doc__.split())
    for system in SYSTEMS:
        users = [s for s in SCENES if scene_units(registry.get(s)) == system]
        assert f"{system.name} scenes ({', '.join(users)})" in text
    assert "sigma: active force of each unit F_a / (k a)" in text


def test_a_network_run_from_the_command_line_with_pi(tmp_path, capsys):
    """`run trapped-unit --Pi 8`: sigma = Pi k_t l_a recorded, summary.json's units the network's, its notes naming
    the unit's x and gamma/k, not Theta and tau; `--from` with another --Pi sets sigma anew."""
    out = tmp_path / "run"
    argv = ["run", "trapped-unit", "--Pi", "8", "--trap", "0.1", "--engine", "reduced", "--duration", "20"]
    assert main([*argv, "--quiet", "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["parameters"]["sigma"] == pytest.approx(0.8)
    units = summary["units"]
    assert (
        units["system"] == NETWORK.name and units["time"] == "gamma/k" and units["coupling"]["Pi"] == pytest.approx(8)
    )
    assert units["results"]["frequency"] == "k/gamma" and units["results"]["amplitude"] == "a"
    assert summary["results"]["notes"]  # 20 gamma/k hold less than two turns of the orbit: said so
    for note in summary["results"]["notes"]:
        assert not any(named(note, s) for s in foreign("trapped-unit")), note
    assert main(["run", "--from", str(out), "--Pi", "4", "--quiet", "--out", str(tmp_path / "again")]) == 0
    assert json.loads((tmp_path / "again" / "summary.json").read_text())["parameters"]["sigma"] == pytest.approx(0.4)
    capsys.readouterr()
