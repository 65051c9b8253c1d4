"""Controller configs: target-relative modes accumulate, configs validate, the mode
tables are generated from the configs."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import make

import unified_manip
from unified_manip.envs.controllers import EEDelta, JointDelta, JointPosition, JointTargetDelta, JointVelocity

ROOT = Path(__file__).resolve().parents[2]
ARM = "UnifiedManip/Arm4PickAndPlace-v0"


def _run(task_id: str, mode: str, action: np.ndarray, steps: int):
    env = make(task_id, mode, max_episode_steps=1000)
    env.reset(seed=0)
    backend = env.unwrapped._backend
    for _ in range(steps):
        env.step(action)
    return env, backend


def test_joint_target_delta_accumulates_the_target_not_the_measured_pose():
    """A constant action: the target grows by a * 0.05 rad per step from the q at reset,
    whatever the servos' lag; joint_delta re-anchors on the measured q, so it falls behind."""
    a = np.array([0.6, 0.0, 0.0, 0.0, 1.0], np.float32)
    step = unified_manip.TASKS[ARM].controllers["joint_target_delta"].max_delta
    env, backend = _run(ARM, "joint_target_delta", np.zeros(5, np.float32), 0)
    rig = backend.rig
    expected = rig.joint_positions().copy()
    for _ in range(8):
        env.step(a)
        expected = np.minimum(np.maximum(expected + a[:4].astype(np.float64) * step, rig.lower), rig.upper)
        np.testing.assert_array_equal(backend.data.ctrl[rig.actuator_ids], expected)
    lead = expected[0] - rig.joint_positions()[0]
    assert lead > 0.005  # the target runs ahead of the lagging joint
    _, relative = _run(ARM, "joint_delta", a, 8)
    q = relative.rig.joint_positions()
    assert relative.data.ctrl[relative.rig.actuator_ids[0]] == pytest.approx(q[0] + 0.6 * step, abs=0.05)
    assert relative.data.ctrl[relative.rig.actuator_ids[0]] < expected[0] - 0.05


def test_ee_target_delta_accumulates_the_site_target():
    a = np.array([0.0, 0.0, 0.8, 1.0], np.float32)
    env, backend = _run(ARM, "ee_target_delta", np.zeros(4, np.float32), 0)
    step = unified_manip.TASKS[ARM].controllers["ee_target_delta"].step
    start = backend.rig.site_position().copy()
    for k in range(1, 6):
        env.step(a)
        np.testing.assert_allclose(
            backend.control.target, start + k * a[:3].astype(np.float64) * step, rtol=0, atol=1e-12
        )
    ahead = backend.control.target[2] - backend.rig.site_position()[2]
    _, relative = _run(ARM, "ee_delta", a, 5)
    moved_target = backend.rig.site_position()[2] - start[2]
    moved_relative = relative.rig.site_position()[2] - start[2]
    assert ahead > 0.005 and moved_target > moved_relative  # no lag compounding


@pytest.mark.parametrize("task_id", ["UnifiedManip/FetchReach-v0", "UnifiedManip/HandReach-v0", "UnifiedManip/Lift-v0"])
def test_joint_target_delta_accumulates_on_every_family(task_id):
    env = make(task_id, "joint_target_delta")
    env.reset(seed=0)
    control = env.unwrapped._backend.control
    n = control.n
    start = control.target.copy()
    a = np.zeros(env.action_space.shape, np.float32)
    a[:n] = np.where(np.arange(n) % 2 == 0, 0.5, -0.5)
    for _ in range(3):
        env.step(a)
    expected = start
    for _ in range(3):
        expected = np.clip(
            expected + a[:n].astype(np.float64) * control.config.max_delta, control.rig.lower, control.rig.upper
        )
    np.testing.assert_array_equal(control.target, expected)
    assert not np.array_equal(control.target, control.rig.joint_positions())


@pytest.mark.parametrize("task_id", [ARM, "UnifiedManip/FetchPickAndPlace-v0"])
def test_joint_position_band_maps_the_box_around_the_reset_posture(task_id):
    """``controller_options={"band": b}``: action 0 holds the posture the episode started
    in, ``a`` commands ``q_reset + a * b`` (clipped to the range), and the scripted policy's
    action for a target lands on it; without options the box is the whole range."""
    env = make(task_id, "joint_position", controller_options={"band": 0.5})
    env.reset(seed=3)
    backend = env.unwrapped._backend
    rig, control = backend.rig, backend.control
    q_reset = rig.joint_positions().copy()
    n = rig.n
    for a in (np.zeros(n), np.full(n, 0.6), np.full(n, -1.0), np.linspace(-1.0, 1.0, n)):
        env.step(np.append(a, 1.0).astype(np.float32))
        expected = np.minimum(np.maximum(q_reset + a.astype(np.float32) * 0.5, rig.lower), rig.upper)
        np.testing.assert_allclose(backend.data.ctrl[rig.actuator_ids], expected, rtol=0, atol=1e-7)
    target = q_reset + np.linspace(-0.2, 0.3, n)
    np.testing.assert_allclose(control.action_toward(target), np.linspace(-0.4, 0.6, n), atol=1e-12)
    assert "q_reset + a * 0.5" in control.config.describe()
    full = make(task_id, "joint_position").unwrapped._backend.control
    np.testing.assert_array_equal(full.scale, 0.5 * (full.rig.upper - full.rig.lower))


