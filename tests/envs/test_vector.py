"""The native vector env: bit for bit the single env, Gymnasium 1.x vector semantics.

The reference is Gymnasium's ``SyncVectorEnv`` over ``gym.make``'s single env: with the
same seed (env ``i`` gets ``seed + i``) and the same actions, sub-env ``i`` of the
native env must produce exactly what single env ``i`` produces, autoresets included,
and its info dict must have ``SyncVectorEnv``'s layout, key for key and dtype for dtype.
"""

from __future__ import annotations

import gc
import pickle
import threading
import weakref

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode, SyncVectorEnv

import unified_manip
from unified_manip.envs.vector import VectorFallbackWarning, native_support
from unified_manip.envs.vector.env import NativeVectorEnv
from unified_manip.envs.vector.pool import PhysicsPool

#: Every native ID x mode; the arm over 2 episodes of 3 envs, Fetch (its physics is 20x
#: dearer) over 1 episode of 2 envs on one task per kind: all modes on PickAndPlace.
NATIVE_CASES = [
    (tid, mode, 3, 2) if spec.family == "arm4" else (tid, mode, 2, 1)
    for tid, spec in unified_manip.TASKS.items()
    if native_support(tid) is None
    for mode in spec.action_modes
    if spec.family == "arm4" or tid == "UnifiedManip/FetchPickAndPlace-v0" or mode == "joint_position"
]
N = 3


def assert_same(a, b, path="") -> None:
    """Bit-identical comparison of nested tuples / dicts / arrays (dtypes included)."""
    if isinstance(a, (tuple, list)):
        assert len(a) == len(b), path
        for j, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{path}[{j}]")
    elif isinstance(a, dict):
        assert a.keys() == b.keys(), f"{path}: {sorted(a)} != {sorted(b)}"
        for k in a:
            assert_same(a[k], b[k], f"{path}/{k}")
    elif isinstance(a, np.ndarray) and a.dtype == object:
        assert b.dtype == object and a.shape == b.shape, path
        for j, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{path}[{j}]")
    elif isinstance(a, np.ndarray):
        assert (a.dtype, a.shape) == (b.dtype, b.shape), f"{path}: {a.dtype}{a.shape} != {b.dtype}{b.shape}"
        assert np.array_equal(a, b), f"{path}: {a} != {b}"
    else:
        assert a == b, f"{path}: {a!r} != {b!r}"


def pair(task_id, n=N, autoreset_mode=AutoresetMode.NEXT_STEP, **kwargs):
    """The native vector env and SyncVectorEnv over the single env, same options."""
    native = gym.make_vec(task_id, num_envs=n, autoreset_mode=autoreset_mode, **kwargs)
    reference = SyncVectorEnv([lambda: gym.make(task_id, **kwargs)] * n, autoreset_mode=autoreset_mode)
    return native, reference


def play(native, reference, steps, seed=0, check=None):
    rng = np.random.default_rng(seed)
    assert_same(native.reset(seed=seed), reference.reset(seed=seed), "reset")
    shape = native.action_space.shape
    for k in range(steps):
        actions = rng.uniform(-1.2, 1.2, shape).astype(np.float32)  # some out of range: clipped
        out = native.step(actions)
        assert_same(out, reference.step(actions), f"step {k}")
        if check is not None:
            check(out)


# ---------------------------------------------------------------------- the central test
@pytest.mark.parametrize("task_id,mode,n,episodes", NATIVE_CASES, ids=lambda p: str(p).replace("UnifiedManip/", ""))
def test_native_matches_single_env_over_autoresets(task_id, mode, n, episodes):
    native, reference = pair(task_id, n, action_mode=mode, reward_type="dense_penalized")
    assert isinstance(native, NativeVectorEnv)
    assert native.observation_space == reference.observation_space
    assert native.action_space == reference.action_space
    assert native.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    truncations = []

    def check(out):
        obs, reward, terminated, truncated, info = out
        truncations.append(truncated.sum())
        stepped = info.get("_reward_terms", np.zeros(n, dtype=bool))
        batched = native.compute_reward(obs["achieved_goal"], obs["desired_goal"], info)
        np.testing.assert_array_equal(batched[stepped], reward[stepped])  # compute_reward == step reward

    play(native, reference, episodes * unified_manip.TASKS[task_id].max_episode_steps + 3, check=check)
    assert sum(truncations) == episodes * n  # each time-limit end is followed by an autoreset
    native.close()
    reference.close()


