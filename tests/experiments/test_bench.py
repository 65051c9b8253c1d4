"""``unified-manip bench`` and ``report``: grids, executors, resume, statistics."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import LOCAL_RAY, TINY_GRID, local_ray, write_grid

from unified_manip.envs.rewards import RewardSpec, Term
from unified_manip.experiments.bench import run_grid
from unified_manip.experiments.curves import read_scalars
from unified_manip.experiments.figures import final_bars
from unified_manip.experiments.grid import GridError, load_grid
from unified_manip.experiments.report import build_report
from unified_manip.experiments.results import read_results, write_results
from unified_manip.experiments.sanity import dense_reward_check
from unified_manip.training.hyperparams import resolve_run
from unified_manip.training.runlock import DirectoryLock

ROOT = Path(__file__).resolve().parents[2]


def cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "unified_manip.cli", *args], capture_output=True, text=True, timeout=300, cwd=ROOT
    )


def _check_complete(out: Path, expected_runs: int) -> list[dict]:
    rows = read_results(out / "results.csv")
    assert len(rows) == expected_runs
    assert len({r["run"] for r in rows}) == expected_runs  # exactly one row per run
    for r in rows:
        assert r["steps"] == 200 and r["curve"][-1][0] >= 200
        assert 0.0 <= r["final_success_rate"] <= 1.0
        assert r["wall_time_s"] > 0 and r["steps_per_s"] > 0
        assert r["versions"]["mujoco"] == "3.9.0"
    return rows


# ---------------------------------------------------------------------- executors
@pytest.mark.slow
def test_local_executor_runs_a_2x2_grid(tmp_path):
    grid = load_grid(write_grid(tmp_path, TINY_GRID))
    assert len(grid.runs) == 4
    summary = run_grid(grid, tmp_path / "out", executor="local", workers=2, progress=False)
    assert summary["finished"] == 4 and summary["failed"] == []
    rows = _check_complete(tmp_path / "out", 4)
    assert {(r["action_mode"], r["seed"]) for r in rows} == {
        ("ee_delta", 0),
        ("ee_delta", 1),
        ("joint_delta", 0),
        ("joint_delta", 1),
    }
    # A second bench skips every finished run.
    again = run_grid(grid, tmp_path / "out", executor="local", workers=2, progress=False)
    assert again["finished"] == 4 and again["wall_time_s"] < 5
    # --collect: finished runs copied into another bench directory give its results.csv
    # the same rows, and no run starts (the two missing ones stay missing).
    other = tmp_path / "other"
    for row in rows[:2]:  # as committed: models, buffers and checkpoints are git-ignored
        shutil.copytree(
            tmp_path / "out" / "runs" / row["run"],
            other / "runs" / row["run"],
            ignore=shutil.ignore_patterns("*.zip", "*.pkl", "checkpoints", "best"),
        )
    done = cli("bench", str(write_grid(tmp_path, TINY_GRID)), "--out", str(other), "--collect", "--no-progress")
    assert done.returncode == 0 and "2/4 runs finished, 0 failed" in done.stdout, done.stderr
    assert {r["run"]: r for r in read_results(other / "results.csv")} == {r["run"]: r for r in rows[:2]}
    assert sorted(p.name for p in (other / "runs").iterdir()) == sorted(r["run"] for r in rows[:2])
    assert not (other / "command.txt").exists()
    both = cli("bench", str(write_grid(tmp_path, TINY_GRID)), "--out", str(other), "--collect", "--only", "seed=0")
    assert both.returncode == 2 and both.stderr.strip() == (
        "unified-manip bench: error: --only chooses runs to train and --collect trains none; give one or the other"
    )


@pytest.mark.slow
@local_ray
def test_ray_executor_runs_the_same_grid_on_a_local_ray(tmp_path):
    # In its own process, as users run it: Ray's head is forked from a small CLI process,
    # never from a test worker that has grown over the whole suite.
    out = tmp_path / "out"
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "unified_manip.cli",
            "bench",
            str(write_grid(tmp_path, TINY_GRID)),
            "--out",
            str(out),
            "--executor",
            "ray",
            "--workers",
            "2",
            "--no-progress",
        ],
        capture_output=True,
        text=True,
        timeout=600,
        cwd=ROOT,
    )
    assert proc.returncode == 0, proc.stderr
    assert f"4/4 runs finished, 0 failed; results in {out / 'results.csv'}" in proc.stdout
    _check_complete(out, 4)


@pytest.mark.slow
def test_a_ray_address_that_cannot_be_used_is_refused_in_one_line(tmp_path):
    grid = str(write_grid(tmp_path, TINY_GRID))
    bad = cli("bench", grid, "--out", str(tmp_path / "out"), "--executor", "ray", "--address", "nohost")
    assert bad.returncode == 2 and bad.stderr.strip().splitlines()[-1] == (
        "unified-manip bench: error: Ray did not start at --address nohost: Invalid address format: nohost"
    ), bad.stderr
    assert "Traceback" not in bad.stderr
    assert not (tmp_path / "out" / "command.txt").exists()  # the directory is left as it was
    local = cli("bench", grid, "--out", str(tmp_path / "out"), "--address", "10.0.0.1:6379")
    assert local.returncode == 2 and local.stderr.strip() == (
        "unified-manip bench: error: --address names a Ray cluster, for --executor ray; "
        "this bench's executor is 'local'"
    )


@pytest.mark.slow
def test_a_crashing_run_is_recorded_retried_and_does_not_block_the_grid(tmp_path):
    doc = dict(TINY_GRID, seeds=[0])
    grid = load_grid(write_grid(tmp_path, doc))
    out = tmp_path / "out"
    # Occupy one run's directory with a foreign file: train refuses it, every attempt.
    bad = out / "runs" / grid.runs[0].name
    bad.mkdir(parents=True)
    (bad / "notes.txt").write_text("not a run")
    summary = run_grid(grid, out, executor="local", workers=2, retries=1, progress=False)
    assert summary["finished"] == 1 and summary["failed"] == [grid.runs[0].name]
    failures = [json.loads(line) for line in (out / "failures.jsonl").read_text().splitlines()]
    assert [f["attempt"] for f in failures] == [1, 2]  # first try + one retry
    assert "is not a unified-manip run directory" in failures[0]["error"]
    assert [r["run"] for r in read_results(out / "results.csv")] == [grid.runs[1].name]


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGINT], ids=["kill", "ctrl-c"])
def test_killed_bench_resumes_with_exactly_one_complete_row_per_run(sig, tmp_path):
    grid_path = write_grid(tmp_path, dict(TINY_GRID, steps=200))
    out = tmp_path / "out"
    cmd = [
        sys.executable,
        "-m",
        "unified_manip.cli",
        "bench",
        str(grid_path),
        "--out",
        str(out),
        "--workers",
        "1",
        "--no-progress",
    ]
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    deadline = time.time() + 600
    while time.time() < deadline:
        results = out / "results.csv"
        if results.is_file() and len(results.read_text().strip().splitlines()) >= 2:  # header + one run
            break
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.2)
    os.killpg(proc.pid, sig)  # the bench and its worker, mid-way (Ctrl-C reaches the whole group)
    out_text, err_text = proc.communicate(timeout=300)
    if sig == signal.SIGINT:  # a clean stop: one line, no traceback
        assert proc.returncode == 130, err_text
        assert b"bench interrupted; run the same command again to resume" in out_text
        assert b"Traceback" not in err_text
    first = read_results(out / "results.csv")
    assert 1 <= len(first) < 4
    finished_before = {r["run"]: r["wall_time_s"] for r in first}

    subprocess.run(cmd, cwd=ROOT, check=True, capture_output=True, timeout=900)
    rows = _check_complete(out, 4)
    for r in rows:  # finished runs were skipped, not run again
        if r["run"] in finished_before:
            assert r["wall_time_s"] == finished_before[r["run"]]
    # The report draws every run's training episodes from its logs, the resumed run's too.
    text = build_report(out / "results.csv", tmp_path / "report", dense_check=False).read_text()
    assert "## Training episodes" in text and (tmp_path / "report" / "Arm4Reach-v0_training.png").is_file()
    for r in rows:
        steps, success = read_scalars(out / "runs" / r["run"])["rollout/success_rate"]
        assert steps[-1] == 200 and (np.diff(steps) > 0).all() and ((success >= 0) & (success <= 1)).all()


@pytest.mark.slow
@pytest.mark.parametrize(
    ("sig", "executor"),
    [
        (signal.SIGTERM, "local"),
        (signal.SIGINT, "local"),
        (signal.SIGHUP, "local"),
        (signal.SIGKILL, "local"),
        pytest.param(signal.SIGTERM, "ray", marks=LOCAL_RAY),
    ],
    ids=["term", "int", "hangup", "kill", "ray-term"],
)
def test_a_signal_to_the_bench_alone_checkpoints_and_stops_its_run_in_progress(sig, executor, tmp_path):
    """What a scheduler or a ``kill PID`` sends reaches the bench's pid only, not its workers."""
    grid_path = write_grid(tmp_path, dict(TINY_GRID, action_modes=["ee_delta"], seeds=[0], steps=50_000))
    out = tmp_path / "out"
    run_dir = out / "runs" / load_grid(grid_path).runs[0].name
    cmd = [sys.executable, "-m", "unified_manip.cli", "bench", str(grid_path), "--out", str(out), "--workers", "1"]
    cmd += ["--executor", executor]
    proc = subprocess.Popen(
        cmd + ["--no-progress"],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGHUP, signal.SIG_DFL),  # not nohup's SIG_IGN
    )
    deadline = time.time() + 300
    while _steps(run_dir) < 100:  # the first checkpoint: the run is learning
        assert proc.poll() is None and time.time() < deadline, proc.communicate()
        time.sleep(0.2)
    os.kill(proc.pid, sig)
    out_text, err_text = proc.communicate(timeout=300)  # its pipes close when the worker ends too
    if sig == signal.SIGKILL:
        assert proc.returncode == -signal.SIGKILL
    else:
        assert proc.returncode == 128 + sig, err_text
        assert b"bench interrupted; run the same command again to resume" in out_text
        assert b"Traceback" not in err_text
    if executor == "local":  # a Ray task's output stays in Ray's logs
        assert b"stopping at the next rollout boundary" in err_text  # the worker heard, once
    DirectoryLock(run_dir).acquire(wait_s=10).release()  # and let go of the run
    status = json.loads((run_dir / "status.json").read_text())
    assert status["state"] == "running" and 100 <= status["num_timesteps"] < 50_000
    assert (run_dir / "checkpoints" / f"{status['num_timesteps']:012d}").is_dir()  # whole, where it stopped


