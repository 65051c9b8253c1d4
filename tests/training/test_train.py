"""``unified-manip train`` / ``eval`` through the CLI, as a user runs them (subprocesses),
plus the rl-baselines3-zoo smoke run. Budgets are tiny: these check the plumbing, the
learning itself is checked by the committed experiments in ``results``."""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import ONE_ID_PER_FAMILY, cli_in_process

import unified_manip
from unified_manip.extras import missing_modules
from unified_manip.training import checkpoints
from unified_manip.training.algorithms import ALGOS
from unified_manip.training.hyperparams import HyperparameterError, resolve

ROOT = Path(__file__).resolve().parents[2]

# Small settings so 300 steps exercise learning, evaluation and checkpoints.
SMOKE = {
    "ppo": ["n_steps=100", "batch_size=50", "n_epochs=2"],
    "sac": ["learning_starts=100", "batch_size=64", "buffer_size=10000"],
    "td3": ["learning_starts=100", "batch_size=64", "buffer_size=10000"],
    "sac_her": ["learning_starts=100", "batch_size=64", "buffer_size=10000"],
    "tqc_her": ["learning_starts=100", "batch_size=64", "buffer_size=10000", "demonstrations=0", "n_envs=1"],
    "crossq_her": ["learning_starts=100", "batch_size=64", "buffer_size=10000", "policy_kwargs.net_arch.qf=[64, 64]"],
}
RUN_SETTINGS = ["eval_freq=150", "n_eval_episodes=2", "checkpoint_freq=100"]


def mode_for(task_id: str) -> str:
    modes = unified_manip.TASKS[task_id].action_modes
    return "ee_delta" if "ee_delta" in modes else "native"


