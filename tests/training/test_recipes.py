"""Device choice, the recipe files and the algorithm keys issue 10 added (short runs only;
learning targets live in the benchmark report, never here)."""

from __future__ import annotations

import subprocess
import sys
from importlib.metadata import version
from pathlib import Path

import pytest
import torch
import yaml
from conftest import COMMITTED_GRIDS, cli_in_process

import unified_manip
from unified_manip.experiments.grid import load_grid
from unified_manip.training.algorithms import ALGOS
from unified_manip.training.devices import DeviceError, resolve_device
from unified_manip.training.hyperparams import load_file, resolve, split_entry

ROOT = Path(__file__).resolve().parents[2]
GPU = torch.cuda.is_available()


cli = cli_in_process


# ---------------------------------------------------------------------- device
def test_auto_resolves_to_cuda_only_where_torch_sees_a_gpu():
    assert resolve_device("auto") == ("cuda" if GPU else "cpu")
    assert resolve_device("cpu") == "cpu"


def test_unknown_device_names_the_choices():
    with pytest.raises(DeviceError, match=r"unknown device 'tpu'; expected one of auto, cpu, cuda"):
        resolve_device("tpu")


@pytest.mark.parametrize(
    "command",
    [
        ["train", "--env", "UnifiedManip/Arm4Reach-v0", "--algo", "sac", "--steps", "10"],
        ["eval", "runs/none"],
        ["bench", "baselines/grids/action_spaces.yaml"],
    ],
)
def test_bad_device_is_one_line_exit_2(command, tmp_path):
    proc = cli(*command, "--device", "gpu")
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1
    assert "argument --device: invalid choice: 'gpu' (choose from 'auto', 'cpu', 'cuda')" in proc.stderr
    if not GPU:  # this machine: cuda is refused before anything is written
        out = (
            ["--run-dir", str(tmp_path / "r")]
            if command[0] == "train"
            else ["--out", str(tmp_path / "b")]
            if command[0] == "bench"
            else []
        )
        proc = cli(*command, *out, "--device", "cuda")
        assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
        assert "device 'cuda' requested but torch sees no GPU here; use --device cpu or auto" in proc.stderr
        assert "Traceback" not in proc.stderr
        assert not (tmp_path / "r").exists() and not (tmp_path / "b").exists()


@pytest.mark.slow
def test_device_is_recorded_and_not_compared_on_resume(tmp_path):
    """A run records where it started; the same run asked for on another device is the
    same run (here cpu, then auto, which is cpu on a machine without a GPU)."""
    run_dir = tmp_path / "run"
    args = [
        "train",
        "--env",
        "UnifiedManip/Arm4Reach-v0",
        "--action-mode",
        "ee_delta",
        "--algo",
        "sac_her",
        "--steps",
        "200",
        "--run-dir",
        str(run_dir),
        "--no-progress",
        "--set",
        "learning_starts=100",
        "--set",
        "batch_size=32",
        "--set",
        "eval_freq=1000",
    ]
    first = cli(*args, "--device", "cpu")
    assert first.returncode == 0, first.stderr
    config = yaml.safe_load((run_dir / "config.yaml").read_text())
    assert config["device"] == "cpu" and "device" not in config["hyperparameters"]
    again = cli(*args, "--device", "auto")
    assert again.returncode == 0, again.stderr
    assert "already finished at 200 steps" in again.stdout


# ---------------------------------------------------------------------- recipe files
@pytest.mark.parametrize("algo", list(ALGOS))
def test_every_hyperparameter_entry_loads_and_type_checks(algo):
    entries = [k for k in load_file(ALGOS[algo]) if k != "default"]
    for entry in entries:  # "<task ID>" or "<task ID> <action mode>"
        task_id, mode = split_entry(entry)
        assert task_id in unified_manip.TASKS, f"{algo}.yaml has an entry for unknown task {task_id}"
        assert mode is None or mode in unified_manip.TASKS[task_id].action_modes, (
            f"{algo}.yaml: unknown mode in {entry!r}"
        )
        # raises on an unknown key or a wrong type
        params = resolve(algo, task_id, action_mode=mode)
        assert params["policy"] == "MultiInputPolicy"
    assert resolve(algo, "default")["policy"] == "MultiInputPolicy"


