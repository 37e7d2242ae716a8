"""The kit's checks (elastoactive.testing): each a `Check` whose promise is one line and whose function raises
`ConformanceError` naming the subject, the check and what broke.

A check takes a `Subject`: the scene under test, the physics of its short case (a term's check: the scene the term
acts on, with the term on) and a cache of the short runs the checks share. Every run goes through the public front
door (elastoactive.simulate, measure, load, the command line), as a user's would.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import tempfile
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import api, plot
from ..cli import main
from ..core import observables as observable_specs
from ..core import registry, term_registry
from ..core.errors import ParameterError
from ..core.parameters import Parameter
from ..core.parameters import get as parameter_spec
from ..core.params import Numerics, Physics
from ..core.trajectory import Trajectory
from ..engines import ENGINES
from ..gate import preflight
from ..scenes.base import Scene
from ..terms.base import Term
from .watch import Outcome, watched

KIT_DURATION = 10.0
"""The short case's length, in the scene's unit of time: both engines' states are compared over all of it."""
BRIEF = 1.0
"""A run long enough to tell two runs apart bit for bit (a parameter's effect, a round trip), in the scene's unit of
time."""
LONG_DURATION = 5000.0
"""A run long enough to need progress (the progress check stops it at its first update)."""
ABSURD_SECONDS = 2.0
"""CPU seconds within which an absurd value is refused, or announced and shown progressing."""
PROGRESS_SECONDS = 3.0
"""CPU seconds within which a long run reports progress."""
ABSURD = (("sigma", 1e6), ("duration", 1e12), ("perturbation", 1e9))
"""The absurd values every scene is given (a term's rates, parameters in 1/tau, get RATE_ABSURD)."""
RATE_ABSURD = 1e6
RATE_UNITS = ("1/tau",)
"""Units of a rate parameter (a drive's frequency): given RATE_ABSURD cycles per unit time."""
SAME = 0.0
"""Largest difference between two runs whose parameter differs that counts as 'no change' (bit-identical)."""


class ConformanceError(AssertionError):
    """A broken promise: `subject` (scene or term), `check` (its name) and what broke."""

    def __init__(self, subject: str, check: str, promise: str, detail: str):
        self.subject, self.check, self.promise, self.detail = subject, check, promise, detail
        super().__init__(f"{subject} fails '{check}' ({promise}): {detail}")


@dataclass
class Subject:
    """What a check is run on: the scene, the physics of the short case, the term (term checks) and the runs cache."""

    scene: Scene
    physics: Physics
    term: Term | None = None
    runs: dict = field(default_factory=dict)

    @property
    def name(self) -> str:
        return f"term {self.term.name!r} on scene {self.scene.name!r}" if self.term else f"scene {self.scene.name!r}"

    def run(self, engine: str, physics: Physics | None = None, duration: float = KIT_DURATION, **options):
        """A short run (cached by its physics, engine and duration)."""
        physics = self.physics if physics is None else physics
        key = (physics, engine, duration, tuple(sorted(options.items())))
        if key not in self.runs:
            self.runs[key] = api.simulate(physics, duration=duration, engine=engine, **options)
        return self.runs[key]


@dataclass(frozen=True)
class Check:
    """One promise: its name, the promise in one line, and the function that holds the subject to it."""

    name: str
    promise: str
    function: Callable[[Subject, Check], None]

    def fail(self, subject: Subject, detail: str) -> ConformanceError:
        return ConformanceError(subject.name, self.name, self.promise, detail)

    def __call__(self, subject: Subject) -> None:
        self.function(subject, self)


# ---------------------------------------------------------------------------------------------------------- helpers
def _state(traj: Trajectory) -> np.ndarray:
    """Every coordinate of the state the run recorded (a chain's angles, a network's node positions), flattened."""
    return np.asarray(traj.positions(), dtype=float).reshape(len(traj.t), -1)


