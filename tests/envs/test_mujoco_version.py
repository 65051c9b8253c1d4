"""An unsupported MuJoCo is refused in one line naming the supported range, before any
simulator code runs, instead of an upstream traceback mid-step."""

from __future__ import annotations

import os
import subprocess
import tomllib
from importlib.metadata import version
from pathlib import Path

import pytest
from conftest import overlay_venv

from unified_manip.envs.mujoco_version import SUPPORTED, UnsupportedMuJoCo, check_mujoco, supported

ROOT = Path(__file__).resolve().parents[2]


def message(found: str) -> str:
    return (
        f"mujoco {found} is installed, but unified_manip supports mujoco>=3.3.0,<3.10 "
        '(the families\' upstreams break on 3.10 and later): pip install "mujoco>=3.3.0,<3.10"'
    )


def test_the_range_is_the_one_pyproject_requires():
    deps = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    assert f"mujoco{SUPPORTED}" in deps


@pytest.mark.parametrize(
    "found, ok",
    [
        ("3.3.0", True),
        ("3.3.7", True),
        ("3.9.0", True),
        ("3.9", True),
        ("3.2.7", False),
        ("3.10.0", False),
        ("3.12.0.dev1", False),
        ("4.0.1", False),
        ("2.3.7", False),
        ("unknown", False),
    ],
)
def test_versions_in_and_out_of_the_range(found, ok):
    assert supported(found) is ok
    if ok:
        check_mujoco(found)
    else:
        with pytest.raises(UnsupportedMuJoCo) as err:
            check_mujoco(found)
        assert str(err.value) == message(found)


def test_the_running_mujoco_is_supported():
    check_mujoco()  # the installed one (CI tests both ends of the range)
    assert supported(version("mujoco"))


@pytest.mark.slow
def test_an_installed_mujoco_3_10_is_refused_in_one_line(tmp_path):
    """A venv whose own mujoco is 3.10.0 (installed over this venv's packages, seen through
    a .pth line): gym.make and the CLI say which range is supported, before any backend
    is built."""
    python = overlay_venv(tmp_path / "venv", "mujoco==3.10.0")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    code = (
        "import gymnasium as gym, unified_manip\n"
        "from importlib.metadata import version\n"
        "from unified_manip.envs.mujoco_version import UnsupportedMuJoCo\n"
        "print(version('mujoco'))\n"
        "try:\n"
        "    gym.make('UnifiedManip/Arm4Reach-v0')\n"
        "except UnsupportedMuJoCo as err:\n"
        "    print(err)\n"
    )
    proc = subprocess.run([python, "-c", code], capture_output=True, text=True, env=env, timeout=300)
    assert proc.stdout.splitlines() == ["3.10.0", message("3.10.0")], proc.stderr
    cli = subprocess.run(
        [
            python,
            "-m",
            "unified_manip.cli",
            "demo",
            "--env",
            "UnifiedManip/Arm4Reach-v0",
            "--out",
            str(tmp_path / "d.png"),
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert (cli.returncode, cli.stderr) == (2, f"unified-manip demo: error: {message('3.10.0')}\n")
    assert not (tmp_path / "d.png").exists()


def _model(xml_body: str, extra: str = ""):
    import mujoco

    return mujoco.MjModel.from_xml_string(f"<mujoco><worldbody>{xml_body}</worldbody>{extra}</mujoco>")


ARM = '<body name="a"><joint name="j"/><geom size=".1"/></body>'
BOX = '<body name="box" pos="1 0 0"><freejoint/><geom size=".1"/></body>'


def test_a_position_servo_is_the_mjcf_position_actuator():
    """set_to_position on the installed MuJoCo compiles to MJCF's own <position kp kv>."""
    import mujoco
    import numpy as np

    from unified_manip.envs.mujoco_version import set_to_position

    spec = mujoco.MjSpec.from_string(f"<mujoco><worldbody>{ARM}</worldbody></mujoco>")
    set_to_position(spec.add_actuator(name="s", target="j", trntype=mujoco.mjtTrn.mjTRN_JOINT), kp=37.0, kv=2.5)
    built = spec.compile()
    reference = _model(ARM, '<actuator><position name="s" joint="j" kp="37" kv="2.5"/></actuator>')
    for field in ("gainprm", "biasprm", "dynprm", "gaintype", "biastype", "dyntype", "ctrllimited", "forcelimited"):
        assert np.array_equal(getattr(built, f"actuator_{field}"), getattr(reference, f"actuator_{field}")), field


def test_deleting_a_body_and_an_equality_leaves_the_model_without_them():
    import mujoco
    import numpy as np

    from unified_manip.envs.mujoco_version import delete_element

    weld = '<equality><weld body1="a" body2="box"/></equality>'
    spec = mujoco.MjSpec.from_string(f"<mujoco><worldbody>{ARM}{BOX}</worldbody>{weld}</mujoco>")
    for eq in list(spec.equalities):
        delete_element(spec, eq)
    delete_element(spec, spec.body("box"))
    built, reference = spec.compile(), _model(ARM)
    assert (built.nbody, built.neq, built.nq) == (reference.nbody, reference.neq, reference.nq) == (2, 0, 1)
    assert np.array_equal(built.body_pos, reference.body_pos)