def test_native_matches_single_env_with_controller_options():
    """A mode's options reach every sub-env: joint_position over a band around the reset
    posture (a controller that keeps per-episode state) stays bit-identical over an autoreset."""
    task_id = "UnifiedManip/Arm4PickAndPlace-v0"
    kwargs = {"action_mode": "joint_position", "controller_options": {"band": 0.3}}
    native, reference = pair(task_id, 2, **kwargs)
    assert all(b.control.config.band == 0.3 for b in native.unwrapped._batched._backends)
    play(native, reference, unified_manip.TASKS[task_id].max_episode_steps + 3)
    native.close()
    reference.close()


@pytest.mark.parametrize("mode", [AutoresetMode.SAME_STEP, AutoresetMode.DISABLED])
def test_other_autoreset_modes(mode):
    """Early terminations (terminate_on_success under a reaching policy) at different
    steps in different envs, in the other two autoreset modes."""
    kwargs = dict(action_mode="joint_delta", reward_type="dense", terminate_on_success=True)
    native, reference = pair("UnifiedManip/Arm4Reach-v0", autoreset_mode=mode, **kwargs)
    assert_same(native.reset(seed=4), reference.reset(seed=4))
    rng = np.random.default_rng(0)
    ends = 0
    for k in range(120):
        actions = rng.uniform(-1, 1, native.action_space.shape)
        out = native.step(actions)
        assert_same(out, reference.step(actions), f"step {k}")
        done = out[2] | out[3]
        ends += done.sum()
        if mode == AutoresetMode.DISABLED and done.any():
            options = {"reset_mask": done}
            assert_same(native.reset(options=dict(options)), reference.reset(options=dict(options)), f"reset {k}")
    assert ends >= N


def test_diverged_physics_keeps_last_observation():
    """A NaN velocity makes MuJoCo reset that env's state: sim_unstable, truncated, the
    last finite observation, exactly as the single env."""
    native, reference = pair("UnifiedManip/Arm4Push-v0", action_mode="joint_torque", reward_type="dense_penalized")
    native.reset(seed=1)
    reference.reset(seed=1)
    native._batched._backends[1].data.qvel[0] = np.nan
    reference.envs[1].unwrapped._backend.data.qvel[0] = np.nan
    actions = np.zeros(native.action_space.shape)
    out = native.step(actions)
    assert_same(out, reference.step(actions))
    assert out[4]["sim_unstable"].tolist() == [False, True, False] and out[3].tolist() == [False, True, False]
    for k in range(3):  # the next step autoresets env 1
        assert_same(native.step(actions), reference.step(actions), f"step {k}")
    # A last substep that leaves a NaN velocity (MuJoCo only flags it on the next step):
    # a non-finite observation is a divergence too.
    last = native.step(actions)[0]
    backend = native._batched._backends[2]
    physics = backend.physics_step

    def diverge():
        physics()
        backend.data.qvel[:] = np.nan

    backend.physics_step = diverge
    obs, _, _, truncated, info = native.step(actions)
    assert info["sim_unstable"].tolist() == [False, False, True] and truncated.tolist() == [False, False, True]
    assert all(np.array_equal(obs[k][2], last[k][2]) for k in obs) and all(np.isfinite(v).all() for v in obs.values())
    assert info["grip_to_object"][2] == 0.0


# ---------------------------------------------------------------------- spaces and conventions
def test_spaces_batch_shapes_and_wrappers():
    env = gym.make_vec("UnifiedManip/Arm4PickAndPlace-v0", num_envs=4, action_mode="ee_delta", reward_type="dense")
    single = gym.make("UnifiedManip/Arm4PickAndPlace-v0", action_mode="ee_delta")
    assert env.single_observation_space == single.observation_space
    assert env.single_action_space == single.action_space
    assert env.observation_space == gym.vector.utils.batch_space(single.observation_space, 4)
    assert env.spec.id == "UnifiedManip/Arm4PickAndPlace-v0" and env.spec.max_episode_steps == 100
    env = gym.wrappers.vector.RecordEpisodeStatistics(env)
    obs, info = env.reset(seed=0)
    assert env.observation_space.contains(obs)
    for _ in range(100):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert env.observation_space.contains(obs)
        assert reward.shape == terminated.shape == truncated.shape == (4,) and reward.dtype == np.float64
        for key in ("is_success", "grip_to_object", "grasped", "ik_residual", "sim_unstable"):
            assert info[key].shape == (4,) and info[f"_{key}"].all(), key
        assert set(info["reward_terms"]) == {"reach", "place", "success", "_reach", "_place", "_success"}
    assert info["episode"]["l"].tolist() == [100] * 4  # the wrapper saw every episode end
    env.close()


def test_fallback_is_sync_with_a_one_line_notice():
    with pytest.warns(VectorFallbackWarning) as caught:
        env = gym.make_vec("UnifiedManip/HandReach-v0", num_envs=2)
    (warning,) = caught
    assert "\n" not in str(warning.message) and "SyncVectorEnv" in str(warning.message)
    assert isinstance(env, SyncVectorEnv)
    env.close()


