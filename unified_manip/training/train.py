"""``unified-manip train``: a Stable-Baselines3 baseline on any registered ID.

Running the same command on an unfinished run directory resumes from its newest
checkpoint that loads (step count, model and replay buffer); a finished one is left
alone, and ``--restart`` starts either over from step 0. One process at a time owns a
run directory: a second is refused. What a run directory holds is
:mod:`unified_manip.training.rundir`'s; the request is :mod:`unified_manip.training.request`'s, the envs
:mod:`unified_manip.training.run_envs`', the callbacks :mod:`unified_manip.training.callbacks`' and
``unified-manip eval`` :mod:`unified_manip.training.evaluation`'s (all re-exported here).
"""

from __future__ import annotations

import signal
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import yaml

from unified_manip.envs.registry import get_task
from unified_manip.training import checkpoints, rundir, speedups
from unified_manip.training.algorithms import get_algo
from unified_manip.training.demonstration_levers import demonstrate, keep_cloning, learn_offline_on_demonstrations
from unified_manip.training.devices import DeviceError, default_threads, resolve_device
from unified_manip.training.evaluation import EvalResult, evaluate, write_video
from unified_manip.training.hyperparams import check_her_warmup, resolve_run
from unified_manip.training.request import TrainError, TrainRequest
from unified_manip.training.run_envs import make_vec_env
from unified_manip.training.run_envs import model_kwargs as _model_kwargs
from unified_manip.training.run_envs import normalized as _normalized
from unified_manip.training.rundir import (
    CONFIG,
    STATUS,
    RunDirectoryError,
    read_config,
    read_status,
    write_atomic,
    write_status,
)
from unified_manip.training.settings import RunConfig

__all__ = [
    "CONFIG",
    "STATUS",
    "EvalResult",
    "RunDirectoryError",
    "TrainError",
    "TrainRequest",
    "evaluate",
    "make_vec_env",
    "read_config",
    "read_status",
    "train",
    "write_atomic",
    "write_status",
    "write_video",
]


def train(
    req: TrainRequest,
    argv: list[str] | None = None,
    progress: bool = True,
    log=print,
    threads: int | None = None,
    lock_wait_s: float = 0.0,
) -> dict[str, Any]:
    """Train (or resume, or skip if finished) the run ``req`` describes.

    ``threads`` is torch's thread count (default: ``OMP_NUM_THREADS`` if set, else up to 2). A caller that runs several
    trainings side by side passes 1: oversubscribed OpenMP threads spin and slow every
    run several-fold. The run directory is owned by this process while it trains; if
    another process owns it, this waits up to ``lock_wait_s`` seconds for it to end.

    The number of envs is ``req.n_envs``, else the hyperparameter file's ``n_envs``,
    else 1; config.yaml records the one used.

    Returns the final status dict. Raises :class:`TrainError` for bad requests, for a
    run directory another process owns and when no checkpoint of the run loads, and
    :class:`KeyboardInterrupt` after checkpointing when interrupted.
    """
    if req.algo == "bc":  # behaviour cloning of a dataset, in gradient steps (unified_manip.training.bc)
        from unified_manip.training.bc import train_bc

        return train_bc(req, argv, progress, log, threads, lock_wait_s)
    try:
        resolved = resolve_run(req.algo, req.env, req.overrides, action_mode=req.action_mode)
        # The device is where a run executes, not what it is: it stays out of the compared
        # hyperparameters, so a run started on one device resumes on another.
        device = resolve_device(req.device or resolved.run.device)
    except DeviceError as err:
        raise TrainError(str(err)) from None
    # The envs a run steps are recorded (and compared) as config.yaml's n_envs.
    n_envs = req.n_envs if req.n_envs is not None else resolved.run.n_envs
    run = replace(resolved.run, device=device, n_envs=n_envs)
    params = {k: v for k, v in resolved.hyperparameters.items() if k not in ("device", "n_envs")}
    from unified_manip.envs.vector.factory import resolve_vec
    from unified_manip.training.pretrain import check_settings as check_demonstration_settings

    try:
        resolve_vec(req.vec, req.env, n_envs)
        check_demonstration_settings(req.env, req.action_mode, get_algo(req.algo).off_policy, run, req.env_config())
        check_her_warmup(req.algo, resolved.algo_kwargs, run, get_task(req.env).max_episode_steps)
        speedups.check(get_algo(req.algo).cls().__name__, run.compile_loss)
    except ValueError as err:
        raise TrainError(str(err)) from None
    get_task(req.env).require_installed()  # the family's extra and MuJoCo, before any file is written
    run_dir = req.directory
    try:
        # A resumed run keeps the speed settings it started with (rundir.KEPT_ON_RESUME).
        kept = rundir.kept_settings(run_dir)
        run, params = replace(run, **kept), {**params, **kept}
        config = rundir.config_document(req, n_envs, params, argv, device)
        # everything below runs as the directory's only owner
        with rundir.owned(run_dir, lock_wait_s), speedups.compiled_loss(run.compile_loss):
            return _train_owned(req, run, resolved.algo_kwargs, run_dir, config, progress, log, threads)
    except RunDirectoryError as err:
        raise TrainError(str(err)) from None