def cli(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    """The CLI in this process (:func:`conftest.cli_in_process`); exit 0 asserted unless ``check`` is off."""
    proc = cli_in_process(*args)
    if check and proc.returncode != 0:
        raise AssertionError(f"exit {proc.returncode}\n{proc.stdout}\n{proc.stderr}")
    return proc


def train_args(task_id: str, algo: str, steps: int, run_dir: Path, extra: list[str] = ()) -> list[str]:
    smoke = SMOKE[algo]
    if algo.endswith("_her"):  # HER samples goals from finished episodes only: the first must end
        episode = unified_manip.TASKS[task_id].max_episode_steps
        smoke = [f"learning_starts={max(100, episode)}" if s == "learning_starts=100" else s for s in smoke]
    sets = [a for s in smoke + RUN_SETTINGS + list(extra) for a in ("--set", s)]
    return [
        "train",
        "--env",
        task_id,
        "--action-mode",
        mode_for(task_id),
        "--reward-type",
        "sparse",
        "--algo",
        algo,
        "--steps",
        str(steps),
        "--seed",
        "0",
        "--run-dir",
        str(run_dir),
        "--no-progress",
        *sets,
    ]


def monitor_rows(run_dir: Path) -> list[dict[str, str]]:
    rows = []
    for path in sorted((run_dir / "monitor").glob("seg*/*.monitor.csv")):
        with path.open() as f:
            next(f)  # the JSON header line
            rows.extend(csv.DictReader(f))
    return rows


def tb_tags(run_dir: Path) -> set[str]:
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    tags: set[str] = set()
    for events in (run_dir / "tb").rglob("events.out.tfevents.*"):
        acc = EventAccumulator(str(events))
        acc.Reload()
        tags.update(acc.Tags()["scalars"])
    return tags


# ---------------------------------------------------------------------- every algorithm
@pytest.mark.slow
@pytest.mark.parametrize(
    "algo, task_id",
    # Every algorithm on the arm, and the benchmark's algorithm on every other family
    # (bc clones a dataset: tests/training/test_bc.py).
    [(algo, ONE_ID_PER_FAMILY[0]) for algo in ALGOS if algo != "bc"]
    + [("tqc_her", task_id) for task_id in ONE_ID_PER_FAMILY[1:]],
)
def test_train_300_steps_writes_a_complete_run(algo, task_id, tmp_path):
    run_dir = tmp_path / "run"
    # 300 steps, or one episode and a few updates where an episode is longer (Meta-World's 500).
    steps = max(300, unified_manip.TASKS[task_id].max_episode_steps + 50)
    cli(*train_args(task_id, algo, steps, run_dir))
    status = json.loads((run_dir / "status.json").read_text())
    assert status["state"] == "finished" and status["num_timesteps"] >= steps
    config = yaml.safe_load((run_dir / "config.yaml").read_text())
    assert config["env"] == task_id and config["algo"] == algo
    assert config["env_kwargs"] == {"action_mode": mode_for(task_id), "reward_type": "sparse"}
    # The simulators' extras are recorded where installed: robosuite's beside MuJoCo 3.9,
    # Meta-World's (which pins MuJoCo 3.3.0) beside the oldest.
    extras = [extra for extra in ("robosuite", "metaworld") if not missing_modules(extra)]
    for package in (
        "python",
        "unified_manip",
        "mujoco",
        "gymnasium",
        "gymnasium-robotics",
        *extras,
        "stable-baselines3",
        "sb3-contrib",
        "torch",
    ):
        assert config["versions"][package] != "not installed"
    rows = monitor_rows(run_dir)
    assert rows and all(r["is_success"] in ("0.0", "1.0", "False", "True") for r in rows)
    evaluations = np.load(run_dir / "eval" / "evaluations.npz")
    assert len(evaluations["timesteps"]) >= 1 and evaluations["successes"].shape[1] == 2
    assert (run_dir / "best" / "best_model.zip").is_file()
    assert (run_dir / "final_model.zip").is_file()
    assert (run_dir / "replay_buffer.pkl").is_file() == ALGOS[algo].off_policy
    # The HER entries normalise observations (as the zoo does): the statistics travel
    # with the final and the best model.
    normalized = bool(config["hyperparameters"].get("normalize"))
    assert normalized == ALGOS[algo].her
    assert (run_dir / "vecnormalize.pkl").is_file() == normalized
    assert (run_dir / "best" / "vecnormalize.pkl").is_file() == normalized
    assert "rollout/success_rate" in tb_tags(run_dir)  # PPO too, which SB3 alone skips


# ---------------------------------------------------------------------- resume
def _wait_for_checkpoint(run_dir: Path, min_steps: int, proc: subprocess.Popen, timeout: float = 600) -> int:
    deadline = time.time() + timeout
    while time.time() < deadline:
        latest = checkpoints.newest(run_dir)
        if latest is not None and latest.step >= min_steps:
            return latest.step
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.2)
    raise AssertionError("no checkpoint appeared")