def _steps(run_dir: Path) -> int:
    try:
        return json.loads((run_dir / "status.json").read_text())["num_timesteps"]
    except (FileNotFoundError, json.JSONDecodeError):
        return 0


def test_training_curves_take_a_resumed_segments_values_over_the_steps_it_repeats(tmp_path):
    from torch.utils.tensorboard import SummaryWriter

    for points in ([(100, 0.1), (200, 0.2), (300, 0.3)], [(250, 0.5), (350, 0.6)]):  # killed after 300, resumed at 200
        writer = SummaryWriter(str(tmp_path / "tb" / "tb_0"))
        for step, value in points:
            writer.add_scalar("rollout/success_rate", value, step)
        writer.close()
        time.sleep(1.1)  # event files are ordered by the start time in their names (whole seconds)
    steps, values = read_scalars(tmp_path)["rollout/success_rate"]
    assert steps.tolist() == [100, 200, 250, 350]
    assert np.allclose(values, [0.1, 0.2, 0.5, 0.6])
    assert "rollout/ep_rew_mean" not in read_scalars(tmp_path)  # a tag never logged is absent


# ---------------------------------------------------------------------- grid errors
@pytest.mark.parametrize(
    "change,message",
    [
        (
            {"seeds": None},
            "missing grid key(s) seeds; required: tasks, action_modes, reward_types, algos, seeds, steps",
        ),
        (
            {"budget": 10},
            "unknown grid key(s) 'budget'; expected tasks, action_modes, reward_types, algos, seeds, steps, name, description, eval_freq, n_eval_episodes, overrides, n_envs",
        ),
        (
            {"tasks": ["UnifiedManip/Nope-v0"]},
            "unknown task 'UnifiedManip/Nope-v0'; expected one of UnifiedManip/Arm4Reach-v0",
        ),
        (
            {"tasks": ["metaworld:MT11"]},
            "unknown task list 'metaworld:MT11'; expected one of metaworld:MT10, metaworld:MT50, metaworld:ML10-train, "
            "metaworld:ML10-test",
        ),
        ({"algos": ["dqn"]}, "unknown algorithm 'dqn'; expected one of ppo, sac, td3, sac_her, tqc_her, crossq_her"),
        (
            {"reward_types": ["shaped"]},
            "unknown reward_type 'shaped'; expected one of 'sparse', 'dense', 'dense_penalized'",
        ),
        ({"steps": 0}, "steps must be a positive integer, got 0"),
        ({"seeds": []}, "grid key 'seeds' must be a non-empty list of int, got []"),
        ({"action_modes": ["teleport"]}, "unknown action_mode 'teleport'; expected one of 'joint_torque', "),
        (
            {"tasks": ["UnifiedManip/HandReach-v0"], "action_modes": ["ee_delta"]},
            "action_mode 'ee_delta' is not supported by UnifiedManip/HandReach-v0; expected one of 'joint_delta', ",
        ),
        ({"overrides": {"sac_her": ["warp=9"]}}, "unknown hyperparameter 'warp' in --set 'warp=9'"),
        (
            {"overrides": {"sac_her": [*TINY_GRID["overrides"]["sac_her"], "bc_steps=10"]}},
            "bc_steps=10 clones the demonstrations; set demonstrations to 1 or more episodes",
        ),
        (
            {"overrides": {"sac_her": [*TINY_GRID["overrides"]["sac_her"], "bc_weight=2"]}},
            "bc_weight=2 imitates the demonstrations; set demonstrations to 1 or more episodes",
        ),
        ({"env_kwargs": ["band"]}, "env_kwargs must be a mapping of gym.make keyword arguments, got ['band']"),
        (
            {"env_kwargs": {"action_mode": "joint_position"}},
            "env_kwargs may not set 'action_mode'; the grid's own keys choose it",
        ),
        (
            {"env_kwargs": {"controller_options": {"band": 0.5}}},
            "unknown controller option 'band' for action_mode 'ee_delta' (EEDelta); expected one of 'step', ",
        ),
        (
            {"algos": ["ppo"], "overrides": {"ppo": ["demonstrations=5"]}},
            "demonstrations go into a replay buffer; use an off-policy algorithm (sac, ",
        ),
    ],
)
def test_malformed_grids_give_exact_errors(tmp_path, change, message):
    doc = dict(TINY_GRID)
    for k, v in change.items():
        if v is None:
            doc.pop(k)
        else:
            doc[k] = v
    path = write_grid(tmp_path, doc)
    with pytest.raises(GridError) as err:
        load_grid(path)
    assert str(err.value).startswith(f"{path}: {message}")


