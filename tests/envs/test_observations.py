"""Observation designs: named groups, presets, the layout, distractors, noise and delay,
the same on every family and in the native vector env; goals stay exact state."""

from __future__ import annotations

import contextlib
import io
import pickle
import re
import warnings

import gymnasium as gym
import numpy as np
import pytest
from conftest import ALL_IDS
from gymnasium.utils.env_checker import check_env as gym_check_env
from gymnasium.vector import AutoresetMode
from stable_baselines3.common.env_checker import check_env as sb3_check_env
from test_vector import assert_same, pair, play

import unified_manip
from unified_manip.envs.observation_docs import observation_groups_doc
from unified_manip.envs.observations import PRESETS, SHARED_GROUPS

REACH = "UnifiedManip/Arm4Reach-v0"
PICK = "UnifiedManip/Arm4PickAndPlace-v0"
SENSORS = {"observation_noise": 0.01, "observation_delay": 2, "observation_distractors": 3}


def _modes(task_id: str) -> list[str]:
    modes = unified_manip.TASKS[task_id].action_modes
    return [m for m in ("native", "joint_delta") if m in modes]


def _ids(p) -> str:
    return str(p).replace("UnifiedManip/", "")


# ---------------------------------------------------------------------- the default is today's vector
@pytest.mark.parametrize("task_id,mode", [(t, m) for t in ALL_IDS for m in _modes(t)], ids=_ids)
def test_default_groups_concatenate_to_the_family_vector(task_id, mode):
    env = gym.make(task_id, action_mode=mode)
    b = env.unwrapped.backend
    groups = b.observation_groups()
    assert set(b.default_observation()) <= set(groups)
    obs, _ = env.reset(seed=3)
    rng = np.random.default_rng(0)
    for step in range(4):
        parts = [np.asarray(groups[n].read(b), dtype=np.float64).ravel() for n in b.default_observation()]
        assert np.array_equal(np.concatenate(parts).astype(np.float32), obs["observation"]), f"step {step}"
        obs = env.step(rng.uniform(-1, 1, env.action_space.shape).astype(np.float32))[0]
    env.close()


# ---------------------------------------------------------------------- checkers, every ID x preset
@pytest.mark.parametrize("preset", PRESETS)
@pytest.mark.parametrize("task_id", ALL_IDS, ids=_ids)
def test_every_preset_passes_both_env_checkers(task_id, preset):
    env = gym.make(task_id, observation=preset, disable_env_checker=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.filterwarnings("ignore", message=r".*infinity. This is probably too (low|high)")
        gym_check_env(env.unwrapped, skip_render_check=True)
        sb3_check_env(env.unwrapped, warn=True, skip_render_check=True)
    layout = env.unwrapped.observation_layout
    assert list(layout) == list(_preset_groups(env.unwrapped.backend, preset))
    env.close()


def _preset_groups(backend, preset):
    groups, kinds = backend.observation_groups(), {n: g.kind for n, g in backend.observation_groups().items()}
    if preset == "default":
        return backend.default_observation()
    if preset == "full":
        return tuple(groups)
    minimal = tuple(n for n in groups if kinds[n] == "state")
    return minimal if preset == "minimal" else minimal + tuple(n for n in ("object_rel", "goal_rel") if n in groups)


def test_presets_on_the_pick_task():
    layouts = {p: gym.make(PICK, observation=p).unwrapped.observation_layout for p in PRESETS}
    assert list(layouts["minimal"]) == ["joint_pos", "gripper", "ee_pos", "object_pos", "object_rot"]
    assert list(layouts["relative"]) == [*layouts["minimal"], "object_rel", "goal_rel"]
    assert list(layouts["full"]) == [
        "joint_pos",
        "gripper",
        "joint_vel",
        "gripper_vel",
        "ee_pos",
        "ee_vel",
        "object_pos",
        "object_rot",
        "object_vel",
        "object_rel",
        "goal_rel",
    ]
    assert all(not n.endswith("_vel") and n not in ("object_rel", "goal_rel") for n in layouts["minimal"])


# ---------------------------------------------------------------------- layout and its documentation
@pytest.mark.parametrize("task_id", ALL_IDS, ids=_ids)
def test_layout_matches_the_vector_and_the_documented_sizes_and_units(task_id):
    env = gym.make(task_id, observation="full", observation_distractors=2)
    obs, _ = env.reset(seed=0)
    layout = env.unwrapped.observation_layout
    stops = [s.stop for s in layout.values()]
    assert [s.start for s in layout.values()] == [0, *stops[:-1]]
    assert stops[-1] == obs["observation"].shape[0] == env.observation_space["observation"].shape[0]
    assert layout["distractors"] == slice(stops[-1] - 2, stops[-1])
    doc = observation_groups_doc(task_id)
    b = env.unwrapped.backend
    for name, group in b.observation_groups().items():
        size = layout[name].stop - layout[name].start
        assert size == np.asarray(group.read(b)).size
        assert re.search(rf"^  {name} +{size} +{group.kind} .*  {re.escape(group.units)}$", doc, re.M), name
    assert [n for n in layout if n in SHARED_GROUPS]  # every family uses the shared names
    env.close()


def test_list_doc_prints_the_groups():
    from unified_manip.cli.main import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["list", "--doc", REACH]) == 0
    text = out.getvalue()
    assert "  goal_rel        3  relative  yes      m (goal - grip site)\n" in text
    assert "  ee_vel          3  velocity           m/s (grip site, world)\n" in text
    assert "  minimal (9): joint_pos, gripper, ee_pos" in text
    assert "Goal-dependent (desired goal minus state; a HER buffer must relabel them too): goal_rel\n" in text