def _differs(a: Trajectory, b: Trajectory) -> float:
    """The largest difference between two runs' states (inf where their shapes differ)."""
    x, y = _state(a), _state(b)
    if x.shape != y.shape:
        return math.inf
    return float(np.max(np.abs(x - y), initial=0.0))


def _engines(subject: Subject, physics: Physics | None = None) -> list[str]:
    """The engines that take the physics (the others refuse it in one line before running: they do not claim it)."""
    physics = subject.physics if physics is None else physics
    taken = []
    for engine in ENGINES:
        try:
            preflight(physics, Numerics(), KIT_DURATION, engine, timestep=False)
        except ParameterError:
            continue
        taken.append(engine)
    return taken


def changed_values(spec: Parameter, value) -> list:
    """Values other than `value` that the spec admits, the nearest first: a flipped switch, another choice, the integer
    next to it, a number half as large again (or a tenth of its range from zero)."""
    if spec.kind is bool:
        return [not value]
    if spec.kind is str:
        return [c for c in (spec.choices or ()) if c != value]
    if spec.kind is int:
        candidates = [value + 1, value - 1, value + 2]
    else:
        candidates = [1.5 * value, 0.5 * value] if value else [0.1, 0.5, 1.0, -0.1]
        if spec.low is not None and spec.high is not None:
            candidates += [spec.low + 0.25 * (spec.high - spec.low), spec.low + 0.75 * (spec.high - spec.low)]
    admitted = []
    for candidate in candidates:
        try:
            spec.check(candidate)
        except (ParameterError, ValueError, TypeError):
            continue
        if candidate != value:
            admitted.append(candidate)
    return admitted


def _with(physics: Physics, name: str, value) -> Physics | None:
    """The physics with one value changed, its switch turned on where the value needs it; None where refused."""
    spec = parameter_spec(name)
    changes = {name: value}
    if spec.needs is not None and not spec.acts_in({**physics.given(), **changes}):
        switch = parameter_spec(spec.needs)
        on = spec.needs_value if spec.needs_value is not None else (True if switch.kind is bool else 1.0)
        changes[spec.needs] = on
    try:
        return physics.replace(**changes)
    except (ParameterError, ValueError, TypeError):
        return None


def _quietly(function: Callable, *args, **kwargs):
    """(result, stdout, stderr) of a call whose printing is captured."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        result = function(*args, **kwargs)
    return result, out.getvalue(), err.getvalue()


def command_options(physics: Physics) -> list[str]:
    """The command line's scene and options for `physics` (what `elastoactive run` takes to run it)."""
    args = [physics.scene]
    for name, value in physics.relevant().items():
        if name == "scene":
            continue
        spec = parameter_spec(name)
        if spec.kind is bool:
            args.append(spec.option if value else "--no-" + spec.option[2:])
        else:
            args += [spec.option, repr(float(value)) if spec.kind is float else str(value)]
    return args


def _one_line(error: BaseException) -> bool:
    return "\n" not in str(error).strip()


# ------------------------------------------------------------------------------------------------------- the checks
def _declares(subject: Subject, check: Check) -> None:
    owner = subject.term or subject.scene
    if not owner.name or not owner.summary:
        raise check.fail(subject, "it needs a non-empty `name` and a one-line `summary`")
    names = [p.name for p in subject.term.parameters] if subject.term else list(subject.scene.own_parameter_names())
    for name in names:
        try:
            parameter_spec(name)
        except (KeyError, ParameterError):
            raise check.fail(subject, f"parameter {name!r} has no registered spec") from None
    for name in owner.observable_names():
        if not observable_specs.known(name):
            raise check.fail(subject, f"observable {name!r} has no registered spec")
    if subject.term is None:
        if registry.get(subject.scene.name) is not subject.scene:
            raise check.fail(subject, "the registry holds another scene under its name")
        for case in subject.scene.validation_cases():
            if case.physics.scene != subject.scene.name:
                raise check.fail(subject, f"a validation case is of scene {case.physics.scene!r}")
    else:
        if term_registry.get(subject.term.name) is not subject.term:
            raise check.fail(subject, "the registry holds another term under its name")