def test_cell_overrides_set_one_cells_runs_after_the_algorithms_overrides(tmp_path):
    """A study where one cell differs (a mode with no dataset runs without demonstrations)."""
    base = TINY_GRID["overrides"]["sac_her"]
    doc = {
        **TINY_GRID,
        "overrides": {"sac_her": [*base, "demonstrations=4"]},
        "cell_overrides": [{"action_mode": "joint_delta", "set": ["demonstrations=0"]}],
    }
    runs = load_grid(write_grid(tmp_path, doc)).runs
    demos = {
        (r.action_mode, r.seed): resolve_run(
            r.algo, r.task, r.overrides, action_mode=r.action_mode
        ).run.demos.demonstrations
        for r in runs
    }
    assert demos == {("ee_delta", 0): 4, ("ee_delta", 1): 4, ("joint_delta", 0): 0, ("joint_delta", 1): 0}
    for bad, message in [
        ([{"action_mode": "joint_delta"}], "cell_overrides must be a list of mappings with 'set'"),
        ([{"mode": "joint_delta", "set": ["demonstrations=0"]}], "unknown key 'mode' in cell_overrides"),
        ([{"action_mode": "joint_delta", "set": ["warp=9"]}], "unknown hyperparameter 'warp' in --set 'warp=9'"),
        (  # a task the grid does not run (another version of it): the setting would be lost
            [{"task": "UnifiedManip/Arm4Reach-v9", "set": ["demonstrations=0"]}],
            "cell_overrides entry {'task': 'UnifiedManip/Arm4Reach-v9'} matches no run of the grid",
        ),
    ]:
        with pytest.raises(GridError) as err:
            load_grid(write_grid(tmp_path, {**doc, "cell_overrides": bad}))
        assert str(err.value).startswith(f"{tmp_path / 'grid.yaml'}: {message}")