@pytest.mark.slow
@pytest.mark.parametrize("how", ["kill", "interrupt"])
def test_killed_run_resumes_step_count_and_replay_buffer(how, tmp_path):
    from stable_baselines3.common.save_util import load_from_pkl

    run_dir = tmp_path / "run"
    args = train_args(
        "UnifiedManip/Arm4Reach-v0",
        "sac_her",
        1000,
        run_dir,
        ["checkpoint_freq=200", "eval_freq=200", "n_eval_episodes=2"],
    )
    if how == "interrupt":  # Ctrl-C in a terminal reaches the env worker processes too
        args += ["--n-envs", "2", "--vec", "subproc"]
    # The child inherits this worker's signal dispositions; SIG_IGN for SIGINT (as after
    # a Ray test, or in a background job) must not stop train from handling Ctrl-C.
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        proc = subprocess.Popen(
            [sys.executable, "-m", "unified_manip.cli", *args],
            cwd=ROOT,
            start_new_session=True,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
    finally:
        signal.signal(signal.SIGINT, previous)
    checkpoint = _wait_for_checkpoint(run_dir, 400, proc)
    os.killpg(proc.pid, signal.SIGKILL if how == "kill" else signal.SIGINT)
    out, err = proc.communicate(timeout=300)
    status = json.loads((run_dir / "status.json").read_text())
    assert status["state"] == "running"  # recognised as unfinished
    if how == "interrupt":
        assert proc.returncode == 130, err
        assert "interrupted at step" in out and "Traceback" not in err, err
        written = checkpoints.newest(run_dir)
        checkpoint = written.step
        # Written where it is whole: the buffer holds every step the count includes (an
        # interrupt between SB3's count and its store once left it one transition short).
        assert written.digests[checkpoints.REPLAY_BUFFER]["rows"] * 2 == checkpoint == status["num_timesteps"]
    assert not (run_dir / "final_model.zip").exists()

    proc = subprocess.Popen(
        [sys.executable, "-m", "unified_manip.cli", *args],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    # Checkpoints keep the uninterrupted schedule (every 200 steps), whatever step the
    # run resumed from.
    assert _wait_for_checkpoint(run_dir, checkpoint + 1, proc) % 200 == 0
    out, err = proc.communicate(timeout=600)
    assert proc.returncode == 0, err
    assert f"resuming from step {checkpoint} of 1000" in out
    status = json.loads((run_dir / "status.json").read_text())
    assert status["state"] == "finished" and status["num_timesteps"] == 1000
    buffer = load_from_pkl(run_dir / "replay_buffer.pkl")
    # Restored transitions up to the checkpoint plus the ones collected after it.
    assert buffer.size() * buffer.n_envs == 1000
    # The observation statistics were restored too: they have seen every step, not
    # only the ones after the resume.
    stats = load_from_pkl(run_dir / "vecnormalize.pkl")
    assert stats.obs_rms["observation"].count >= 1000
    # So do the evaluations, the last one at the budget.
    assert np.load(run_dir / "eval" / "evaluations.npz")["timesteps"].tolist() == [200, 400, 600, 800, 1000]
    # A second run of the same command leaves the finished run alone.
    again = cli(*args)
    assert "already finished at 1000 steps" in again.stdout


# ---------------------------------------------------------------------- reproducibility
@pytest.mark.slow
def test_a_seed_trains_bit_for_bit_on_one_machine(tmp_path):
    """The same command twice, the benchmark's recipe shape (TQC+HER, parallel native envs,
    scripted demonstrations, observation normalisation): the same weights, evaluations and
    training episodes, to the bit. (Across CPU kinds the floats differ; see the README.)"""
    from stable_baselines3.common.save_util import load_from_zip_file

    extra = ["n_envs=2", "demonstrations=2", "learning_starts=100"]
    runs = [tmp_path / "a", tmp_path / "b", tmp_path / "other_seed"]
    for run_dir, seed in zip(runs, ["0", "0", "1"]):
        cli(*train_args("UnifiedManip/Arm4Push-v0", "tqc_her", 300, run_dir, extra), "--vec", "native", "--seed", seed)
    first, second, other = (
        load_from_zip_file(run_dir / "final_model.zip", device="cpu")[1]["policy"] for run_dir in runs
    )
    assert first.keys() == second.keys()
    assert all(np.array_equal(first[k].numpy(), second[k].numpy()) for k in first)
    assert not all(np.array_equal(first[k].numpy(), other[k].numpy()) for k in first)  # the check can fail
    evaluations = [np.load(run_dir / "eval" / "evaluations.npz") for run_dir in runs]
    assert np.array_equal(evaluations[0]["results"], evaluations[1]["results"])
    assert [(r["r"], r["l"]) for r in monitor_rows(runs[0])] == [(r["r"], r["l"]) for r in monitor_rows(runs[1])]


# ---------------------------------------------------------------------- eval
@pytest.fixture(scope="module")
def trained_run(tmp_path_factory) -> Path:
    run_dir = tmp_path_factory.mktemp("trained") / "run"
    cli(*train_args("UnifiedManip/Arm4Reach-v0", "sac_her", 300, run_dir))
    return run_dir


@pytest.mark.slow
def test_eval_reports_success_with_confidence_interval_and_video(trained_run, tmp_path):
    video = tmp_path / "episodes.gif"
    out = tmp_path / "eval.json"
    proc = cli("eval", str(trained_run), "--episodes", "6", "--video", str(video), "--json", str(out))
    result = json.loads(out.read_text())
    assert result["episodes"] == 6 and 0 <= result["successes"] <= 6
    assert result["ci_low"] <= result["success_rate"] <= result["ci_high"]
    assert result["ci_high"] - result["ci_low"] > 0.2  # 6 episodes cannot be precise
    assert f"{result['successes']}/6 episodes" in proc.stdout
    import imageio.v3 as iio

    frames = iio.imread(video, index=None)
    assert frames.shape[0] == 2 * (50 + 1) and frames.shape[-1] == 3


@pytest.mark.slow
def test_eval_in_another_action_mode_is_a_clear_error(trained_run):
    proc = cli("eval", str(trained_run), "--action-mode", "joint_torque", check=False)
    assert proc.returncode == 2
    assert proc.stderr.strip() == (
        "unified-manip eval: error: the model was trained with action_mode 'ee_delta'; it cannot be "
        "evaluated with action_mode 'joint_torque' (the actions mean different things)"
    )


# ---------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "args,message",
    [
        (
            ["--algo", "dqn"],
            "argument --algo: invalid choice: 'dqn' (choose from 'ppo', 'sac', 'td3', 'sac_her', 'tqc_her', 'crossq_her', 'bc')",
        ),
        (
            ["--env", "UnifiedManip/Nope-v0"],
            "argument --env: unknown task 'UnifiedManip/Nope-v0'; expected one of UnifiedManip/",
        ),
        (["--action-mode", "cartesian"], "argument --action-mode: invalid choice: 'cartesian'"),
        (["--reward-type", "shaped"], "argument --reward-type: invalid choice: 'shaped'"),
        (["--steps", "0"], "argument --steps: expected a positive integer, got '0'"),
        (["--steps", "-5"], "argument --steps: expected a positive integer, got '-5'"),
        (["--set", "learning_rate"], "malformed --set 'learning_rate'; expected key=value, e.g. learning_rate=0.0003"),
        (["--set", "learning_rate=fast"], "--set 'learning_rate=fast': learning_rate must be float, got str"),
        (["--set", "warp=9"], "unknown hyperparameter 'warp' in --set 'warp=9'; expected one of "),
    ],
)
def test_bad_train_input_is_one_line_exit_2(args, message, tmp_path):
    base = {"--env": "UnifiedManip/Arm4Reach-v0", "--algo": "sac", "--steps": "10", "--run-dir": str(tmp_path / "r")}
    for flag, value in zip(args[::2], args[1::2]):
        base[flag] = value
    argv = ["train", "--no-progress"] + [x for kv in base.items() for x in kv if kv[0] != "--set"]
    if "--set" in base:
        argv += ["--set", base["--set"]]
    proc = cli(*argv, check=False)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], proc.stderr
    assert not (tmp_path / "r").exists()


