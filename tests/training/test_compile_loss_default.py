"""The compiled quantile loss is the shipped TQC recipes' default, and every run keeps the
setting it started with: the committed runs trained before it was the default (their
``config.yaml`` lacks the key) read, and resume, without it."""

from __future__ import annotations

import shutil
from dataclasses import replace
from pathlib import Path

import pytest
import yaml
from conftest import interrupt_after_first_checkpoint, resume_to_the_end

from unified_manip.training import rundir
from unified_manip.training.hyperparams import resolve_run

ROOT = Path(__file__).resolve().parents[2]
CONFIGS = sorted((ROOT / "results").rglob("config.yaml"))


def _recipe_entries() -> list[tuple[str, str | None]]:
    """Every (task, mode) entry of the shipped TQC recipe file."""
    keys = yaml.safe_load((ROOT / "baselines" / "tqc_her.yaml").read_text())
    entries = [tuple(k.split(" ")) if " " in k else (k, None) for k in keys if k != "default"]
    return [(task, mode) for task, mode in entries]


def test_every_shipped_tqc_entry_compiles_its_loss():
    entries = _recipe_entries()
    assert len(entries) >= 10
    for task, mode in entries:
        assert resolve_run("tqc_her", task, action_mode=mode).run.compile_loss is True, (task, mode)
    # An override still turns it off, as a grid or `--set` may.
    assert resolve_run("tqc_her", entries[0][0], ("compile_loss=false",)).run.compile_loss is False


def test_every_committed_run_keeps_the_setting_it_ran_with():
    kept = {}
    for config in CONFIGS:
        stored = rundir.read_config(config.parent)
        if stored.get("algo") != "tqc_her":
            continue
        recorded = stored["hyperparameters"].get("compile_loss")
        setting = rundir.kept_settings(config.parent)["compile_loss"]
        assert setting is (recorded if recorded is not None else False), config
        assert rundir.run_settings(config.parent, stored)[0].compile_loss is setting, config
        kept[config.parent.parent.parent.name] = kept.get(config.parent.parent.parent.name, set()) | {setting}
    assert kept["benchmark"] == {False} and kept["compile_loss_check"] == {True}


def test_a_different_speed_setting_is_the_same_run_and_another_hyperparameter_is_not(tmp_path):
    old = next(c for c in CONFIGS if c.parent.parent.parent.name == "benchmark")
    run_dir = tmp_path / "run"
    run_dir.mkdir()
    shutil.copy(old, run_dir / "config.yaml")
    config = rundir.read_config(run_dir)
    assert "compile_loss" not in config["hyperparameters"]
    now = {**config, "hyperparameters": {**config["hyperparameters"], "compile_loss": True}}
    rundir.check_same_run(run_dir, now, rundir.COMPARED)  # the recipe's new default: same run
    other = {**config, "hyperparameters": {**config["hyperparameters"], "batch_size": 64}}
    with pytest.raises(rundir.RunDirectoryError, match="it differs in hyperparameters"):
        rundir.check_same_run(run_dir, other, rundir.COMPARED)


@pytest.mark.slow
def test_a_run_started_eager_resumes_eager_under_the_compiled_recipe(tmp_path):
    from unified_manip.training.request import TrainRequest
    from unified_manip.training.train import train

    sets = ("learning_starts=100", "batch_size=32", "buffer_size=2000", "checkpoint_freq=200", "eval_freq=400")
    sets += ("n_eval_episodes=1", "n_envs=1", "demonstrations=0")
    request = TrainRequest(
        env="UnifiedManip/Arm4Reach-v0",
        action_mode="ee_delta",
        reward_type="sparse",
        algo="tqc_her",
        steps=400,
        seed=0,
        run_dir=tmp_path / "run",
        overrides=sets,
    )
    eager = replace(request, overrides=(*sets, "compile_loss=false"))
    interrupt_after_first_checkpoint(request.run_dir, lambda: train(eager, progress=False, threads=1))
    resume_to_the_end(request)  # the recipe now says compile_loss: true; the run says false
    assert rundir.read_config(request.run_dir)["hyperparameters"]["compile_loss"] is False