def test_a_grid_without_n_envs_leaves_it_to_the_hyperparameter_file(tmp_path):
    """None reaches train, which takes the file's n_envs (else 1); a grid's own wins."""
    assert {r.n_envs for r in load_grid(write_grid(tmp_path, TINY_GRID)).runs} == {None}
    three = {**TINY_GRID, "n_envs": {"sac_her": 3}}
    with pytest.raises(
        GridError,
        match=r"learning_starts=50 starts training at step 51, before the first episodes end "
        r"at step 150 \(3 envs x 50 steps\)",
    ):
        load_grid(write_grid(tmp_path, three))  # checked with the grid's n_envs, before any run starts
    three["overrides"] = {"sac_her": [*TINY_GRID["overrides"]["sac_her"], "learning_starts=150"]}
    assert {r.n_envs for r in load_grid(write_grid(tmp_path, three)).runs} == {3}


@pytest.mark.slow
def test_a_grids_env_kwargs_reach_every_run_its_config_and_its_report(tmp_path):
    """The zoo's env_kwargs: here a controller option, recorded in config.yaml (so resume
    compares it and eval rebuilds the same env) and stated in the report."""
    doc = {
        **TINY_GRID,
        "action_modes": ["joint_position"],
        "seeds": [0],
        "env_kwargs": {"controller_options": {"band": 0.4}},
    }
    grid = load_grid(write_grid(tmp_path, doc))
    assert [r.env_kwargs for r in grid.runs] == [{"controller_options": {"band": 0.4}}]
    out = tmp_path / "out"
    assert run_grid(grid, out, executor="local", workers=1, progress=False)["finished"] == 1
    run = out / "runs" / grid.runs[0].name
    config = yaml.safe_load((run / "config.yaml").read_text())
    assert config["env_kwargs"] == {
        "action_mode": "joint_position",
        "reward_type": "sparse",
        "controller_options": {"band": 0.4},
    }
    done = cli("eval", str(run), "--episodes", "1")
    assert done.returncode == 0, done.stderr
    text = build_report(out / "results.csv", tmp_path / "report", command="r", dense_check=False).read_text()
    assert (
        '- Env keyword arguments of every run (the grid\'s `env_kwargs`): `{"controller_options": {"band": 0.4}}`.'
        in text
    )