def _train_owned(
    req: TrainRequest,
    run: RunConfig,
    algo_kwargs: dict[str, Any],
    run_dir: Path,
    config: dict[str, Any],
    progress: bool,
    log,
    threads: int | None,
) -> dict[str, Any]:
    import shutil

    import torch

    from unified_manip.training.callbacks import StopOnSignal, make_callbacks
    from unified_manip.training.run_envs import eval_env as make_eval_env

    algo = get_algo(req.algo)
    n_envs, device = run.n_envs, run.device
    gamma = float(algo_kwargs.get("gamma", 0.99))
    rundir.check_same_run(run_dir, config, rundir.COMPARED)
    if req.restart:
        rundir.clear_outputs(run_dir)
        log(f"{run_dir}: restarting from step 0")
    status = read_status(run_dir)
    if status and status.get("state") == "finished":
        log(f"{run_dir}: already finished at {status['num_timesteps']} steps; nothing to do")
        return status
    # EvalCallback copies the training statistics into the eval env before each evaluation.
    # It is made first: env keyword arguments the task refuses end here, before any file.
    eval_env = _normalized(make_eval_env(req, n_envs), run, None, training=False, gamma=gamma)
    if algo.off_policy:  # an image buffer can need more memory than the machine has: refuse it now
        _check_buffer(eval_env, algo_kwargs, algo.her)
    if not (run_dir / CONFIG).is_file():
        write_atomic(run_dir / CONFIG, yaml.safe_dump(config, sort_keys=False))

    torch.set_num_threads(threads or default_threads())
    candidates = checkpoints.published(run_dir)
    if not candidates:  # starting (again) from step 0: logs of an aborted attempt would mislead
        for sub in ("monitor", "eval", "best", "tb"):
            shutil.rmtree(run_dir / sub, ignore_errors=True)
    segment = len(list((run_dir / "monitor").glob("seg*"))) if (run_dir / "monitor").is_dir() else 0
    raw_env = make_vec_env(
        req.env, req.env_config(), n_envs, req.seed + 1000 * segment, run_dir / "monitor" / f"seg{segment}", req.vec
    )
    cls = algo.cls()
    started = time.time()
    elapsed_before = float((status or {}).get("wall_time_s", 0.0))

    def load(ckpt: checkpoints.Checkpoint):
        stats = ckpt.path(checkpoints.VECNORMALIZE)
        if run.normalize and stats is None:
            raise checkpoints.CheckpointError(
                f"{ckpt.directory}: no observation statistics (vecnormalize) for a normalize run"
            )
        model = algo.load(
            ckpt.path(checkpoints.MODEL),
            algo_kwargs.get("policy"),
            env=_normalized(raw_env, run, stats, training=True, gamma=gamma),
            device=device,
        )
        if model.num_timesteps != ckpt.step:
            raise checkpoints.CheckpointError(
                f"{ckpt.path(checkpoints.MODEL)}: at step {model.num_timesteps}, the manifest says {ckpt.step}"
            )
        if algo.off_policy:
            checkpoints.restore_replay_buffer(model, ckpt)
        return model

    # Ctrl-C and kill both end in a checkpoint, written where it is whole (see
    # StopOnSignal). The handlers go in before the model is loaded or built: a signal
    # during a long load or the demonstrations' prefill stops the run at its first rollout
    # (a bench worker ignores SIGINT until here, so it was lost). SIGINT is set
    # explicitly: a process started in the background (or by a parent that ignores it)
    # inherits SIG_IGN.
    stop = StopOnSignal()
    previous_term = signal.signal(signal.SIGTERM, stop.request)
    previous_int = signal.signal(signal.SIGINT, stop.request)
    try:
        if candidates:
            try:
                model, ckpt = checkpoints.load_first_good(candidates, load, log)
            except checkpoints.CheckpointError as err:
                raise TrainError(
                    f"{run_dir}: no checkpoint loads ({err}); run the same command with --restart to start over from step 0"
                ) from None
            buffered = f" with {_transitions(model)} transitions in the replay buffer" if algo.off_policy else ""
            log(f"{run_dir}: resuming from step {model.num_timesteps} of {req.steps} on {device}{buffered}")
        else:
            if status is not None:
                log(f"{run_dir}: unfinished run without a checkpoint; starting again from step 0")
            env = _normalized(raw_env, run, None, training=True, gamma=gamma)
            model = cls(
                env=env,
                seed=req.seed,
                device=device,
                tensorboard_log=str(run_dir / "tb"),
                verbose=0,
                **_model_kwargs(req.algo, algo_kwargs, run, env),
            )
            if run.demos.demonstrations:
                demonstrate(model, req, run, log)
        if run.cloning_loss.bc_weight:
            keep_cloning(model, req, run.cloning_loss)
        if not candidates and run.offline.offline_steps:  # with the cloning loss, if any, in its actor updates
            learn_offline_on_demonstrations(model, req, run.offline.offline_steps, log, progress)
        checkpoints.prune(run_dir)  # an unpublished checkpoint of a writer that was killed
        write_status(run_dir, state="running", num_timesteps=int(model.num_timesteps), wall_time_s=elapsed_before)
        remaining = req.steps - model.num_timesteps
        callbacks = make_callbacks(
            req.steps,
            run_dir,
            run,
            eval_env,
            algo.off_policy,
            progress,
            _reward_scales(req),
            elapsed=lambda: elapsed_before + time.time() - started,
            resumed_at=int(model.num_timesteps),
            stop=stop,
        )
        try:
            if remaining > 0:
                model.learn(total_timesteps=remaining, callback=callbacks, reset_num_timesteps=False, tb_log_name="tb")
        except KeyboardInterrupt:
            if stop.whole:
                checkpoints.write(model, run_dir, algo.off_policy)
                write_status(
                    run_dir,
                    state="running",
                    num_timesteps=int(model.num_timesteps),
                    wall_time_s=elapsed_before + time.time() - started,
                )
                log(f"{run_dir}: interrupted at step {model.num_timesteps}; run the same command again to resume")
            else:
                log(
                    f"{run_dir}: stopped at once at step {model.num_timesteps}, without a checkpoint; run the same "
                    f"command again to resume from step {read_status(run_dir)['num_timesteps']}"
                )
            raise
        rundir.write_final(run_dir, model, algo.off_policy)
        final = {
            "state": "finished",
            "num_timesteps": int(model.num_timesteps),
            "wall_time_s": elapsed_before + time.time() - started,
        }
        write_status(run_dir, **final)
        # The final files supersede the checkpoints (a replay buffer can be large).
        shutil.rmtree(run_dir / "checkpoints", ignore_errors=True)
        log(f"{run_dir}: finished {model.num_timesteps} steps")
        return read_status(run_dir)
    finally:
        signal.signal(signal.SIGTERM, previous_term)
        signal.signal(signal.SIGINT, previous_int)
        raw_env.close()
        eval_env.close()


def _check_buffer(env, algo_kwargs: dict[str, Any], her: bool) -> None:
    from unified_manip.training.images import SB3_BUFFER_SIZE, check_buffer_fits

    size = int(algo_kwargs.get("buffer_size", SB3_BUFFER_SIZE))
    try:
        check_buffer_fits(env.observation_space, env.action_space.shape[0], size, her)
    except ValueError as err:
        env.close()
        raise TrainError(str(err)) from None


def _reward_scales(req: TrainRequest) -> dict[str, float]:
    """Each reward term's scale in the run's reward design (what the raw terms are logged from)."""
    spec = get_task(req.env).terms.design(req.reward_type)
    return {term.name: float(term.scale) for term in spec.terms}


def _transitions(model) -> int:
    buffer = model.replay_buffer
    return int(buffer.size() * buffer.n_envs)
