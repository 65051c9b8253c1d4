"""Fault injection: a second owner, kill -9 mid-checkpoint, damaged checkpoints, a killed Ray
worker, physics that diverges during training, a second bench.

Runs are real (``unified-manip train`` / ``bench`` in subprocesses, SB3 SAC+HER on the
4-DOF arm) but learn nothing: ``learning_starts`` is past the budget, so each run is a few
seconds of env steps, checkpoints and resumes. The checkpoint writer's test hook
(``UNIFIED_MANIP_TEST_PAUSE_CHECKPOINT=N``) holds the N-th checkpoint after its model file
until the ``PAUSED`` file it creates is removed.
"""

from __future__ import annotations

import dataclasses
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import yaml
from conftest import local_ray

import unified_manip
from unified_manip.envs.registry import TASKS, register_task
from unified_manip.experiments.grid import load_grid
from unified_manip.experiments.results import read_results
from unified_manip.training import checkpoints
from unified_manip.training.runlock import read_owner

# Each test trains, kills or resumes real runs (7-14 s each).
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
TASK = "UnifiedManip/Arm4Reach-v0"
NO_LEARNING = ["learning_starts=100000", "buffer_size=5000", "policy_kwargs.net_arch=[16,16]", "checkpoint_freq=200"]


def train_args(run_dir: Path, steps: int, extra: tuple[str, ...] = ("eval_freq=100000",)) -> list[str]:
    sets = [a for s in NO_LEARNING + list(extra) for a in ("--set", s)]
    return [
        "train",
        "--env",
        TASK,
        "--action-mode",
        "ee_delta",
        "--algo",
        "sac_her",
        "--steps",
        str(steps),
        "--run-dir",
        str(run_dir),
        "--no-progress",
        "--device",
        "cpu",
        *sets,
    ]


def cli(*args: str, pause: int | None = None, wait: bool = True):
    env = dict(os.environ)
    if pause is not None:
        env[checkpoints.PAUSE_ENV] = str(pause)
    cmd = [sys.executable, "-m", "unified_manip.cli", *args]
    if wait:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=600, cwd=ROOT, env=env)
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT, env=env)


def wait_for(condition, proc: subprocess.Popen | None = None, timeout: float = 300):
    deadline = time.time() + timeout
    while time.time() < deadline:
        found = condition()
        if found:
            return found
        assert proc is None or proc.poll() is None, proc.communicate()
        time.sleep(0.05)
    raise AssertionError("timed out")


def paused(directory: Path):
    return next(iter(directory.rglob("checkpoints/*/PAUSED")), None)


def assert_one_line_error(proc, message: str) -> None:
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert re.fullmatch(message, proc.stderr.strip()), proc.stderr


def in_use(what: str, directory: Path, pid: int) -> str:
    return (
        rf"unified-manip \w+: error: {what} {re.escape(str(directory))} is in use by pid {pid} "
        rf"on host {re.escape(socket.gethostname())} \(started \d{{4}}-\d\d-\d\d \d\d:\d\d:\d\d\)"
    )


# ---------------------------------------------------------------------- ownership
def test_a_second_train_on_a_run_directory_is_refused_and_the_first_finishes_intact(tmp_path):
    run_dir = tmp_path / "run"
    first = cli(*train_args(run_dir, 400), pause=1, wait=False)  # held inside its first checkpoint
    marker = wait_for(lambda: paused(run_dir), first)
    config = (run_dir / "config.yaml").read_text()
    second = cli(*train_args(run_dir, 400))
    assert_one_line_error(second, in_use("run directory", run_dir, first.pid))
    marker.unlink()
    out, err = first.communicate(timeout=300)
    assert first.returncode == 0, err
    assert f"{run_dir}: finished 400 steps" in out
    status = json.loads((run_dir / "status.json").read_text())
    assert status["state"] == "finished" and status["num_timesteps"] == 400
    assert (run_dir / "config.yaml").read_text() == config
    assert [p.name for p in (run_dir / "monitor").iterdir()] == ["seg0"]  # the second started nothing
    from stable_baselines3.common.save_util import load_from_pkl

    assert load_from_pkl(run_dir / "replay_buffer.pkl").size() == 400


