"""A run's record on disk: summary.json (its settings, results and provenance, with their digests), trajectory.npz and
the inputs it read (a network file, plug-in files, its start state: RunInputs), written atomically and read back
checked. The numbers themselves are measured by elastoactive.results."""

from __future__ import annotations

import dataclasses
import hashlib
import io
import json
import warnings
import zipfile
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import plugins
from .core.errors import ParameterError
from .core.params import Numerics, Physics
from .core.trajectory import Trajectory
from .io.jsonio import from_jsonable, to_jsonable
from .io.outputs import InputFile, sha256, write_files, write_text
from .networks.files import SUFFIX as NETWORK_SUFFIX
from .results import check_transient, measure
from .sensitivity import estimate as estimate_sensitivity
from .sensitivity import needs_estimate
from .wording import summary_units

ENGINE_NUMERICS = {
    "mujoco": ("dt", "mass_ratio", "integrator", "perturbation", "sample_dt", "seed"),
    # the reduced model: its mass ratio decides overdamped or inertial (engines.reduced.regime); dt only with noise
    "reduced": ("sample_dt", "perturbation", "seed", "mass_ratio"),
}
"""The numerical settings each engine uses, which its summary.json records (all a re-run needs)."""


def recorded_numerics(engine: str, physics: Physics) -> tuple[str, ...]:
    """The Numerics fields a run of `physics` with `engine` uses: what summary.json records and `run --from` needs."""
    names = ENGINE_NUMERICS[engine]
    return names + ("dt",) if engine == "reduced" and physics.stochastic else names


def summary(
    traj: Trajectory,
    numerics: Numerics,
    duration: float,
    transient: float | None = None,
    provenance: dict | None = None,
    sensitivity: bool = True,
) -> dict:
    """Everything summary.json holds: parameters, numerical settings, wall time, results, their units (the scene's:
    wording.summary_units), solver information and (when given) the provenance record of elastoactive.io.outputs.
    An irregular run's results also carry `sensitivity` (elastoactive.sensitivity: errors of its numbers, whether its
    dynamics is sensitive) unless sensitivity=False. Measuring runs here: what it raises propagates (the record of a run
    whose measuring failed is `unmeasured_summary`)."""
    transient = check_transient(duration, transient)
    numerics, out = _record(traj, numerics, duration, transient, provenance)
    results = measure(traj, transient)
    recorded = results.as_dict()
    if sensitivity and needs_estimate(traj, results.periodic):  # an irregular run: its numbers with their errors
        try:
            estimate = estimate_sensitivity(traj, transient, numerics)
        except ParameterError as refusal:  # the pilots run the reduced engine, which may not cover this run's terms
            recorded["notes"] = [
                *recorded["notes"],
                f"irregular, and no error estimate: its pilots run the reduced "
                f"engine, which refuses this run ({refusal}); rerun at dt / 2 to gauge its error",
            ]
        else:
            recorded["sensitivity"] = estimate.as_dict()
            recorded["notes"] = [*recorded["notes"], estimate.note(results.amplitude, results.frequency)]
    out["results"] = recorded
    out["units"] = summary_units(traj.physics, recorded)
    return _ordered(out)


MEASURING = "not measured: the run stopped while its trajectory was being measured"
"""The measure_error of the summary written with a run's trajectory, before it is measured (`unmeasured_summary`):
what a folder holds when the process is killed while measuring."""


def unmeasured_summary(
    traj: Trajectory,
    numerics: Numerics,
    duration: float,
    transient: float | None = None,
    provenance: dict | None = None,
    error: str = MEASURING,
) -> dict:
    """summary.json of a run that has not been measured, or whose measuring failed: the settings and solver
    information as `summary` records them (the same settings digest), `results` null and `measure_error`, one line."""
    transient = check_transient(duration, transient)
    _, out = _record(traj, numerics, duration, transient, provenance)
    out["results"] = None
    out["measure_error"] = " ".join(str(error).split())
    out["units"] = summary_units(traj.physics, {})
    return _ordered(out)


def error_line(err: BaseException) -> str:
    """An exception as one line: its type and message, whitespace collapsed."""
    return " ".join(f"{type(err).__name__}: {err}".split())


_ORDER = ("engine", "parameters", "numerics", "wall_time_s", "results", "measure_error", "units", "solver")