def _engines_agree(subject: Subject, check: Check) -> None:
    engines = _engines(subject)
    if len(engines) < len(ENGINES):
        return  # one engine only: nothing to agree with (the refusal's words are the absurd check's)
    runs = {engine: subject.run(engine) for engine in engines}
    first, second = (runs[e] for e in ENGINES)
    n = min(first.t.size, second.t.size)
    if n < 2 or not np.allclose(first.t[:n], second.t[:n], rtol=0, atol=1e-9):
        raise check.fail(subject, "the engines' records are not sampled at the same times")
    diff, scale = subject.scene.state_difference(first, second, np.ones(n, dtype=bool))
    error = diff / max(scale, 1e-12)
    agreement = max([subject.scene.agreement, *(t.agreement or 0.0 for t in subject.physics.active_terms())])
    if not error <= agreement:
        raise check.fail(
            subject,
            f"over {KIT_DURATION:g} time units of {subject.physics.relevant()} the states differ by "
            f"{100 * error:.3g}% (agreement {100 * agreement:g}%): one engine leaves out physics the "
            "other has",
        )


def _parameter_acts(subject: Subject, check: Check, name: str, cases: list[Physics]) -> None:
    """`name` changes the result in every engine that takes it, in some case of the subject's: a change seen in one
    engine and not in another fails at once (one engine leaves the parameter out); no change anywhere fails at the
    end."""
    spec = parameter_spec(name)
    tried = []
    for base in cases:
        value = getattr(base, name)
        for new in changed_values(spec, value):
            changed, before = _with(base, name, new), _with(base, name, value)
            if changed is None or before is None:
                continue
            engines = [e for e in _engines(subject, changed) if e in _engines(subject, before)]
            differences = {e: _difference(subject, e, before, changed) for e in engines}
            engines = [e for e in engines if differences[e] is not None]  # one that refuses the change: not its
            still = [e for e in engines if differences[e] <= SAME]
            if engines and not still:
                return
            if still and len(still) < len(engines):
                raise check.fail(
                    subject,
                    f"parameter {name}: {value!r} -> {new!r} changes the run in "
                    f"{', '.join(e for e in engines if e not in still)} and nothing in {', '.join(still)}",
                )
            if still:
                tried.append(f"{value!r} -> {new!r}")
    if tried:
        raise check.fail(subject, f"parameter {name} changes nothing in any engine ({'; '.join(tried[:3])})")


def _difference(subject: Subject, engine: str, before: Physics, changed: Physics) -> float | None:
    """How far a brief run of `changed` ends from one of `before` in `engine` (over the short case's length where a
    brief run shows no change: a contact needs the chain to fold first); None where the engine refuses either in one
    line as it starts (it does not take that setting: MuJoCo's noise has no Stratonovich reading)."""
    try:
        for duration in (BRIEF, KIT_DURATION):
            difference = _differs(subject.run(engine, before, duration), subject.run(engine, changed, duration))
            if difference > SAME:
                break
    except ParameterError:
        return None
    return difference


def _parameters_act(subject: Subject, check: Check) -> None:
    names = [p.name for p in subject.term.parameters] if subject.term else list(subject.scene.own_parameter_names())
    cases = [subject.physics, *(c.physics for c in subject.scene.validation_cases())]
    for name in names:
        spec = parameter_spec(name)
        if spec.instead_of is not None:
            continue  # given in place of another (Pi for sigma): that one is checked
        acting = [c for c in cases if _with(c, name, getattr(c, name)) is not None]
        if acting:
            _parameter_acts(subject, check, name, acting)