# ---------------------------------------------------------------------- bad input
def test_bad_input():
    env = gym.make_vec("UnifiedManip/Arm4Reach-v0", num_envs=3, action_mode="joint_position")
    with pytest.raises(gym.error.ResetNeeded):
        env.step(np.zeros((3, 5)))
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"actions must have shape \(3, 5\) .*num_envs=3.*got shape \(2, 5\)"):
        env.step(np.zeros((2, 5)))
    with pytest.raises(ValueError, match=r"got shape \(5,\)"):
        env.step(np.zeros(5))
    bad = np.zeros((3, 5))
    bad[2, 1] = np.nan
    with pytest.raises(ValueError, match=r"action of env 2 must be finite"):
        env.step(bad)
    bad[2, 1], bad[1, 0] = 0.0, np.inf
    with pytest.raises(ValueError, match=r"action of env 1 must be finite"):
        env.step(bad)
    with pytest.raises(ValueError, match=r"a list of num_envs=3 seeds, got 2 seeds"):
        env.reset(seed=[0, 1])
    for mask in ([True, False, True], np.zeros(3, dtype=bool), np.ones(2, dtype=bool), np.ones(3, dtype=int)):
        with pytest.raises(ValueError, match=r"reset_mask'\] must be a bool array of shape \(3,\) with a True"):
            env.reset(options={"reset_mask": mask})
    env.close()
    for n in (0, -1, 1.5, True):
        with pytest.raises(ValueError, match=r"num_envs must be a positive int"):
            gym.make_vec("UnifiedManip/Arm4Reach-v0", num_envs=n)
    with pytest.raises(ValueError, match=r"num_threads must be a positive int"):
        gym.make_vec("UnifiedManip/Arm4Reach-v0", num_envs=2, num_threads=0)
    with pytest.raises(ValueError, match=r"unknown action_mode 'fly'; expected one of"):
        gym.make_vec("UnifiedManip/Arm4Reach-v0", num_envs=2, action_mode="fly")


# ---------------------------------------------------------------------- close, pickling, leaks
def test_pickle_round_trip_and_close():
    env = gym.make_vec("UnifiedManip/Arm4Push-v0", num_envs=2, action_mode="ee_delta", num_threads=2)
    env.reset(seed=3)
    actions = np.random.default_rng(0).uniform(-1, 1, (10,) + env.action_space.shape)
    for a in actions[:5]:
        env.step(a)
    copy = pickle.loads(pickle.dumps(env))
    for a in actions[5:]:
        assert_same(env.step(a), copy.step(a))
    copy.close()
    before = threading.active_count()
    env.close()
    assert threading.active_count() == before - 1  # the pool's worker thread is gone
    with pytest.raises(RuntimeError, match="thread pool is shut down"):
        env.step(actions[0])


def _rss_mb() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096 / 2**20


def test_make_close_cycles_leak_nothing():
    def cycle():
        env = gym.make_vec("UnifiedManip/Arm4Reach-v0", num_envs=2, action_mode="ee_delta", num_threads=2)
        env.reset(seed=0)
        env.step(np.zeros(env.action_space.shape))
        env.close()
        return weakref.ref(env.unwrapped)

    for _ in range(5):  # warm-up: lazy imports, allocator pools
        cycle()
    gc.collect()
    threads, rss = threading.active_count(), _rss_mb()
    refs = [cycle() for _ in range(100)]
    gc.collect()
    assert threading.active_count() == threads
    assert all(r() is None for r in refs)
    assert _rss_mb() - rss < 40, f"RSS grew by {_rss_mb() - rss:.1f} MB over 100 make/close cycles"


def test_pool_runs_every_index_and_reraises():
    pool = PhysicsPool(2)
    seen = []
    pool.run(seen.append, range(50))
    assert sorted(seen) == list(range(50))
    order = []
    pool.pipeline(lambda i: order.append(("prepare", i)), lambda i: order.append(("advance", i)), range(10))
    assert [i for k, i in order if k == "prepare"] == list(range(10))  # in order, on the caller
    assert sorted(i for k, i in order if k == "advance") == list(range(10))

    def boom(i):
        if i == 3:
            raise KeyError(i)

    with pytest.raises(KeyError):
        pool.run(boom, range(10))
    with pytest.raises(KeyError):
        pool.pipeline(lambda i: None, boom, range(10))
    pool.shutdown()
    with pytest.raises(RuntimeError, match="shut down"):
        pool.run(seen.append, [1])
    with pytest.raises(ValueError, match="num_threads must be a positive int"):
        PhysicsPool(0)
