"""The network scenes `lattice` and `trapped-unit` in the reduced engine: their parameters (what acts, what is
refused in one line), the trapped unit's transition against its derivation (docs/network.md), collective actuation of
the pinned hexagon, the record's nodes saved and loaded."""

from __future__ import annotations

import math

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.core import observables
from elastoactive.core.errors import ParameterError
from elastoactive.core.surface import command_line
from elastoactive.records import load_trajectory, summary, write_run
from elastoactive.scenes.trap import orbit


@pytest.mark.parametrize(
    "values, name",
    [
        (dict(n=7), "n"),
        (dict(active="follower"), "active"),
        (dict(rings=0), "rings"),
        (dict(rings=7), "rings"),
        (dict(alignment_length=-0.5), "alignment_length"),
        (dict(boundary="clamped"), "boundary"),
        (dict(noise=0.1), "noise"),
        (dict(drag_ratio=2.0), "drag_ratio"),
        (dict(loaded="tip"), "loaded"),
    ],
)
def test_lattice_refuses_in_one_line_naming_the_parameter(values, name):
    with pytest.raises(ParameterError, match=rf"^{name}\b") as err:
        ea.Physics(scene="lattice", **values)
    assert "\n" not in str(err.value)


def test_network_parameters():
    physics = ea.Physics(scene="lattice", rings=3, boundary="centre", sigma=0.1)
    assert physics.active == "self-aligning" and physics.n_angles == 0
    assert physics.scene_def.network(physics).positions.shape == (37, 2)
    assert ea.Physics(scene="lattice", active="self-aligning") == ea.Physics(scene="lattice")
    assert ea.scenes.get("trapped-unit").own_parameter_names() == ("trap",)
    chain = ea.scenes.get("one-pinned")
    assert chain.kind == "chain" and not hasattr(chain, "network")  # a network's part of the contract is its kind's


@pytest.mark.parametrize("sigma, trap, la", [(0.2, 1.0, 0.4), (0.8, 0.1, 1.0), (0.5, 1.0, 0.1), (2.0, 2.0, 0.25)])
def test_trapped_unit_against_the_derivation(sigma, trap, la):
    """Pi = sigma / (trap l_a) <= 1: rest at l_e = sigma / trap; above: a circle of radius sqrt(l_e l_a) at angular
    frequency trap sqrt(Pi - 1)."""
    physics = ea.Physics(scene="trapped-unit", sigma=sigma, trap=trap, alignment_length=la)
    traj = ea.simulate(physics, duration=400 / trap, engine="reduced")
    res = ea.measure(traj)
    radius, rate = orbit(sigma, trap, la)
    assert res.orbit_radius == pytest.approx(radius, rel=1e-3)
    assert abs(res.orbit_rate) == pytest.approx(rate, rel=1e-3, abs=1e-6)
    assert abs(res.extra["polarity_rate"]) == pytest.approx(rate, rel=1e-3, abs=1e-6)
    assert res.extra["polarity_speed"] == pytest.approx(rate, rel=1e-3, abs=1e-6)  # one unit: the same way
    if rate > 0:
        assert res.frequency == pytest.approx(rate / (2 * math.pi), rel=1e-3) and res.periodic


def test_pinned_hexagon_actuates_collectively_above_threshold_and_rests_below():
    """R = 2, pinned, l_a = 0.1: at Pi = 2 every unit turns together (actuation 1, polarization ~1), the nodes beat
    at the units' turning rate, and the elastic energy condenses on the two softest (degenerate) modes; at Pi = 1
    (below the softest mode's eigenvalue, 1.136) every fixed point is stable and the patch comes to rest."""
    moving = ea.measure(
        ea.simulate(ea.Physics(scene="lattice", sigma=0.2, alignment_length=0.1), duration=300, engine="reduced")
    )
    assert moving.extra["actuation"] > 0.999 and moving.extra["polarization"] > 0.95
    assert moving.frequency == pytest.approx(abs(moving.extra["polarity_rate"]) / (2 * math.pi), rel=1e-3)
    assert moving.extra["condensation"] > 0.9
    assert {moving.extra["dominant_mode"], moving.extra["second_mode"]} == {1.0, 2.0}
    still = ea.measure(
        ea.simulate(ea.Physics(scene="lattice", sigma=0.1, alignment_length=0.1), duration=300, engine="reduced")
    )
    assert still.extra["actuation"] == 0.0 and still.amplitude < 1e-6 and still.frequency == 0.0


