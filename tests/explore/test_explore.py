"""The front door as complete as the command line: ea.sweep, ea.ramp, ea.stability and ea.save give what `sweep`,
`ramp`, `stability` and `run --out` write or print, and a refusal names a setting as the caller spells it."""

import dataclasses
import json
import math

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.cli import main
from elastoactive.core import surface

REDUCED = dict(engine="reduced", workers=1)


def test_sweep_is_the_dataset_the_command_writes(tmp_path, capsys):
    out = tmp_path / "cli.nc"
    argv = ["sweep", "one-pinned", "--grid", "sigma=2,3", "--n", "3", "--duration", "10", "--engine", "reduced"]
    assert main([*argv, "--workers", "1", "--quiet", "--out", str(out)]) == 0
    capsys.readouterr()
    ds = ea.sweep({"scene": "one-pinned", "n": 3}, {"sigma": "2,3"}, duration=10, **REDUCED)
    written = ea.load(out)
    assert set(ds.data_vars) == set(written.data_vars)
    np.testing.assert_allclose(ds["amplitude"].values, written["amplitude"].values, rtol=1e-9)
    assert ds["amplitude"].attrs == written["amplitude"].attrs and ds.attrs["sweep_spec"] == written.attrs["sweep_spec"]


def test_sweep_resumes_the_command_s_file(tmp_path, capsys):
    """The same sweep from Python and from the command line is one sweep: either resumes the other's file."""
    out = tmp_path / "s.nc"
    physics = ea.Physics(n=3, sigma=2.0)
    ds = ea.sweep(physics, {"sigma": [2.0, 3.0]}, duration=10, out=out, **REDUCED)
    argv = ["sweep", "one-pinned", "--grid", "sigma=2,3", "--n", "3", "--duration", "10", "--engine", "reduced"]
    assert main([*argv, "--workers", "1", "--quiet", "--out", str(out)]) == 0
    assert "2 of 2 points" in capsys.readouterr().out
    assert ea.load(out)["amplitude"].equals(ds["amplitude"])
    with pytest.raises(ea.ParameterError, match="another sweep|differ"):
        ea.sweep(physics, {"sigma": [2.0, 4.0]}, duration=10, out=out, **REDUCED)


def test_sweep_refusals_name_the_argument():
    with pytest.raises(ea.ParameterError, match="sigma given both fixed and on the grid"):
        ea.sweep({"scene": "one-pinned", "sigma": 1.0}, {"sigma": [2, 3]}, duration=10, **REDUCED)
    with pytest.raises(ea.ParameterError, match=r"^numerics\.integrator: integrator only affects the MuJoCo"):
        ea.sweep("one-pinned", {"sigma": [2, 3]}, {"integrator": "Euler"}, duration=10, **REDUCED)
    with pytest.raises(TypeError, match="grid must be a dict"):
        ea.sweep("one-pinned", ["sigma=2,3"], duration=10, **REDUCED)


def test_sweep_on_a_dask_client():
    distributed = pytest.importorskip("dask.distributed")
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as client:
        ds = ea.sweep(ea.Physics(n=3), {"sigma": [2.0, 3.0]}, duration=10, engine="reduced", scheduler=client)
    assert (ds["status"].values == "ok").all() and ds["amplitude"].dims == ("sigma",)


def test_ramp_is_the_loop_the_command_writes(tmp_path, capsys):
    out = tmp_path / "cli.nc"
    argv = ["ramp", "one-pinned", "--n", "3", "--ramp", "sigma=2,3", "--duration", "10", "--workers", "1"]
    assert main([*argv, "--quiet", "--out", str(out)]) == 0
    capsys.readouterr()
    ds = ea.ramp({"scene": "one-pinned", "n": 3}, "sigma", [2, 3], duration=10, workers=1)
    written = ea.load(out)
    assert ds["amplitude"].dims == ("seed", "direction", "sigma") and list(ds["direction"].values) == ["up", "down"]
    np.testing.assert_allclose(ds["amplitude"].values, written["amplitude"].values, rtol=1e-9)
    with pytest.raises(ea.ParameterError, match=r"^sigma: sigma is ramped"):
        ea.ramp({"scene": "one-pinned", "sigma": 2.0}, "sigma", [2, 3], duration=10)


def test_stability_is_typed_and_prints_as_the_command(capsys):
    result = ea.stability(ea.Physics(n=7), sigma=0.8)
    assert isinstance(result, ea.Stability)
    assert result.sigma_c == pytest.approx(0.1575, abs=1e-4) and result.omega_c > 0 and "Hopf" in result.kind
    assert result.growth > 0 and result.unstable and result.frequency >= 0
    assert ea.stability("one-pinned", sigma=0.1).unstable is False
    assert main(["stability", "one-pinned", "--n", "7", "--sigma", "0.8"]) == 0
    assert capsys.readouterr().out == str(result) + "\n"
    with pytest.raises(dataclasses.FrozenInstanceError):
        result.sigma_c = 1.0  # type: ignore[misc]
    without = ea.stability("coupled-pair")
    assert without.growth is None and without.unstable is None and math.isfinite(without.sigma_c)


def test_stability_refuses_a_scene_without_an_operator():
    from elastoactive.explore import with_operator

    scenes = [s for s in ea.scenes.names() if s not in with_operator()]
    if not scenes:
        pytest.skip("every registered scene has a linear operator")
    with pytest.raises(ea.ParameterError, match="has no linear operator"):
        ea.stability(scenes[0])


