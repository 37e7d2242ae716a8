"""Every registered scene x every term's switch x both engines: each combination runs, or is refused before it
simulates in one line naming a parameter (ParameterError; the CLI prints it as one line, never a traceback).

The combinations come from the registries (a new scene or term is covered without editing this file): each term's
switches (its parameters that need no other one: contact, noise, drive_amplitude, active, clamp_amplitude,
drag_ratio, loaded), at a value off their default, with each choice of a text parameter that needs the switch
(clamp_motion) and each numeric one (noise_correlation). tests/test_options_apply.py holds the other half of the
rule: a parameter the scene does not have is refused everywhere.
"""

from __future__ import annotations

import json

import pytest

import elastoactive as ea
from elastoactive import terms as term_registry
from elastoactive.cli import main
from elastoactive.core import parameters, registry
from elastoactive.core.params import Numerics, scene_parameters
from elastoactive.sweep import make_sweep

SHORT = 2.0
"""tau: the shortest run every scene records and measures."""
SMALL_N = 3
"""particles per chain: the fewest every chain scene takes (the ring's minimum)."""


def _off_default(spec) -> list:
    """Values of a parameter off its default: every other choice of a text one, on for a switch, else one in range."""
    if spec.kind is bool:
        return [not spec.default]
    if spec.choices:
        return [c for c in spec.choices if c != spec.default]
    for value in (0.1, 0.5, 2.0, spec.default * 2 if spec.default else 1.0):
        try:
            if spec.check(value) != spec.default:
                return [value]
        except ea.ParameterError:
            pass
    return []


def switches() -> list[dict]:
    """Each term's switches off their default, combined with each choice of what needs them."""
    out = []
    for term in term_registry.terms():
        names = {p.name for p in term.parameters}
        for switch in (p for p in term.parameters if p.needs is None or p.needs not in names):
            for value in _off_default(switch):
                out.append({switch.name: value})
                for dependent in (
                    p for p in term.parameters if p.needs == switch.name and (p.choices or p.kind is float)
                ):
                    if dependent.need_met(value):
                        out += [{switch.name: value, dependent.name: v} for v in _off_default(dependent)]
    return out


def combinations() -> list[tuple[str, dict]]:
    cases = []
    for scene in registry.names():
        usable = set(scene_parameters(registry.get(scene)))
        for values in switches():
            if set(values) <= usable:  # a parameter the scene lacks: tests/test_options_apply.py
                base = {"n": max(SMALL_N, registry.get(scene).min_n)} if "n" in usable else {}
                cases.append((scene, {**base, **values}))
    return cases


CASES = combinations()


def _ids(case):
    scene, values = case
    return scene + ":" + ",".join(f"{k}={v}" for k, v in values.items())


def _one_line_naming(err: Exception, values: dict, scene: str) -> None:
    text = str(err)
    assert "\n" not in text.strip(), text
    named = set(values) | set(scene_parameters(registry.get(scene))) | {"engine", "mujoco", "reduced", "scene"}
    assert any(name in text for name in named), text


def test_the_matrix_covers_every_scene_and_switch():
    scenes = {scene for scene, _ in CASES}
    assert scenes == set(registry.names())
    keys = {k for _, values in CASES for k in values}
    for name in (
        "contact",
        "noise",
        "noise_correlation",
        "drive_amplitude",
        "active",
        "clamp_amplitude",
        "clamp_motion",
        "drag_ratio",
        "loaded",
    ):
        assert name in keys or not parameters.known(name), name


@pytest.mark.parametrize("case", CASES, ids=_ids)
def test_each_combination_is_a_physics_or_a_one_line_refusal(case):
    scene, values = case
    try:
        physics = ea.Physics(scene=scene, **values)
    except ea.ParameterError as err:
        _one_line_naming(err, values, scene)
        return
    assert physics.scene == scene


def _physics_or_none(scene, values):
    try:
        return ea.Physics(scene=scene, **values)
    except ea.ParameterError:
        return None


@pytest.mark.slow
@pytest.mark.parametrize("engine", ["mujoco", "reduced"])
@pytest.mark.parametrize("case", CASES, ids=_ids)
def test_each_combination_runs_or_is_refused_before_simulating(case, engine):
    scene, values = case
    physics = _physics_or_none(scene, values)
    if physics is None:  # refused at once: test above
        return
    try:
        traj = ea.simulate(
            physics, Numerics.preset("fast") if engine == "mujoco" else Numerics(), duration=SHORT, engine=engine
        )
    except ea.ParameterError as err:
        _one_line_naming(err, values, scene)
        return
    assert traj.t.size > 1
    ea.measure(traj)


@pytest.mark.parametrize("scene", registry.names())
def test_a_two_point_sweep_is_made_for_every_scene(scene):
    """make_sweep over sigma (every scene has it) sizes its arrays from the scene's physics, refusing nothing."""
    sweep = make_sweep(scene, {"sigma": [0.3, 0.5]}, numerics=Numerics(), duration=SHORT, engine="reduced")
    assert sweep.chains == sweep.physics.n_chains and sweep.size == 2


@pytest.mark.slow
@pytest.mark.parametrize("scene", registry.names())
def test_sweep_run_from_and_a_still_for_every_scene(scene, tmp_path, capsys):
    """The commands on every scene at its defaults (and a star of two arms): a 2-point sweep, a run, its re-run
    with --from, and a still of it; each either works or prints one line."""
    fixed = ["--arms", "2"] if "arms" in scene_parameters(registry.get(scene)) else []
    sweep = [
        "sweep",
        scene,
        *fixed,
        "--grid",
        "sigma=0.3,0.5",
        "--duration",
        str(SHORT),
        "--engine",
        "reduced",
        "--out",
        str(tmp_path / "sweep"),
        "--quiet",
    ]
    assert main(sweep) == 0, capsys.readouterr().err
    run = tmp_path / "run"
    assert main(["run", scene, *fixed, "--duration", str(SHORT), "--out", str(run), "--quiet"]) == 0, (
        capsys.readouterr().err
    )
    again = tmp_path / "again"
    assert main(["run", "--from", str(run), "--out", str(again), "--quiet"]) == 0, capsys.readouterr().err
    first, second = (json.loads((d / "summary.json").read_text())["results"] for d in (run, again))
    assert first == second
    code = main(["render", str(run), "--still", str(tmp_path / "still.png")])
    err = capsys.readouterr().err
    assert code == 0 or (code == 2 and err.strip().count("\n") == 0 and "Traceback" not in err), err


@pytest.mark.parametrize(
    "case",
    [c for s in registry.scenes() for c in s.validation_cases()[:1] if s.builder != "elastoactive.mjcf.chain"],
    ids=lambda c: c.physics.scene,
)
def test_the_chain_builder_refuses_a_network_in_one_line(case):
    """elastoactive.mjcf.chain builds chains; a scene of another kind handed to it is told where its model is built."""
    from elastoactive.mjcf.chain import build_model

    physics = case.physics
    with pytest.raises(ea.ParameterError, match=physics.scene_def.builder.removeprefix("elastoactive.")) as err:
        build_model(physics)
    assert "\n" not in str(err.value)
