"""``train --algo bc --demonstrations DATASET`` (issue 39 item 4): behaviour cloning of a
dataset, its budget in gradient steps, evaluated, checkpointed, resumable, and a bench
grid's run that ``report`` reads. On the committed arm example dataset (3 episodes)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml

from unified_manip.training.request import TrainError, TrainRequest
from unified_manip.training.train import train

ARM = "UnifiedManip/Arm4PickAndPlace-v0"
#: Three scripted ee_delta episodes (sparse reward), committed for tests and examples.
EXAMPLES = Path(__file__).resolve().parents[2] / "datasets" / "examples"
DATASET = EXAMPLES / "arm4-pickandplace-ee_delta-v0"
SETTINGS = ("eval_freq=100", "n_eval_episodes=2", "checkpoint_freq=100", "batch_size=64")


def _request(run_dir: Path, mode: str = "ee_delta", demonstrations: Path | None = DATASET, steps: int = 200):
    extra = (f"demonstrations={demonstrations}",) if demonstrations else ()
    return TrainRequest(
        env=ARM,
        action_mode=mode,
        reward_type="sparse",
        algo="bc",
        steps=steps,
        run_dir=run_dir,
        overrides=SETTINGS + extra,
    )


def _interrupt_at_first_checkpoint(run: Path, call, monkeypatch) -> None:
    """Ctrl-C ``call()`` while its first checkpoint is being written (the checkpoint
    writer's test hook holds it there), so that the run stops right after it."""
    import os
    import signal
    import threading

    from unified_manip.training import checkpoints

    monkeypatch.setenv(checkpoints.PAUSE_ENV, str(checkpoints._written + 1))

    def interrupt():
        while not list(run.glob("checkpoints/*/PAUSED")):
            threading.Event().wait(0.05)
        os.kill(os.getpid(), signal.SIGINT)
        threading.Event().wait(0.2)
        next(run.glob("checkpoints/*/PAUSED")).unlink()

    watcher = threading.Thread(target=interrupt, daemon=True)
    watcher.start()
    with pytest.raises(KeyboardInterrupt):
        call()
    watcher.join()


def test_a_200_step_bc_run_is_evaluated_resumed_and_recorded_in_gradient_steps(tmp_path, monkeypatch):
    run = tmp_path / "run"
    first: list[str] = []
    _interrupt_at_first_checkpoint(
        run, lambda: train(_request(run), progress=False, threads=1, log=first.append), monkeypatch
    )
    monkeypatch.delenv("UNIFIED_MANIP_TEST_PAUSE_CHECKPOINT")
    assert any("interrupted at gradient step 100" in line for line in first), first
    again: list[str] = []
    status = train(_request(run), progress=False, threads=1, log=again.append)
    assert any("resuming from gradient step 100 of 200" in line for line in again), again
    assert (status["state"], status["num_timesteps"]) == ("finished", 200)
    config = yaml.safe_load((run / "config.yaml").read_text())
    assert (config["budget"], config["steps"], config["algo"]) == ("gradient steps", 200, "bc")
    record = json.loads((run / "demonstrations.json").read_text())
    assert (record["episodes"], record["transitions"], record["budget"]) == (3, 300, "gradient steps")
    with np.load(run / "eval" / "evaluations.npz") as data:
        assert data["timesteps"].tolist() == [100, 200]  # the evaluation before the interruption is kept
        assert data["successes"].shape == data["results"].shape == (2, 2)
    assert (run / "final_model.zip").is_file() and (run / "best" / "best_model.zip").is_file()
    assert not (run / "checkpoints").exists()


@pytest.mark.slow
def test_bc_runs_in_a_bench_grid_and_loads_in_report(tmp_path):
    from unified_manip.experiments.bench import run_grid
    from unified_manip.experiments.grid import load_grid
    from unified_manip.experiments.report import build_report

    grid_file = tmp_path / "grid.yaml"
    grid_file.write_text(
        yaml.safe_dump(
            {
                "name": "bc_smoke",
                "tasks": [ARM],
                "action_modes": ["ee_delta"],
                "reward_types": ["sparse"],
                "algos": ["bc"],
                "seeds": [0],
                "steps": 100,
                "eval_freq": 100,
                "n_eval_episodes": 2,
                # {action_mode}: each mode's own dataset (here the ee_delta example)
                "overrides": {
                    "bc": [f"demonstrations={EXAMPLES}/arm4-pickandplace-{{action_mode}}-v0", "batch_size=64"]
                },
            }
        )
    )
    summary = run_grid(load_grid(grid_file), tmp_path / "out", executor="local", workers=1, progress=False)
    assert (summary["finished"], summary["failed"]) == (1, [])
    report = build_report(tmp_path / "out" / "results.csv", tmp_path / "report", dense_check=False)
    text = report.read_text()
    assert "100 gradient steps" in text and "bc" in text
    assert (  # a cloned policy learns from the dataset: no replay buffer, and within its budget
        f"- Demonstrations: 1 of 1 runs are behaviour cloning, fitted to 3 episodes of `{DATASET}` "
        "(their success 1.00–1.00); their budget counts gradient steps on them.\n"
    ) in text
    assert "in the replay buffer" not in text
    assert "## Success against gradient steps" in text  # and its figures' x axis (steps_label)
    record = json.loads((tmp_path / "out" / "runs" / summary_run(tmp_path) / "demonstrations.json").read_text())
    assert record["dataset"] == str(DATASET)


def summary_run(tmp_path: Path) -> str:
    (run,) = [p.name for p in (tmp_path / "out" / "runs").iterdir()]
    return run


@pytest.mark.parametrize(
    "mode,demonstrations,message",
    [
        ("ee_delta", None, "bc clones a dataset: pass --demonstrations DATASET"),
        ("joint_delta", DATASET, "--action-mode joint_delta --out "),
    ],
)
def test_bc_without_a_matching_dataset_is_refused_before_anything_is_written(tmp_path, mode, demonstrations, message):
    with pytest.raises(TrainError) as err:
        train(_request(tmp_path / "run", mode, demonstrations), progress=False, threads=1)
    assert message in str(err.value)
    assert not (tmp_path / "run").exists()


def test_a_bc_run_killed_outright_keeps_its_time_up_to_the_last_checkpoint(tmp_path):
    """A session's end kills runs without a checkpoint of their own: the status must keep
    the time to the last periodic checkpoint, which the resumed run adds its own to."""
    import os
    import signal
    import subprocess
    import sys
    import time

    from unified_manip.training import checkpoints

    run = tmp_path / "run"
    sets = [a for s in (*SETTINGS, f"demonstrations={DATASET}") for a in ("--set", s)]
    args = ["train", "--env", ARM, "--action-mode", "ee_delta", "--algo", "bc", "--run-dir", str(run)]
    args += ["--no-progress", *sets, "--steps"]
    env = {**os.environ, checkpoints.PAUSE_ENV: "2"}  # hold the second checkpoint (step 200)
    child = subprocess.Popen([sys.executable, "-m", "unified_manip.cli", *args, "300"], env=env)
    deadline = time.time() + 300
    while not list(run.glob("checkpoints/*/PAUSED")):
        assert child.poll() is None and time.time() < deadline
        time.sleep(0.05)
    child.send_signal(signal.SIGKILL)
    child.wait()
    killed = json.loads((run / "status.json").read_text())
    assert (killed["state"], killed["num_timesteps"]) == ("running", 100) and killed["wall_time_s"] > 0, killed
    train(_request(run, steps=300), progress=False, threads=1, log=lambda _: None)
    final = json.loads((run / "status.json").read_text())
    assert final["num_timesteps"] == 300 and final["wall_time_s"] > killed["wall_time_s"]
