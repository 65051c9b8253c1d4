"""Behaviour cloning of a dataset: ``unified-manip train --algo bc --demonstrations DATASET``.

A baseline that learns from the dataset alone, with no env step of its own. The
dataset's episodes go into a replay buffer as a prefilled run's do
(:mod:`unified_manip.training.dataset_demonstrations`, so its action mode, observation
design and reward type must be the run's), and the actor of TD3's ``MultiInputPolicy``
is fitted to their actions with the project's actor-cloning step
(:func:`unified_manip.training.pretrain.behaviour_clone`: the squared error of the
deterministic action, batches of ``batch_size``, the actor's own Adam). The critic is
built but never trained. imitation and d3rlpy, which ship behaviour cloning, do not
install beside this stack's pins (gymnasium 1.4, SB3 2.9).

**The budget is gradient steps:** ``--steps N`` takes N actor updates, and ``eval_freq``
and ``checkpoint_freq`` count them too; ``config.yaml`` and ``demonstrations.json`` say so
(``budget: gradient steps``). The rest is a run like any other: the evaluations of
SB3's ``EvalCallback`` (``eval/evaluations.npz``, deterministic episodes with their
success, the best model in ``best/``), resumable checkpoints with the model and its
optimiser (the buffer is refilled from the dataset on resume), ``final_model.zip``,
``status.json`` written last, so ``unified-manip eval``, ``bench`` and ``report`` read it.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from unified_manip.training import checkpoints, rundir
from unified_manip.training.request import TrainError, TrainRequest
from unified_manip.training.settings import RunConfig, demonstration_settings

#: What a bc run's ``--steps`` counts (recorded in config.yaml and demonstrations.json).
BUDGET = "gradient steps"

#: Gradient steps between looks at Ctrl-C (and progress-bar updates).
CHUNK = 100


def train_bc(
    req: TrainRequest, argv: list[str] | None, progress: bool, log, threads: int | None, lock_wait_s: float
) -> dict[str, Any]:
    """Train (or resume, or skip if finished) the bc run ``req`` describes; what
    :func:`unified_manip.training.train.train` does for ``--algo bc``."""
    from unified_manip.training.devices import DeviceError, resolve_device
    from unified_manip.training.hyperparams import resolve_run
    from unified_manip.training.pretrain import check_settings

    try:
        resolved = resolve_run(req.algo, req.env, req.overrides, action_mode=req.action_mode)
        device = resolve_device(req.device or resolved.run.device)
    except (DeviceError, ValueError) as err:
        raise TrainError(str(err)) from None
    run = replace(resolved.run, device=device, n_envs=1)
    if not isinstance(run.demos.demonstrations, str):
        raise TrainError(
            "bc clones a dataset: pass --demonstrations DATASET (written by unified-manip collect or convert)"
        )
    asked = [k for k in ("bc_steps", "offline_steps", "bc_weight") if demonstration_settings(run)[k]]
    if asked or run.normalize:
        raise TrainError(
            f"bc takes --steps gradient steps of cloning and nothing else; unset {', '.join(asked or ['normalize'])}"
        )
    try:
        check_settings(req.env, req.action_mode, True, run, req.env_config())
    except ValueError as err:
        raise TrainError(str(err)) from None
    params = {k: v for k, v in resolved.hyperparameters.items() if k not in ("device", "n_envs")}
    config = {**rundir.config_document(req, 1, params, argv, device), "budget": BUDGET}
    try:
        with rundir.owned(req.directory, lock_wait_s):
            return _train_owned(req, run, resolved.algo_kwargs, config, progress, log, threads)
    except rundir.RunDirectoryError as err:
        raise TrainError(str(err)) from None


def _train_owned(req, run: RunConfig, algo_kwargs, config, progress: bool, log, threads: int | None) -> dict[str, Any]:
    import torch
    from tqdm import tqdm

    from unified_manip.training.algorithms import get_algo
    from unified_manip.training.dataset_demonstrations import dataset_path, prefill
    from unified_manip.training.run_envs import eval_env as make_eval_env
    from unified_manip.training.run_envs import make_vec_env

    run_dir = req.directory
    rundir.check_same_run(run_dir, config, rundir.COMPARED)
    if req.restart:
        rundir.clear_outputs(run_dir)
        log(f"{run_dir}: restarting from step 0")
    status = rundir.read_status(run_dir)
    if status and status.get("state") == "finished":
        log(f"{run_dir}: already finished at {status['num_timesteps']} gradient steps; nothing to do")
        return status
    evaluation_env = make_eval_env(req, 1)
    if not (run_dir / rundir.CONFIG).is_file():
        rundir.write_atomic(run_dir / rundir.CONFIG, yaml.safe_dump(config, sort_keys=False))
    torch.set_num_threads(threads or max(1, int(os.environ.get("OMP_NUM_THREADS", "2") or 2)))
    algo = get_algo(req.algo)
    env = make_vec_env(req.env, req.env_config(), 1, req.seed, None, "dummy")  # its spaces; never stepped
    source = run.demos.demonstrations
    candidates = checkpoints.published(run_dir)
    if not candidates:  # from step 0: the evaluations of an aborted attempt would mislead
        for sub in ("eval", "best"):
            shutil.rmtree(run_dir / sub, ignore_errors=True)
    started, elapsed_before = time.time(), float((status or {}).get("wall_time_s", 0.0))
    stop = _Stop()
    handlers = {sig: signal.signal(sig, stop.request) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        if candidates:

            def load(ckpt):
                return algo.load(ckpt.path(checkpoints.MODEL), algo_kwargs.get("policy"), env=env, device=run.device)

            try:
                model, _ = checkpoints.load_first_good(candidates, load, log)
            except checkpoints.CheckpointError as err:
                raise TrainError(
                    f"{run_dir}: no checkpoint loads ({err}); run the same command with --restart"
                ) from None
            log(f"{run_dir}: resuming from gradient step {model.num_timesteps} of {req.steps}")
        else:
            kwargs = {
                **algo_kwargs,
                "buffer_size": _rows(dataset_path(source, req.env, req.env_config())),
                "learning_starts": 0,
            }
            model = algo.cls()(env=env, seed=req.seed, device=run.device, verbose=0, **kwargs)
        done = prefill(model, source, req.env, req.env_config())
        log(f"{run_dir}: cloning {done['episodes']} episodes ({done['transitions']} transitions) of {done['dataset']}")
        if not candidates:
            record = {**done, **demonstration_settings(run), "budget": BUDGET}
            rundir.write_atomic(run_dir / "demonstrations.json", json.dumps(record, indent=2) + "\n")
        evaluations = _Evaluations(run_dir, evaluation_env, run.n_eval_episodes, int(model.num_timesteps))
        rundir.write_status(
            run_dir, state="running", num_timesteps=int(model.num_timesteps), wall_time_s=elapsed_before
        )
        with tqdm(
            total=req.steps, initial=int(model.num_timesteps), desc="bc", unit="step", disable=not progress
        ) as bar:
            while model.num_timesteps < req.steps:
                if stop.requested:
                    checkpoints.write(model, run_dir, off_policy=False)
                    elapsed = elapsed_before + time.time() - started
                    rundir.write_status(
                        run_dir, state="running", num_timesteps=int(model.num_timesteps), wall_time_s=elapsed
                    )
                    log(
                        f"{run_dir}: interrupted at gradient step {model.num_timesteps}; run the same command to resume"
                    )
                    raise KeyboardInterrupt
                chunk = _next_stop(int(model.num_timesteps), req.steps, run) - int(model.num_timesteps)
                _clone(model, chunk)
                bar.update(chunk)
                step = int(model.num_timesteps)
                if step % run.eval_freq == 0 or step == req.steps:
                    evaluations.evaluate(model, step)
                if step % run.checkpoint_freq == 0 and step < req.steps:
                    checkpoints.write(model, run_dir, off_policy=False)
                    # The time so far goes with the checkpoint: a run killed outright (a
                    # session's end) resumes from here and would otherwise lose it.
                    elapsed = elapsed_before + time.time() - started
                    rundir.write_status(run_dir, state="running", num_timesteps=step, wall_time_s=elapsed)
        rundir.write_final(run_dir, model, off_policy=False)
        rundir.write_status(
            run_dir,
            state="finished",
            num_timesteps=int(model.num_timesteps),
            wall_time_s=elapsed_before + time.time() - started,
        )
        shutil.rmtree(run_dir / checkpoints.CHECKPOINTS, ignore_errors=True)
        log(f"{run_dir}: finished {model.num_timesteps} gradient steps")
        return rundir.read_status(run_dir)
    finally:
        for sig, handler in handlers.items():
            signal.signal(sig, handler)
        env.close()
        evaluation_env.close()


def _rows(path: str) -> int:
    """Replay-buffer rows that hold every transition of the dataset at ``path``."""
    from unified_manip.datasets.store import open_dataset

    return max(int(open_dataset(Path(path)).total_steps), 1)


def _next_stop(step: int, total: int, run: RunConfig) -> int:
    """The next step at which to evaluate, checkpoint, look at Ctrl-C or end."""

    def following(freq: int) -> int:
        return (step // freq + 1) * freq

    return min(total, following(run.eval_freq), following(run.checkpoint_freq), step + CHUNK)


def _clone(model, steps: int) -> None:
    from unified_manip.training.pretrain import behaviour_clone

    behaviour_clone(model, steps)
    model.num_timesteps += steps


class _Stop:
    """Ctrl-C or SIGTERM: stop at the next chunk's end, with a checkpoint."""

    def __init__(self) -> None:
        self.requested = False

    def request(self, signum, frame) -> None:
        self.requested = True