def test_unsupported_mode_for_task_names_the_valid_modes(tmp_path):
    hand = next((t for t, s in unified_manip.TASKS.items() if "ee_delta" not in s.action_modes), None)
    assert hand is not None, "expected a task without ee_delta (the Shadow Hand tasks)"
    proc = cli(
        "train",
        "--env",
        hand,
        "--action-mode",
        "ee_delta",
        "--algo",
        "sac",
        "--steps",
        "10",
        "--run-dir",
        str(tmp_path / "r"),
        check=False,
    )
    assert proc.returncode == 2
    expected = ", ".join(repr(m) for m in unified_manip.TASKS[hand].action_modes)
    # The env's own words (EnvConfig.require_supported), as gym.make says them.
    assert proc.stderr.strip().endswith(
        f"action_mode 'ee_delta' is not supported by {hand}; expected one of {expected}"
    )


def test_hyperparameter_files_resolve_with_anchors_and_literals_only():
    for algo in ALGOS:
        text = (ROOT / "baselines" / f"{algo}.yaml").read_text()
        assert "Source:" in text  # each file records where its values come from
        assert "dict(" not in text and "lambda " not in text and "!!python" not in text
        params = resolve(algo, "UnifiedManip/Arm4PickAndPlace-v0")
        assert params["policy"] == "MultiInputPolicy"
    # The anchor shares the CPU recipe (8 envs, net [256]*3) between Fetch and the arm's and
    # robosuite's object tasks, which add 100 scripted demonstrations (not in robosuite's
    # own controller, which no scripted policy plays).
    recipe = resolve("tqc_her", "UnifiedManip/FetchPush-v0")
    assert resolve("tqc_her", "UnifiedManip/Arm4Push-v0") == {**recipe, "demonstrations": 100}
    assert resolve("tqc_her", "UnifiedManip/Lift-v0", action_mode="joint_delta") == {**recipe, "demonstrations": 100}
    assert resolve("tqc_her", "UnifiedManip/Lift-v0", action_mode="native") == {
        **recipe,
        "demonstrations": 0,
        "learning_starts": 2000,
    }
    assert resolve("tqc_her", "UnifiedManip/Arm4Push-v0", ("demonstrations=0",))["demonstrations"] == 0
    assert recipe["policy_kwargs"] == {"net_arch": [256, 256, 256], "n_critics": 2}
    assert (recipe["n_envs"], recipe["gradient_steps"], recipe["batch_size"]) == (8, 2, 512)
    assert "n_envs" not in resolve("tqc_her", "UnifiedManip/FetchReach-v0")
    with pytest.raises(HyperparameterError, match="buffer_size must be int, got float"):
        resolve("sac", "UnifiedManip/Arm4Reach-v0", ("buffer_size=1.5",))
    assert resolve("sac", "UnifiedManip/Arm4Reach-v0", ("learning_rate=3e-4",))["learning_rate"] == 3e-4