def _ordered(out: dict) -> dict:
    return {**{k: out[k] for k in _ORDER if k in out}, **{k: v for k, v in out.items() if k not in _ORDER}}


def _record(
    traj: Trajectory, numerics: Numerics, duration: float, transient: float, provenance: dict | None
) -> tuple[Numerics, dict]:
    """The numerics as the run used them, and the summary's settings and solver information (no results)."""
    if traj.engine == "mujoco":  # what ran: a long chain's or a network's automatic numerics, so --from repeats it
        numerics = numerics.for_physics(traj.physics)
        ran = traj.info.get("automatic_numerics") or {}  # the engine's record (a network's: engines.network_mujoco)
        numerics = dataclasses.replace(
            numerics, **{k: v for k, v in ran.items() if k in ("integrator", "dt", "mass_ratio")}
        )
    settings = dataclasses.asdict(numerics)
    if traj.engine in ENGINE_NUMERICS:
        settings = {k: settings[k] for k in recorded_numerics(traj.engine, traj.physics)}
    out = {
        "engine": traj.engine,
        "parameters": traj.physics.relevant(),
        "numerics": {**settings, "duration": duration, "transient": transient},
        "wall_time_s": traj.wall_time_s,
        "solver": traj.info,
    }
    if provenance is not None:
        out["provenance"] = provenance
    return numerics, out


def jsonable(value):
    """summary.json's JSON form of `value` (jsonio.to_jsonable): numpy scalars as Python numbers, non-finite
    floats as null."""
    return to_jsonable(value, nonfinite="null")


SETTINGS = ("engine", "parameters", "numerics")
"""What defines a run in its summary.json: covered by settings_sha256, recorded in the summary and in the
trajectory file, so that an edited summary (another sigma on the same trajectory) is refused rather than used."""
INPUTS = "inputs"
"""The summary's record of the files and plug-ins a run read (RunInputs); covered by settings_sha256 when present."""


def settings_digest(summary_dict: Mapping) -> str:
    """SHA-256 of a summary's SETTINGS, and its INPUTS where it has them, as canonical JSON (the same before writing
    and after reading back)."""
    settings = {k: summary_dict.get(k) for k in SETTINGS}
    if summary_dict.get(INPUTS) is not None:
        settings[INPUTS] = summary_dict[INPUTS]
    return hashlib.sha256(json.dumps(jsonable(settings), sort_keys=True, separators=(",", ":")).encode()).hexdigest()


NETWORK_COPY = "network.json"
"""The run folder's copy of the network file a network run read (its `geometry`)."""
START_COPY = "start.npz"
"""The run folder's copy of the state a run started from (--start-from)."""
STATE_ARRAYS = ("theta", "positions", "polarity")
"""The arrays of a start state (elastoactive.starts.Start), in the order state_digest reads them."""


def state_digest(arrays: Mapping[str, np.ndarray | None]) -> str:
    """SHA-256 of a start state: each of STATE_ARRAYS that is given, by name, shape and float64 bytes."""
    digest = hashlib.sha256()
    for name in STATE_ARRAYS:
        value = arrays.get(name)
        if value is not None:
            value = np.ascontiguousarray(value, dtype=np.float64)
            digest.update(f"{name}{value.shape}".encode())
            digest.update(value.tobytes())
    return digest.hexdigest()


@dataclass(frozen=True)
class StartInput:
    """The state a run started from: `path`, the start run's folder (absolute), `state_sha256` (state_digest) and
    `copy`, the run folder's file holding that state (START_COPY)."""

    path: str
    state_sha256: str
    copy: str = START_COPY