def test_nodes_are_saved_and_loaded(tmp_path):
    physics = ea.Physics(scene="lattice", rings=1, boundary="centre", sigma=0.3, alignment_length=0.2)
    traj = ea.simulate(physics, duration=20, engine="reduced")
    assert traj.nodes.shape == (traj.t.size, 7, 2) and traj.theta.shape == (traj.t.size, 0)
    assert traj.polarity.shape == (traj.t.size, 6)
    np.testing.assert_array_equal(traj.nodes[:, 0], 0.0)  # the pinned centre
    write_run(tmp_path, traj, summary(traj, ea.Numerics(), 20.0, sensitivity=False))
    back = load_trajectory(tmp_path)
    np.testing.assert_array_equal(back.nodes, traj.nodes)
    np.testing.assert_array_equal(back.polarity, traj.polarity)
    assert back.physics == physics


def test_a_mass_outside_the_overdamped_limit_is_refused_by_both_engines(capsys):
    """The network models are overdamped: a mass ratio whose inertia matters (m x rate > INERTIA_RESOLUTION) is
    refused in one line by the reduced engine as by MuJoCo (the reduced engine had run the massless model and recorded
    the mass)."""
    from conftest import refused

    for engine in ("reduced", "mujoco"):
        refused(
            capsys,
            ["run", "lattice", "--mass-ratio", "1", "--engine", engine, "--duration", "5", "--quiet"],
            "mass_ratio = 1",
            "overdamped",
        )


def test_a_record_too_coarse_for_the_units_turning_says_so():
    """At l_a = 1e-5 the trapped unit orbits at ~89 rad/tau, sampled every 0.05 tau: the measured orbit rate came out
    +38 against -88 (aliased, even in sign) with only a note to run longer. The record's coarseness against the fastest
    rate a term imposes (Term.rate) is now a note naming the setting; a resolved record has none."""
    physics = ea.Physics(scene="trapped-unit", alignment_length=1e-5)
    traj = ea.simulate(physics, engine="reduced", duration=2.5)
    assert any("may alias" in note and "numerics.sample_dt <=" in note for note in ea.measure(traj).notes)
    with command_line():  # the command line's entry names the options to type
        assert any("may alias" in note and "--sample-dt <=" in note for note in ea.measure(traj).notes)
    fine = ea.measure(
        ea.simulate(ea.Physics(scene="trapped-unit", sigma=0.8, trap=0.1), engine="reduced", duration=100.0)
    )
    assert not any("alias" in note for note in fine.notes)


def test_units_at_rest_are_not_actuated():
    """A trapped unit below Pi = 1 comes to rest: its polarity's residual turning (~1e-5, decaying) has no direction
    worth a ratio, so actuation is 0 (it had read 1.0, 'collective'), as for a pinned patch below onset."""
    rest = ea.measure(
        ea.simulate(ea.Physics(scene="trapped-unit", sigma=0.05, trap=0.1), engine="reduced", duration=100.0)
    )
    assert rest.extra["actuation"] == 0.0


def test_polarity_speed_reports_how_fast_units_turn_either_way():
    """Half the units turning one way, half the other: the signed mean rate is ~0, but the units turn at their rate;
    polarity_speed (mean |dpsi/dt|) says so beside it, and actuation is their ratio. Declared as every observable."""
    from elastoactive.analysis.network import observables as nobs

    t = np.linspace(0.0, 50.0, 1001)
    rates = np.array([0.5, -0.5, 0.55, -0.55, 0.5, -0.5])
    psi = np.mod(np.outer(t, rates) + np.arange(6), 2 * np.pi)
    assert abs(nobs.polarity_rate(t, psi)) < 1e-12
    assert nobs.polarity_speed(t, psi) == pytest.approx(np.abs(rates).mean(), rel=1e-9)
    assert nobs.actuation(t, psi) < 1e-9
    for scene in ("lattice", "trapped-unit"):
        assert "polarity_speed" in ea.scenes.get(scene).observable_names() and observables.known("polarity_speed")