@pytest.mark.parametrize("key", ["UnifiedManip/Lift-v9", "UnifiedManip/Lift-v0 nativ", "Lift-v0 native"])
def test_an_entry_that_names_no_task_or_mode_is_an_error(key, tmp_path):
    """A misspelt entry would otherwise be ignored and the default trained in its place."""
    (tmp_path / "sac.yaml").write_text(
        f"# Source: test\ndefault: {{policy: MultiInputPolicy}}\n'{key}': {{batch_size: 64}}\n"
    )
    with pytest.raises(HyperparameterError, match=f"sac.yaml:3: entry '{key}' names no registered task; expected "):
        resolve("sac", "UnifiedManip/Lift-v0", directory=tmp_path, action_mode="native")
    (tmp_path / "sac.yaml").write_text(
        "default: {policy: MultiInputPolicy}\n'UnifiedManip/Lift-v0 native': {batch_size: 64}\n"
    )
    assert resolve("sac", "UnifiedManip/Lift-v0", directory=tmp_path, action_mode="native")["batch_size"] == 64
    assert "batch_size" not in resolve("sac", "UnifiedManip/Lift-v0", directory=tmp_path, action_mode="ee_delta")


@pytest.mark.slow
@pytest.mark.parametrize("algo", list(ALGOS))
def test_the_shipped_entries_train_in_every_mode_of_every_id(algo):
    """No entry asks a mode for demonstrations its scripted policy cannot play (or asks a
    task without one), so ``train --algo ALGO`` works with the defaults on every ID x mode."""
    from unified_manip.training.algorithms import get_algo
    from unified_manip.training.demonstrations import check
    from unified_manip.training.hyperparams import check_her_warmup, resolve_run

    for task_id, spec in unified_manip.TASKS.items():
        for mode in spec.action_modes:
            resolved = resolve_run(algo, task_id, action_mode=mode)
            check(task_id, mode, get_algo(algo).off_policy, resolved.run.demos.demonstrations)
            check_her_warmup(algo, resolved.algo_kwargs, resolved.run, spec.max_episode_steps)


