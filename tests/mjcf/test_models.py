"""Every model compiles and steps without MuJoCo warnings (after mujoco_menagerie's test/model_test.py).

Two kinds of model: the ones elastoactive builds (every registered scene, at several N and the
default parameters, stepped with the follower-force callback installed) and the base MJCF files
as they stand (opened on their own, as MuJoCo's viewer would open them, stepped without it).
"""

import xml.etree.ElementTree as ET

import mujoco
import numpy as np
import pytest

from elastoactive import scenes
from elastoactive.controllers import follower_forces
from elastoactive.core.params import Numerics, Physics
from elastoactive.mjcf import mjcf_path
from elastoactive.mjcf.chain import prepare

N_VALUES = (1, 2, 7, 40)
STEPS = 200
BASE_FILE_STEPS = 20
COMMON = "common.xml"


def base_path(scene):
    return mjcf_path(scenes.get(scene).base_file)


def raised_warnings(data):
    """MuJoCo's warnings that fired on `data`: {name: how often}."""
    return {
        name: data.warning[int(w)].number
        for name, w in mujoco.mjtWarning.__members__.items()
        if w != mujoco.mjtWarning.mjNWARNING and data.warning[int(w)].number
    }


def _cases():
    for scene in scenes.names():
        if scenes.get(scene).term_parameters is not None:  # a network scene has no n (tests/test_network*)
            continue
        min_n = scenes.get(scene).min_n
        for n in N_VALUES:
            marks = pytest.mark.skip(reason=f"{scene} needs N >= {min_n}") if n < min_n else ()
            yield pytest.param(scene, n, id=f"{scene}-N{n}", marks=marks)


@pytest.mark.parametrize("scene,n", list(_cases()))
def test_built_model_steps_without_warnings(scene, n):
    physics, numerics = Physics(scene=scene, n=n), Numerics()
    model, data = prepare(physics, numerics)
    with follower_forces():
        mujoco.mj_step(model, data, nstep=STEPS)
    assert not raised_warnings(data), f"{scene} N={n}: MuJoCo warnings {raised_warnings(data)}"
    assert np.all(np.isfinite(data.qpos)) and np.all(np.isfinite(data.qvel))
    assert data.time == pytest.approx(STEPS * model.opt.timestep)


@pytest.mark.parametrize("scene", scenes.names())
def test_base_file_compiles_and_steps_without_warnings(scene):
    model = mujoco.MjModel.from_xml_path(str(base_path(scene)))
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data, nstep=BASE_FILE_STEPS)
    assert not raised_warnings(data), f"{scene} base file: MuJoCo warnings {raised_warnings(data)}"


@pytest.mark.parametrize("scene", scenes.names())
def test_base_file_includes_common(scene):
    """Shared settings live in common.xml only: each scene file includes it and does not repeat them."""
    root = ET.parse(base_path(scene)).getroot()
    includes = [child.get("file") for child in root if child.tag == "include"]
    assert includes == [COMMON], f"{scene}: includes {includes}"
    shared = {child.tag for child in ET.parse(mjcf_path(COMMON)).getroot()} - {"option", "worldbody"}
    repeated = shared & {child.tag for child in root}
    assert not repeated, f"{scene} repeats what {COMMON} holds: {sorted(repeated)}"