def _degenerate_pair():
    """The pinned R = 2 patch's modes, its softest pair (lambda_1 = lambda_2) turned by `angle` within their plane."""
    from elastoactive.reduced.network import normal_modes

    values, vectors = normal_modes(ea.analysis.network.hexagonal_patch(2))
    assert values[1] - values[0] < 1e-9 * values[-1] < values[2] - values[1]

    def turned(angle):
        out = vectors.copy()
        c, s = np.cos(angle), np.sin(angle)
        out[:, 0], out[:, 1] = c * vectors[:, 0] + s * vectors[:, 1], -s * vectors[:, 0] + c * vectors[:, 1]
        return out

    return values, vectors, turned


@pytest.mark.parametrize("ratio", [1.0, 0.6])
def test_degenerate_modes_are_labelled_canonically(ratio):
    """A state on the softest degenerate pair (a circle, or an ellipse with axes 1 : ratio, tilted) reads the same
    whichever basis of the pair the eigensolver returned: the same energies and the labels 1, 2 (the more energetic
    principal axis on the lower rank; a tie to the lower rank), never 2, 1."""
    from elastoactive.analysis.network import observables as nobs

    values, vectors, turned = _degenerate_pair()
    phase = np.linspace(0.0, 2 * np.pi, 400, endpoint=False)
    tilt = turned(0.4)
    motion = 0.01 * (np.outer(np.cos(phase), tilt[:, 0]) + ratio * np.outer(np.sin(phase), tilt[:, 1]))
    motion += 1e-4 * np.outer(np.cos(3 * phase), vectors[:, 5])
    first = nobs.mode_energies(motion, values, vectors)
    for angle in np.linspace(0.0, np.pi, 13):
        modes = nobs.mode_energies(motion, values, turned(angle))
        assert modes.dominant_modes == (1, 2)
        np.testing.assert_allclose(modes.energy, first.energy, rtol=1e-9, atol=1e-18)
        assert modes.condensation == pytest.approx(first.condensation, rel=1e-12)


def _rigid_record(boundary, velocity, spin, duration=40.0):
    """A synthetic record of the R = 2 patch moving rigidly (translating at `velocity`, turning at `spin` about its
    centroid, or its pinned centre), its units aligned and still."""
    from elastoactive.core.trajectory import Trajectory

    physics = ea.Physics(scene="lattice", rings=2, boundary=boundary, sigma=0.8, alignment_length=1.0)
    network = physics.scene_def.network(physics)
    t = np.arange(0.0, duration + 1e-9, 0.05)
    angle = spin * t
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    x, y = network.positions[:, 0], network.positions[:, 1]
    nodes = np.stack([c * x - s * y, s * x + c * y], axis=-1) + np.outer(t, velocity)[:, None, :]
    polarity = np.full((t.size, int(network.active.sum())), 1.2)
    return Trajectory(
        t=t, theta=np.empty((t.size, 0)), physics=physics, engine="reduced", nodes=nodes, polarity=polarity
    )


@pytest.mark.parametrize(
    "boundary, velocity, spin", [("free", (0.3, 0.7), 0.0), ("free", (0.0, 0.8), 0.05), ("centre", (0.0, 0.0), 0.1)]
)
def test_a_patch_moving_rigidly_is_measured_apart_from_its_deformation(boundary, velocity, spin):
    """A free patch whose units have aligned translates at sigma with its units still (actuation 0): its rigid motion
    is patch_drift and patch_rotation_rate, not a beat (the beat is of the motion's rate: a steady drift or turn has
    none) and not deformation (the mode energies are those of the patch in its own frame: none, undeformed; a finite
    rotation's displacements from rest had read as energy on stiff modes)."""
    res = ea.measure(_rigid_record(boundary, velocity, spin))
    assert res.extra["patch_drift"] == pytest.approx(np.hypot(*velocity), rel=1e-9, abs=1e-9)
    assert res.extra["patch_rotation_rate"] == pytest.approx(spin, rel=1e-9, abs=1e-12)
    assert res.extra["actuation"] == 0.0 and res.extra["polarity_speed"] == 0.0
    assert res.amplitude < 1e-9 and res.frequency == 0.0
    assert res.extra["dominant_mode"] == 0.0 and res.extra["second_mode"] == 0.0
    assert math.isnan(res.extra["condensation"])
    assert "patch_drift" in ea.scenes.get("lattice").observable_names()


