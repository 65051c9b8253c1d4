"""The interface contract, checked on every registered ID x action mode x reward type.

In the style of gymnasium-robotics' ``tests/envs/test_envs.py``: env checkers, seeded
determinism with two envs side by side, the ``reward == compute_reward`` invariant
(batched), pickling, rendering and bad input.
"""

from __future__ import annotations

import pickle
import warnings

import gymnasium as gym
import numpy as np
import pytest
from conftest import ALL_IDS, ID_MODE_REWARDS, ID_MODES, SAMPLED_MODES, make, random_actions, rollout, smoke_mode
from gymnasium.utils.env_checker import check_env as gym_check_env
from stable_baselines3.common.env_checker import check_env as sb3_check_env

import unified_manip


def _assert_close(a: np.ndarray, b: np.ndarray) -> None:
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-9)


def _assert_same(a, b):
    """Bit-identical comparison of nested observations / infos / rewards."""
    if isinstance(a, dict):
        assert a.keys() == b.keys()
        for k in a:
            _assert_same(a[k], b[k])
    elif isinstance(a, (tuple, list)):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            _assert_same(x, y)
    elif isinstance(a, np.ndarray):
        assert a.dtype == b.dtype and a.shape == b.shape
        assert np.array_equal(a, b), f"{a} != {b}"
    else:
        assert a == b or (a != a and b != b), f"{a!r} != {b!r}"


@pytest.fixture
def new_env():
    """``make``, with every env it made closed when the test ends (pass or fail): an
    unclosed robosuite env keeps its MuJoCo memory until a full garbage collection."""
    made: list[gym.Env] = []

    def factory(*args, **kwargs) -> gym.Env:
        made.append(make(*args, **kwargs))
        return made[-1]

    yield factory
    for env in made:
        env.close()


def _case_id(case) -> str:
    return "-".join(case).replace("UnifiedManip/", "")


@pytest.fixture(
    scope="module",
    params=[pytest.param(c, id=_case_id(c), marks=pytest.mark.xdist_group(_case_id(c))) for c in ID_MODE_REWARDS],
)
def case(request):
    """One env per ID x mode x reward, shared by the tests of that case (each starts with a
    seeded reset), made once and closed after its last test. Its xdist group keeps the
    case's tests on one worker, and pytest runs them one after another."""
    task_id, mode, reward = request.param
    env = make(task_id, mode, reward)
    yield task_id, mode, reward, env
    env.close()


@pytest.fixture(
    scope="module",
    params=[pytest.param(c, id=_case_id(c), marks=pytest.mark.xdist_group("pair-" + _case_id(c))) for c in ID_MODES],
)
def pair(request):
    """Two envs per ID x mode (dense_penalized: every reward term is live), shared by the
    per-mode contracts below (each starts with seeded resets, as a user's code would) and
    closed after the last. Making a robosuite env compiles its model (~0.7 s), so the
    contracts share two rather than making ten."""
    task_id, mode = request.param
    envs = make(task_id, mode, "dense_penalized"), make(task_id, mode, "dense_penalized")
    yield task_id, mode, *envs
    for env in envs:
        env.close()


# ---------------------------------------------------------------------- checkers
def test_gymnasium_env_checker(case):
    task_id, mode, reward, env = case
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # every checker warning is a failure, except:
        # unbounded observation boxes, which gymnasium-robotics' own envs use too.
        warnings.filterwarnings("ignore", message=r".*infinity. This is probably too (low|high)")
        # Its close check makes and closes a fresh env of the ID: once per family's backend
        # (test_closing_twice_is_allowed), not per mode and reward.
        gym_check_env(env.unwrapped, skip_render_check=True, skip_close_check=True)


def test_sb3_env_checker(case):
    task_id, mode, reward, env = case
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sb3_check_env(env.unwrapped, warn=True, skip_render_check=True)