def _absurd_runs(subject: Subject) -> list[tuple[str, str, Callable[[], object]]]:
    """(what, the parameter's name, the run) for every absurd value of the subject, in every engine."""
    physics = subject.physics
    cases: list[tuple[str, dict, float, dict | None]] = []  # (name, physics changes, duration, numerics)
    if subject.term is None:
        for name, value in ABSURD:
            if name == "duration":
                cases.append((name, {}, value, None))
            elif name == "perturbation":
                cases.append((name, {}, KIT_DURATION, {name: value}))
            else:
                cases.append((name, {name: value}, KIT_DURATION, None))
    else:
        for spec in subject.term.parameters:
            if spec.units in RATE_UNITS and spec.kind is float and _with(physics, spec.name, 1.0) is not None:
                cases.append((spec.name, {spec.name: RATE_ABSURD}, KIT_DURATION, None))

    def run(changes: dict, duration: float, numerics: dict | None, engine: str):
        """The absurd run, from the physics on: a refusal by Physics itself is a refusal too."""
        case = physics
        for name, value in changes.items():
            case = _with(case, name, value) or case.replace(**changes)
        return api.simulate(case, numerics, duration=duration, engine=engine, progress=True)

    return [
        (
            f"{name} = {(changes or numerics or {name: duration})[name]:g} in engine {engine}",
            name,
            lambda changes=changes, duration=duration, numerics=numerics, engine=engine: run(
                changes, duration, numerics, engine
            ),
        )
        for name, changes, duration, numerics in cases
        for engine in ENGINES
    ]


def _warm(subject: Subject) -> None:
    """A brief run in every engine that takes the subject, before any is timed: loading an engine (numba's cache,
    MuJoCo's library, the compiled callback) is the process's once, not a run's cost."""
    for engine in _engines(subject):
        subject.run(engine, duration=BRIEF)


def _absurd_values(subject: Subject, check: Check) -> None:
    _warm(subject)
    for what, name, run in _absurd_runs(subject):
        shown = lambda o: o.announced is not None and o.updated is not None
        outcome, _, _ = _quietly(watched, run, ABSURD_SECONDS, shown)
        if outcome.refusal is not None:
            text = str(outcome.refusal)
            if not _one_line(outcome.refusal) or name not in text:
                raise check.fail(subject, f"{what}: the refusal does not name {name} in one line: {text!r}")
            continue
        if outcome.error is not None:
            raise check.fail(
                subject, f"{what}: a raw {type(outcome.error).__name__} ({outcome.error}), not one line naming {name}"
            )
        if outcome.finished:
            continue  # it ran through within the limit
        if outcome.stopped and outcome.announced is not None and outcome.updated is not None:
            if max(outcome.announced, outcome.updated) <= ABSURD_SECONDS:
                continue
        raise check.fail(subject, _silence(what, outcome, ABSURD_SECONDS, "neither refused nor announced"))


def _silence(what: str, outcome: Outcome, limit: float, verdict: str) -> str:
    said = (f"announced at {outcome.announced:.2f} s" if outcome.announced is not None else "no announcement") + (
        f", first progress at {outcome.updated:.2f} s" if outcome.updated is not None else ", no progress"
    )
    return f"{what}: {verdict} within {limit:g} s of CPU ({said})"


def _progress_shows(subject: Subject, check: Check) -> None:
    _warm(subject)
    for engine in _engines(subject):

        def run(engine=engine):
            return api.simulate(subject.physics, duration=LONG_DURATION, engine=engine, progress=True)

        outcome, _, _ = _quietly(watched, run, PROGRESS_SECONDS, lambda o: o.updated is not None)
        what = f"a run of {LONG_DURATION:g} time units in engine {engine}"
        if outcome.refusal is not None or outcome.finished:
            continue  # refused before it ran (its words are the absurd check's), or done within the limit
        if outcome.error is not None:
            raise check.fail(subject, f"{what}: raised {type(outcome.error).__name__}: {outcome.error}")
        if not (outcome.stopped and outcome.updated is not None and outcome.updated <= PROGRESS_SECONDS):
            raise check.fail(subject, _silence(what, outcome, PROGRESS_SECONDS, "no progress shown"))