# ---------------------------------------------------------------------- goals stay exact
def test_goals_and_rewards_do_not_depend_on_the_design():
    envs = [gym.make(PICK, reward_type="dense", observation=p, **SENSORS) for p in ("minimal", "full")]
    envs.append(gym.make(PICK, reward_type="dense"))
    actions = np.random.default_rng(1).uniform(-1, 1, (30, 5)).astype(np.float32)
    outs = []
    for env in envs:
        obs, _ = env.reset(seed=5)
        goals = [(obs["achieved_goal"], obs["desired_goal"])]
        for a in actions:
            obs, r, *_ = env.step(a)
            goals.append((obs["achieved_goal"], obs["desired_goal"], r))
        outs.append(goals)
    assert_same(outs[0], outs[2])
    assert_same(outs[1], outs[2])


# ---------------------------------------------------------------------- the sensor model
def _play(task_id, seed, steps=20, **kwargs):
    env = gym.make(task_id, **kwargs)
    rng = np.random.default_rng(7)
    obs, _ = env.reset(seed=seed)
    out = [obs["observation"]]
    for _ in range(steps):
        out.append(env.step(rng.uniform(-1, 1, env.action_space.shape).astype(np.float32))[0]["observation"])
    env.close()
    return np.array(out)


@pytest.mark.parametrize("task_id", [PICK, "UnifiedManip/FetchPush-v0"], ids=_ids)
def test_noise_is_seeded_gaussian_and_leaves_the_state_alone(task_id):
    clean = _play(task_id, 0)
    noisy = _play(task_id, 0, observation_noise=0.01)
    assert np.array_equal(noisy, _play(task_id, 0, observation_noise=0.01))  # same seed, same bits
    assert not np.array_equal(noisy, _play(task_id, 1, observation_noise=0.01))
    diff = (noisy - clean).astype(np.float64)
    assert abs(diff.mean()) < 0.001 and 0.009 < diff.std() < 0.011


def test_noise_per_group_touches_only_that_group():
    layout = gym.make(PICK).unwrapped.observation_layout
    diff = _play(PICK, 0, observation_noise={"object_pos": 0.05}) - _play(PICK, 0)
    inside = np.zeros(diff.shape[1], dtype=bool)
    inside[layout["object_pos"]] = True
    assert (diff[:, inside] != 0).all() and (diff[:, ~inside] == 0).all()


def test_delay_repeats_the_reset_observation_then_lags():
    plain = _play(PICK, 0)
    delayed = _play(PICK, 0, observation_delay=3)
    assert np.array_equal(delayed[:4], np.repeat(plain[:1], 4, axis=0))
    assert np.array_equal(delayed[3:], plain[:-3])


def test_distractors_are_a_seeded_random_walk_appended():
    plain = _play(REACH, 0, observation="relative")
    walk = _play(REACH, 0, observation="relative", observation_distractors=4)
    assert np.array_equal(walk[:, :-4], plain)
    d = walk[:, -4:].astype(np.float64)
    assert (np.abs(d[0]) <= 0.1).all() and (np.diff(d, axis=0) != 0).all()
    assert np.array_equal(walk, _play(REACH, 0, observation="relative", observation_distractors=4))
    assert not np.array_equal(d, _play(REACH, 1, observation="relative", observation_distractors=4)[:, -4:])