# ---------------------------------------------------------------------- spaces and info
def test_spaces_and_info(case):
    task_id, mode, reward, env = case
    spec = unified_manip.TASKS[task_id]
    assert isinstance(env.observation_space, gym.spaces.Dict)
    assert set(env.observation_space.spaces) == {"observation", "achieved_goal", "desired_goal"}
    for space in env.observation_space.spaces.values():
        assert space.dtype == np.float32
    assert env.observation_space["desired_goal"].shape == (spec.goal_dim,)
    assert env.action_space == gym.spaces.Box(-1.0, 1.0, env.action_space.shape, np.float32)
    assert env.spec.max_episode_steps == spec.max_episode_steps

    obs, info = env.reset(seed=3)
    assert env.observation_space.contains(obs)
    assert info["is_success"] in (0.0, 1.0)
    obs, r, terminated, truncated, info = env.step(env.action_space.sample())
    assert env.observation_space.contains(obs)
    assert isinstance(r, float)
    assert set(spec.terms.info_keys) <= info.keys()
    assert info["is_success"] in (0.0, 1.0)
    assert info["sim_unstable"] is False
    assert r == pytest.approx(sum(info["reward_terms"].values()), abs=1e-12)
    assert tuple(info["reward_terms"]) == env.unwrapped.reward_spec.term_names
    if mode in ("ee_delta", "ee_target_delta"):
        assert info["ik_residual"] >= 0.0
        assert isinstance(info["ik_limit_active"], bool)


# ---------------------------------------------------------------------- determinism
def test_seeded_determinism_side_by_side(pair):
    """Two envs, same seed and actions: bit-identical rollouts, across several resets."""
    task_id, mode, env1, env2 = pair
    actions = random_actions(env1, 10, seed=1)  # long rollouts: the golden test
    for seed in (0, 7, 0):
        _assert_same(rollout(env1, seed, actions), rollout(env2, seed, actions))
    # A different seed gives a different episode: another goal, or (a task whose goal is
    # always the same, e.g. a door fully open) another start.
    o1, _ = env1.reset(seed=1)
    o2, _ = env2.reset(seed=2)
    assert not all(np.array_equal(o1[k], o2[k]) for k in ("desired_goal", "observation"))


def test_unseeded_reset_continues_the_rng_stream(pair):
    task_id, mode, env1, env2 = pair
    env1.reset(seed=5)
    env2.reset(seed=5)
    _assert_same(env1.reset()[0], env2.reset()[0])


# ---------------------------------------------------------------------- reward invariant
def test_compute_reward_equals_step_reward_batched(case):
    task_id, mode, reward, env = case
    env.reset(seed=11)
    ag, dg, infos, rewards = [], [], [], []
    for a in random_actions(env, 30, seed=2):
        obs, r, _, _, info = env.step(a)
        ag.append(obs["achieved_goal"])
        dg.append(obs["desired_goal"])
        infos.append(info)
        rewards.append(r)
    ag, dg = np.array(ag), np.array(dg)
    infos = np.array(infos, dtype=object)
    batched = env.unwrapped.compute_reward(ag, dg, infos)
    assert batched.shape == (len(rewards),)
    np.testing.assert_array_equal(batched, np.array(rewards))
    # Single-transition calls agree with the batch, and relabelled goals (as HER
    # does) give the reward the step would have given for that goal.
    for i in (0, 17, 29):
        assert env.unwrapped.compute_reward(ag[i], dg[i], infos[i]) == rewards[i]
    # Relabelled with the achieved goal, every transition succeeds: it never pays less,
    # and it earns the whole success term.
    relabelled = env.unwrapped.compute_reward(ag, ag, infos)
    assert np.all(relabelled >= batched - 1e-12)
    if reward == "sparse":
        np.testing.assert_array_equal(relabelled, 0.0)
        assert set(np.unique(batched)) <= {-1.0, 0.0}
    else:
        np.testing.assert_array_equal(env.unwrapped.compute_reward_terms(ag, ag, infos)["success"], 10.0)


def test_compute_terminated_and_truncated(pair, new_env):
    task_id, mode, env, _ = pair
    env = env.unwrapped
    obs, info = env.reset(seed=0)
    ag = obs["achieved_goal"]
    assert not env.compute_terminated(ag, ag, info)
    assert env.compute_truncated(ag, ag, info) is False
    env2 = new_env(task_id, mode, terminate_on_success=True).unwrapped
    assert env2.compute_terminated(ag, ag, info)
    # The episode's own goal (ag + 1 is no goal of a task whose goal holds a quaternion):
    # terminated exactly where reset reported success, which it almost never does.
    assert env2.compute_terminated(ag, obs["desired_goal"], info) == (info["is_success"] == 1.0)


