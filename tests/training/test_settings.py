"""Run settings (:mod:`unified_manip.training.settings`): one typed, self-validating
:class:`RunConfig`, one name and one default per setting, from the hyperparameter file
through config.yaml, demonstrations.json and results.csv to the report; old run
directories and every committed result still read."""

from __future__ import annotations

import dataclasses
import json
import re
from pathlib import Path

import pytest
import yaml
from conftest import COMMITTED_GRIDS, extra_marks, interrupt_after_first_checkpoint, resume_to_the_end
from test_pretrain import _request as demonstrated_request

from unified_manip.envs.task_lists import expand_task_lists
from unified_manip.experiments.grid import GridError, load_grid
from unified_manip.experiments.report import _demonstrations_line, build_report
from unified_manip.experiments.report import _demonstrations_lines as report_demonstration_lines
from unified_manip.experiments.results import collect_row, read_results, write_results
from unified_manip.training import rundir
from unified_manip.training.hyperparams import HyperparameterError, resolve, resolve_run
from unified_manip.training.settings import (
    KEYS,
    CloningLossConfig,
    DemonstrationConfig,
    OfflineConfig,
    RunConfig,
    RunConfigError,
    demonstration_record,
)
from unified_manip.training.train import train

ROOT = Path(__file__).resolve().parents[2]
COMMITTED = sorted((ROOT / "results").glob("*/results.csv"))


# ---------------------------------------------------------------------- the config itself
def test_the_defaults_are_stated_once_and_read_flat():
    assert RunConfig().to_mapping() == {
        "eval_freq": 10_000,
        "n_eval_episodes": 20,
        "checkpoint_freq": 10_000,
        "action_noise_std": None,
        "normalize": False,
        "device": "auto",
        "n_envs": 1,
        "relabel_goal_rel": True,
        "compile_loss": False,
        "demonstrations": 0,
        "bc_steps": 0,
        "bc_weight": 0.0,
        "bc_q_filter": True,
        "bc_sampled": False,
        "offline_steps": 0,
    }
    assert set(KEYS) == set(RunConfig().to_mapping())
    run = RunConfig.from_mapping({"demonstrations": 100, "bc_weight": 2.5, "offline_steps": 7, "gamma": 0.95})
    assert run.demos == DemonstrationConfig(demonstrations=100)
    assert run.cloning_loss == CloningLossConfig(bc_weight=2.5)
    assert run.offline == OfflineConfig(offline_steps=7)
    with pytest.raises(dataclasses.FrozenInstanceError):
        run.n_envs = 2  # type: ignore[misc]


@pytest.mark.parametrize(
    "key,value,message",
    [
        ("eval_freq", 0, "eval_freq must be an integer >= 1, got 0"),
        ("n_eval_episodes", 2.5, "n_eval_episodes must be an integer >= 1, got 2.5"),
        ("checkpoint_freq", True, "checkpoint_freq must be an integer >= 1, got True"),
        ("action_noise_std", -0.1, "action_noise_std must be a number >= 0 or null, got -0.1"),
        ("normalize", "yes", "normalize must be true or false, got 'yes'"),
        ("device", "gpu", "device must be one of auto, cpu, cuda, got 'gpu'"),
        ("n_envs", 0, "n_envs must be an integer >= 1, got 0"),
        ("relabel_goal_rel", "yes", "relabel_goal_rel must be true or false, got 'yes'"),
        ("demonstrations", -1, "demonstrations must be an integer >= 0 or a dataset path, got -1"),
        ("bc_steps", -1, "bc_steps must be an integer >= 0, got -1"),
        ("bc_weight", "x", "bc_weight must be a number >= 0, got 'x'"),
        ("bc_weight", float("nan"), "bc_weight must be a number >= 0, got nan"),
        ("bc_q_filter", 1, "bc_q_filter must be true or false, got 1"),
        ("bc_sampled", None, "bc_sampled must be true or false, got None"),
        ("offline_steps", -1, "offline_steps must be an integer >= 0, got -1"),
    ],
)
def test_a_bad_setting_is_refused_in_one_line_naming_it(key, value, message):
    with pytest.raises(RunConfigError) as err:
        RunConfig.from_mapping({key: value})
    assert str(err.value) == message