# ---------------------------------------------------------------------- checkpoints
@pytest.fixture(scope="module")
def killed_in_third_checkpoint(tmp_path_factory) -> Path:
    """A run killed -9 while writing its third checkpoint (600): 200 and 400 are complete."""
    run_dir = tmp_path_factory.mktemp("killed") / "run"
    proc = cli(*train_args(run_dir, 800), pause=3, wait=False)
    wait_for(lambda: paused(run_dir), proc)
    proc.kill()
    proc.communicate(timeout=60)
    assert [c.step for c in checkpoints.published(run_dir)] == [400, 200]
    return run_dir


def copy_of(run_dir: Path, tmp_path: Path) -> Path:
    return Path(shutil.copytree(run_dir, tmp_path / "run", symlinks=True))


def test_kill_9_mid_checkpoint_resumes_from_the_last_complete_one(killed_in_third_checkpoint, tmp_path):
    run_dir = copy_of(killed_in_third_checkpoint, tmp_path)
    # The status kept the wall time up to the last checkpoint (it used to keep 0 until an
    # interrupt or the end, so a run killed at a session's end lost that segment's time).
    killed = json.loads((run_dir / "status.json").read_text())
    assert killed["state"] == "running" and killed["num_timesteps"] == 400 and killed["wall_time_s"] > 0, killed
    proc = cli(*train_args(run_dir, 800))
    assert proc.returncode == 0, proc.stderr
    assert f"{run_dir}: resuming from step 400 of 800 on cpu with 400 transitions in the replay buffer" in proc.stdout
    assert "warning" not in proc.stdout  # the half-written one was never published
    final = json.loads((run_dir / "status.json").read_text())
    assert final["num_timesteps"] == 800 and final["wall_time_s"] > killed["wall_time_s"]