def test_save_writes_the_folder_run_out_writes(tmp_path, capsys):
    """ea.save's folder is the command's: the same settings digest and results, read by ea.load and run --from."""
    physics, numerics = ea.Physics(n=4, sigma=3.0), ea.Numerics(sample_dt=0.1, seed=3)
    traj = ea.simulate(physics, numerics, duration=10, engine="reduced")
    assert ea.save(traj, tmp_path / "api") == tmp_path / "api"
    argv = ["run", "one-pinned", "--n", "4", "--sigma", "3", "--sample-dt", "0.1", "--seed", "3"]
    assert main([*argv, "--duration", "10", "--engine", "reduced", "--quiet", "--out", str(tmp_path / "cli")]) == 0
    capsys.readouterr()
    api, cli = (json.loads((tmp_path / name / "summary.json").read_text()) for name in ("api", "cli"))
    assert api["settings_sha256"] == cli["settings_sha256"] and api["results"]["amplitude"] == pytest.approx(
        cli["results"]["amplitude"], rel=1e-9
    )
    assert set(api["provenance"]) == set(cli["provenance"]) and api["trajectory_sha256"]
    loaded = ea.load(tmp_path / "api")
    np.testing.assert_array_equal(loaded.theta, traj.theta)
    assert main(["run", "--from", str(tmp_path / "api"), "--quiet", "--out", str(tmp_path / "again")]) == 0
    assert ea.save(loaded, tmp_path / "copy") == tmp_path / "copy"  # a loaded run saves as its summary records it


def test_save_records_the_start_and_refuses_another_run(tmp_path):
    first = ea.simulate(ea.Physics(n=3, sigma=3.0), duration=4, engine="reduced")
    then = ea.simulate(ea.Physics(n=3, sigma=3.0), duration=4, engine="reduced", start=first)
    folder = ea.save(then, tmp_path / "run")
    record = json.loads((folder / "summary.json").read_text())
    assert record["inputs"]["start"]["state_sha256"] and (folder / "start.npz").is_file()
    other = ea.simulate(ea.Physics(n=3, sigma=4.0), duration=4, engine="reduced")
    with pytest.raises(ea.ParameterError, match=r"^path = '.*' already holds a run with other settings .* pass force"):
        ea.save(other, folder)
    ea.save(other, folder, force=True)
    with pytest.raises(ea.ParameterError, match="numerics, duration: give"):
        ea.save(ea.Trajectory(t=first.t, theta=first.theta, physics=first.physics, engine="reduced"), tmp_path / "x")


def test_the_timestep_refusal_speaks_the_caller_s_language(capsys):
    physics, numerics = ea.Physics(n=7, sigma=0.8), ea.Numerics(dt=0.05, mass_ratio=1e-4)
    with pytest.raises(ea.ParameterError) as err:
        ea.simulate(physics, numerics, duration=10)
    assert "Numerics(dt=0.025, mass_ratio=0.0001, integrator='implicitfast')" in str(err.value)
    assert "--dt" not in str(err.value)
    argv = ["run", "one-pinned", "--n", "7", "--sigma", "0.8", "--dt", "0.05", "--mass-ratio", "0.0001"]
    assert main([*argv, "--duration", "10", "--quiet"]) == 2
    line = capsys.readouterr().err
    assert "--dt 0.025 --mass-ratio 0.0001 --integrator implicitfast" in line and "Numerics(" not in line
    assert surface.current() == surface.PYTHON  # the command's wording ends with the command


@pytest.mark.parametrize(
    ("call", "python", "command_line"),
    [
        (lambda: ea.simulate("one-pinned", duration=0.1, engine="reduced"), "lengthen duration", "lengthen --duration"),
        (
            lambda: ea.simulate("one-pinned", {"integrator": "Euler"}, duration=10, engine="reduced"),
            "numerics.integrator:",
            "--integrator:",
        ),
    ],
)
def test_refusals_name_settings_by_the_surface(call, python, command_line):
    with pytest.raises(ea.ParameterError, match=python.replace(".", r"\.")):
        call()
    with surface.command_line(), pytest.raises(ea.ParameterError, match=command_line):
        call()


def test_surface_words():
    assert surface.option("numerics.dt") == "numerics.dt" and surface.option("sigma", 0.5) == "sigma = 0.5"
    assert surface.settings("Numerics", dt=0.01, integrator="euler") == "Numerics(dt=0.01, integrator='euler')"
    with surface.command_line():
        assert surface.option("numerics.mass_ratio") == "--mass-ratio" and surface.option("sigma", 0.5) == "--sigma 0.5"
        assert surface.settings("Numerics", dt=0.01, integrator="euler") == "--dt 0.01 --integrator euler"


def test_ea_sweep_is_the_sweep_package_called():
    """One name, one thing: ea.sweep is the package elastoactive.sweep, whose call is its verb (signature included),
    however it was imported."""
    import inspect

    import elastoactive.sweep.grid as grid
    from elastoactive import sweep
    from elastoactive.sweep import run_sweep
    from elastoactive.sweep.verb import sweep as verb

    assert sweep is ea.sweep and callable(sweep) and callable(run_sweep) and grid.parse_grid
    assert inspect.signature(ea.sweep) == inspect.signature(verb) and "grid" in inspect.signature(ea.sweep).parameters
