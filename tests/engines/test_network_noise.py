"""Noise on a network's units (terms.unit_noise): rotational diffusion of the polarities and translational diffusion of
the nodes, Ito, seeded, in both engines. Nodes without bonds with sigma = 0, in a trap too weak to matter (TRAP t =
1e-3), diffuse freely: the mean-square displacement 4 D_t t and the polarities' 2 D_r t, against which both engines are
checked within their statistical error; the engines draw the same realisation (the counter-based stream), so they
also agree node by node."""

from __future__ import annotations

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.core.errors import ParameterError
from elastoactive.networks.files import write_network
from elastoactive.networks.geometry import make_network

NODES = 600
"""Independent free nodes: the estimates' relative standard errors are 1 / sqrt(NODES) (|dx|^2 of a 2D Gaussian,
exponential) and sqrt(2 / NODES) (dpsi^2, chi-squared with one degree of freedom)."""
D_T, D_R, DURATION = 0.02, 0.05, 1.0
TRAP = 1e-3
"""A trap's stiffness: an unbonded network needs some force for the pre-flight check's fastest rate."""


@pytest.fixture(scope="module")
def free_nodes(tmp_path_factory):
    path = tmp_path_factory.mktemp("noise") / "free.json"
    write_network(make_network(np.column_stack([3.0 * np.arange(NODES), np.zeros(NODES)]), [], trap=TRAP), path)
    return str(path)


def _physics(geometry, **noise):
    return ea.Physics(scene="network", geometry=geometry, sigma=0.0, alignment_length=0.1, **noise)


NUMERICS = ea.Numerics(perturbation=0.0, sample_dt=0.05, seed=4)


@pytest.fixture(scope="module")
def runs(free_nodes):
    physics = _physics(free_nodes, translational_diffusion=D_T, rotational_diffusion=D_R)
    return {
        engine: ea.simulate(physics, NUMERICS, duration=DURATION, engine=engine) for engine in ("reduced", "mujoco")
    }


@pytest.mark.parametrize("engine", ["reduced", "mujoco"])
def test_free_nodes_and_polarities_diffuse_at_their_rates(runs, engine):
    traj = runs[engine]
    t = traj.t[-1]
    msd = float(((traj.nodes[-1] - traj.nodes[0]) ** 2).sum(axis=-1).mean())
    angular = float(((traj.polarity[-1] - traj.polarity[0]) ** 2).mean())
    assert msd == pytest.approx(4 * D_T * t, rel=4 / np.sqrt(NODES))
    assert angular == pytest.approx(2 * D_R * t, rel=4 * np.sqrt(2 / NODES))
    assert traj.info["noise"]["seed"] == NUMERICS.seed


def test_the_engines_draw_the_same_realisation(runs):
    reduced, mujoco = runs["reduced"], runs["mujoco"]
    assert np.abs(reduced.nodes - mujoco.nodes).max() < 1e-3 * np.sqrt(2 * D_T * DURATION)
    assert np.abs(reduced.polarity - mujoco.polarity).max() < 0.02 * np.sqrt(2 * D_R * DURATION)


def test_a_noisy_run_is_reproducible_from_its_seed(free_nodes):
    physics = _physics(free_nodes, rotational_diffusion=D_R)
    first = ea.simulate(physics, NUMERICS, duration=0.5, engine="reduced")
    again = ea.simulate(physics, NUMERICS, duration=0.5, engine="reduced")
    other = ea.simulate(physics, ea.Numerics(perturbation=0.0, sample_dt=0.05, seed=5), duration=0.5, engine="reduced")
    assert np.array_equal(first.polarity, again.polarity)
    assert not np.allclose(first.polarity[-1], other.polarity[-1])


def test_noise_is_a_network_parameter_only():
    with pytest.raises(ParameterError, match="rotational_diffusion"):
        ea.Physics(scene="two-pinned", rotational_diffusion=0.1)
    with pytest.raises(ParameterError, match="translational_diffusion"):
        ea.Physics(scene="lattice", translational_diffusion=-1.0)
    assert ea.Physics(scene="lattice", rotational_diffusion=0.1).rotational_diffusion == 0.1
