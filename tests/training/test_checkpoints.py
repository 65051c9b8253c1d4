"""The pieces under resume: trimmed replay buffers, the checkpoint manifest, directory locks."""

from __future__ import annotations

import pickle
import socket
import threading

import numpy as np
import pytest
from gymnasium import spaces
from stable_baselines3 import HerReplayBuffer
from stable_baselines3.common.buffers import DictReplayBuffer, ReplayBuffer

from unified_manip.training import checkpoints, replay_buffers
from unified_manip.training.her import GoalRelHerReplayBuffer
from unified_manip.training.runlock import DirectoryInUse, DirectoryLock, read_owner

BOX = spaces.Box(-1, 1, (5,), np.float32)
GOALS = spaces.Dict(
    {
        "observation": BOX,
        "achieved_goal": spaces.Box(-1, 1, (3,), np.float32),
        "desired_goal": spaces.Box(-1, 1, (3,), np.float32),
    }
)
ACTION = spaces.Box(-1, 1, (2,), np.float32)
N_ENVS = 2


def make_buffer(kind: str, capacity: int, **kwargs):
    if kind == "flat":
        return ReplayBuffer(capacity, BOX, ACTION, n_envs=N_ENVS, **kwargs)
    if kind == "dict":
        return DictReplayBuffer(capacity, GOALS, ACTION, n_envs=N_ENVS)
    return HerReplayBuffer(capacity, GOALS, ACTION, env=None, n_envs=N_ENVS, copy_info_dict=True)


def fill(buffer, transitions: int, seed: int = 0) -> None:
    """``transitions`` vectorised adds, episodes of 7 steps (so HER records lengths)."""
    rng = np.random.default_rng(seed)
    space = buffer.observation_space

    def obs():
        if isinstance(space, spaces.Dict):
            return {k: rng.standard_normal((N_ENVS, *s.shape)).astype(np.float32) for k, s in space.spaces.items()}
        return rng.standard_normal((N_ENVS, *space.shape)).astype(np.float32)

    for t in range(transitions):
        done = np.full(N_ENVS, (t + 1) % 7 == 0)
        infos = [{"TimeLimit.truncated": bool(d), "step": t} for d in done]
        buffer.add(
            obs(),
            obs(),
            rng.uniform(-1, 1, (N_ENVS, 2)).astype(np.float32),
            rng.standard_normal(N_ENVS).astype(np.float32),
            done,
            infos,
        )


def assert_same_state(a, b) -> None:
    """Every attribute equal: arrays element by element, dicts of arrays key by key."""
    skip = {"observation_space", "action_space", "device", "env"}
    assert vars(a).keys() == vars(b).keys()
    for name in vars(a).keys() - skip:
        x, y = getattr(a, name), getattr(b, name)
        if isinstance(x, dict) and x and isinstance(next(iter(x.values())), np.ndarray):
            assert x.keys() == y.keys(), name
            for k in x:
                np.testing.assert_array_equal(x[k], y[k], err_msg=f"{name}[{k}]")
        elif isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.shape == y.shape, name
            assert np.array_equal(x, y), name
        else:
            assert x == y, name