def test_a_free_patch_drifts_at_sigma_in_the_reduced_engine():
    """The free hexagon's units align and the patch translates at sigma |<n>| = sigma (the springs' forces sum to
    zero): patch_drift reads it; its centroid's velocity does not beat."""
    physics = ea.Physics(scene="lattice", rings=1, boundary="free", sigma=0.8, alignment_length=1.0)
    res = ea.measure(ea.simulate(physics, duration=60.0, engine="reduced"))
    assert res.extra["polarization"] > 0.9999 and res.extra["actuation"] == 0.0
    assert res.extra["patch_drift"] == pytest.approx(0.8, rel=1e-4)
    assert res.amplitude < 1e-4


def test_the_guide_lattice_examples_show_what_their_table_says():
    """The R = 3 examples of docs/beyond.md (a table row per run: coupling, sigma, duration, state, reduced / MuJoCo
    numbers): each run shows the state its row names (collective actuation: every unit turning the same way;
    mixed chirality: the units turning, some each way), its reduced numbers are the run's, and it has settled: a
    run twice as long gives the same numbers within a unit of their last quoted digit (the example had read as
    collective actuation where it was the mixed state, and had been measured before it settled)."""
    import re
    from pathlib import Path

    from elastoactive.core.trajectory import Trajectory

    guide = (Path(__file__).resolve().parents[2] / "docs" / "beyond.md").read_text()
    section = guide[guide.index("## Active solids") :]
    section = section.split("\n## ", 1)[0]  # to the next section, or the page's end
    header = [h.strip() for h in re.search(r"^\| run \| state \|(.*)\|$", section, re.M).group(1).split("|")]
    rows = re.findall(r"^\| Pi = ([\d.]+) \(sigma ([\d.]+)\), ([\d.]+) tau \| ([a-z ]+) \|(.*)\|$", section, re.M)
    assert {state for *_, state, _ in rows} == {"collective actuation", "mixed chirality"}
    for pi, sigma, duration, state, cells in rows:
        physics = ea.Physics(scene="lattice", rings=3, sigma=float(sigma), alignment_length=0.1)
        assert physics.scene_def.coupling(physics) == pytest.approx(float(pi))
        run = ea.simulate(physics, duration=2 * float(duration), engine="reduced")
        half = run.t <= float(duration) + 1e-9
        short = Trajectory(
            t=run.t[half],
            theta=run.theta[half],
            physics=physics,
            engine="reduced",
            nodes=run.nodes[half],
            polarity=run.polarity[half],
        )
        quoted = dict(zip(header, (cell.split("/")[0].strip() for cell in cells.split("|"))))
        modes = quoted.pop("modes")
        for res in (ea.measure(short), ea.measure(run)):
            got = {**res.extra, "amplitude": res.amplitude, "frequency": res.frequency}
            assert modes == f"{got['dominant_mode']:.0f}, {got['second_mode']:.0f}"
            for name, text in quoted.items():
                unit = 10.0 ** -len(text.split(".")[1]) if "." in text else 1.0
                assert abs(got[name] - float(text)) <= unit * (1 + 1e-9), (pi, name, got[name], text)
            if state == "collective actuation":
                assert got["actuation"] > 0.99
            else:
                assert got["actuation"] < 0.2 and got["polarity_speed"] > 5 * abs(got["polarity_rate"])
        psi = np.unwrap(run.polarity[~half], axis=0)
        turning = (psi[-1] - psi[0]) / (run.t[-1] - run.t[~half][0])
        assert np.all(np.abs(turning) > 0.5 * np.abs(turning).max())  # every unit turns
        assert (state == "mixed chirality") == (turning.min() < 0 < turning.max())