def test_a_nested_config_of_the_wrong_kind_is_refused():
    with pytest.raises(RunConfigError) as err:
        RunConfig(demos={"demonstrations": 5})  # type: ignore[arg-type]
    assert str(err.value) == "demos must be a DemonstrationConfig, got {'demonstrations': 5}"


# ---------------------------------------------------------------------- built once, errors name where
def test_resolve_run_splits_the_run_settings_from_the_algorithm():
    resolved = resolve_run("tqc_her", "UnifiedManip/Arm4Push-v0", ("bc_weight=2.5", "gamma=0.9"))
    assert resolved.run.demos.demonstrations == 100 and resolved.run.cloning_loss.bc_weight == 2.5
    assert resolved.run.n_envs == 8 and resolved.run.normalize is True
    assert resolved.algo_kwargs["gamma"] == 0.9
    assert not set(resolved.algo_kwargs) & set(KEYS)
    assert resolved.hyperparameters == resolve("tqc_her", "UnifiedManip/Arm4Push-v0", ("bc_weight=2.5", "gamma=0.9"))


def _file(tmp_path: Path, text: str) -> Path:
    (tmp_path / "tqc_her.yaml").write_text(text)
    return tmp_path


@pytest.mark.parametrize(
    "text,overrides,message",
    [
        (
            "default: {policy: MultiInputPolicy}\nUnifiedManip/Lift-v0: {bc_weight: x}\n",
            (),
            "{d}/tqc_her.yaml: UnifiedManip/Lift-v0: bc_weight must be a number >= 0, got 'x'",
        ),
        (
            "default: {policy: MultiInputPolicy, eval_freq: 0}\n",
            (),
            "{d}/tqc_her.yaml: default: eval_freq must be an integer >= 1, got 0",
        ),
        (
            "default: {policy: MultiInputPolicy}\n'UnifiedManip/Lift-v0 joint_delta': {bc_q_filter: maybe}\n",
            (),
            "{d}/tqc_her.yaml: UnifiedManip/Lift-v0 joint_delta: bc_q_filter must be true or false, got 'maybe'",
        ),
        (
            "default: {policy: MultiInputPolicy}\n",
            ("bc_weight=x",),
            "--set 'bc_weight=x': bc_weight must be a number >= 0, got 'x'",
        ),
        (
            "default: {policy: MultiInputPolicy}\n",
            ("offline_steps=-3",),
            "--set 'offline_steps=-3': offline_steps must be an integer >= 0, got -3",
        ),
    ],
)
def test_a_bad_setting_names_the_file_the_entry_and_the_key(tmp_path, text, overrides, message):
    directory = _file(tmp_path, text)
    with pytest.raises(HyperparameterError) as err:
        resolve_run("tqc_her", "UnifiedManip/Lift-v0", overrides, directory, action_mode="joint_delta")
    assert str(err.value) == message.replace("{d}", str(directory))


def test_a_grid_override_of_a_bad_setting_names_the_grid(tmp_path):
    grid = {
        "tasks": ["UnifiedManip/Arm4Reach-v0"],
        "action_modes": ["ee_delta"],
        "reward_types": ["sparse"],
        "algos": ["sac_her"],
        "seeds": [0],
        "steps": 200,
        "overrides": {"sac_her": ["learning_starts=100", "bc_sampled=often"]},
    }
    path = tmp_path / "grid.yaml"
    path.write_text(yaml.safe_dump(grid))
    with pytest.raises(GridError) as err:
        load_grid(path)
    assert str(err.value) == f"{path}: --set 'bc_sampled=often': bc_sampled must be true or false, got 'often'"


def _grids(paths: list[Path], name) -> list:
    """Grid files as parameters, with the markers of their tasks' extras: reading a grid
    builds one backend of each of its tasks (``check_design``)."""
    params = []
    for path in paths:
        tasks = expand_task_lists(yaml.safe_load(path.read_text()).get("tasks") or [])  # metaworld:MT10
        marks = {m.name: m for t in tasks for m in extra_marks(t)}
        params.append(pytest.param(path, marks=list(marks.values()), id=name(path)))
    return params


@pytest.mark.parametrize("path", _grids(COMMITTED_GRIDS, lambda p: p.stem))
def test_every_committed_grid_still_reads(path):
    assert load_grid(path).runs