@pytest.mark.slow
@pytest.mark.parametrize("grid", COMMITTED_GRIDS, ids=lambda p: p.stem)
def test_every_committed_grid_loads(grid):
    loaded = load_grid(grid)
    assert loaded.runs and all(r.steps > 0 for r in loaded.runs)


# ---------------------------------------------------------------------- per-task budgets
def _grid(tmp_path: Path, steps) -> Path:
    path = tmp_path / "g.yaml"
    path.write_text(
        yaml.safe_dump(
            {
                "tasks": ["UnifiedManip/Arm4Reach-v0", "UnifiedManip/FetchReach-v0"],
                "action_modes": ["ee_delta"],
                "reward_types": ["sparse"],
                "algos": ["sac_her"],
                "seeds": [0],
                "steps": steps,
            }
        )
    )
    return path


def test_a_grid_may_give_each_task_its_own_budget(tmp_path):
    grid = load_grid(_grid(tmp_path, {"default": 1000, "UnifiedManip/FetchReach-v0": 3000}))
    assert {r.task: r.steps for r in grid.runs} == {
        "UnifiedManip/Arm4Reach-v0": 1000,
        "UnifiedManip/FetchReach-v0": 3000,
    }


@pytest.mark.parametrize(
    "steps,message",
    [
        (
            {"UnifiedManip/Lift-v0": 10, "default": 5},
            "steps names 'UnifiedManip/Lift-v0', which is not one of the grid's tasks",
        ),
        (
            {"UnifiedManip/Arm4Reach-v0": 10},
            "steps gives no value for 'UnifiedManip/FetchReach-v0'; add it or a 'default'",
        ),
        ({"default": -1}, "steps for 'default' must be a positive integer, got -1"),
        ("many", "steps must be a positive integer, got 'many'"),
    ],
)
def test_bad_budgets_are_refused(tmp_path, steps, message):
    from unified_manip.experiments.grid import GridError

    with pytest.raises(GridError, match=message):
        load_grid(_grid(tmp_path, steps))


def test_n_envs_may_differ_by_algorithm(tmp_path):
    path = tmp_path / "g.yaml"
    path.write_text(
        yaml.safe_dump(
            {
                "tasks": ["UnifiedManip/Arm4Reach-v0"],
                "action_modes": ["ee_delta"],
                "reward_types": ["dense"],
                "algos": ["ppo", "sac"],
                "seeds": [0],
                "steps": 100,
                "n_envs": {"default": 1, "ppo": 8},
            }
        )
    )
    assert {r.algo: r.n_envs for r in load_grid(path).runs} == {"ppo": 8, "sac": 1}


def test_only_selects_runs_and_refuses_what_matches_nothing(tmp_path):
    from unified_manip.experiments.grid import GridError, selected

    grid = load_grid(ROOT / "baselines" / "grids" / "reward_design_1m.yaml")
    ppo = selected(grid, ("algo=ppo",))
    assert ppo and all("__ppo__" in name for name in ppo)
    assert selected(grid, ("algo=ppo", "seed=0", "seed=1")) == {n for n in ppo if n.endswith(("s0", "s1"))}
    with pytest.raises(GridError, match="malformed --only 'algorithm=ppo'; expected KEY=VALUE with KEY one of task"):
        selected(grid, ("algorithm=ppo",))
    with pytest.raises(GridError, match="--only algo=td3 selects none of the grid's"):
        selected(grid, ("algo=td3",))
    proc = cli(
        "bench",
        str(ROOT / "baselines" / "grids" / "reward_design_1m.yaml"),
        "--out",
        str(tmp_path / "b"),
        "--only",
        "seed",
    )
    assert (
        proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1 and "malformed --only 'seed'" in proc.stderr
    )