@pytest.mark.parametrize("damaged", [checkpoints.MODEL, checkpoints.REPLAY_BUFFER])
def test_a_truncated_newest_checkpoint_falls_back_to_the_previous_one(damaged, killed_in_third_checkpoint, tmp_path):
    run_dir = copy_of(killed_in_third_checkpoint, tmp_path)
    path = run_dir / "checkpoints" / "000000000400" / damaged
    size = path.stat().st_size
    os.truncate(path, size // 2)
    proc = cli(*train_args(run_dir, 800))
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert lines[0] == (
        f"warning: checkpoint at step 400 cannot be loaded ({path}: {size // 2} bytes, the manifest says {size} "
        "(truncated or overwritten)); falling back to the checkpoint at step 200"
    )
    assert lines[1] == f"{run_dir}: resuming from step 200 of 800 on cpu with 200 transitions in the replay buffer"
    assert json.loads((run_dir / "status.json").read_text())["num_timesteps"] == 800


def test_no_loadable_checkpoint_is_one_line_and_restart_starts_over(killed_in_third_checkpoint, tmp_path):
    run_dir = copy_of(killed_in_third_checkpoint, tmp_path)
    for step in (200, 400):
        os.truncate(run_dir / "checkpoints" / f"{step:012d}" / checkpoints.MODEL, 10)
    proc = cli(*train_args(run_dir, 800))
    ckpt = re.escape(str(run_dir / "checkpoints"))
    assert_one_line_error(
        proc,
        (
            rf"unified-manip train: error: {re.escape(str(run_dir))}: no checkpoint loads \({ckpt}/000000000400/model.zip: "
            rf"10 bytes, .*; {ckpt}/000000000200/model.zip: 10 bytes, .*\); run the same command with --restart to start "
            r"over from step 0"
        ),
    )
    proc = cli(*train_args(run_dir, 800), "--restart")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.splitlines()[0] == f"{run_dir}: restarting from step 0"
    assert json.loads((run_dir / "status.json").read_text())["num_timesteps"] == 800


def test_a_run_checkpointed_in_the_earlier_one_file_layout_still_resumes(killed_in_third_checkpoint, tmp_path):
    """Runs checkpointed before the layout changed (latest.json, model_<step>.zip, SB3's
    whole-buffer pickle) resume too."""
    from stable_baselines3 import SAC
    from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

    run_dir = copy_of(killed_in_third_checkpoint, tmp_path)
    root = run_dir / "checkpoints"
    ckpt = checkpoints.newest(run_dir)
    env = VecNormalize.load(
        str(ckpt.path(checkpoints.VECNORMALIZE)), DummyVecEnv([lambda: gym.make(TASK, action_mode="ee_delta")])
    )
    model = SAC.load(ckpt.path(checkpoints.MODEL), env=env)
    checkpoints.restore_replay_buffer(model, ckpt)
    model.save(root / "model_400.zip")
    model.save_replay_buffer(root / "replay_buffer_400.pkl")
    env.save(str(root / "vecnormalize_400.pkl"))
    for c in checkpoints.published(run_dir):
        shutil.rmtree(c.directory)
    (root / "latest.json").write_text(
        json.dumps(
            {
                "num_timesteps": 400,
                "model": "model_400.zip",
                "replay_buffer": "replay_buffer_400.pkl",
                "vecnormalize": "vecnormalize_400.pkl",
            }
        )
    )
    proc = cli(*train_args(run_dir, 800))
    assert proc.returncode == 0, proc.stderr
    assert f"{run_dir}: resuming from step 400 of 800 on cpu with 400 transitions in the replay buffer" in proc.stdout


# ---------------------------------------------------------------------- benches
GRID = {
    "name": "faults",
    "tasks": [TASK],
    "action_modes": ["ee_delta"],
    "reward_types": ["sparse"],
    "algos": ["sac_her"],
    "seeds": [0],
    "steps": 600,
    "eval_freq": 200,
    "n_eval_episodes": 1,
    "overrides": {"sac_her": NO_LEARNING},
}


def test_a_second_bench_on_one_output_directory_is_refused(tmp_path):
    grid = tmp_path / "grid.yaml"
    grid.write_text(yaml.safe_dump(GRID))
    out = tmp_path / "out"
    first = cli("bench", str(grid), "--out", str(out), "--workers", "1", "--no-progress", pause=1, wait=False)
    marker = wait_for(lambda: paused(out), first)  # its run is held inside its first checkpoint
    second = cli("bench", str(grid), "--out", str(out), "--workers", "1", "--no-progress")
    assert_one_line_error(second, in_use("bench directory", out, first.pid))
    marker.unlink()
    _, err = first.communicate(timeout=300)
    assert first.returncode == 0, err
    (row,) = read_results(out / "results.csv")
    assert row["steps"] == 600 and [t for t, _ in row["curve"]] == [200, 400, 600]


@local_ray
def test_a_killed_ray_worker_is_retried_and_leaves_one_complete_row(tmp_path):
    # The bench runs in its own process, as users run it: Ray's head is forked from a small
    # CLI process, never from a test worker that has grown over the whole suite.
    grid = _write(tmp_path / "grid.yaml", dict(GRID, steps=800))
    out = tmp_path / "out"
    run_dir = out / "runs" / load_grid(grid).runs[0].name
    bench = cli(
        "bench",
        str(grid),
        "--out",
        str(out),
        "--executor",
        "ray",
        "--workers",
        "1",
        "--retries",
        "1",
        "--no-progress",
        pause=2,
        wait=False,
    )  # each Ray worker holds its second checkpoint
    try:
        wait_for(lambda: (run_dir / "checkpoints" / f"{400:012d}" / "PAUSED").exists(), bench)  # 200 is complete
        os.kill(read_owner(run_dir)["pid"], signal.SIGKILL)  # the Ray worker that trains the run, mid-checkpoint
        # The retry resumes from 200, writes 400, and holds 600: let it go on.
        marker = wait_for(lambda: next(iter((run_dir / "checkpoints").glob(f"{600:012d}/PAUSED")), None), bench)
        marker.unlink()
        _, err = bench.communicate(timeout=600)
    finally:
        if bench.poll() is None:
            bench.kill()
    assert bench.returncode == 0, err
    (failure,) = [json.loads(line) for line in (out / "failures.jsonl").read_text().splitlines()]
    assert failure["attempt"] == 1 and "Worker" in failure["error"], failure
    (row,) = read_results(out / "results.csv")
    # The retry resumed: the evaluations made before the kill are kept, none repeated.
    assert row["steps"] == 800 and [t for t, _ in row["curve"]] == [200, 400, 600, 800]


def test_a_retried_run_waits_for_a_live_attempt_and_never_writes_beside_it(tmp_path, monkeypatch):
    from unified_manip.experiments import executors
    from unified_manip.training.runlock import DirectoryLock
    from unified_manip.training.train import TrainError

    spec = load_grid(_write(tmp_path / "grid.yaml", GRID)).runs[0]
    run_dir = tmp_path / "out" / "runs" / spec.name
    monkeypatch.setattr(executors, "RUN_LOCK_WAIT_S", 1.0)
    with DirectoryLock(run_dir):  # the earlier attempt, alive on another worker
        start = time.monotonic()
        with pytest.raises(TrainError, match=f"run directory {re.escape(str(run_dir))} is in use by pid {os.getpid()}"):
            executors.run_one(spec, str(tmp_path / "out"))
        assert time.monotonic() - start >= 1.0  # it waited before giving up
    assert [p.name for p in run_dir.iterdir()] == [".lock"]  # and wrote nothing


def _write(path: Path, doc: dict) -> Path:
    path.write_text(yaml.safe_dump(doc))
    return path


# ---------------------------------------------------------------------- diverging physics
class DivergesOnStep:
    """The arm's backend, whose physics blows up on its k-th step: the last substep leaves
    a NaN velocity, which MuJoCo itself would only notice (and reset) on the next step."""

    def __init__(self, inner, k: int) -> None:
        self.inner, self.k, self.steps = inner, k, 0

    def step(self, action):
        self.steps += 1
        diagnostics = self.inner.step(action)
        if self.steps == self.k:
            self.inner.data.qvel[:] = np.nan  # what a diverging integrator leaves behind
        return diagnostics

    def __getattr__(self, name):
        return getattr(self.inner, name)


@pytest.fixture
def diverging_task():
    """``UnifiedManip/ArmDiverges-v0``, registered for this test only."""
    base = TASKS[TASK]
    spec = dataclasses.replace(
        base,
        name="ArmDiverges",
        family="test",
        make_backend=lambda config, controller: DivergesOnStep(base.make_backend(config, controller), k=130),
    )
    register_task(spec)
    try:
        yield spec.id
    finally:
        del TASKS[spec.id]
        del gym.envs.registry[spec.id]
    assert spec.id not in unified_manip.TASKS and spec.id not in gym.envs.registry


def test_diverging_physics_ends_the_episode_and_writes_no_nan(diverging_task, tmp_path):
    from unified_manip.training.train import TrainRequest, train

    run_dir = tmp_path / "run"
    req = TrainRequest(
        env=diverging_task,
        action_mode="ee_delta",
        reward_type="sparse",
        algo="sac_her",
        steps=300,
        run_dir=run_dir,
        overrides=tuple(NO_LEARNING + ["eval_freq=100000"]),
        device="cpu",
    )
    assert train(req, progress=False, log=lambda msg: None)["num_timesteps"] == 300
    import pandas as pd

    episodes = pd.read_csv(next((run_dir / "monitor" / "seg0").glob("*.monitor.csv")), skiprows=1)
    # Episodes of 50 steps; the third ends early, at the 130th step, flagged.
    assert episodes["l"].tolist()[:4] == [50, 50, 30, 50]
    assert episodes["sim_unstable"].tolist()[:4] == [False, False, True, False]
    from stable_baselines3.common.save_util import load_from_pkl

    buffer = load_from_pkl(run_dir / "replay_buffer.pkl")
    assert buffer.size() == 300
    for name in ("observations", "next_observations"):
        for key, values in getattr(buffer, name).items():
            assert np.isfinite(values[:300]).all(), (name, key)
    assert np.isfinite(buffer.rewards[:300]).all() and np.isfinite(buffer.actions[:300]).all()
    assert buffer.timeouts[129, 0] == 1.0  # stored as a truncation, not a terminal state