@dataclass(frozen=True)
class RunInputs:
    """What a run read besides its settings, as summary.json's `inputs` records it: the network file
    (`network_file`), the plug-in files (`plugin_files`, elastoactive.plugins), the entry points of installed
    distributions that provided its scene or terms (`entry_points`), the state it started from (`start`). `copies`
    maps a file name in the run's folder to the bytes written there (the network file's and plug-in files' bytes as
    read, the start state); not recorded."""

    network_file: InputFile | None = None
    plugin_files: tuple[InputFile, ...] = ()
    entry_points: tuple[plugins.EntryPointSource, ...] = ()
    start: StartInput | None = None
    copies: Mapping[str, bytes] = field(default_factory=dict, compare=False, repr=False)

    def as_dict(self) -> dict:
        """summary.json's `inputs` (the empty ones left out)."""
        out = {
            "network_file": self.network_file,
            "plugin_files": list(self.plugin_files),
            "entry_points": list(self.entry_points),
            "start": self.start,
        }
        return to_jsonable({k: v for k, v in out.items() if v})

    @classmethod
    def of(cls, record: Mapping, where: str = "summary.json") -> RunInputs:
        """The inputs a summary records (none for a record without them); malformed ones are refused naming
        `where`."""
        inputs = record.get(INPUTS)
        if inputs is None:
            return cls()
        try:
            network = inputs.get("network_file")
            start = inputs.get("start")
            return cls(
                network_file=None if network is None else from_jsonable(InputFile, network),
                plugin_files=tuple(plugins.plugin_files(record).values()),
                entry_points=tuple(plugins.entry_points(record)),
                start=None if start is None else from_jsonable(StartInput, start),
            )
        except (TypeError, KeyError, ValueError, AttributeError):
            raise ParameterError(f"{where}: its inputs record is not one elastoactive run writes") from None


def network_file(physics: Physics) -> Path | None:
    """The network file a run of `physics` reads (its `geometry`, when that names a file), else None."""
    geometry = physics.relevant().get("geometry")
    if isinstance(geometry, str) and geometry.endswith(NETWORK_SUFFIX):
        return Path(geometry).expanduser()
    return None


def resolved_inputs(physics: Physics) -> Physics:
    """`physics` with its network file's path absolute and resolved, so a record names it from any folder."""
    path = network_file(physics)
    if path is None or str(path.resolve()) == physics.geometry:
        return physics
    return physics.replace(geometry=str(path.resolve()))


def run_inputs(
    physics: Physics, start_state: Mapping[str, np.ndarray | None] | None = None, start_path=None
) -> RunInputs:
    """The inputs of a run of `physics` (RunInputs), read now: its network file's bytes, the bytes its plug-in files
    ran from (elastoactive.plugins.loaded_file), the entry points that provided its scene and terms, and the state it
    starts from (`start_state`: a Start's arrays, from the run at `start_path`)."""
    copies: dict[str, bytes] = {}
    network = None
    path = network_file(physics)
    if path is not None:
        try:
            network, copies[NETWORK_COPY] = InputFile.of(path, NETWORK_COPY)
        except OSError as err:
            raise ParameterError(f"geometry: the network file {path} cannot be read ({err.strerror or err})") from None
    files = []
    for spec in plugins.needed(physics):
        loaded = plugins.loaded_file(spec)
        if loaded is None:
            continue
        digest, data = loaded
        name = _copy_name(f"plugin-{Path(spec).stem}", ".py", copies)
        copies[name] = data
        files.append(InputFile(spec, digest, name))
    start = None
    if start_state is not None:
        buffer = io.BytesIO()
        np.savez(buffer, **{k: np.asarray(v, dtype=np.float64) for k, v in start_state.items() if v is not None})
        copies[START_COPY] = buffer.getvalue()
        where = str(Path(start_path).expanduser().resolve()) if start_path is not None else "given"
        start = StartInput(where, state_digest(start_state))
    return RunInputs(network, tuple(files), tuple(plugins.entry_point_sources(physics)), start, copies)


def _copy_name(stem: str, suffix: str, taken: Mapping[str, bytes]) -> str:
    name, k = stem + suffix, 1
    while name in taken:
        k += 1
        name = f"{stem}-{k}{suffix}"
    return name


COMPRESS_BYTES = 64 * 2**20
"""A trajectory of up to this many bytes of arrays is written compressed; a larger one as it is: sampled floats
compress by a tenth at most, and deflating the 330 MB of a 10 000-node network's run took 12 s of its whole
process (np.load reads either kind)."""