@pytest.mark.parametrize("path", _grids(sorted(ROOT.glob("results/*/grid.yaml")), lambda p: p.parent.name))
def test_every_committed_experiment_reads_without_its_datasets(path, tmp_path, monkeypatch):
    """A clean clone has no demonstration datasets (data/ is not committed): the grid of an
    experiment trained elsewhere still reads, for its report and headline."""
    monkeypatch.chdir(tmp_path)
    assert load_grid(path, datasets=False).runs


def test_a_grid_naming_a_missing_dataset_is_refused_unless_its_runs_are_done(tmp_path):
    grid = {
        "tasks": ["UnifiedManip/Arm4PickAndPlace-v0"],
        "action_modes": ["ee_delta"],
        "reward_types": ["sparse"],
        "algos": ["tqc_her"],
        "seeds": [0],
        "steps": 2000,
        "overrides": {"tqc_her": [f"demonstrations={tmp_path}/none/{{task}}/{{action_mode}}-v0"]},
    }
    path = tmp_path / "grid.yaml"
    path.write_text(yaml.safe_dump(grid))
    with pytest.raises(GridError, match=r"none/Arm4PickAndPlace-v0/ee_delta-v0 is not a dataset"):
        load_grid(path)
    [run] = load_grid(path, datasets=False).runs
    assert f"demonstrations={tmp_path}/none/{{task}}/{{action_mode}}-v0" in run.overrides


# ---------------------------------------------------------------------- config.yaml and demonstrations.json
def test_the_settings_round_trip_through_config_yaml(tmp_path):
    """What train ran with is what its config.yaml reads back as (n_envs and device: the
    ones it ran with), and a resume of the same settings is the same run."""
    run_dir = tmp_path / "run"
    request = demonstrated_request(run_dir, bc_steps=0, bc_weight=1.5, bc_q_filter=False)
    assert train(request, progress=False, threads=1, log=lambda msg: None)["state"] == "finished"
    config = rundir.read_config(run_dir)
    run, algo_kwargs = rundir.run_settings(run_dir, config)
    expected = resolve_run(request.algo, request.env, request.overrides, action_mode=request.action_mode)
    assert run == dataclasses.replace(expected.run, device="cpu")
    assert algo_kwargs == expected.algo_kwargs
    assert RunConfig.from_mapping(yaml.safe_load(yaml.safe_dump(run.to_mapping()))) == run
    record = json.loads((run_dir / "demonstrations.json").read_text())
    assert {
        k: record[k] for k in ("demonstrations", "bc_steps", "bc_weight", "bc_q_filter", "bc_sampled", "offline_steps")
    } == {
        "demonstrations": 2,
        "bc_steps": 0,
        "bc_weight": 1.5,
        "bc_q_filter": False,
        "bc_sampled": False,
        "offline_steps": 0,
    }


#: How runs recorded before the settings had one name wrote demonstrations.json.
def _to_old_format(record: dict) -> dict:
    old = {k: record[k] for k in ("episodes", "transitions", "success")}
    if record["bc_steps"]:
        old["behaviour_cloning"] = {"steps": record["bc_steps"], **record["behaviour_cloning"]}
    if record["bc_weight"]:
        old["cloning_loss_weight"] = record["bc_weight"]
        old["cloning_loss_q_filter"] = record["bc_q_filter"]
        if record["bc_sampled"]:
            old["cloning_loss_sampled"] = True
    return old


