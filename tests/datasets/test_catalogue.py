"""``unified-manip collect --all`` (issue 39 item 5) on a tiny subset: one task, two
episodes per dataset, resumed; a task without a scripted policy or trained run is skipped
with its reason."""

from __future__ import annotations

import json

import minari
import pytest
from conftest import ROOT

from unified_manip.cli.main import main
from unified_manip.datasets.catalogue import collect_all, dataset_name, plan

REACH = "UnifiedManip/Arm4Reach-v0"


def test_collect_all_writes_every_mode_of_a_task_and_resumes(tmp_path, capsys, monkeypatch):
    root = tmp_path / "all"
    args = ["collect", "--all", "--env", REACH, "--episodes", "2", "--out", str(root), "--no-progress"]
    assert main(args) == 0
    modes = [m for _, m in plan([REACH])]
    assert modes[0] == "ee_delta" and len(modes) == 8  # every mode of the arm's shared controllers
    catalogue = json.loads((root / "catalogue.json").read_text())
    assert {e["state"] for e in catalogue.values()} == {"written"}
    for name, entry in catalogue.items():  # each dataset's cost, so a resumed set's cost sums
        files = [f for f in (root / name).rglob("*") if f.is_file()]
        assert entry["bytes"] == sum(f.stat().st_size for f in files) > 0
        assert entry["wall_s"] > 0 and entry["cpu_s"] > 0
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(root))
    written = {}
    for mode in modes:
        name = dataset_name(REACH, mode)
        dataset = minari.load_dataset(name)
        assert dataset.total_episodes == 2
        assert dataset.storage.metadata["unified_manip"]["env_kwargs"]["action_mode"] == mode
        written[name] = (root / name / "data" / "main_data.hdf5").stat().st_mtime_ns
    capsys.readouterr()
    assert main(args) == 0  # again: everything is there, nothing is redone
    assert "8 datasets in" in capsys.readouterr().out
    assert {n: (root / n / "data" / "main_data.hdf5").stat().st_mtime_ns for n in written} == written


def test_a_task_without_a_scripted_policy_or_trained_run_is_skipped_with_its_reason(tmp_path):
    lines: list[str] = []
    catalogue = collect_all(tmp_path, 2, ["UnifiedManip/HandReach-v0"], trained={}, progress=False, log=lines.append)
    (entry,) = catalogue.values()
    assert entry["state"] == "skipped"
    assert entry["reason"] == (
        "no scripted policy to collect it and no finished run with a final model under results/ "
        "(models are committed only in results/policies/)"
    )
    assert lines == [f"HandReach-v0-trained-v0: skipped ({entry['reason']})"]


def test_collect_without_all_still_needs_env_and_episodes(tmp_path, capsys):
    assert main(["collect", "--env", REACH, "--out", str(tmp_path / "x-v0")]) == 2
    assert capsys.readouterr().err.strip() == (
        "unified-manip collect: error: collect needs --env ID and --episodes N (or --all)"
    )


@pytest.mark.parametrize("extra", [["--policy", "random"], ["--action-mode", "joint_delta"]])
def test_all_refuses_a_policy_or_mode_of_its_own(tmp_path, capsys, extra):
    assert main(["collect", "--all", "--out", str(tmp_path), *extra]) == 2
    assert "--all chooses the policies and modes itself" in capsys.readouterr().err


def test_all_plays_the_best_finished_run_under_results_for_a_task_without_a_scripted_policy(
    tmp_path, monkeypatch, capsys
):
    """HandReach has no scripted policy: ``--all`` finds a finished run of it under
    ``results/*/runs/`` (relative to the working directory) and plays it. An untrained one
    cannot give a successful episode in ten, so the task is skipped, naming the run."""
    hand = "UnifiedManip/HandReach-v0"
    run = tmp_path / "results" / "study" / "runs" / "hand"
    sets = ["learning_starts=50", "batch_size=32", "buffer_size=1000", "eval_freq=100", "n_eval_episodes=1"]
    train = ["train", "--env", hand, "--algo", "sac_her", "--steps", "100", "--run-dir", str(run), "--no-progress"]
    collect = ["collect", "--all", "--env", hand, "--episodes", "1", "--out", "all", "--no-progress"]
    monkeypatch.chdir(tmp_path)
    assert main(collect) == 0  # no run yet: the task's placeholder entry says so
    assert list(json.loads((tmp_path / "all" / "catalogue.json").read_text())) == ["HandReach-v0-trained-v0"]
    assert main(train + [a for s in sets for a in ("--set", s)]) == 0
    assert main(collect) == 0
    assert "0 datasets in all, 1 skipped" in capsys.readouterr().out.splitlines()[-1]
    (entry,) = json.loads((tmp_path / "all" / "catalogue.json").read_text()).values()  # the placeholder is gone
    assert entry["source"] == f"run {run.relative_to(tmp_path)} (deterministic)"
    assert (entry["state"], entry["mode"]) == ("skipped", "native")
    assert entry["wall_s"] > 0 and entry["cpu_s"] > 0  # its cost counts in the set's
    assert entry["reason"] == (
        f"the run policy succeeded in 0 of 10 episodes of {hand}; 1 successful ones cannot be collected"
    )


def test_a_clone_collects_handreach_from_the_committed_policy(tmp_path, monkeypatch, capsys):
    """``results/policies/`` commits HandReach's model, so ``--all`` in a clone plays it:
    the dataset is written from that run, with its cost, and loads back."""
    monkeypatch.chdir(ROOT)
    out = tmp_path / "all"
    args = ["collect", "--all", "--env", "UnifiedManip/HandReach-v0", "--episodes", "2", "--out", str(out)]
    assert main([*args, "--no-progress"]) == 0
    assert "1 datasets in" in capsys.readouterr().out
    (entry,) = json.loads((out / "catalogue.json").read_text()).values()
    run = "results/policies/runs/HandReach-v0__native__sparse__tqc_her__s0"
    assert (entry["name"], entry["state"], entry["source"]) == (
        "HandReach-v0-native-v0",
        "written",
        f"run {run} (deterministic)",
    )
    assert entry["bytes"] > 0 and entry["wall_s"] > 0
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(out))
    dataset = minari.load_dataset("HandReach-v0-native-v0")
    assert dataset.total_episodes == 2
    assert all(e.infos["is_success"][-1] > 0.5 for e in dataset.iterate_episodes())