# ---------------------------------------------------------------------- episode end
@pytest.mark.parametrize("task_id", ALL_IDS)
def test_time_limit_truncates_not_terminates(task_id, new_env):
    # The time limit is the ID's (its registered max_episode_steps); one whole episode per ID.
    env = new_env(task_id, smoke_mode(task_id))
    env.reset(seed=0)
    n = env.spec.max_episode_steps
    zeros = np.zeros(env.action_space.shape, np.float32)
    for i in range(n):
        _, _, terminated, truncated, info = env.step(zeros)
        assert not terminated
        assert truncated == (i == n - 1)


def test_zero_action_holds_in_every_mode(pair):
    # Every mode's zero action keeps the episode going: no termination, no early
    # truncation (a diverging simulation truncates with a flag).
    task_id, mode, env, _ = pair
    obs, _ = env.reset(seed=0)
    zeros = np.zeros(env.action_space.shape, np.float32)
    for _ in range(min(50, env.spec.max_episode_steps - 1)):
        obs, _, terminated, truncated, info = env.step(zeros)
        assert not (terminated or truncated), info
    assert np.all(np.isfinite(obs["observation"]))


def test_max_episode_steps_kwarg(new_env):
    env = new_env(ALL_IDS[0], max_episode_steps=3)
    env.reset(seed=0)
    zeros = np.zeros(env.action_space.shape, np.float32)
    assert [env.step(zeros)[3] for _ in range(3)] == [False, False, True]


# ---------------------------------------------------------------------- pickling / vec
def test_pickle_roundtrip_continues_identically(pair):
    task_id, mode, env, _ = pair
    env.reset(seed=4)
    actions = random_actions(env, 10, seed=3)
    for a in actions[:5]:
        env.step(a)
    clone = pickle.loads(pickle.dumps(env))
    for a in actions[5:]:
        _assert_same(env.step(a), clone.step(a))
    clone.close()


def test_a_checkpoint_steps_on_in_another_env(pair):
    """What ``convert``'s search relies on: a backend's checkpoint, restored into another
    env of the same ID and mode reset with the same seed, steps on as the first would: the
    same simulator states and achieved goals over 3 steps, bit for bit. (Observations may also carry
    memory outside the physics, e.g. Meta-World's previous frame.) MuJoCo 3.3.0 binds no
    ``mj_copyData``: there the restored state is recomputed, and steps on to rounding."""
    import mujoco

    task_id, mode, env, other = pair
    same = _assert_same if hasattr(mujoco, "mj_copyData") else _assert_close
    actions = random_actions(env, 6, seed=3)
    env.reset(seed=4)
    other.reset(seed=4)
    for a in actions[:3]:
        env.step(a)
    other.unwrapped.backend.restore(env.unwrapped.backend.checkpoint())
    other.unwrapped.np_random.bit_generator.state = env.unwrapped.np_random.bit_generator.state
    for a in actions[3:]:
        ag, ag_other = env.step(a)[0]["achieved_goal"], other.step(a)[0]["achieved_goal"]
        same(env.unwrapped.backend.get_state(), other.unwrapped.backend.get_state())
        same(ag, ag_other)


# One ID per family: what a worker process does (import the package, make the ID from its
# entry point, step, answer env_method) is the family's code; each worker costs a process start.
ONE_PER_FAMILY = [
    tid
    for i, tid in enumerate(ALL_IDS)
    if all(unified_manip.TASKS[other].family != unified_manip.TASKS[tid].family for other in ALL_IDS[:i])
]


@pytest.mark.slow
@pytest.mark.parametrize("task_id", ONE_PER_FAMILY)
def test_subproc_vec_env_of_two(task_id):
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.vec_env import SubprocVecEnv

    # "module:ID" makes each worker import unified_manip, which registers the IDs.
    vec = make_vec_env(
        f"unified_manip:{task_id}",
        n_envs=2,
        seed=0,
        vec_env_cls=SubprocVecEnv,
        env_kwargs={"action_mode": smoke_mode(task_id)},
    )
    try:
        obs = first = vec.reset()
        assert obs["observation"].shape[0] == 2
        for _ in range(5):
            obs, rewards, dones, infos = vec.step(np.stack([vec.action_space.sample() for _ in range(2)]))
        assert rewards.shape == (2,) and len(infos) == 2 and "is_success" in infos[0]
        # The two workers were seeded differently: their goals differ, or, where the goal is
        # fixed (the kitchen's), their first observations (the kitchen's seeded noise).
        assert not np.array_equal(obs["desired_goal"][0], obs["desired_goal"][1]) or not np.array_equal(
            first["observation"][0], first["observation"][1]
        )
        rewards = vec.env_method(
            "compute_reward", obs["achieved_goal"], obs["desired_goal"], np.array(infos), indices=[0]
        )[0]
        assert rewards.shape == (2,)
    finally:
        vec.close()


