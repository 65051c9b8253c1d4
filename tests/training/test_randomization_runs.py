"""Domain randomisation in training, evaluation and benchmarks: ``train --randomization``,
``eval`` and ``robustness`` on the test distributions (default, in-range, extreme), a
grid's ``randomizations:`` axis, run names, ``config.yaml``, ``results.csv`` and the
report. Nominal runs keep every name and file they had before randomisation."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml
from conftest import write_grid

from unified_manip.cli.main import build_parser, main
from unified_manip.experiments.grid import GridError, load_grid, selected
from unified_manip.experiments.report import build_report
from unified_manip.experiments.results import collect_row, read_results, write_results
from unified_manip.experiments.robustness import read_robustness
from unified_manip.training.evaluation import evaluated_randomization
from unified_manip.training.request import TrainError

ROOT = Path(__file__).resolve().parents[2]
REACH = "UnifiedManip/Arm4Reach-v0"
NAME = "Arm4Reach-v0__ee_delta__sparse__sac_her__rand-dynamics__s0"
SETS = [
    "learning_starts=250",
    "batch_size=32",
    "buffer_size=1000",
    "eval_freq=300",
    "n_eval_episodes=1",
    "policy_kwargs.net_arch=[16,16]",
]
GRID = {"tasks": [REACH], "action_modes": ["ee_delta"], "reward_types": ["sparse"], "algos": ["sac_her"]}


@pytest.fixture(scope="module")
def bench(tmp_path_factory) -> Path:
    """A bench directory holding one 300-step run trained under ``dynamics``, by its
    default name (train run from the bench directory)."""
    import contextlib

    bench = tmp_path_factory.mktemp("bench")
    train = ["train", "--env", REACH, "--action-mode", "ee_delta", "--algo", "sac_her", "--steps", "300"]
    with contextlib.chdir(bench):
        assert (
            main([*train, "--randomization", "dynamics", "--no-progress", *[a for s in SETS for a in ("--set", s)]])
            == 0
        )
    write_results(bench, [collect_row(bench / "runs" / NAME)])
    return bench


def test_train_records_the_preset_in_config_yaml_and_the_run_name(bench):
    config = yaml.safe_load((bench / "runs" / NAME / "config.yaml").read_text())
    assert config["env_kwargs"] == {"action_mode": "ee_delta", "reward_type": "sparse", "randomization": "dynamics"}
    [row] = read_results(bench / "results.csv")
    assert (row["run"], row["randomization"]) == (NAME, "dynamics")


def test_eval_runs_a_test_distribution_of_the_training_preset(bench, tmp_path):
    """default is the nominal task and extreme the preset's ``:extreme`` counterpart; the
    worlds differ, so a dense reward's return over the same seed differs too."""
    results = {}
    for distribution in ("default", "extreme"):
        out = tmp_path / f"{distribution}.json"
        argv = ["eval", str(bench / "runs" / NAME), "--episodes", "1", "--reward-type", "dense"]
        assert main([*argv, "--test-distribution", distribution, "--json", str(out)]) == 0
        results[distribution] = json.loads(out.read_text())
    assert [(r["randomization"], r["test_distribution"]) for r in results.values()] == [
        ("none", "default"),
        ("dynamics:extreme", "extreme"),
    ]
    assert results["default"]["mean_return"] != results["extreme"]["mean_return"]


def test_robustness_writes_a_row_per_distribution_and_the_report_shows_the_gap(bench, capsys):
    command = ["robustness", str(bench), "--test-distribution", "default", "in-range", "extreme", "--episodes", "1"]
    assert main(command) == 0
    rows = read_robustness(bench / "robustness.csv")
    assert [
        (r["randomization"], r["distribution"], r["tested"], r["noise"], r["delay"], r["episodes"]) for r in rows
    ] == [
        ("dynamics", "default", "none", 0.0, 0, 1),
        ("dynamics", "in-range", "dynamics", 0.0, 0, 1),
        ("dynamics", "extreme", "dynamics:extreme", 0.0, 0, 1),
    ]
    before = (bench / "robustness.csv").read_bytes()
    assert main(command) == 0  # every condition done: nothing is evaluated again
    assert (bench / "robustness.csv").read_bytes() == before
    text = build_report(bench / "results.csv", bench / "report", command="r", dense_check=False).read_text()
    assert "| task | algo | action mode | reward | randomization | seeds |" in text
    assert "| Arm4Reach-v0 | sac_her | ee_delta | sparse | dynamics | 1 |" in text
    success = {r["distribution"]: r["success_rate"] for r in rows}
    gaps = [success["default"] - success[d] for d in ("in-range", "extreme")]
    assert f"| Arm4Reach-v0 | default | ee_delta | dynamics | 1 | {gaps[0]:+.2f} | {gaps[1]:+.2f} |" in text
    assert "| observation design | mode | randomization | default | in-range | extreme |" in text


