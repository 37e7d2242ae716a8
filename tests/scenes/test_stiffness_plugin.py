"""A plug-in chain scene whose joints are stiffer (Scene.stiffness (2,)) runs the same in both engines: the reduced
model takes its stiffness (the record in units of chain 1's, reduced_system), and refuses in one line what that
record leaves out (the inertial model's mass)."""

from __future__ import annotations

import pytest

import elastoactive as ea
from elastoactive.scenes import ChainScene


class StiffChain(ChainScene):
    name = "toy-stiff-chain"
    summary = "a chain clamped at one end, its joints twice as stiff (a test's toy scene)"
    base_file = "one-pinned.xml"

    def stiffness(self, physics):
        return (2.0,)


@pytest.fixture
def stiff():
    scene = ea.scenes.register(StiffChain())
    yield scene
    ea.scenes.unregister(scene.name)


def test_both_engines_agree_on_a_stiffer_chain(stiff):
    physics = ea.Physics(scene=stiff.name, n=7, sigma=1.6)
    runs = {engine: ea.measure(ea.simulate(physics, duration=80, engine=engine)) for engine in ("mujoco", "reduced")}
    assert runs["mujoco"].amplitude == pytest.approx(runs["reduced"].amplitude, rel=0.01)
    assert runs["mujoco"].frequency == pytest.approx(runs["reduced"].frequency, rel=0.01)
    # the unit chain at sigma / k, its time scaled by k: the same beat at twice the frequency
    unit = ea.measure(ea.simulate(ea.Physics(n=7, sigma=0.8), duration=160, engine="reduced"))
    assert runs["reduced"].amplitude == pytest.approx(unit.amplitude, rel=1e-3)
    assert runs["reduced"].frequency == pytest.approx(2 * unit.frequency, rel=1e-3)


def test_the_record_is_in_units_of_chain_one(stiff):
    physics = ea.Physics(scene=stiff.name, n=7, sigma=1.6, drag_ratio=2.0)
    system = stiff.reduced_system(physics)
    assert (system.sigma, system.gamma_t, system.gamma_l, system.rho) == (0.8, 0.5, 1.0, 1.0)
    assert not stiff.inertial_model(physics)


def test_the_inertial_model_is_refused(stiff):
    physics = ea.Physics(scene=stiff.name, n=7, sigma=1.6)
    with pytest.raises(ea.ParameterError, match=r"^engine reduced: chain 1.s joint stiffness is 2 C1, and the inertia"):
        ea.simulate(physics, ea.Numerics(mass_ratio=1.0), duration=1, engine="reduced")