class _Evaluations:
    """``eval/evaluations.npz`` as SB3's ``EvalCallback`` writes it (timesteps, results,
    ep_lengths, successes), here at gradient steps, and the best model (by mean return,
    as EvalCallback) in ``best/``. A resumed run keeps the evaluations up to its step."""

    def __init__(self, run_dir: Path, env, episodes: int, resumed_at: int) -> None:
        self.path, self.best = run_dir / "eval" / "evaluations.npz", run_dir / "best"
        self.env, self.episodes = env, episodes
        self.rows: dict[str, list] = {"timesteps": [], "results": [], "ep_lengths": [], "successes": []}
        if resumed_at and self.path.is_file():
            with np.load(self.path) as data:
                keep = data["timesteps"] <= resumed_at
                self.rows = {k: data[k][keep].tolist() for k in self.rows}
        self.best_mean = max((float(np.mean(r)) for r in self.rows["results"]), default=-np.inf)

    def evaluate(self, model, step: int) -> None:
        from stable_baselines3.common.evaluation import evaluate_policy

        successes: list[float] = []

        def on_step(locals_, globals_) -> None:
            if locals_["done"] and locals_["info"].get("is_success") is not None:
                successes.append(float(locals_["info"]["is_success"]))

        returns, lengths = evaluate_policy(
            model, self.env, self.episodes, deterministic=True, return_episode_rewards=True, callback=on_step
        )
        for key, value in zip(self.rows, (step, returns, lengths, successes)):
            self.rows[key].append(value)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        tmp = self.path.with_name("evaluations.tmp.npz")
        np.savez(tmp, **{k: np.array(v) for k, v in self.rows.items()})
        os.replace(tmp, self.path)
        if float(np.mean(returns)) > self.best_mean:
            self.best_mean = float(np.mean(returns))
            self.best.mkdir(exist_ok=True)
            model.save(self.best / "best_model.tmp.zip")
            os.replace(self.best / "best_model.tmp.zip", self.best / "best_model.zip")