@pytest.mark.parametrize(
    "options, message",
    [
        (
            {"bnd": 0.5},
            "unknown controller option 'bnd' for action_mode 'joint_position' (JointPosition); expected one of 'band'",
        ),
        (
            {"band:0.5": None},
            "unknown controller option 'band:0.5' for action_mode 'joint_position' (JointPosition); "
            "expected one of 'band' (YAML reads 'band:0.5' as one name: write a space after the colon)",
        ),
        ({"band": 0.0}, "JointPosition.band must be positive, got 0.0"),
        ({"band": [0.5, 0.5]}, "JointPosition.band has 2 entries; expected 1 or one per arm joint (4)"),
        ("band=0.5", "controller_options must be a mapping of parameter names to values, got 'band=0.5'"),
    ],
)
def test_bad_controller_options_fail_at_make_naming_the_choices(options, message):
    with pytest.raises((ValueError, TypeError)) as err:
        make(ARM, "joint_position", controller_options=options)
    assert str(err.value).startswith(message)


def test_controller_options_on_a_mode_without_parameters_are_refused():
    with pytest.raises(
        ValueError,
        match=r"action_mode 'native' here \(Native\) has no parameters; expected no "
        r"controller_options, got \{'max_delta': 0.1\}",
    ):
        make("UnifiedManip/FetchReach-v0", "native", controller_options={"max_delta": 0.1})
    # Where native is one of the shared configs (the arm's joint_delta), its parameters apply.
    env = make(ARM, "native", controller_options={"max_delta": 0.1})
    assert env.unwrapped._backend.control.config == JointDelta(max_delta=0.1)
    assert JointPosition(band=(0.1, 0.2, 0.3, 0.4)).band == (0.1, 0.2, 0.3, 0.4)


@pytest.mark.parametrize(
    "build, message",
    [
        (lambda: JointDelta(max_delta=0.0), "JointDelta.max_delta must be positive, got 0.0"),
        (lambda: JointDelta(max_delta="half"), "JointDelta.max_delta must be positive, got 'half'"),
        (lambda: JointTargetDelta(max_delta=-1.0), "JointTargetDelta.max_delta must be positive, got -1.0"),
        (lambda: JointVelocity(kv=(1.0, 0.0)), "JointVelocity.kv must be positive, got (1.0, 0.0)"),
        (lambda: EEDelta(step=float("nan")), "EEDelta.step must be positive, got nan"),
        (lambda: EEDelta(iterations=0), "EEDelta.iterations must be a positive int, got 0"),
        (lambda: JointPosition(band=-0.1), "JointPosition.band must be positive, got -0.1"),
    ],
)
def test_configs_validate(build, message):
    with pytest.raises(ValueError) as err:
        build()
    assert str(err.value) == message


def test_every_mode_is_documented_from_its_config():
    for spec in unified_manip.TASKS.values():
        for mode, config in spec.controllers.items():
            assert re.search(rf"^    {mode} ", spec.doc, re.M), (spec.id, mode)
            assert config.describe().replace("`", "")[:40] in " ".join(spec.doc.split()), (spec.id, mode)


def test_every_task_page_names_the_parameters_controller_options_may_set():
    from dataclasses import fields

    for spec in unified_manip.TASKS.values():
        page = " ".join(spec.doc.split())
        for mode, config in spec.controllers.items():
            if config.controller is not None and fields(config):
                values = ", ".join(f"{f.name}={getattr(config, f.name)!r}" for f in fields(config))
                assert f"{mode}: {values}" in page, (spec.id, mode)
    assert "joint_position: band=None" in " ".join(unified_manip.TASKS[ARM].doc.split())


def test_mode_table_shows_every_tasks_config():
    """Each task's config of each mode has a row naming its family (a variant whose
    config differs, like Arm4Push-v1's doubled steps, by its own ID)."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "docs" / "_gen"))
    from mode_table import mode_table

    rows = mode_table().splitlines()
    for spec in unified_manip.TASKS.values():
        for mode, config in spec.controllers.items():
            assert any(
                row.startswith(f"| `{mode}` |") and row.endswith(f"| {config.describe()} |") and spec.family in row
                for row in rows
            ), (spec.id, mode)
    assert any("arm4 (Arm4Push-v1)" in row and "0.1 rad" in row for row in rows)