@pytest.mark.parametrize("kind", ["flat", "dict", "her"])
@pytest.mark.parametrize("transitions", [30, 95], ids=["partly-filled", "wrapped-around"])
def test_trimmed_buffer_restores_to_the_same_capacity_and_state(kind, transitions, tmp_path):
    original = make_buffer(kind, 80)
    fill(original, transitions)
    path = tmp_path / "buffer.pkl"
    rows = replay_buffers.save_trimmed(original, path)
    assert rows == min(transitions, 80 // N_ENVS)  # a row holds one transition of each env
    restored = make_buffer(kind, 80)
    replay_buffers.restore(restored, path)
    assert_same_state(original, restored)


def test_optimize_memory_usage_keeps_the_row_holding_the_last_next_observation(tmp_path):
    original = make_buffer("flat", 80, optimize_memory_usage=True, handle_timeout_termination=False)
    fill(original, 12)
    assert replay_buffers.save_trimmed(original, tmp_path / "b.pkl") == 13
    restored = make_buffer("flat", 80, optimize_memory_usage=True, handle_timeout_termination=False)
    replay_buffers.restore(restored, tmp_path / "b.pkl")
    assert_same_state(original, restored)


def test_trimmed_buffer_is_a_fraction_of_the_whole_pickle(tmp_path):
    buffer = make_buffer("her", 20_000)
    fill(buffer, 100)
    replay_buffers.save_trimmed(buffer, tmp_path / "trimmed.pkl")
    with open(tmp_path / "whole.pkl", "wb") as f:
        pickle.dump(buffer, f)
    # 100 of 10,000 rows: the whole pickle is about 100 times larger.
    assert (tmp_path / "whole.pkl").stat().st_size > 50 * (tmp_path / "trimmed.pkl").stat().st_size


def test_a_buffer_saved_by_sb3s_her_restores_into_the_her_algorithms_buffer(tmp_path):
    """Checkpoints written before the HER algorithms used GoalRelHerReplayBuffer resume;
    the reverse (its save into SB3's own buffer) is refused."""
    saved = make_buffer("her", 80)
    fill(saved, 10)
    replay_buffers.save_trimmed(saved, tmp_path / "old.pkl")
    ours = GoalRelHerReplayBuffer(80, GOALS, ACTION, env=None, n_envs=N_ENVS, copy_info_dict=True)
    replay_buffers.restore(ours, tmp_path / "old.pkl")
    assert (ours.pos, ours.full) == (saved.pos, saved.full)
    for key, rows in saved.observations.items():
        np.testing.assert_array_equal(ours.observations[key], rows)
    np.testing.assert_array_equal(ours.ep_length, saved.ep_length)
    replay_buffers.save_trimmed(ours, tmp_path / "new.pkl")
    with pytest.raises(replay_buffers.ReplayBufferMismatch, match="saved from a unified_manip.training.her.GoalRel"):
        replay_buffers.restore(make_buffer("her", 80), tmp_path / "new.pkl")


@pytest.mark.parametrize(
    "target,message",
    [
        (lambda: make_buffer("her", 40), "capacity 40 x 2 envs saved, 20 x 2 expected (buffer_size or n_envs changed)"),
        (
            lambda: make_buffer("dict", 80),
            "saved from a stable_baselines3.her.her_replay_buffer.HerReplayBuffer, "
            "restoring into a stable_baselines3.common.buffers.DictReplayBuffer",
        ),
    ],
    ids=["capacity", "class"],
)
def test_restoring_into_another_buffer_is_refused(target, message, tmp_path):
    saved = make_buffer("her", 80)
    fill(saved, 10)
    replay_buffers.save_trimmed(saved, tmp_path / "b.pkl")
    with pytest.raises(replay_buffers.ReplayBufferMismatch) as err:
        replay_buffers.restore(target(), tmp_path / "b.pkl")
    assert str(err.value) == message


def test_a_checkpoint_without_its_manifest_is_not_published(tmp_path):
    root = tmp_path / "checkpoints"
    (root / "000000000100").mkdir(parents=True)
    (root / "000000000100" / "model.zip").write_bytes(b"half")
    assert checkpoints.published(tmp_path) == []
    checkpoints.prune(tmp_path)
    assert list(root.iterdir()) == []


def test_verify_names_the_file_and_why(tmp_path):
    directory = tmp_path / "checkpoints" / "000000000100"
    directory.mkdir(parents=True)
    (directory / "model.tmp").write_bytes(b"0123456789")
    digest = checkpoints._publish_file(directory / "model.tmp", directory / "model.zip")
    ckpt = checkpoints.Checkpoint(directory, 100, {"model.zip": directory / "model.zip"}, {"model.zip": digest})
    checkpoints.verify(ckpt)
    (directory / "model.zip").write_bytes(b"0123456780")
    with pytest.raises(checkpoints.CheckpointError, match="model.zip: contents differ from the manifest's SHA-256"):
        checkpoints.verify(ckpt)
    (directory / "model.zip").write_bytes(b"01234")
    with pytest.raises(checkpoints.CheckpointError, match="model.zip: 5 bytes, the manifest says 10"):
        checkpoints.verify(ckpt)


# ---------------------------------------------------------------------- locks
def test_a_directory_has_one_owner_and_the_refusal_names_it(tmp_path):
    first = DirectoryLock(tmp_path / "run").acquire()
    with pytest.raises(DirectoryInUse) as err:
        DirectoryLock(tmp_path / "run").acquire()
    owner = read_owner(tmp_path / "run")
    assert str(err.value).startswith(
        f"run directory {tmp_path / 'run'} is in use by pid {owner['pid']} on host {socket.gethostname()} (started "
    )
    first.release()
    with DirectoryLock(tmp_path / "run", "bench directory") as second:
        assert second.held


def test_a_waiting_owner_gets_the_directory_when_the_first_lets_go(tmp_path):
    first = DirectoryLock(tmp_path).acquire()
    threading.Timer(0.3, first.release).start()
    second = DirectoryLock(tmp_path).acquire(wait_s=10, poll_s=0.05)
    assert second.held
    second.release()


# ---------------------------------------------------------------------- the size benchmark
def test_checkpoint_size_benchmark_compares_whole_and_trimmed_buffers():
    from benchmarks.checkpoint_size import measure, table

    result = measure("UnifiedManip/Arm4Reach-v0", buffer_size=20_000, steps=300, repeats=1)
    before, after = result["before"], result["after"]
    # 300 of 20,000 rows: the trimmed buffer is a small fraction of the whole pickle.
    assert after["buffer_bytes"] * 20 < before["buffer_bytes"]
    assert after["checkpoint_bytes"] < before["checkpoint_bytes"]
    assert all(v > 0 for v in (before["write_s"], after["write_s"], before["buffer_load_s"], after["buffer_load_s"]))
    assert "| of which replay buffer (MB) |" in table(result)