@pytest.mark.slow
def test_committed_grids_are_valid():
    for path in sorted((ROOT / "baselines" / "grids").glob("*.yaml")):
        grid = load_grid(path)
        assert len(grid.runs) > 0 and len({r.seed for r in grid.runs}) >= 3
    # Recipe grids (one seed, to establish a recipe) load and type-check too.
    recipes = sorted((ROOT / "baselines" / "grids" / "recipes").glob("*.yaml"))
    assert len(recipes) >= 6 and all(load_grid(path).runs for path in recipes)
    # Pilot grids (seed 0, to set a study's budget) too.
    pilots = sorted((ROOT / "baselines" / "grids" / "pilots").glob("*.yaml"))
    assert len(pilots) >= 1 and all(load_grid(path).runs for path in pilots)
    # Grids that keep a trained policy with its model (one seed, for collect --all) too.
    policies = sorted((ROOT / "baselines" / "grids" / "policies").glob("*.yaml"))
    assert len(policies) >= 1 and all(load_grid(path).runs for path in policies)


def _without_demonstrations(doc: dict) -> set[tuple[str, str]]:
    """The (task name, mode) cells a grid file's ``cell_overrides`` run without demonstrations."""
    return {
        (c["task"].split("/")[-1], c["action_mode"]) for c in doc["cell_overrides"] if "demonstrations=0" in c["set"]
    }


def test_the_cross_family_study_grid_names_one_dataset_per_task_and_mode():
    """Issue 40's grid reads 24 datasets made by its script, so CI cannot load it (it is
    left out of ``COMMITTED_GRIDS``); its file states the protocol, checked here."""
    study = ROOT / "baselines" / "grids" / "studies"
    doc = yaml.safe_load((study / "action_spaces_families.yaml").read_text())
    assert doc["action_modes"] == "all" and doc["seeds"] == [0, 1, 2] and doc["algos"] == ["tqc_her"]
    assert doc["steps"] == {
        "UnifiedManip/Arm4PickAndPlace-v0": 60_000,
        "UnifiedManip/FetchPickAndPlace-v0": 70_000,
        "UnifiedManip/Lift-v0": 80_000,
    }
    assert "demonstrations=data/{task}/{action_mode}-v0" in doc["overrides"]["tqc_her"]
    assert ("FetchPickAndPlace-v0", "native") in _without_demonstrations(doc)
    assert "ROOT=${ROOT:-data}" in (study / "make_datasets.sh").read_text()


def test_the_mt10_study_grid_states_its_protocol():
    """The MT10 comparison reads 40 datasets and needs Meta-World, which CI's first leg
    lacks, so its file's protocol is checked here: MT10's ten tasks, the four modes, 3
    seeds, 100k steps (the most allowed), and one dataset per task and mode (where one was
    made; the test below holds the cells without one)."""
    study = ROOT / "baselines" / "grids" / "studies"
    doc = yaml.safe_load((study / "action_spaces_mt10.yaml").read_text())
    assert doc["tasks"] == ["metaworld:MT10"] and doc["seeds"] == [0, 1, 2] and doc["algos"] == ["tqc_her"]
    assert doc["action_modes"] == ["native", "ee_delta", "joint_delta", "joint_target_delta"]
    assert doc["steps"] == 100_000 and doc["n_envs"] == 8
    assert "demonstrations=data/{task}/{action_mode}-v0" in doc["overrides"]["tqc_her"]
    assert "COLLECT=${COLLECT:-}" in (study / "make_datasets.sh").read_text()  # native: recorded, not converted