def file_variables(traj: Trajectory) -> dict[str, np.ndarray]:
    """The arrays a run's trajectory.npz holds for its scene's `file_variables` (Scene.file_variables): each named
    variable of Scene.state_variables under its name, its dimensions joined by spaces under NAME_dims and each of its
    attributes as a string under NAME_<attribute> (NAME_units, NAME_long_name), as the netCDF of
    Trajectory.to_xarray has them. The 3D chain's: position (T, 1, N, 3), position_dims "time chain particle xyz",
    position_units "l". Empty for a scene that names none (the planar and network scenes: their files are unchanged)."""
    scene = traj.physics.scene_def
    if not scene.file_variables:
        return {}
    _, variables = scene.state_variables(traj)
    arrays = {}
    for name in scene.file_variables:
        dims, values, attrs = variables[name]
        arrays[name] = np.asarray(values, dtype=float)
        arrays[f"{name}_dims"] = np.array(" ".join(dims))
        arrays.update({f"{name}_{key}": np.array(str(value)) for key, value in attrs.items()})
    return arrays


class RunWriteError(OSError):
    """A run's trajectory.npz could not be written (write_run); `summary` is the summary.json written without it, or
    None when none was (the folder keeps the run it held)."""

    def __init__(self, errno: int | None, strerror: str, filename: str, summary: Path | None):
        super().__init__(errno, strerror, filename)
        self.summary = summary


def write_run(out: Path, traj: Trajectory, summary_dict: dict, copies: Mapping[str, bytes] | None = None) -> list[Path]:
    """summary.json and trajectory.npz (t in tau, theta: one column per particle; head (T, 2) for a scene whose
    pivot moves; the scene's file variables, e.g. the 3D chain's positions: file_variables; compressed up to
    COMPRESS_BYTES), and the run's copies of its inputs (`copies`: file name -> bytes, RunInputs.copies), written
    together: each into a temporary file first, the trajectory and the copies renamed into place before the summary
    that records their SHA-256, so a summary never describes another trajectory unnoticed. Both record the digest of
    the run's settings (settings_digest), so neither can be edited into describing another run unnoticed.
    A trajectory that cannot be written (a full disk, the file-size limit) does not take the summary with it: into a
    folder holding no earlier run the summary is written alone, with trajectory_sha256 null and trajectory_error; an
    earlier run's files are kept whole. Either way a RunWriteError naming trajectory.npz is raised after."""
    checksum = {}
    digest = settings_digest(summary_dict)

    def trajectory(tmp: Path) -> None:
        head = {} if traj.head is None else {"head": traj.head}
        if traj.polarity is not None:
            head["polarity"] = traj.polarity
        if traj.nodes is not None:
            head["nodes"] = traj.nodes
        arrays = {"t": traj.t, "theta": traj.theta, **head, **file_variables(traj)}
        save = np.savez_compressed if sum(a.nbytes for a in arrays.values()) <= COMPRESS_BYTES else np.savez
        save(tmp, scene=traj.physics.scene, n=traj.physics.n, settings_sha256=digest, **arrays)
        checksum["sha256"] = sha256(tmp)

    def summary_file(tmp: Path) -> None:
        tmp.write_text(_summary_text(summary_dict, digest, checksum.get("sha256"), checksum.get("error")))

    def copy(data: bytes):
        return lambda tmp: tmp.write_bytes(data)

    out = Path(out)
    earlier = [name for name in ("summary.json", "trajectory.npz") if (out / name).exists()]
    writers = {"trajectory.npz": trajectory, **{name: copy(data) for name, data in (copies or {}).items()}}
    try:
        return write_files(out, {**writers, "summary.json": summary_file})
    except OSError as err:
        if err.filename != str(out / "trajectory.npz"):
            raise
        if earlier:  # an earlier run's files: kept whole, not half replaced
            raise RunWriteError(
                err.errno, f"{err.strerror}; nothing was replaced: {out} keeps the run it held", err.filename, None
            ) from None
        failed = err
    # the trajectory (the large file) could not be written: the summary (small: the results, the settings) still is,
    # recording the failure and no trajectory checksum
    checksum.pop("sha256", None)
    checksum["error"] = f"not written: {failed.strerror}"
    try:
        written = write_files(out, {"summary.json": summary_file})
    except OSError:
        raise failed from None
    raise RunWriteError(
        failed.errno,
        f"{failed.strerror}; {written[0]} was written without it (the run's results and "
        "settings; re-run it with --from to have the trajectory)",
        failed.filename,
        written[0],
    ) from None