def test_her_training_that_would_start_before_any_episode_ends_is_one_line_exit_2(tmp_path):
    """8 envs x 200 steps of Stack-v0: HER has no finished episode to sample goals from
    before step 1600, and SB3 would stop the run there with a traceback."""
    args = [
        "train",
        "--env",
        "UnifiedManip/Stack-v0",
        "--action-mode",
        "ee_delta",
        "--algo",
        "tqc_her",
        "--steps",
        "10",
        "--no-progress",
        "--run-dir",
        str(tmp_path / "run"),
        "--set",
        "demonstrations=0",
    ]
    proc = cli(*args, check=False)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.strip() == (
        "unified-manip train: error: learning_starts=1000 starts training at step 1008, before the first episodes end "
        "at step 1600 (8 envs x 200 steps), and HER samples goals from finished episodes only; set learning_starts to "
        "1600 or more, or add demonstrations"
    )
    from unified_manip.training.hyperparams import check_her_warmup
    from unified_manip.training.settings import DemonstrationConfig, RunConfig

    eight = RunConfig(n_envs=8)
    check_her_warmup("tqc_her", {"learning_starts": 1592}, eight, 200)  # first update at step 1600: fine
    with pytest.raises(HyperparameterError, match="starts training at step 1592, before the first episodes end"):
        check_her_warmup("tqc_her", {"learning_starts": 1591}, eight, 200)
    demonstrated = RunConfig(n_envs=8, demos=DemonstrationConfig(demonstrations=1))
    check_her_warmup("tqc_her", {"learning_starts": 1000}, demonstrated, 200)  # finished episodes first
    check_her_warmup("sac", {"learning_starts": 0}, eight, 200)  # no HER


# ---------------------------------------------------------------------- rl-baselines3-zoo
@pytest.mark.slow
def test_rl_zoo3_trains_a_unified_manip_id(tmp_path):
    env = dict(os.environ)
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "rl_zoo3.train",
            "--gym-packages",
            "unified_manip",
            "--algo",
            "tqc",
            "--env",
            "UnifiedManip/FetchReach-v0",
            "--conf-file",
            str(ROOT / "baselines" / "zoo" / "tqc.yml"),
            "-n",
            "300",
            "--env-kwargs",
            "action_mode:'native'",
            "reward_type:'sparse'",
            "--hyperparams",
            "learning_starts:100",
            "--eval-freq",
            "-1",
            "--seed",
            "0",
            "--log-folder",
            str(tmp_path),
        ],
        capture_output=True,
        text=True,
        timeout=900,
        env=env,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    run = tmp_path / "tqc" / "UnifiedManip-FetchReach-v0_1"
    assert (run / "UnifiedManip-FetchReach-v0.zip").is_file()
    config = (run / "UnifiedManip-FetchReach-v0" / "args.yml").read_text()
    assert "action_mode" in config and "native" in config


# ---------------------------------------------------------------------- reward terms, n_envs
def _tiny_request(run_dir: Path, **kwargs):
    from unified_manip.training.train import TrainRequest

    settings = ("learning_starts=50", "batch_size=32", "eval_freq=150", "n_eval_episodes=1", "checkpoint_freq=1000")
    base = dict(
        env="UnifiedManip/Arm4Reach-v0",
        action_mode="ee_delta",
        reward_type="sparse",
        algo="sac",
        steps=300,
        run_dir=run_dir,
        overrides=settings,
    )
    return TrainRequest(**{**base, **kwargs})