def test_a_sensor_env_pickles_mid_episode():
    env = gym.make(PICK, observation=["object_rel", "goal_rel", "joint_pos"], **SENSORS).unwrapped
    env.reset(seed=2)
    a = np.full(5, 0.3, dtype=np.float32)
    env.step(a)
    twin = pickle.loads(pickle.dumps(env))
    for _ in range(3):
        assert_same(env.step(a), twin.step(a))


# ---------------------------------------------------------------------- the native vector env
@pytest.mark.parametrize(
    "task_id,kwargs",
    [
        (REACH, {"observation": "relative", **SENSORS}),
        (PICK, {"observation": "full", "action_mode": "ee_delta", "observation_noise": {"object_rel": 0.02}}),
        ("UnifiedManip/FetchPush-v0", {"observation": "minimal", **SENSORS}),
    ],
    ids=_ids,
)
def test_native_vector_env_matches_the_single_env(task_id, kwargs):
    native, reference = pair(task_id, 2, **kwargs)
    assert native.observation_space == reference.observation_space
    assert native.observation_layout == gym.make(task_id, **kwargs).unwrapped.observation_layout
    steps = unified_manip.TASKS[task_id].max_episode_steps + 3 if task_id == REACH else 8
    play(native, reference, steps)
    native.close()
    reference.close()


def test_native_vector_env_matches_in_same_step_autoreset():
    native, reference = pair(REACH, 2, AutoresetMode.SAME_STEP, observation="minimal", **SENSORS)
    play(native, reference, unified_manip.TASKS[REACH].max_episode_steps + 3)


# ---------------------------------------------------------------------- bad input
BAD = [
    (
        {"observation": "tiny"},
        "unknown observation preset 'tiny'; expected one of 'default', 'minimal', 'relative', 'full' "
        "or a list of groups of UnifiedManip/Arm4Reach-v0 ('joint_pos', 'gripper', 'joint_vel', "
        "'gripper_vel', 'ee_pos', 'ee_vel', 'goal_rel')",
    ),
    (
        {"observation": ["joint_pos", "wrist_cam"]},
        "unknown observation group 'wrist_cam' for UnifiedManip/Arm4Reach-v0; expected some of 'joint_pos', "
        "'gripper', 'joint_vel', 'gripper_vel', 'ee_pos', 'ee_vel', 'goal_rel'",
    ),
    (
        {"observation": ["object_pos"]},
        "observation group 'object_pos' is not available on UnifiedManip/Arm4Reach-v0; expected some of "
        "'joint_pos', 'gripper', 'joint_vel', 'gripper_vel', 'ee_pos', 'ee_vel', 'goal_rel'",
    ),
    ({"observation": ["ee_pos", "ee_pos"]}, "observation group 'ee_pos' is listed twice"),
    ({"observation": []}, "observation must be a preset or a non-empty list of group names, got ()"),
    ({"observation_noise": -0.1}, "observation_noise must be a standard deviation >= 0, got -0.1"),
    (
        {"observation_noise": {"ee_pos": -1.0}},
        "observation_noise['ee_pos'] must be a standard deviation >= 0, got -1.0",
    ),
    (
        {"observation": "minimal", "observation_noise": {"goal_rel": 0.1}},
        "observation_noise names group 'goal_rel', which the observation does not have; "
        "expected some of 'joint_pos', 'gripper', 'ee_pos'",
    ),
    ({"observation_delay": -1}, "observation_delay must be an int >= 0, got -1"),
    ({"observation_delay": 1.5}, "observation_delay must be an int >= 0, got 1.5"),
    ({"observation_distractors": -2}, "observation_distractors must be an int >= 0, got -2"),
]


@pytest.mark.parametrize("kwargs,message", BAD, ids=[m[:40] for _, m in BAD])
def test_bad_observation_options_fail_in_one_line(kwargs, message):
    for make in (lambda: gym.make(REACH, **kwargs), lambda: gym.make_vec(REACH, num_envs=2, **kwargs)):
        with pytest.raises(ValueError) as err:
            make()
        assert str(err.value).split(" was raised from")[0] == message