def _run_cli(subject: Subject, check: Check, argv: list[str]) -> str:
    """Run the command line; its stderr, or a failure naming the command."""
    code, _, err = _quietly(main, argv)
    if code != 0:
        last = err.strip().splitlines()[-1] if err.strip() else f"exit status {code}"
        raise check.fail(subject, f"`elastoactive {' '.join(argv)}` failed: {last}")
    return err


def _arrays(folder: Path) -> dict[str, np.ndarray]:
    with np.load(folder / "trajectory.npz", allow_pickle=False) as data:
        return {k: data[k] for k in data.files}


def _round_trip(subject: Subject, check: Check) -> None:
    physics = subject.physics
    with tempfile.TemporaryDirectory(prefix="elastoactive-kit-") as tmp:
        tmp = Path(tmp)
        for engine in _engines(subject):
            first, again = tmp / f"{engine}-run", tmp / f"{engine}-again"
            options = ["--engine", engine, "--duration", repr(BRIEF), "--quiet"]
            _run_cli(subject, check, ["run", *command_options(physics), *options, "--out", str(first)])
            loaded = api.load(first)
            fresh = subject.run(engine, duration=BRIEF)
            if not (np.array_equal(loaded.t, fresh.t) and np.array_equal(_state(loaded), _state(fresh))):
                raise check.fail(subject, f"ea.load of a {engine} run is not the run that ea.simulate makes")
            _run_cli(subject, check, ["run", "--from", str(first), "--out", str(again), "--quiet"])
            saved, repeated = _arrays(first), _arrays(again)
            if saved.keys() != repeated.keys() or any(
                not np.array_equal(saved[k], repeated[k], equal_nan=saved[k].dtype.kind in "fc") for k in saved
            ):
                raise check.fail(subject, f"`run --from` does not repeat the {engine} run bit for bit")
        still = tmp / "still.png"
        if _gl_available():
            _run_cli(subject, check, ["render", str(tmp / f"{ENGINES[-1]}-run"), "--still", str(still), "--quiet"])
            if not still.is_file() or still.stat().st_size == 0:
                raise check.fail(subject, "`render --still` wrote no picture")


def _gl_available() -> bool:
    from .. import render  # the renderer's boundary: GL

    try:
        render.gl_backend()
    except render.RenderError:
        return False
    return True


def _foreign_starts(subject: Subject) -> list[tuple[Scene, Physics]]:
    """Other registered scenes, with the physics of their short case, whose state the subject does not accept as its
    start (Scene.accepts_start): one of its kind and one of another kind, where there are such."""
    others = [
        (s, kit_physics(s))
        for s in registry.scenes()
        if s.name != subject.scene.name and not subject.scene.accepts_start(kit_physics(s), subject.physics)
    ]
    same = [o for o in others if o[0].kind == subject.scene.kind]
    other = [o for o in others if o[0].kind != subject.scene.kind]
    return [*same[:1], *other[:1]]


def _foreign_start_refused(subject: Subject, check: Check) -> None:
    engine = _engines(subject)[-1]
    mine = subject.scene.name
    with tempfile.TemporaryDirectory(prefix="elastoactive-kit-") as tmp:
        for other, physics in _foreign_starts(subject):
            start = api.simulate(physics, duration=BRIEF, engine="reduced")
            try:
                api.simulate(subject.physics, duration=BRIEF, engine=engine, start=start)
            except ParameterError as err:
                text = str(err)
                if not (_one_line(err) and "start" in text and mine in text and other.name in text):
                    raise check.fail(
                        subject, f"a state of {other.name} is refused without naming start and both scenes: {text!r}"
                    ) from None
            else:
                raise check.fail(subject, f"a state of scene {other.name} was taken as its start")
            folder = Path(tmp) / other.name
            brief = ["--duration", repr(BRIEF)]
            origin = ["run", *command_options(physics), "--engine", "reduced", *brief, "--out", str(folder)]
            _run_cli(subject, check, origin)
            code, _, err = _quietly(
                main,
                ["run", *command_options(subject.physics), "--start-from", str(folder), *brief, "--out", f"{folder}+"],
            )
            lines = [line for line in err.strip().splitlines() if line.strip()]
            if code == 0 or not lines or not ("--start-from" in lines[-1] and other.name in lines[-1]):
                raise check.fail(
                    subject,
                    f"`run {mine} --start-from` a run of {other.name} is not refused in one line naming "
                    f"--start-from and both scenes (exit {code}: {lines[-1] if lines else 'nothing said'})",
                )