def _summary_text(summary_dict: Mapping, digest: str, trajectory_sha256: str | None, error: str | None) -> str:
    record = {**summary_dict, "settings_sha256": digest, "trajectory_sha256": trajectory_sha256}
    if error is not None:
        record["trajectory_error"] = error
    return json.dumps(jsonable(record), indent=2) + "\n"


def rewrite_summary(out: Path, summary_dict: dict) -> Path:
    """Replace, atomically, the summary.json that write_run wrote into `out` for this run by `summary_dict` (the same
    run: the same settings digest, e.g. its record once measured), keeping what that one recorded of the trajectory
    file (its checksum, or why it was not written). Refuses (ValueError) a summary.json of other settings."""
    path = Path(out) / "summary.json"
    current = json.loads(path.read_text())
    digest = settings_digest(summary_dict)
    if current.get("settings_sha256") != digest:
        raise ValueError(f"{path} holds another run's summary; not replaced")
    return write_text(
        path, _summary_text(summary_dict, digest, current.get("trajectory_sha256"), current.get("trajectory_error"))
    )


def _edited(path: Path) -> ParameterError:
    return ParameterError(
        f"{path} was changed after the run wrote it (its engine, parameters or numerics no longer "
        "match the checksum recorded with them); restore it, or re-run the simulation"
    )


def read_summary(path: Path) -> dict:
    """A run's summary.json (a folder written by `run --out`, or the file itself), refused (ParameterError) unless
    it holds settings_sha256 and that digest matches its settings (settings_digest): an edited summary, its digest
    removed or not, never reads as a run's record."""
    path = Path(path)
    if path.is_dir():
        path = path / "summary.json"
    try:
        summary_dict = json.loads(path.read_text())
    except FileNotFoundError:
        raise ParameterError(
            f"{path} not found: give a folder written by `elastoactive run --out` or its summary.json"
        ) from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as err:
        raise ParameterError(f"{path} is not a readable summary.json ({err})") from None
    if not isinstance(summary_dict, dict) or not isinstance(summary_dict.get("parameters"), dict):
        raise ParameterError(f"{path} is not a summary.json written by elastoactive run (no parameters)")
    recorded = summary_dict.get("settings_sha256")
    if recorded is None:  # without its checksum a summary's settings cannot be told from an edit of them
        raise ParameterError(
            f"{path} has no settings_sha256 (the checksum `elastoactive run` records with its engine, "
            "parameters and numerics), so it may have been changed after the run wrote it; restore "
            "it, or re-run the simulation"
        )
    if recorded != settings_digest(summary_dict):
        raise _edited(path)
    return summary_dict


class RecordWarning(UserWarning):
    """An input of a run's record (its network file, a plug-in file, the distribution of a plug-in) changed since the
    run; the message, one line, says what is read instead."""


def recorded_physics(summary_dict: Mapping, folder: Path, what: str) -> tuple[Physics, list[str]]:
    """The Physics a run's summary describes, reading what the run read, and one note per input that changed since:
    the distributions its entry-point scene and terms came from must provide them here (elastoactive.plugins.
    check_entry_points; refused otherwise, one line starting with `what`); its network file is the original while
    that holds the bytes the run read, else the copy in the run's `folder` (a note says so), and neither is refused;
    plug-in files that changed are noted (elastoactive.plugins.recorded loads the run's copy)."""
    notes = plugins.check_entry_points(dict(summary_dict), what)
    inputs = RunInputs.of(summary_dict, f"{what}: summary.json")
    parameters = dict(summary_dict["parameters"])
    if inputs.network_file is not None:
        found, note = inputs.network_file.locate(folder, "network file")
        if found is None:
            raise ParameterError(f"{what}: {note}; restore the network file it ran")
        if note is not None:
            notes.append(note)
            parameters["geometry"] = str(found)
    notes += plugins.file_notes(folder, dict(summary_dict))
    return Physics(**parameters), notes


def load_trajectory(path: Path, physics: Physics | None = None) -> Trajectory:
    """Read a trajectory.npz written by write_run (the physics from summary.json beside it: recorded_physics, whose
    notes are issued as RecordWarning); see read_run."""
    traj, notes = read_run(path, physics)
    for note in notes:
        warnings.warn(note, RecordWarning, stacklevel=2)
    return traj