def test_the_mt10_grid_runs_without_demonstrations_exactly_where_its_datasets_cannot_fill_a_round():
    """A cell whose dataset was never written, or holds fewer episodes than the grid's
    envs, must not name it (the grid would refuse to start), and one whose dataset gives
    each env an episode must use it: the grid's ``demonstrations=0`` cells are the "none"
    cells of ``action_spaces_mt10_datasets.md`` and those under ``n_envs`` episodes."""
    study = ROOT / "baselines" / "grids" / "studies"
    doc = yaml.safe_load((study / "action_spaces_mt10.yaml").read_text())
    lines = [
        line for line in (study / "action_spaces_mt10_datasets.md").read_text().splitlines() if line.startswith("| ")
    ]
    modes = [c.strip() for c in lines[0].strip("|").split("|")][1:]
    none = set()
    for line in lines[1:]:
        task, *cells = (c.strip() for c in line.strip("|").split("|"))
        none |= {
            (task, mode)
            for mode, cell in zip(modes, cells, strict=True)
            if cell.startswith("none") or int(cell.split()[0]) < doc["n_envs"]
        }
    assert len(lines) == 11 and sorted(modes) == sorted(doc["action_modes"])  # header and ten tasks
    assert (
        _without_demonstrations(doc)
        == none
        == {
            ("MetaWorldDoorOpen-v2", "native"),
            ("MetaWorldPegInsertSide-v2", "joint_delta"),
            ("MetaWorldDrawerOpen-v2", "joint_delta"),
        }
    )


@pytest.mark.robosuite  # loading the grid builds a Lift backend per observation design (check_design)
def test_the_action_space_pilot_grid_loads_with_the_runs_it_names():
    """Issue 40's budget pilot (once ``baselines/grids/action_spaces_families_pilot.yaml``):
    seed 0 of ee_delta and joint_delta, 150k steps on Fetch and 100k on Lift, with the cells
    already committed elsewhere left out by its ``only`` list."""
    grid = load_grid(ROOT / "baselines" / "grids" / "pilots" / "action_spaces_families.yaml")
    assert grid.name == "action_spaces_families_pilot"
    runs = {(r.task.split("/")[-1], r.action_mode, r.seed, r.steps, r.algo, r.reward_type) for r in grid.runs}
    assert runs == {
        ("FetchPickAndPlace-v0", "ee_delta", 0, 150_000, "tqc_her", "sparse"),
        ("FetchPickAndPlace-v0", "joint_delta", 0, 150_000, "tqc_her", "sparse"),
        ("Lift-v0", "joint_delta", 0, 100_000, "tqc_her", "sparse"),
    }
    assert all(r.n_envs == 8 and "demonstrations=100" in r.overrides for r in grid.runs)


# ---------------------------------------------------------------------- report
def _fixture_rows() -> list[dict]:
    versions = json.dumps({"mujoco": "3.9.0", "stable-baselines3": "2.9.2"})
    rows = []
    finals = {"ee_delta": [0.2, 0.4, 0.6, 0.8], "joint_delta": [0.1, 0.1, 0.3, 0.3]}
    for mode, values in finals.items():
        for seed, final in enumerate(values):
            rows.append(
                {
                    "run": f"Arm4Reach-v0__{mode}__sparse__sac_her__s{seed}",
                    "task": "UnifiedManip/Arm4Reach-v0",
                    "action_mode": mode,
                    "reward_type": "sparse",
                    "algo": "sac_her",
                    "seed": seed,
                    "steps": 1000,
                    "final_success_rate": final,
                    "curve": json.dumps([[500, final / 2], [1000, final]]),
                    "wall_time_s": 100.0,
                    "steps_per_s": 10.0,
                    "versions": versions,
                }
            )
    return rows