def _declared_observables(subject: Subject, physics: Physics) -> list[str]:
    """The observables a run of `physics` must report: the scene's own (not its occasional ones) and those of the
    terms it measures (Physics.measured_terms: those that act, and at rest those measured at rest)."""
    names = list(subject.scene.observable_names())
    for term in physics.measured_terms():
        names += term.reported(physics)
    return names


def _observables_defined(subject: Subject, check: Check) -> None:
    cases = [("its defaults", subject.scene.physics())]
    if subject.term is not None:
        cases = [
            ("the term's defaults", subject.physics.replace(**_rest(subject.term))),
            ("the term on", subject.physics),
        ]
    for where, physics in cases:
        traj = subject.run(_engines(subject, physics)[-1], physics, duration=4 * KIT_DURATION)
        results = api.measure(traj)
        measured = set(results.extra) | set(results.as_dict())
        missing = [n for n in _declared_observables(subject, physics) if n not in measured]
        if missing:
            raise check.fail(
                subject,
                f"at {where} ({physics.relevant()}) {', '.join(missing)} {'is' if len(missing) == 1 else 'are'} not "
                "measured (measure it there, or declare the term's observables occasional: measured_at_rest = False)",
            )


def _rest(term: Term) -> dict:
    """The term's parameters at their defaults (the term at rest)."""
    return {p.name: p.default for p in term.parameters if p.instead_of is None}


def _words_fit(subject: Subject, check: Check) -> None:
    import matplotlib  # the plots' boundary: matplotlib loads only for this check

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt  # after the back end is chosen

    physics = subject.physics
    traj = subject.run(_engines(subject)[-1])
    results = api.measure(traj)
    try:
        json.dumps(results.as_dict(), allow_nan=True)
    except (TypeError, ValueError) as err:
        raise check.fail(subject, f"its results are not JSON: {err}") from None
    for note in results.notes:
        if not isinstance(note, str) or not note.strip() or "\n" in note:
            raise check.fail(subject, f"a note is not one line of text: {note!r}")
    for what, text in (("caption", subject.scene.caption_line(physics)), ("label", subject.scene.label(physics))):
        if not isinstance(text, str) or not text.strip():
            raise check.fail(subject, f"its {what} is empty")
    dataset = traj.to_xarray()
    for name, variable in dataset.data_vars.items():
        if "units" not in variable.attrs or "long_name" not in variable.attrs:
            raise check.fail(subject, f"the dataset's variable {name} has no units or long_name")
    for draw in (plot.shape, plot.theta):
        try:
            axes = draw(traj)
        except ParameterError:
            continue  # refused in one line (a picture the scene does not have)
        except Exception as err:  # noqa: BLE001  (any other failure is the broken promise)
            raise check.fail(subject, f"ea.plot.{draw.__name__} fails: {type(err).__name__}: {err}") from None
        plt.close(getattr(axes, "figure", None) or "all")


SCENE_CHECKS: tuple[Check, ...] = (
    Check("declares", "its name, summary, parameters and observables are registered specs", _declares),
    Check("engines agree", "both engines run a short case and agree within the scene's agreement", _engines_agree),
    Check("parameters act", "every parameter it declares changes the result in every engine", _parameters_act),
    Check(
        "absurd values stop",
        f"an absurd value is refused in one line, or announced and shown progressing, within {ABSURD_SECONDS:g} s",
        _absurd_values,
    ),
    Check(
        "progress shows", f"a long run shows progress within {PROGRESS_SECONDS:g} s in every engine", _progress_shows
    ),
    Check("round trip", "run --out, ea.load, run --from and render round-trip, bit for bit", _round_trip),
    Check(
        "foreign start refused",
        "another scene's state as its start is refused in one line naming start and both scenes",
        _foreign_start_refused,
    ),
    Check("observables defined", "every observable it declares is measured at its defaults", _observables_defined),
    Check("words fit", "notes, summary, caption, label, dataset and plots work on its results", _words_fit),
)
"""What check_scene holds a scene to, in order."""

