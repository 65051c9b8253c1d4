"""The observation design as a benchmark axis: ``train --observation``, a grid's
``observations:``, run names, ``config.yaml`` and ``results.csv``; ``eval`` under
observation noise and delay. Default designs keep today's run names."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest
import yaml
from conftest import TINY_GRID, cli_in_process, write_grid

from unified_manip.cli.main import main
from unified_manip.experiments.grid import GridError, load_grid, selected
from unified_manip.experiments.results import collect_row
from unified_manip.training.request import TrainRequest

ROOT = Path(__file__).resolve().parents[2]
REACH = "UnifiedManip/Arm4Reach-v0"


cli = cli_in_process


@pytest.mark.parametrize(
    "env_kwargs,name",
    [
        ({}, "Arm4Reach-v0__ee_delta__sparse__sac_her__s3"),
        ({"observation": "default"}, "Arm4Reach-v0__ee_delta__sparse__sac_her__s3"),
        ({"observation": "minimal"}, "Arm4Reach-v0__ee_delta__sparse__sac_her__obs-minimal__s3"),
        ({"observation": ["ee_pos", "goal_rel"]}, "Arm4Reach-v0__ee_delta__sparse__sac_her__obs-ee_pos+goal_rel__s3"),
        ({"observation_distractors": 32}, "Arm4Reach-v0__ee_delta__sparse__sac_her__obs-default+distractors32__s3"),
        (
            {"observation": "minimal", "observation_noise": 0.005, "observation_delay": 1},
            "Arm4Reach-v0__ee_delta__sparse__sac_her__obs-minimal+noise0.005+delay1__s3",
        ),
        (
            {"observation_noise": {"ee_pos": 0.01, "goal_rel": 0.0}},
            "Arm4Reach-v0__ee_delta__sparse__sac_her__obs-default+noise_ee_pos0.01__s3",
        ),
    ],
)
def test_run_names_carry_a_non_default_design(env_kwargs, name):
    req = TrainRequest(REACH, "ee_delta", "sparse", "sac_her", 100, seed=3, env_kwargs=env_kwargs)
    assert req.directory == Path("runs") / name


@pytest.mark.slow
def test_a_grid_crosses_observation_designs(tmp_path):
    distractors = {"observation": "default", "observation_distractors": 32}
    designs = ["default", "relative", ["ee_pos"], distractors]
    doc = {**TINY_GRID, "action_modes": ["ee_delta"], "seeds": [0], "observations": designs}
    grid = load_grid(write_grid(tmp_path, doc))
    assert [(r.name, r.env_kwargs) for r in grid.runs] == [
        ("Arm4Reach-v0__ee_delta__sparse__sac_her__s0", {}),
        ("Arm4Reach-v0__ee_delta__sparse__sac_her__obs-relative__s0", {"observation": "relative"}),
        ("Arm4Reach-v0__ee_delta__sparse__sac_her__obs-ee_pos__s0", {"observation": ["ee_pos"]}),
        ("Arm4Reach-v0__ee_delta__sparse__sac_her__obs-default+distractors32__s0", {"observation_distractors": 32}),
    ]
    # bench --only picks designs by their run-name label.
    assert selected(grid, ("observation=default", "observation=default+distractors32")) == {
        "Arm4Reach-v0__ee_delta__sparse__sac_her__s0",
        "Arm4Reach-v0__ee_delta__sparse__sac_her__obs-default+distractors32__s0",
    }


@pytest.mark.parametrize(
    "observations,message",
    [
        (
            ["minimal", ["object_pos"]],
            "observation group 'object_pos' is not available on UnifiedManip/Arm4Reach-v0; expected some of "
            "'joint_pos', 'gripper', 'joint_vel', 'gripper_vel', 'ee_pos', 'ee_vel', 'goal_rel'",
        ),
        (
            ["tiny"],
            "unknown observation preset 'tiny'; expected one of 'default', 'minimal', 'relative', 'full' or a list "
            "of groups of UnifiedManip/Arm4Reach-v0 ('joint_pos', 'gripper', 'joint_vel', 'gripper_vel', "
            "'ee_pos', 'ee_vel', 'goal_rel')",
        ),
        (
            "minimal",
            "observations must be a non-empty list of presets (default, minimal, relative, full), lists of group "
            "names or mappings with keys from observation, observation_distractors, observation_noise, "
            "observation_delay, got 'minimal'",
        ),
        (
            ["minimal", {"observation": "minimal", "observation_lag": 1}],
            "unknown key 'observation_lag' in observations; expected observation, observation_distractors, "
            "observation_noise, observation_delay",
        ),
        (
            ["minimal", ["minimal"]],
            "observation design 'minimal' is listed twice",
        ),
        (
            [{"observation": "default", "observation_distractors": -2}],
            "observation_distractors must be an int >= 0, got -2",
        ),
    ],
)
def test_a_grid_with_a_bad_design_fails_in_one_line(tmp_path, observations, message):
    path = write_grid(tmp_path, {**TINY_GRID, "observations": observations})
    with pytest.raises(GridError) as err:
        load_grid(path)
    assert str(err.value) == f"{path}: {message}"


@pytest.mark.slow
def test_train_observation_then_eval_under_noise_and_delay(tmp_path, capsys):
    """In this process (``main``), as a user's shell would run each command."""

    def cli(*args: str) -> subprocess.CompletedProcess:
        try:
            code = main(list(args))
        except SystemExit as exit_:
            code = exit_.code
        out = capsys.readouterr()
        return subprocess.CompletedProcess(args, code or 0, out.out, out.err)

    run_dir = tmp_path / "run"
    sets = ["learning_starts=50", "batch_size=32", "policy_kwargs.net_arch=[16,16]", "eval_freq=100"]
    args = ["train", "--env", REACH, "--action-mode", "ee_delta", "--algo", "sac_her", "--steps", "100"]
    proc = cli(*args, "--run-dir", str(run_dir), "--observation", "ee_pos,goal_rel", "--no-progress",
               *[x for s in sets for x in ("--set", s)])  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    config = yaml.safe_load((run_dir / "config.yaml").read_text())
    assert config["env_kwargs"]["observation"] == ["ee_pos", "goal_rel"]
    assert collect_row(run_dir)["observation"] == "ee_pos+goal_rel"
    results = {}
    for extra in ((), ("--observation-noise", "0.01"), ("--observation-delay", "1")):
        out = tmp_path / f"eval{len(results)}.json"
        proc = cli("eval", str(run_dir), "--episodes", "2", "--reward-type", "dense", "--json", str(out), *extra)
        assert proc.returncode == 0, proc.stderr
        results[extra] = json.loads(out.read_text())
    returns = [r["mean_return"] for r in results.values()]  # dense: the actions, and so the returns, differ
    assert returns[0] != returns[1] and returns[0] != returns[2]
    for extra, message in (
        (("--observation-noise", "-0.5"), "--observation-noise must be a standard deviation >= 0, got -0.5"),
        (("--observation-delay", "-1"), "--observation-delay must be an int >= 0, got -1"),
    ):
        proc = cli("eval", str(run_dir), "--episodes", "2", *extra)
        assert proc.returncode == 2
        assert proc.stderr.strip().splitlines()[-1].endswith(message), proc.stderr
        assert "Traceback" not in proc.stderr
    bad = cli(*args, "--run-dir", str(tmp_path / "bad"), "--observation", "object_pos")
    assert bad.returncode == 2 and "Traceback" not in bad.stderr
    assert "observation group 'object_pos' is not available on UnifiedManip/Arm4Reach-v0" in bad.stderr