def test_an_old_format_run_directory_resumes_and_reports_the_same(tmp_path):
    """A run interrupted with demonstrations.json in the old names (cloning_loss_weight,
    behaviour_cloning.steps) resumes (the cloning loss reads the record again), and its
    results row reports what it was given."""
    run_dir = tmp_path / "runs" / "run"
    request = demonstrated_request(run_dir, bc_steps=20, bc_weight=2.5, eval_freq=100)
    interrupt_after_first_checkpoint(run_dir, lambda: train(request, progress=False, threads=1, log=lambda m: None))
    path = run_dir / "demonstrations.json"
    new = json.loads(path.read_text())
    path.write_text(json.dumps(_to_old_format(new), indent=2) + "\n")
    config = yaml.safe_load((run_dir / "config.yaml").read_text())
    assert config["hyperparameters"]["bc_weight"] == 2.5  # config.yaml keeps the hyperparameter file's names
    resume_to_the_end(request)
    write_results(tmp_path, [collect_row(run_dir)])
    (row,) = read_results(tmp_path / "results.csv")
    assert {
        k: row["demonstrations"][k] for k in ("bc_steps", "bc_weight", "bc_q_filter", "bc_sampled", "offline_steps")
    } == {
        "bc_steps": 20,
        "bc_weight": 2.5,
        "bc_q_filter": True,
        "bc_sampled": False,
        "offline_steps": 0,
    }
    assert _demonstrations_line([row], 1) == (
        "- Demonstrations: 1 of 1 runs started with 2 episodes of the task's scripted policy in the replay buffer "
        f"(their success {row['demonstrations']['success']:.2f}–{row['demonstrations']['success']:.2f}); they are "
        "not counted in the budget. The actor of 1 of them was behaviour-cloned on them first (20 gradient steps). "
        "1 of them kept a cloning loss on them in every actor update (weight 2.5, Q-filtered)."
    )


@pytest.mark.parametrize(
    "old,new",
    [
        ({"episodes": 104, "transitions": 10400, "success": 1.0}, {}),
        ({"cloning_loss_weight": 2.5}, {"bc_weight": 2.5}),
        (
            {"cloning_loss_weight": 2.5, "cloning_loss_q_filter": False, "cloning_loss_sampled": True},
            {"bc_weight": 2.5, "bc_q_filter": False, "bc_sampled": True},
        ),
        ({"behaviour_cloning": {"steps": 5000, "loss_first": 3.0}}, {"bc_steps": 5000}),
        ({"offline": {"steps": 20000, "first": {}, "last": {}}}, {"offline_steps": 20000}),
    ],
)
def test_an_old_record_reads_under_the_one_name_with_the_one_default(old, new):
    base = {"episodes": 104, "transitions": 10400, "success": 1.0}
    record = demonstration_record({**base, **old})
    assert {k: record[k] for k in ("bc_steps", "bc_weight", "bc_q_filter", "bc_sampled", "offline_steps")} == {
        "bc_steps": 0,
        "bc_weight": 0.0,
        "bc_q_filter": True,
        "bc_sampled": False,
        "offline_steps": 0,
        **new,
    }
    assert record["demonstrations"] == 104  # old records hold only the episodes stored


# ---------------------------------------------------------------------- every committed result
def _demonstrations_lines(text: str) -> list[str]:
    return [line for line in text.splitlines() if line.startswith("- Demonstrations:")]


@pytest.mark.parametrize("results", COMMITTED, ids=lambda p: p.parent.name)
def test_every_committed_result_states_its_demonstrations_as_its_committed_report(results):
    """The committed reports were written by the code before the names were one: each
    states its runs' demonstrations, cloning and losses exactly as the same rows read now."""
    rows = read_results(results)
    demonstrated = [r for r in rows if r["demonstrations"]]
    now = report_demonstration_lines(demonstrated, len(rows))
    assert now == _demonstrations_lines((results.parent / "report" / "report.md").read_text())


@pytest.mark.slow
@pytest.mark.parametrize("results", COMMITTED, ids=lambda p: p.parent.name)
def test_every_committed_result_still_reports_and_plots(results, tmp_path):
    from unified_manip.experiments.plot import plot_overview

    report = build_report(results, tmp_path / "report", command="report", dense_check=False).read_text()
    assert _demonstrations_lines(report) == _demonstrations_lines((results.parent / "report" / "report.md").read_text())
    titles = plot_overview([results], tmp_path / "overview.png")
    assert titles and (tmp_path / "overview.png").stat().st_size > 0


@pytest.mark.parametrize("results", COMMITTED, ids=lambda p: p.parent.name)
def test_every_committed_report_shows_its_commands_as_they_are(results):
    """A report quotes its bench's ``command.txt`` ("Runs:"); a line added to the file
    after the report was written must reach the report too (``unified-manip report``)."""
    command = results.parent / "command.txt"
    report = (results.parent / "report" / "report.md").read_text()
    quoted = re.search(r"^Runs:\n\n```bash\n(.*?)\n```$", report, re.S | re.M)
    if not command.is_file():
        assert not quoted, f"{results.parent.name}: the report quotes a command.txt that is gone"
        return
    assert quoted, f"{results.parent.name}: the report does not quote command.txt; run unified-manip report again"
    assert quoted.group(1) == command.read_text().strip(), f"{results.parent.name}: run unified-manip report again"