def test_robustness_factors_tests_each_term_alone_and_the_report_ranks_their_drops(bench, tmp_path, capsys):
    """``--factors``: each term of a shifted distribution that applies to the run's task,
    alone, one row each beside the distribution as a whole; resumable; the report's
    section gives each factor's drop from ``default``, and its figure."""
    import shutil

    copy = tmp_path / "bench"
    shutil.copytree(bench, copy)
    (copy / "robustness.csv").unlink(missing_ok=True)  # another test's rows
    command = ["robustness", str(copy), "--test-distribution", "default", "extreme", "--factors", "--episodes", "2",
               "--only", "action_mode=ee_delta", "--only", "randomization=dynamics"]  # fmt: skip
    assert main(command) == 0
    rows = read_robustness(copy / "robustness.csv")
    assert [(r["distribution"], r["tested"], r["factor"]) for r in rows] == [
        ("default", "none", ""),
        ("extreme", "dynamics:extreme", ""),
        ("extreme", "dynamics:extreme", "robot.actuator_gain"),
        ("extreme", "dynamics:extreme", "robot.armature"),
        ("extreme", "dynamics:extreme", "robot.damping"),
        ("extreme", "dynamics:extreme", "table.friction"),
    ]
    assert "extreme: robot.damping only" in capsys.readouterr().err
    before = (copy / "robustness.csv").read_bytes()
    assert main(command) == 0  # resumes to nothing
    assert (copy / "robustness.csv").read_bytes() == before
    text = build_report(copy / "results.csv", copy / "report", command="r", dense_check=False).read_text()
    section = text[text.index("## One factor at a time") :]
    default = rows[0]["success_rate"]
    for r in rows[1:]:
        factor = r["factor"] or "all together"
        assert f"| default | ee_delta | dynamics | 1 | {factor} | — | {default - r['success_rate']:+.2f} |" in section
    assert (copy / "report" / "Arm4Reach-v0_factors.png").stat().st_size > 10_000
    # The factor rows stay out of the whole-distribution table and the generalisation gap.
    assert "| observation design | mode | randomization | default | extreme |" in text


@pytest.mark.parametrize(
    "extra,message",
    [
        (["--test-distribution", "default", "--factors"],
         "--factors needs --test-distribution in-range or extreme (the ranges it shifts)"),
        (["--only", "action_mode=joint_delta"], "--only action_mode=joint_delta selects none of the finished runs in"),
        (["--only", "mode=ee_delta"], "malformed --only 'mode=ee_delta'; expected KEY=VALUE with KEY one of task, "
         "action_mode, reward_type, algo, seed, observation, randomization"),
    ],
)  # fmt: skip
def test_robustness_refuses_bad_factors_and_selections_in_one_line(bench, capsys, extra, message):
    with pytest.raises(SystemExit) as exit_:
        main(["robustness", str(bench), *extra])
    assert exit_.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0], err


def test_a_grid_expands_its_randomizations_axis(tmp_path):
    grid = load_grid(write_grid(tmp_path, {**GRID, "seeds": [0], "steps": 100, "randomizations": ["none", "dynamics"]}))
    assert [(r.name, r.randomization, r.env_kwargs) for r in grid.runs] == [
        ("Arm4Reach-v0__ee_delta__sparse__sac_her__s0", "none", {}),
        ("Arm4Reach-v0__ee_delta__sparse__sac_her__rand-dynamics__s0", "dynamics", {"randomization": "dynamics"}),
    ]
    assert selected(grid, ("randomization=dynamics",)) == {grid.runs[1].name}


@pytest.mark.parametrize(
    "change,message",
    [
        ({"randomizations": ["windy"]}, "unknown randomization preset 'windy'; expected one of 'none', 'dynamics'"),
        ({"randomizations": ["dynamics", "dynamics"]}, "randomization 'dynamics' is listed twice"),
        ({"randomizations": "dynamics"}, "randomizations must be a non-empty list of randomization presets"),
        ({"randomizations": ["objects"]}, "randomization 'objects' has no term that applies to UnifiedManip/Arm4Reach"),
        (
            {"randomizations": ["dynamics"], "env_kwargs": {"randomization": "visual"}},
            "randomization is set in both env_kwargs and randomizations",
        ),
    ],
)
def test_a_bad_randomizations_axis_is_refused_before_any_run(change, message, tmp_path):
    with pytest.raises(GridError, match=message):
        load_grid(write_grid(tmp_path, {**GRID, "seeds": [0], "steps": 100, **change}))


