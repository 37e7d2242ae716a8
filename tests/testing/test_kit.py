"""The conformance kit catches each broken promise: one deliberately broken plug-in per check, each failing that
check with a message naming it (and a sound plug-in scene and term passing every check they are held to)."""

import time

import numpy as np
import pytest

import elastoactive as ea
from elastoactive import testing
from elastoactive.core.observables import Observable
from elastoactive.core.parameters import Parameter
from elastoactive.scenes import ChainScene
from elastoactive.terms.base import Term


class Toy(ChainScene):
    """A sound plug-in scene: a single clamped chain of its own name."""

    name = "toy-kit-chain"
    summary = "a clamped chain (the conformance kit's test scene)"
    base_file = "one-pinned.xml"


def _broken(check: str, scene_or_term, match: str) -> None:
    """`scene_or_term` fails `check`, and the message names the check and what broke."""
    kit = testing.check_term if isinstance(scene_or_term, Term) else testing.check_scene
    with pytest.raises(testing.ConformanceError, match=match) as caught:
        kit(scene_or_term, only=check)
    assert caught.value.check == check and f"'{check}'" in str(caught.value)


def _burn(seconds: float) -> None:
    """Use `seconds` of this thread's CPU, saying nothing."""
    start = time.thread_time()
    while time.thread_time() - start < seconds:
        pass


def test_a_sound_plugin_scene_passes_the_cheap_checks():
    assert testing.check_scene(Toy, only=["declares", "engines agree", "observables defined"]) == [
        "declares",
        "engines agree",
        "observables defined",
    ]
    assert Toy.name not in ea.scenes.names()  # registered for the checks only


def test_declares_needs_a_summary():
    class Nameless(Toy):
        name = "toy-kit-nameless"
        summary = ""

    _broken("declares", Nameless(), "summary")


def test_engines_agree_catches_physics_one_engine_leaves_out():
    """A chain whose MuJoCo joints are twice as stiff as the reduced model's (the stiffness the reduced engine never
    read): 10% off in amplitude over a beat, silently, until the kit compares the engines."""

    class Stiff(Toy):
        name = "toy-kit-stiff"

        def build(self, spec, physics, numerics):
            for joint in spec.joints:
                joint.stiffness = [2.0 * joint.stiffness[0], 0.0, 0.0]

    _broken("engines agree", Stiff(), "states differ by")


GAIN = Parameter("toy_kit_gain", 1.0, "a gain the scene never reads", low=0.0, title="unused gain")


def test_parameters_act_catches_a_parameter_that_does_nothing():
    class Unused(Toy):
        name = "toy-kit-unused"
        parameters = (GAIN,)

    _broken("parameters act", Unused(), "toy_kit_gain changes nothing in any engine")


MUJOCO_GAIN = Parameter("toy_kit_mujoco_gain", 1.0, "a joint stiffness only MuJoCo reads", low=0.1, title="gain")


def test_parameters_act_catches_a_parameter_one_engine_leaves_out():
    class OneEngine(Toy):
        name = "toy-kit-one-engine"
        parameters = (MUJOCO_GAIN,)

        def build(self, spec, physics, numerics):
            for joint in spec.joints:
                joint.stiffness = [physics.toy_kit_mujoco_gain * joint.stiffness[0], 0.0, 0.0]

    _broken("parameters act", OneEngine(), "changes the run in mujoco and nothing in reduced")


def test_absurd_values_catch_a_silent_wait():
    class Silent(Toy):
        name = "toy-kit-silent"

        def check(self, physics):
            if physics.sigma > 1e3:
                _burn(1.5 * testing.ABSURD_SECONDS)

    _broken("absurd values stop", Silent(), "sigma = 1e\\+06 in engine mujoco: neither refused nor announced")


def test_absurd_values_catch_a_raw_traceback():
    class Raw(Toy):
        name = "toy-kit-raw"

        def check(self, physics):
            if physics.sigma > 1e3:
                raise TypeError("mj_step(): incompatible function arguments")

    _broken("absurd values stop", Raw(), "a raw TypeError")


def test_progress_shows_catches_a_silent_engine():
    class Quiet(Toy):
        name = "toy-kit-quiet"

        def run_reduced(self, physics, numerics, duration, **options):
            if duration > 1000:
                _burn(1.5 * testing.PROGRESS_SECONDS)
            return super().run_reduced(physics, numerics, duration, **options)

    _broken("progress shows", Quiet(), "engine reduced: no progress shown")


def test_round_trip_catches_an_unrepeatable_start():
    class Unseeded(Toy):
        name = "toy-kit-unseeded"

        def initial_angles(self, physics, numerics):
            return np.random.default_rng().normal(0.0, 0.01, physics.n)

    _broken("round trip", Unseeded(), "ea.load of a mujoco run is not the run that ea.simulate makes")


def test_observables_defined_catches_a_declared_observable_never_measured():
    class Forgetful(Toy):
        name = "toy-kit-forgetful"
        observables = (Observable("toy_kit_twist", "rad", "a twist it never measures"),)

    _broken("observables defined", Forgetful(), "toy_kit_twist is not measured")


def test_words_fit_catches_a_result_that_is_not_json():
    class Unwritable(Toy):
        name = "toy-kit-unwritable"
        observables = (Observable("toy_kit_set", "1", "a value JSON cannot hold", error="none"),)

        def measure_extra(self, traj, transient):
            return {"toy_kit_set": {1, 2}}

    _broken("words fit", Unwritable(), "not JSON")


WORK = Observable("toy_kit_work", "1", "work of the toy force over the window", error="absolute")
STRENGTH = Parameter("toy_kit_strength", 0.0, "strength of a uniform force on every particle", title="strength")


class Push(Term):
    """A plug-in term of the reduced engine's node forces: a uniform force g along x on every particle, with its work
    as an observable; at g = 0 (its default) it rests and its work is 0."""

    name = "toy-kit-push"
    summary = "a uniform push along x (the conformance kit's test term)"
    parameters = (STRENGTH,)
    observables = (WORK,)

    def node_forces(self, physics):
        g = physics.toy_kit_strength

        def law(t, positions):
            force = np.zeros_like(positions)
            force[:, 0] = g
            return force

        return law

    def measure(self, traj, transient):
        x = traj.positions()[:, 0, :, 0]
        return {"toy_kit_work": traj.physics.toy_kit_strength * float(np.sum(x[-1] - x[0]))}


def test_a_plugin_terms_observable_is_measured_at_rest():
    """At g = 0 the term rests; its observable is still measured (0), not missing (a sweep's NaN)."""
    term = ea.terms.register(Push())
    try:
        traj = ea.simulate(ea.Physics("one-pinned", n=3), duration=20.0, engine="reduced")
        assert ea.measure(traj).toy_kit_work == 0.0
        testing.check_term(term, only=["declares", "observables defined"])
    finally:
        ea.terms.unregister(term.name)


def test_observables_defined_catches_a_term_that_forgets_its_observable_at_rest():
    class Forgetful(Push):
        name = "toy-kit-forgetful-push"

        def measure(self, traj, transient):
            return {} if traj.physics.toy_kit_strength == 0 else super().measure(traj, transient)

    _broken("observables defined", Forgetful(), "toy_kit_work is not measured")


def test_only_names_a_check():
    with pytest.raises(ValueError, match="'no such check' is not a check"):
        testing.check_scene("one-pinned", only="no such check")