# ---------------------------------------------------------------------- rendering
@pytest.mark.parametrize("task_id", ALL_IDS)
def test_render_rgb_array_headless(task_id, new_env):
    env = new_env(task_id, smoke_mode(task_id), render_mode="rgb_array", render_width=160, render_height=120)
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (120, 160, 3) and frame.dtype == np.uint8
    assert frame.std() > 5.0  # a real picture, not a blank buffer
    env.step(env.action_space.sample())
    assert env.render().shape == (120, 160, 3)


@pytest.mark.parametrize("task_id", ALL_IDS)
def test_closing_twice_is_allowed(task_id):
    """Gymnasium's close check, quietly: a second close() neither raises nor warns."""
    env = make(task_id, smoke_mode(task_id))
    env.reset(seed=0)
    env.step(env.action_space.sample())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        env.close()
        env.close()


def test_render_none_returns_none(new_env):
    env = new_env(ALL_IDS[0])
    env.reset(seed=0)
    assert env.render() is None


# ---------------------------------------------------------------------- bad input
def test_bad_action_shape_and_values(pair):
    task_id, mode, env, fresh = pair
    env.reset(seed=0)
    n = env.action_space.shape[0]
    with pytest.raises(ValueError) as err:
        env.step(np.zeros(n + 1, np.float32))
    layout = env.unwrapped.backend.action_layout  # "2 × (3 + 1)" on two arms, else ""
    assert str(err.value) == (
        f"action must have shape ({n},){f' ({layout})' if layout else ''} for {task_id} "
        f"with action_mode={mode!r}, got shape ({n + 1},)"
    )
    bad = np.zeros(n, np.float32)
    bad[0] = np.nan
    with pytest.raises(ValueError) as err:
        env.step(bad)
    assert str(err.value) == f"action must be finite, got {bad.astype(np.float64).tolist()} (NaN or inf)"
    bad[0] = np.inf
    with pytest.raises(ValueError, match=r"action must be finite"):
        env.step(bad)
    # Nothing was applied by the rejected actions: the state equals the other env's after
    # the same seeded reset.
    fresh.reset(seed=0)
    a = np.full(n, 5.0, np.float32)  # out of range: clipped, not an error
    _assert_same(env.step(a), fresh.step(np.ones(n, np.float32)))


def test_the_sampled_modes_name_registered_ids_families_and_modes():
    """A misspelt key or mode in conftest's sample would quietly test fewer modes."""
    families = {spec.family for spec in unified_manip.TASKS.values()}
    for key, sample in SAMPLED_MODES.items():
        assert key in unified_manip.TASKS or key in families, key
        ids = [t for t, s in unified_manip.TASKS.items() if key in (t, s.family)]
        modes = {m for t in ids for m in unified_manip.TASKS[t].action_modes}
        assert sample is None or set(sample) <= modes, (key, sample)
    # Every family keeps one ID in every mode in the suites, but the kitchen (one ID, slow
    # steps: tests/conftest.py says why).
    for family in families - {"kitchen"}:
        ids = [t for t in ALL_IDS if unified_manip.TASKS[t].family == family]
        assert any({m for i, m in ID_MODES if i == t} == set(unified_manip.TASKS[t].action_modes) for t in ids), family