def read_run(path: Path, physics: Physics | None = None, what: str | None = None) -> tuple[Trajectory, list[str]]:
    """A trajectory.npz written by write_run (the physics from summary.json beside it: recorded_physics, whose refusals
    start with `what`, default the path) and the notes on its inputs. Its records are read (t, theta, head, polarity,
    nodes); the scene's file variables (the 3D chain's positions) are not: they are what Trajectory.positions computes
    again from the angles, the same numbers.

    Refuses, naming the file, a truncated or foreign file, missing or misshapen arrays, non-finite
    angles, and a trajectory that is not the one its summary.json describes (checksum)."""
    path = Path(path)
    if path.is_dir():
        path = path / "trajectory.npz"
    summary_file = path.with_name("summary.json")
    recorded = read_summary(summary_file) if summary_file.exists() else None
    notes: list[str] = []
    if physics is None:
        if recorded is None:
            raise ParameterError(f"{summary_file} not found: the physics of {path} is unknown")
        physics, notes = recorded_physics(recorded, path.parent, what or str(path.parent))
    try:
        with np.load(path) as f:
            t, theta = np.asarray(f["t"], dtype=float), np.asarray(f["theta"], dtype=float)
            moving = physics.scene_def.head_count(physics) or "head" in f.files  # a moving pivot, or a moving clamp
            head = np.asarray(f["head"], dtype=float) if moving else None
            digest = str(f["settings_sha256"]) if "settings_sha256" in f.files else None
            polarity = np.asarray(f["polarity"], dtype=float) if "polarity" in f.files else None
            nodes = np.asarray(f["nodes"], dtype=float) if "nodes" in f.files else None
    except FileNotFoundError:
        raise ParameterError(f"{path} not found") from None
    except KeyError as err:
        raise ParameterError(
            f"{path} lacks the array {err} (expected t and theta, and head for a moving pivot)"
        ) from None
    except (OSError, ValueError, EOFError, zipfile.BadZipFile) as err:
        raise ParameterError(f"{path} is not a readable trajectory.npz (truncated or foreign file: {err})") from None
    if t.ndim != 1 or t.size < 2 or theta.shape != (t.size, physics.n_angles):
        raise ParameterError(
            f"{path}: expected t of shape (T,) with T >= 2 and theta of shape (T, {physics.n_angles}) "
            f"for {physics.scene_def.label(physics)}; got {t.shape} and {theta.shape}"
        )
    if not (np.all(np.isfinite(t)) and np.all(np.diff(t) > 0)):
        raise ParameterError(f"{path}: the sample times t are not finite and increasing")
    columns = physics.scene_def.head_count(physics) or 2  # the scene's moving pivot, or a moving clamp's (x_c, y_c)
    if head is not None and head.shape != (t.size, columns):
        raise ParameterError(f"{path}: expected head of shape ({t.size}, {columns}), got {head.shape}")
    if polarity is not None and (polarity.ndim != 2 or polarity.shape[0] != t.size):
        raise ParameterError(f"{path}: expected polarity of shape ({t.size}, units), got {polarity.shape}")
    if nodes is not None and (nodes.ndim != 3 or nodes.shape[0] != t.size or nodes.shape[2] != 2):
        raise ParameterError(f"{path}: expected nodes of shape ({t.size}, nodes, 2), got {nodes.shape}")
    state = theta if head is None else np.hstack([theta, head])
    if nodes is not None:
        state = np.hstack([state, nodes.reshape(t.size, -1)])
    if not np.all(np.isfinite(state)):
        bad = t[~np.all(np.isfinite(state), axis=1)][0]
        raise ParameterError(f"{path}: the angles are not finite from t = {bad:g} tau on (a diverged run?)")
    if recorded is not None and recorded.get("trajectory_sha256") not in (None, sha256(path)):
        raise ParameterError(
            f"{path} is not the trajectory {summary_file.name} describes (checksum differs: an "
            "interrupted or mixed write); re-run the simulation"
        )
    if recorded is not None and digest is not None and digest != settings_digest(recorded):
        raise _edited(summary_file)
    traj = Trajectory(
        t=t,
        theta=theta,
        physics=physics,
        engine=(recorded or {}).get("engine", "file"),
        head=head,
        polarity=polarity,
        nodes=nodes,
    )
    return traj, notes
