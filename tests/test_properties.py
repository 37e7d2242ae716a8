"""Property-based: over the parameter space of the library and the CLI, every input either runs or is
refused with one line naming the parameter; never a traceback."""

from __future__ import annotations

import contextlib
import functools
import io
import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import elastoactive as ea
from elastoactive.cli import main

ODD_NUMBERS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True, width=64),
    st.floats(min_value=-3, max_value=3),
    st.integers(min_value=-10, max_value=10**6),
    st.text(max_size=4),
    st.none(),
    st.booleans(),
)
PHYSICS_FIELDS = ("n", "sigma", "delta", "kappa", "rho", "drag_ratio", "noise")
NUMERICS_FIELDS = ("dt", "mass_ratio", "perturbation", "sample_dt", "seed", "integrator")


def _names_parameter(message: str, keys) -> bool:
    return any(k in message for k in keys)


@settings(max_examples=300, deadline=None, derandomize=True)
@given(
    scene=st.one_of(st.sampled_from(ea.scenes.names()), st.text(max_size=8)),
    values=st.dictionaries(st.sampled_from(PHYSICS_FIELDS), ODD_NUMBERS, max_size=4),
)
def test_physics_runs_or_names_the_parameter(scene, values):
    try:
        physics = ea.Physics(scene=scene, **values)
    except ea.ParameterError as err:
        assert "\n" not in str(err) and _names_parameter(str(err), ("scene", *values)), str(err)
    else:
        assert physics.n >= physics.scene_def.min_n and all(
            math.isfinite(getattr(physics, k)) for k in PHYSICS_FIELDS[1:]
        )


@settings(max_examples=300, deadline=None, derandomize=True)
@given(
    values=st.dictionaries(
        st.sampled_from(NUMERICS_FIELDS), st.one_of(ODD_NUMBERS, st.sampled_from(("RK4", "Euler"))), max_size=4
    ),
    duration=ODD_NUMBERS,
)
def test_numerics_and_duration_run_or_name_the_parameter(values, duration):
    try:
        numerics = ea.Numerics(**values)
        numerics.check_duration(duration)
    except ea.ParameterError as err:
        assert "\n" not in str(err) and _names_parameter(str(err), ("duration", "sample", *values)), str(err)


def _run(argv: list[str]) -> tuple[int, str]:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            code = main(argv)
        except SystemExit as exit_:  # argparse's own refusals (a malformed number, an unknown choice)
            code = exit_.code
    return code, err.getvalue()


NUMBER_TEXT = st.one_of(
    st.floats(min_value=-1, max_value=3).map(lambda x: f"{x:.3g}"),
    st.sampled_from(["nan", "inf", "-inf", "0", "1e9", "-1", "1e-9", "abc", ""]),
)


TIMESTEP_TEXT = st.sampled_from(
    ["nan", "inf", "-1", "0", "abc", "", "1e-9", "1e-300", "0.2", "0.05", "0.01", "0.0025", "0.001"]
)
"""dt values: every kind of refusal, and valid ones that keep a 5-tau run short (a tiny valid dt would
simply run long, which is not what this test is about; MAX_STEPS refuses the absurd ones)."""


@pytest.mark.parametrize("engine", ["reduced", "mujoco"])  # two tests: the suite's workers run them side by side
@settings(max_examples=30, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(
    scene=st.sampled_from(ea.scenes.names()),
    options=st.dictionaries(
        st.sampled_from(
            [
                "--n",
                "--sigma",
                "--delta",
                "--kappa",
                "--rho",
                "--noise",
                "--mass-ratio",
                "--sample-dt",
                "--duration",
                "--transient",
                "--seed",
            ]
        ),
        NUMBER_TEXT,
        max_size=3,
    ),
    dt=st.one_of(st.none(), TIMESTEP_TEXT),
)
def test_cli_run_runs_or_refuses_in_one_line(scene, engine, options, dt):
    options = {"--n": "3", "--duration": "5", **options, **({"--dt": dt} if dt is not None else {})}
    argv = ["run", scene, "--engine", engine, "--quiet"] + [x for kv in options.items() for x in kv]
    code, stderr = _run(argv)
    assert "Traceback" not in stderr, stderr
    assert code in (0, 2, 3), (argv, code, stderr)
    if code:
        lines = [
            line
            for line in stderr.splitlines()
            if line.strip() and not line.startswith("usage:") and not line.startswith(" ")
        ]
        assert lines and lines[-1].startswith(("elastoactive: ", "elastoactive run: error:")), (argv, stderr)


SCENE_OR_PRESET = st.sampled_from((*ea.scenes.names(), "accurate", "fast"))
ARGUMENT = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-3, 10),
    st.floats(allow_nan=True),
    st.text(max_size=6),
    SCENE_OR_PRESET,
    st.lists(st.integers(0, 3), max_size=2),
    st.dictionaries(
        st.sampled_from(["n", "sigma", "scene", "dt", "sample_dt", "seed", "bogus"]),
        st.one_of(st.integers(1, 4), st.floats(0.01, 1.0), st.text(max_size=3), SCENE_OR_PRESET),
        max_size=2,
    ),
)
"""What a user may pass as the physics or the numerics of ea.simulate, or as the trajectory of ea.measure."""


@settings(max_examples=150, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(physics=ARGUMENT, numerics=ARGUMENT)
def test_api_takes_its_arguments_in_obvious_forms_or_names_them(physics, numerics):
    """A Physics, a scene name or a dict of fields; a Numerics, a preset name, a dict of settings or None: anything
    else is a TypeError naming the argument, a bad value a ParameterError, never an AttributeError."""
    try:
        traj = ea.simulate(physics, numerics, duration=1.0, engine="reduced")
    except TypeError as err:
        assert "\n" not in str(err) and str(err).startswith(("physics", "numerics")), str(err)
    except ea.ParameterError as err:
        assert "\n" not in str(err), str(err)
    else:
        assert traj.t.size >= 2 and traj.theta.shape[1] == traj.physics.n_angles


@settings(max_examples=60, deadline=None, derandomize=True)
@given(trajectory=ARGUMENT, transient=st.one_of(st.none(), st.floats(allow_nan=True), st.text(max_size=3)))
def test_api_measure_takes_a_trajectory_or_names_the_argument(trajectory, transient):
    try:
        ea.measure(trajectory, transient)
    except TypeError as err:
        assert str(err).startswith("trajectory"), str(err)
    else:
        raise AssertionError(f"measured {trajectory!r}")


@settings(max_examples=40, deadline=None, derandomize=True)
@given(
    transient=st.one_of(
        st.none(), st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=3), st.integers(-5, 30)
    )
)
def test_api_measure_takes_a_transient_or_names_it(transient):
    trajectory = _short_run()
    try:
        ea.measure(trajectory, transient)
    except ea.ParameterError as err:
        assert "\n" not in str(err) and "transient" in str(err), str(err)


@functools.lru_cache(maxsize=1)
def _short_run():
    return ea.simulate(ea.Physics(n=3), duration=20, engine="reduced")


@pytest.mark.parametrize("sample_dt", [0.0, -0.05])
def test_a_sample_spacing_that_is_not_positive_is_named(sample_dt):
    """With dt at its default, dt follows sample_dt (its largest whole fraction): a spacing of 0 or less is refused
    in one line naming sample_dt, before anything divides by it."""
    with pytest.raises(ea.ParameterError, match="sample_dt"):
        ea.Numerics(sample_dt=sample_dt)