@pytest.mark.slow
def test_training_logs_raw_reward_terms_beside_the_scaled_ones(tmp_path):
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    from unified_manip.training.train import train

    run_dir = tmp_path / "run"
    train(_tiny_request(run_dir, reward_type="dense_penalized"), progress=False, log=lambda msg: None)
    scalars: dict[str, dict[int, float]] = {}  # tag -> {step: value}
    for events in (run_dir / "tb").rglob("events.out.tfevents.*"):
        acc = EventAccumulator(str(events))
        acc.Reload()
        for tag in acc.Tags()["scalars"]:
            scalars.setdefault(tag, {}).update({e.step: e.value for e in acc.Scalars(tag)})
    spec = unified_manip.TASKS["UnifiedManip/Arm4Reach-v0"].terms.design("dense_penalized")
    for term in spec.terms:
        scaled, raw = scalars[f"reward_terms/{term.name}"], scalars[f"reward_terms_raw/{term.name}"]
        assert scaled.keys() == raw.keys() and len(scaled) >= 1
        for step in scaled:
            assert raw[step] * term.scale == pytest.approx(scaled[step], rel=1e-5, abs=1e-6)
    # Logged together, the episode totals of the scaled terms add up to SB3's episode return.
    common = set(scalars["rollout/ep_rew_mean"]).intersection(*(scalars[f"reward_terms/{t.name}"] for t in spec.terms))
    assert common
    for step in common:
        total = sum(scalars[f"reward_terms/{t.name}"][step] for t in spec.terms)
        assert total == pytest.approx(scalars["rollout/ep_rew_mean"][step], rel=1e-4, abs=1e-4)


def test_hyperparameter_file_n_envs_applies_unless_the_request_sets_it(tmp_path, monkeypatch):
    from unified_manip.training import hyperparams
    from unified_manip.training.train import train

    task = "UnifiedManip/Arm4Reach-v0"
    doc = yaml.safe_load((Path(hyperparams.DEFAULT_DIR) / "sac.yaml").read_text())
    doc[task] = {**(doc.get(task) or {}), "n_envs": 2}
    (tmp_path / "hp").mkdir()
    (tmp_path / "hp" / "sac.yaml").write_text(yaml.safe_dump(doc))
    monkeypatch.setattr(hyperparams, "DEFAULT_DIR", tmp_path / "hp")
    quiet = dict(progress=False, log=lambda msg: None)
    # Arm4Reach-v0 has a native vector env: its 2 envs are stepped (and monitored) as one;
    # one env is a DummyVecEnv of one Monitor-ed env.
    for run, n_envs, expected, monitors in (
        ("file", None, 2, ["native.monitor.csv"]),
        ("cli", 1, 1, ["0.monitor.csv"]),
    ):
        train(_tiny_request(tmp_path / run, steps=100, n_envs=n_envs), **quiet)
        config = yaml.safe_load((tmp_path / run / "config.yaml").read_text())
        assert config["n_envs"] == expected and "n_envs" not in config["hyperparameters"]
        assert sorted(p.name for p in (tmp_path / run / "monitor" / "seg0").glob("*.csv")) == monitors
    # The run resolves the same n_envs again: it is recognised as finished, not refused.
    assert train(_tiny_request(tmp_path / "file", steps=100), **quiet)["state"] == "finished"
    with pytest.raises(hyperparams.HyperparameterError) as err:
        hyperparams.resolve("sac", task, ("n_envs=0",))
    assert str(err.value) == "--set 'n_envs=0': n_envs must be an integer >= 1, got 0"


def test_torch_threads_follow_omp_num_threads_where_set(monkeypatch):
    """A user who sets OMP_NUM_THREADS=1 to train beside another run gets one torch thread
    (torch.set_num_threads would otherwise override it, and oversubscribed threads spin)."""
    from unified_manip.training.devices import default_threads

    monkeypatch.setenv("OMP_NUM_THREADS", "1")
    assert default_threads() == 1
    monkeypatch.setenv("OMP_NUM_THREADS", "3")
    assert default_threads() == 3
    monkeypatch.delenv("OMP_NUM_THREADS")
    # Unset: up to 2, never more than the machine has, and 1 where it cannot tell.
    for cores, threads in ((16, 2), (2, 2), (1, 1), (None, 1)):
        monkeypatch.setattr(os, "cpu_count", lambda cores=cores: cores)
        assert default_threads() == threads