def test_report_numbers_match_hand_computed_values(tmp_path):
    bench = tmp_path / "bench"
    bench.mkdir()
    write_results(bench, _fixture_rows())
    path = build_report(bench / "results.csv", tmp_path / "report", command="unified-manip report fixture")
    text = path.read_text()
    table = {
        line.split("|")[3].strip(): [c.strip() for c in line.split("|")]
        for line in text.splitlines()
        if line.startswith("| Arm4Reach-v0 | sac_her |")
    }
    ee, jd = table["ee_delta"], table["joint_delta"]
    assert ee[6] == "0.50" and jd[6] == "0.20"  # means: (0.2+0.4+0.6+0.8)/4 and (0.1+0.1+0.3+0.3)/4
    # Four seeds: the interval is their range, labelled so, and no IQM or CI is claimed.
    assert ee[7] == "[0.20, 0.80] (range of 4 seeds)" and jd[7] == "[0.10, 0.30] (range of 4 seeds)"
    assert ee[8] == jd[8] == "— (under 5 seeds)"
    assert ee[9] == "0.20, 0.40, 0.60, 0.80"
    # P(ee > jd): pairs (x, y) with x > y count 1, ties 1/2. By hand: 0.2 beats the two
    # 0.1s, 0.4, 0.6 and 0.8 beat all four: 14 of 16 pairs -> 0.875, shown as 0.88.
    assert "| 2 | joint_delta | 0.20 | 0.88 |" in text
    assert "| 1 | ee_delta | 0.50 | — |" in text
    for needle in (
        "Budget: 1,000 environment steps",
        "Seeds: 0, 1, 2, 3",
        "mujoco 3.9.0",
        "unified-manip report fixture",
        "![UnifiedManip/Arm4Reach-v0](Arm4Reach-v0_success.png)",
        "Dense-reward sanity check",
    ):
        assert needle in text
    assert (tmp_path / "report" / "Arm4Reach-v0_success.png").stat().st_size > 10_000
    # The final-success figure: one bar per setting, best first, labelled by what differs.
    assert "![UnifiedManip/Arm4Reach-v0 final success per setting](Arm4Reach-v0_final.png)" in text
    assert (tmp_path / "report" / "Arm4Reach-v0_final.png").stat().st_size > 10_000
    groups = {}
    for r in _fixture_rows():
        groups.setdefault((r["algo"], r["action_mode"], r["reward_type"], "default", "none"), []).append(r)
    bars = final_bars(groups)
    assert [(b.label, round(b.mean, 6), b.values) for b in bars] == [
        ("ee_delta", 0.5, (0.2, 0.4, 0.6, 0.8)),
        ("joint_delta", 0.2, (0.1, 0.1, 0.3, 0.3)),
    ]
    assert f"[{bars[0].low:.2f}, {bars[0].high:.2f}] (range of 4 seeds)" == ee[7]  # the table's interval
    mixed = {
        ("sac_her", "ee_delta", "sparse", "default", "none"): groups[
            ("sac_her", "ee_delta", "sparse", "default", "none")
        ],
        ("ppo", "ee_delta", "dense", "default", "none"): groups[
            ("sac_her", "joint_delta", "sparse", "default", "none")
        ],
    }
    assert [b.label for b in final_bars(mixed)] == ["sparse / sac_her", "dense / ppo"]
    designs = {
        ("sac_her", "ee_delta", "sparse", "default", "none"): groups[
            ("sac_her", "ee_delta", "sparse", "default", "none")
        ],
        ("sac_her", "ee_delta", "sparse", "minimal", "none"): groups[
            ("sac_her", "joint_delta", "sparse", "default", "none")
        ],
    }
    assert [b.label for b in final_bars(designs)] == ["default", "minimal"]