# ---------------------------------------------------------------------- exploration diagnostic
def test_exploration_measures_what_random_actions_give_her():
    from benchmarks.exploration import measure

    arm = measure("UnifiedManip/Arm4Push-v0", "ee_delta", episodes=3)
    # Arm4Push's goals lie at least 10 cm from the cube: never met by chance.
    assert arm.chance_success == 0.0 and arm.episode_steps == 100 and arm.control_dt == pytest.approx(0.02)
    assert 0.0 <= arm.object_moved <= 1.0 and arm.mean_object_displacement_m >= 0.0
    assert 0.1 < arm.gripper_cm_per_step < 2.5  # ee_delta moves at most 2.5 cm per step
    # Seeded: what these three episodes measure, per step and per second, on each MuJoCo
    # of CI (3.9.0 recorded 2026-11-27, 3.3.0 2026-12-05).
    recorded = {"3.9.0": (1.248617, 62.430872), "3.3.0": (1.222376, 61.118808)}
    mujoco = version("mujoco")
    assert mujoco in recorded, f"no recorded figures for mujoco {mujoco}"
    assert (arm.gripper_cm_per_step, arm.gripper_cm_per_s) == pytest.approx(recorded[mujoco], abs=1e-6)


def test_step_response_shows_the_servo_overshoot_only_where_a_mode_holds_its_target():
    from benchmarks.step_response import measure

    # One full step on j1 (axis 1): joint_target_delta holds the target and the stiff servo
    # overshoots it; joint_delta re-targets from where the arm is, so the overshoot is gone.
    held = measure("UnifiedManip/Arm4Push-v0", "joint_target_delta", axis=1, episodes=2)
    retargeted = measure("UnifiedManip/Arm4Push-v0", "joint_delta", axis=1, episodes=2)
    assert held.overshoot > 0.05 and retargeted.overshoot < 0.03
    assert held.peak_cm >= held.settled_cm > 1.0 and held.settle_steps > retargeted.settle_steps
    # ee_target_delta's target moves exactly one 2.5 cm step, wherever the arm overshoots to.
    ee = measure("UnifiedManip/Arm4Push-v0", "ee_target_delta", axis=0, episodes=1)
    assert ee.settled_cm == pytest.approx(2.5, abs=0.05)
    with pytest.raises(ValueError, match="axis 9 is outside"):
        measure("UnifiedManip/Arm4Push-v0", "ee_delta", axis=9, episodes=1)


# ---------------------------------------------------------------------- new algo keys resume
@pytest.mark.slow
def test_crossq_her_resumes_after_kill_9(tmp_path):
    """Each new algorithm key resumes after a kill with its step count and replay buffer."""
    import json
    import signal

    from stable_baselines3.common.save_util import load_from_pkl
    from test_train import _wait_for_checkpoint, train_args

    run_dir = tmp_path / "run"
    args = train_args(
        "UnifiedManip/Arm4Reach-v0", "crossq_her", 800, run_dir, ["checkpoint_freq=200", "eval_freq=10000"]
    )
    proc = subprocess.Popen(
        [sys.executable, "-m", "unified_manip.cli", *args],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    checkpoint = _wait_for_checkpoint(run_dir, 200, proc)
    proc.send_signal(signal.SIGKILL)
    proc.communicate(timeout=300)
    assert not (run_dir / "final_model.zip").exists()
    resumed = cli(*args)
    assert resumed.returncode == 0, resumed.stderr
    assert f"resuming from step {checkpoint} of 800" in resumed.stdout
    assert json.loads((run_dir / "status.json").read_text())["num_timesteps"] == 800
    assert load_from_pkl(run_dir / "replay_buffer.pkl").size() == 800


@pytest.mark.slow
def test_evaluation_schedule_counts_env_steps_over_all_training_envs(tmp_path):
    """eval_freq is in env steps whatever --n-envs is (EvalCallback counts vector steps)."""
    import numpy as np

    run_dir = tmp_path / "run"
    proc = cli(
        "train",
        "--env",
        "UnifiedManip/Arm4Reach-v0",
        "--action-mode",
        "joint_delta",
        "--algo",
        "sac_her",
        "--steps",
        "400",
        "--n-envs",
        "4",
        "--vec",
        "native",
        "--run-dir",
        str(run_dir),
        "--no-progress",
        "--set",
        "learning_starts=240",
        "--set",
        "batch_size=32",
        "--set",
        "eval_freq=100",
        "--set",
        "n_eval_episodes=1",
    )
    assert proc.returncode == 0, proc.stderr
    assert np.load(run_dir / "eval" / "evaluations.npz")["timesteps"].tolist() == [100, 200, 300, 400]