def test_committed_results_keep_their_names_and_read_their_grids_randomization():
    """Every committed results.csv reads with ``randomization`` none unless its grid has a
    ``randomizations:`` axis, then with one of that axis's values; each of its runs is still
    named as run names are made now (the name a grid gives it)."""
    from unified_manip.training.request import run_name

    studies = 0
    for results in sorted(ROOT.glob("results/*/results.csv")):
        grid = (
            yaml.safe_load((results.parent / "grid.yaml").read_text())
            if (results.parent / "grid.yaml").exists()
            else {}
        )
        allowed = set(grid.get("randomizations", ["none"]))
        studies += "randomizations" in grid
        for r in read_results(results):
            assert r["randomization"] in allowed, results
            keys = ("task", "action_mode", "reward_type", "algo", "seed", "observation", "randomization")
            assert run_name(*(r[k] for k in keys)) == r["run"], results
    assert studies >= 1, "the randomisation study's results are committed"


def test_the_robustness_figure_pairs_each_mode_with_and_without_randomised_training():
    """With runs trained nominal and randomised, the figure has a panel per action mode, a
    line per training (the committed study); without, one panel with a line per design."""
    from unified_manip.experiments.robustness_report import _cells, figure_panels

    cells, _, _ = _cells([r for r in read_robustness(ROOT / "results/randomization_modes/robustness.csv")
                          if not r["factor"]])  # fmt: skip
    panels = figure_panels(cells["UnifiedManip/Arm4PickAndPlace-v0"])
    modes = ["ee_delta", "ee_target_delta", "joint_delta", "joint_target_delta"]
    assert [title for title, _ in panels] == modes
    for mode, (_, lines) in zip(modes, panels):
        assert [(key, label) for key, label, _ in lines] == [
            (("default", mode, "none"), "trained nominal"),
            (("default", mode, "dynamics+objects"), "trained under dynamics+objects"),
        ]
    cells, _, _ = _cells(read_robustness(ROOT / "results/observation_designs/robustness.csv"))
    ((title, lines),) = figure_panels(cells["UnifiedManip/FetchPush-v0"])
    assert title == "" and [label for _, label, _ in lines] == [
        "native, default", "native, default+distractors32", "native, full", "native, minimal", "native, relative"
    ]  # fmt: skip


def test_train_with_randomization_none_is_the_run_it_was_before():
    """``--randomization none`` adds nothing to env_kwargs or the name, so a run directory
    from before randomisation resumes under it."""
    from unified_manip.cli.runs import _train_env_kwargs
    from unified_manip.training.request import TrainRequest

    argv = ["train", "--env", REACH, "--algo", "sac_her", "--steps", "10", "--action-mode", "ee_delta"]
    for extra, kwargs in (
        ([], {}),
        (["--randomization", "none"], {}),
        (["--randomization", "all"], {"randomization": "all"}),
    ):
        args = build_parser().parse_args([*argv, *extra])
        assert _train_env_kwargs(args) == kwargs
    request = TrainRequest(env=REACH, action_mode="ee_delta", reward_type="sparse", algo="sac_her", steps=10)
    assert request.directory.name == "Arm4Reach-v0__ee_delta__sparse__sac_her__s0"


def test_the_evaluated_randomization_of_each_distribution():
    assert evaluated_randomization(None, None, None) == "none"  # a run from before randomisation
    assert evaluated_randomization("objects", None, None) == "objects"  # the run's own
    assert evaluated_randomization("none", "dynamics+objects", "extreme") == "dynamics:extreme+objects:extreme"
    assert evaluated_randomization("objects", "visual:extreme", None) == "visual:extreme"
    assert (
        evaluated_randomization([{"entity": "object", "field": "mass", "range": (0.5, 2)}], None, "default") == "none"
    )
    for trained in (None, [{"entity": "object", "field": "mass", "range": (0.5, 2)}]):
        with pytest.raises(TrainError, match="--test-distribution in-range takes its ranges from a preset"):
            evaluated_randomization(trained, None, "in-range")