def test_report_states_the_demonstrations_runs_started_with(tmp_path):
    """Runs given scripted demonstrations say so in the report (a prior they did not
    collect); a results.csv written before the column existed still reads."""
    rows = _fixture_rows()
    for r in rows[:4]:
        r["demonstrations"] = json.dumps({"episodes": 104, "transitions": 10400, "success": 0.98 if r["seed"] else 1.0})
    bench = tmp_path / "bench"
    bench.mkdir()
    write_results(bench, rows)
    read = read_results(bench / "results.csv")
    assert sum(r["demonstrations"] is not None for r in read) == 4
    text = build_report(bench / "results.csv", tmp_path / "report", command="r", dense_check=False).read_text()
    assert (
        "- Demonstrations: 4 of 8 runs started with 104 episodes of the task's scripted policy in the replay "
        "buffer (their success 0.98–1.00); they are not counted in the budget.\n"
    ) in text
    # Runs whose actor was behaviour-cloned on them (bc_steps) say that too.
    cloned = json.loads(rows[0]["demonstrations"])
    rows[0]["demonstrations"] = json.dumps(
        {**cloned, "behaviour_cloning": {"steps": 5000, "loss_first": 3.0, "loss_last": -20.0}}
    )
    write_results(bench, rows)
    text = build_report(bench / "results.csv", tmp_path / "report", command="r", dense_check=False).read_text()
    assert (
        "they are not counted in the budget. The actor of 1 of them was behaviour-cloned on them first "
        "(5,000 gradient steps).\n"
    ) in text
    # And those that kept a cloning loss during training (bc_weight) say that.
    rows[1]["demonstrations"] = json.dumps({**cloned, "cloning_loss_weight": 2.5})  # recorded before bc_q_filter
    rows[2]["demonstrations"] = json.dumps({**cloned, "cloning_loss_weight": 2.5, "cloning_loss_q_filter": False})
    write_results(bench, rows)
    text = build_report(bench / "results.csv", tmp_path / "report", command="r", dense_check=False).read_text()
    assert (
        "(5,000 gradient steps). 2 of them kept a cloning loss on them in every actor update "
        "(weight 2.5, unfiltered; weight 2.5, Q-filtered).\n"
    ) in text
    # On the sampled action (bc_sampled), recorded only where set.
    rows[2]["demonstrations"] = json.dumps({**json.loads(rows[2]["demonstrations"]), "cloning_loss_sampled": True})
    write_results(bench, rows)
    text = build_report(bench / "results.csv", tmp_path / "report", command="r", dense_check=False).read_text()
    assert "(weight 2.5, unfiltered, on sampled actions; weight 2.5, Q-filtered).\n" in text
    # And those that took offline steps on them (offline_steps) say that.
    rows[3]["demonstrations"] = json.dumps({**cloned, "offline": {"steps": 20000, "first": {}, "last": {}}})
    write_results(bench, rows)
    text = build_report(bench / "results.csv", tmp_path / "report", command="r", dense_check=False).read_text()
    assert (
        "(5,000 gradient steps). 1 of them took 20,000 gradient steps of the algorithm's own update on them "
        "alone before the first rollout. 2 of them kept"
    ) in text
    import csv

    from unified_manip.experiments.results import RESULT_COLUMNS

    old = bench / "old.csv"
    with old.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=RESULT_COLUMNS)
        writer.writeheader()
        writer.writerow({k: rows[5][k] for k in RESULT_COLUMNS})
    (row,) = read_results(old)
    assert row["demonstrations"] is None and row["run"] == rows[5]["run"]


def test_report_ranks_reward_settings_and_sets_claims_beside_measurements(tmp_path):
    """One action mode, several algorithm x reward settings (the reward-design grid)."""
    rows = _fixture_rows()
    for r in rows:  # relabel: ee_delta rows become "sac dense", joint_delta rows "ppo sparse"
        dense = r["action_mode"] == "ee_delta"
        r.update(
            action_mode="ee_delta",
            algo="sac" if dense else "ppo",
            reward_type="dense" if dense else "sparse",
            run=r["run"].replace("sac_her", "sac" if dense else "ppo"),
        )
    bench = tmp_path / "bench"
    bench.mkdir()
    write_results(bench, rows)
    claims = {
        "PPO, sparse reward": {
            "task": "UnifiedManip/Arm4Reach-v0",
            "algo": "ppo",
            "reward_type": "sparse",
            "claimed": "~5%",
            "claimed_budget": "1M steps",
        }
    }
    text = build_report(
        bench / "results.csv", tmp_path / "report", command="r", dense_check=False, claims=claims
    ).read_text()
    assert "## Ranking of algorithm and reward settings" in text
    assert "| 1 | sac | dense | 0.50 | — |" in text
    assert "| 2 | ppo | sparse | 0.20 | 0.88 |" in text  # the same hand-computed 14/16 as above
    assert "| PPO, sparse reward | ~5% (1M steps) | 0.20 [" in text
    assert "(1,000 steps, 4 seeds) |" in text
    write_results(bench, [r for r in rows if r["algo"] == "sac" or r["seed"] == 0])  # one seed: no interval
    text = build_report(
        bench / "results.csv", tmp_path / "report", command="r", dense_check=False, claims=claims
    ).read_text()
    assert "| PPO, sparse reward | ~5% (1M steps) | 0.10 (1,000 steps, 1 seed) |" in text


def test_dense_rewards_peak_inside_the_success_region():
    for task in ("UnifiedManip/Arm4Reach-v0", "UnifiedManip/Arm4PickAndPlace-v0"):
        for reward in ("dense", "dense_penalized"):
            check = dense_reward_check(task, reward)
            assert not check.flagged and check.max_inside > check.max_outside


def test_dense_check_flags_a_reward_whose_optimum_misses_the_goal():
    """A shaping that prefers hovering 10 cm from the goal is caught."""
    hover = RewardSpec("dense", (Term("hover", lambda d, s, ctx: -np.abs(d - 0.10), 1.0),))
    check = dense_reward_check("UnifiedManip/Arm4Reach-v0", "dense", reward_spec=hover)
    assert check.flagged and check.max_outside > check.max_inside