TERM_CHECKS: tuple[Check, ...] = tuple(
    c for c in SCENE_CHECKS if c.name not in ("progress shows", "round trip", "foreign start refused")
)
"""What check_term holds a term to, on the scene it acts on (the scene's own promises are check_scene's)."""


# ----------------------------------------------------------------------------------------------------- the front door
def _registered(subject, get, every, register, unregister):
    """(the registered instance, a function that undoes a registration made here) for a name, class or instance."""
    if isinstance(subject, str):
        return get(subject), lambda: None
    if isinstance(subject, type):
        found = [s for s in every() if type(s) is subject]
        if found:
            return found[0], lambda: None
        subject = subject()
    if any(s is subject for s in every()):
        return subject, lambda: None
    register(subject)
    return subject, lambda: unregister(subject.name)


def _selected(checks, only) -> tuple[Check, ...]:
    if only is None:
        return checks
    names = {c.name for c in checks}
    unknown = [n for n in ([only] if isinstance(only, str) else only) if n not in names]
    if unknown:
        raise ValueError(f"only: {unknown[0]!r} is not a check (checks: {', '.join(sorted(names))})")
    return tuple(c for c in checks if c.name in ([only] if isinstance(only, str) else only))


def _hold(subject: Subject, checks: tuple[Check, ...]) -> list[str]:
    """Run `checks` on the subject in order (the first broken promise raises); the names of those passed."""
    for check in checks:
        check(subject)
    return [check.name for check in checks]


def kit_physics(scene: Scene) -> Physics:
    """The scene's short case: its first validation case's physics, else the physics of its base file."""
    cases = scene.validation_cases()
    return cases[0].physics if cases else scene.base_physics()


def check_scene(scene, only=None) -> list[str]:
    """Hold a scene (its registered name, its class or an instance; an unregistered one is registered for the
    checks) to every promise of SCENE_CHECKS, or those named in `only`. Raises ConformanceError at the first broken
    promise; returns the names of the checks passed."""
    instance, undo = _registered(scene, registry.get, registry.scenes, registry.register, registry.unregister)
    try:
        return _hold(Subject(instance, kit_physics(instance)), _selected(SCENE_CHECKS, only))
    finally:
        undo()


def term_scene(term: Term) -> Physics:
    """The physics a term is checked on: its short case's (Term.short_case), else the first registered scene that takes
    its parameters, with the term on (its first parameter changed from its default)."""
    case = term.short_case(Physics)
    if case is not None:
        return case
    for scene in registry.scenes():
        physics = kit_physics(scene)
        if not term.takes(physics):
            continue
        if term.active(physics):
            return physics
        for spec in term.parameters:
            for value in changed_values(spec, spec.default):
                changed = _with(physics, spec.name, value)
                if changed is not None and term.active(changed):
                    return changed
    raise ParameterError(f"term {term.name}: no registered scene takes its parameters")


def check_term(term, only=None) -> list[str]:
    """Hold a physical term (its registered name, its class or an instance; an unregistered one is registered for
    the checks) to every promise of TERM_CHECKS on the scene it acts on (term_scene), or those named in `only`.
    Raises ConformanceError at the first broken promise; returns the names of the checks passed."""
    instance, undo = _registered(
        term, term_registry.get, term_registry.terms, term_registry.register, term_registry.unregister
    )
    try:
        physics = term_scene(instance)
        return _hold(Subject(physics.scene_def, physics, term=instance), _selected(TERM_CHECKS, only))
    finally:
        undo()