@pytest.mark.slow
def test_robustness_evaluates_final_policies_resumes_and_reports(tmp_path, capsys):
    """``unified-manip robustness``: every finished run's final model under each noise and
    delay, one row each in robustness.csv; a second pass adds nothing; the report shows it."""
    from unified_manip.experiments.report import build_report
    from unified_manip.experiments.results import write_results
    from unified_manip.experiments.robustness import read_robustness

    bench = tmp_path / "bench"
    run_dir = bench / "runs" / "Arm4Reach-v0__ee_delta__sparse__sac_her__obs-relative__s0"
    sets = ["learning_starts=50", "batch_size=32", "policy_kwargs.net_arch=[16,16]", "eval_freq=100"]
    args = ["train", "--env", REACH, "--action-mode", "ee_delta", "--algo", "sac_her", "--steps", "100"]
    assert main([*args, "--run-dir", str(run_dir), "--observation", "relative", "--no-progress",
                 *[x for s in sets for x in ("--set", s)]]) == 0  # fmt: skip
    write_results(bench, [collect_row(run_dir)])
    command = ["robustness", str(bench), "--noise", "0", "0.01", "--delay", "1", "--episodes", "3"]
    assert main(command) == 0
    assert "[3/3] Arm4Reach-v0__ee_delta__sparse__sac_her__obs-relative__s0: delay 1" in capsys.readouterr().err
    rows = read_robustness(bench / "robustness.csv")
    assert [(r["noise"], r["delay"], r["episodes"], r["observation"]) for r in rows] == [
        (0.0, 0, 3, "relative"),
        (0.01, 0, 3, "relative"),
        (0.0, 1, 3, "relative"),
    ]
    # Noise 0 is the final policy's plain evaluation, as eval gives it.
    plain = tmp_path / "plain.json"
    assert main(["eval", str(run_dir / "final_model.zip"), "--episodes", "3", "--json", str(plain)]) == 0
    assert json.loads(plain.read_text())["successes"] == rows[0]["successes"]
    before = (bench / "robustness.csv").read_bytes()
    assert main(command) == 0  # everything done: resumes to nothing
    assert (bench / "robustness.csv").read_bytes() == before
    assert "]" not in capsys.readouterr().err
    text = build_report(bench / "results.csv", bench / "report", command="r", dense_check=False).read_text()
    section = text[text.index("## Robustness of the final policies") :]
    assert "| observation design | mode | noise 0 | noise 0.01 | delay 1 |" in section
    assert f"| relative | ee_delta | {rows[0]['success_rate']:.2f} |" in section
    assert (bench / "report" / "Arm4Reach-v0_robustness.png").stat().st_size > 10_000


@pytest.mark.parametrize(
    "setup,message",
    [
        (lambda b: None, "has no runs/ directory; expected a bench's output directory"),
        (lambda b: (b / "runs").mkdir(), "holds no finished run"),
    ],
)
def test_robustness_refuses_what_it_cannot_evaluate_in_one_line(tmp_path, capsys, setup, message):
    bench = tmp_path / "bench"
    bench.mkdir()
    setup(bench)
    with pytest.raises(SystemExit) as exit_:
        main(["robustness", str(bench)])
    assert exit_.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].endswith(message), err


def test_committed_results_without_models_are_refused():
    from unified_manip.experiments.robustness import RobustnessError, evaluate_bench

    with pytest.raises(RobustnessError, match=r"has no final_model.zip \(committed results carry no models\)"):
        evaluate_bench(ROOT / "results" / "pixels_arm4reach", [])