def test_unknown_action_mode_and_reward_type():
    tid = ALL_IDS[0]
    with pytest.raises(ValueError) as err:
        make(tid, action_mode="cartesian")
    assert str(err.value) == (
        "unknown action_mode 'cartesian'; expected one of 'joint_torque', 'joint_position', "
        "'joint_delta', 'joint_target_delta', 'joint_velocity', 'ee_delta', 'ee_target_delta', 'native'"
    )
    with pytest.raises(ValueError) as err:
        make(tid, reward_type="shaped")
    assert str(err.value) == "unknown reward_type 'shaped'; expected one of 'sparse', 'dense', 'dense_penalized'"
    with pytest.raises(ValueError) as err, pytest.warns(UserWarning, match="render_mode='ansi'"):
        make(tid, render_mode="ansi")  # gymnasium warns first, then our config rejects it
    assert str(err.value) == "unknown render_mode 'ansi'; expected None or one of 'rgb_array', 'human'"


def test_unknown_task_id_lists_ids():
    with pytest.raises(ValueError) as err:
        unified_manip.get_task("UnifiedManip/Nope-v0")
    assert str(err.value).startswith("unknown task 'UnifiedManip/Nope-v0'; expected one of UnifiedManip/")


def test_a_misspelt_task_id_names_the_closest_ids_not_every_id():
    with pytest.raises(ValueError) as err:
        unified_manip.get_task("UnifiedManip/MetaWorldDoorOpn-v0")
    assert str(err.value) == (
        "unknown task 'UnifiedManip/MetaWorldDoorOpn-v0'; did you mean UnifiedManip/MetaWorldDoorOpen-v0 or "
        "UnifiedManip/MetaWorldDoorOpen-v2 or UnifiedManip/MetaWorldDoorOpen-v1? "
        f"(unified-manip list names all {len(unified_manip.TASKS)} IDs)"
    )


# ---------------------------------------------------------------------- stability
def test_diverged_physics_truncates_with_flag(new_env):
    """A blown-up state ends the episode with truncated=True and sim_unstable=True."""
    env = new_env("UnifiedManip/Arm4PickAndPlace-v0", "joint_torque")
    obs0, _ = env.reset(seed=0)
    data = env.unwrapped._backend.data
    data.qvel[:] = 1e12  # what a diverging integrator produces
    obs, reward, terminated, truncated, info = env.step(np.zeros(5, np.float32))
    assert truncated is True and terminated is False
    assert info["sim_unstable"] is True
    assert all(np.isfinite(v).all() for v in obs.values())
    assert np.isfinite(reward)
    # Reset brings back a healthy simulator.
    env.reset(seed=0)
    _, _, _, truncated, info = env.step(np.zeros(5, np.float32))
    assert not truncated and info["sim_unstable"] is False


@pytest.mark.slow
def test_random_steps_stay_stable(pair):
    """``TaskSpec.stability_steps`` random steps (2,000 unless the task sets fewer), over
    episodes of the task's own length."""
    task_id, mode, env, _ = pair
    env.reset(seed=0)
    rng = np.random.default_rng(0)
    steps = unified_manip.TASKS[task_id].stability_steps
    actions = rng.uniform(-1, 1, size=(steps,) + env.action_space.shape).astype(np.float32)
    unstable = 0
    for a in actions:
        obs, _, terminated, truncated, info = env.step(a)
        unstable += info["sim_unstable"]
        if terminated or truncated:
            env.reset()
    assert unstable == 0


def test_arm4_pick_and_place_v1_puts_half_of_its_goals_on_the_table():
    """v1 changes only the goal distribution (Fetch's): about half of the goals lie at the
    cube's resting height, the rest in v0's band in the air, where all of v0's are."""
    from unified_manip.envs.tasks.arm4.goals import PLACE_GOAL_HIGH, PLACE_GOAL_LOW
    from unified_manip.envs.tasks.arm4.scene import CUBE_REST_Z

    heights = {}
    for version in (0, 1):
        env = make(f"UnifiedManip/Arm4PickAndPlace-v{version}", "ee_delta", "sparse")
        heights[version] = np.array([env.reset(seed=s)[0]["desired_goal"][2] for s in range(200)])
        env.close()
    in_air = (heights[1] >= PLACE_GOAL_LOW[2]) & (heights[1] <= PLACE_GOAL_HIGH[2])
    on_table = np.isclose(heights[1], CUBE_REST_Z, atol=1e-6)
    assert np.all(heights[0] >= PLACE_GOAL_LOW[2])
    assert np.all(in_air | on_table) and 0.4 < on_table.mean() < 0.6, on_table.mean()