def test_the_committed_results_are_all_found():
    assert len(COMMITTED) >= 21  # the 21 studies committed before RunConfig, and any since


def test_every_committed_config_yaml_reads_its_run_settings():
    """``eval`` and a resume read the settings of old run directories from their config.yaml."""
    configs = sorted((ROOT / "results").rglob("config.yaml"))
    assert len(configs) >= 139  # the 139 run directories committed before RunConfig, and any since
    runs = [rundir.run_settings(c.parent, rundir.read_config(c.parent))[0] for c in configs]
    # The committed studies' demonstration levers, as their grids set them.
    # Episode counts of the scripted policy, or (the bc pilot) the dataset each mode cloned.
    demonstrations = {r.demos.demonstrations for r in runs}
    # issue 39's cloning study: one dataset per mode at each size (25, 100, 400 episodes),
    # converted open loop (data/bc/nN) or by the search (data/bc/search/nN)
    cloning = {
        d
        for d in demonstrations
        if re.fullmatch(r"data/bc/(search/)?n(25|100|400)/\{task\}/\{action_mode\}-v0", str(d))
    }
    assert {"data/bc/n400/{task}/{action_mode}-v0", "data/bc/search/n25/{task}/{action_mode}-v0"} <= cloning
    assert demonstrations - cloning == {
        0,
        100,
        "/tmp/all100/Arm4PickAndPlace-v0-{action_mode}-v0",
        "data/{task}/{action_mode}-v0",  # issue 40's study: one dataset per task and mode
    }
    assert {r.demos.bc_steps for r in runs} == {0, 5000}
    assert {r.cloning_loss.bc_weight for r in runs} == {0.0, 1.6, 2.0, 1000}
    assert {r.offline.offline_steps for r in runs} == {0, 10000}


@pytest.mark.slow
def test_compile_loss_is_for_tqc_only_and_compiles_while_the_run_trains():
    import torch
    from sb3_contrib.tqc import tqc as tqc_module

    from unified_manip.training.speedups import SpeedupError, check, compiled_loss

    eager = tqc_module.quantile_huber_loss
    gen = torch.Generator().manual_seed(0)
    # As TQC calls it: (batch, critics, quantiles) against (batch, 1, kept target quantiles).
    current, target = torch.randn(512, 2, 25, generator=gen), torch.randn(512, 1, 46, generator=gen)
    with compiled_loss(True):
        compiled = tqc_module.quantile_huber_loss
        assert getattr(compiled, "_torchdynamo_orig_callable", None) is eager
        value = compiled(current, target, sum_over_quantiles=False)
    assert tqc_module.quantile_huber_loss is eager  # restored for the next run of the process
    expected = eager(current, target, sum_over_quantiles=False)
    torch.testing.assert_close(value, expected)
    with compiled_loss(False):
        assert tqc_module.quantile_huber_loss is eager
    check("TQC", True)
    with pytest.raises(
        SpeedupError, match=r"compile_loss compiles TQC's quantile Huber loss; this run's algorithm is SAC"
    ):
        check("SAC", True)


@pytest.mark.metaworld  # Meta-World pins MuJoCo 3.3.0: only CI's second leg can load it
def test_the_mt10_pilot_grid_runs_four_modes_on_two_tasks_with_demonstrations():
    """The MT10 study's budget pilot: seed 0 of drawer-open and push in native, ee_delta,
    joint_delta and joint_target_delta, to 100k steps, each with 100 live scripted
    demonstrations (native among them: Meta-World's policies emit it)."""
    grid = load_grid(Path(__file__).parents[2] / "baselines" / "grids" / "studies" / "action_spaces_mt10_pilot.yaml")
    cells = {(r.task.split("/")[-1], r.action_mode) for r in grid.runs}
    modes = ("native", "ee_delta", "joint_delta", "joint_target_delta")
    assert cells == {(t, m) for t in ("MetaWorldDrawerOpen-v1", "MetaWorldPush-v1") for m in modes}
    assert {(r.seed, r.steps) for r in grid.runs} == {(0, 100_000)}
    assert all("demonstrations=100" in r.overrides for r in grid.runs)
