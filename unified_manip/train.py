"""``unified-manip train`` and ``eval``: Stable-Baselines3 baselines on any registered ID.

A run directory holds everything about one run::

    config.yaml          resolved hyperparameters, env kwargs, package versions, command
    status.json          {"state": "running" | "finished", "num_timesteps": N, ...}
    monitor/segK/        Monitor CSVs (with is_success) of the K-th start or resume
    tb/                  TensorBoard events
    eval/evaluations.npz periodic evaluation (EvalCallback): returns and successes
    best/best_model.zip  the best evaluated model
    checkpoints/<step>/  the last two resumable checkpoints (model + replay buffer + obs
                         statistics + manifest; see :mod:`unified_manip.checkpoints`)
    .lock                held by the process that owns the run (:mod:`unified_manip.runlock`)
    final_model.zip      written when the run finishes
    replay_buffer.pkl    off-policy algorithms, written when the run finishes
    vecnormalize.pkl     observation statistics of runs with ``normalize: true`` (final;
                         ``best/vecnormalize.pkl`` belongs to the best model)

Running the same command on an unfinished run directory resumes from its newest
checkpoint that loads (step count, model and replay buffer); a finished one is left
alone, and ``--restart`` starts either over from step 0. One process at a time owns a
run directory: a second is refused. Every file is written to a temporary name and
renamed, so a kill never leaves a half-written file that is later read as whole.
"""

from __future__ import annotations

import os
import platform
import shlex
import signal
import sys
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from . import checkpoints, rundir
from .config import REWARD_TYPES
from .devices import DEVICES, DeviceError, resolve_device
from .hyperparams import ALGOS, RUN_KEYS, get_algo, resolve
from .registry import TASKS, get_task
from .rundir import CONFIG, STATUS, RunDirectoryError, read_config, read_status, write_atomic, write_status  # noqa: F401


class TrainError(ValueError):
    """Invalid training or evaluation request (reported as a one-line error, exit 2)."""


# ---------------------------------------------------------------------- request
@dataclass(frozen=True)
class TrainRequest:
    """What ``unified-manip train`` was asked to do.

    Attributes:
        env: Registered task ID.
        action_mode: One of the task's action modes.
        reward_type: ``sparse``, ``dense`` or ``dense_penalized``.
        algo: ``ppo``, ``sac``, ``td3``, ``sac_her`` or ``tqc_her``.
        steps: Total environment steps (over all envs).
        seed: Seed of the model and of the envs (env k gets ``seed + k``).
        n_envs: Parallel envs, stepped as ``vec`` says.
        run_dir: Where the run lives.
        overrides: ``key=value`` hyperparameter overrides.
        env_kwargs: Extra env keyword arguments (e.g. ``robot``).
        device: ``auto``, ``cpu`` or ``cuda``; ``None`` takes the hyperparameter file's
            ``device`` key, and ``auto`` where that has none.
        vec: How the envs are stepped: ``native`` (the native vector env, through
            :class:`~unified_manip.vector.sb3.NativeSB3VecEnv`), ``dummy`` (SB3's
            ``DummyVecEnv``), ``subproc`` (``SubprocVecEnv``), or ``auto``: native where
            the ID has a native vector env and ``n_envs > 1``, else dummy for one env
            and subproc for more.
        restart: Start the run over from step 0, discarding its checkpoints, logs and
            models (same run: the settings must match its ``config.yaml``).
    """

    env: str
    action_mode: str
    reward_type: str
    algo: str
    steps: int
    seed: int = 0
    n_envs: int = 1
    run_dir: Path | None = None
    overrides: tuple[str, ...] = ()
    env_kwargs: dict[str, Any] = field(default_factory=dict)
    device: str | None = None
    vec: str = "auto"
    restart: bool = False

    def __post_init__(self) -> None:
        if self.env not in TASKS:
            raise TrainError(f"unknown task {self.env!r}; expected one of {', '.join(TASKS)}")
        spec = get_task(self.env)
        if self.action_mode not in spec.action_modes:
            raise TrainError(
                f"action mode {self.action_mode!r} is not supported by {self.env}; "
                f"expected one of {', '.join(spec.action_modes)}"
            )
        if self.reward_type not in REWARD_TYPES:
            raise TrainError(f"unknown reward type {self.reward_type!r}; expected one of {', '.join(REWARD_TYPES)}")
        if self.algo not in ALGOS:
            raise TrainError(f"unknown algorithm {self.algo!r}; expected one of {', '.join(ALGOS)}")
        if self.device is not None and self.device not in DEVICES:
            raise TrainError(f"unknown device {self.device!r}; expected one of {', '.join(DEVICES)}")
        for name in ("steps", "n_envs"):
            if getattr(self, name) <= 0:
                raise TrainError(f"--{name.replace('_', '-')} must be positive, got {getattr(self, name)}")
        from .vector.factory import resolve_vec

        try:
            resolve_vec(self.vec, self.env, self.n_envs)
        except ValueError as err:
            raise TrainError(str(err)) from None
        if self.run_dir is not None and ".." in Path(self.run_dir).parts:
            raise TrainError(
                f"--run-dir {str(self.run_dir)!r} climbs out of its directory with '..'; "
                "expected a path without '..' (relative, or absolute)"
            )

    @property
    def directory(self) -> Path:
        if self.run_dir is not None:
            return Path(self.run_dir)
        name = self.env.split("/")[-1]
        return Path("runs") / f"{name}__{self.action_mode}__{self.reward_type}__{self.algo}__s{self.seed}"

    def env_config(self) -> dict[str, Any]:
        return {"action_mode": self.action_mode, "reward_type": self.reward_type, **self.env_kwargs}


# ---------------------------------------------------------------------- small I/O helpers
def package_versions() -> dict[str, str]:
    from importlib.metadata import version

    names = ("unified_manip", "mujoco", "gymnasium", "gymnasium-robotics", "robosuite", "stable-baselines3", "sb3-contrib", "torch", "numpy", "mink")
    out = {"python": platform.python_version()}
    for n in names:
        try:
            out[n] = version(n)
        except Exception:  # pragma: no cover - reported, not fatal
            out[n] = "not installed"
    return out


# ---------------------------------------------------------------------- env construction
def make_vec_env(env_id: str, env_kwargs: dict[str, Any], n_envs: int, seed: int, monitor_dir: Path | None,
                 vec: str = "auto"):
    """Monitored envs (``is_success`` logged), stepped as ``vec`` says: the native vector
    env (one ``VecMonitor``), or a ``DummyVecEnv`` / ``SubprocVecEnv`` of ``Monitor``-ed
    envs (see :func:`unified_manip.vector.factory.resolve_vec` for ``auto``)."""
    from stable_baselines3.common.env_util import make_vec_env as sb3_make_vec_env
    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

    from .vector.factory import resolve_vec

    kind = resolve_vec(vec, env_id, n_envs)
    if kind == "native":
        from .vector.sb3 import make_monitored

        return make_monitored(env_id, env_kwargs, n_envs, seed, monitor_dir, ("is_success", "sim_unstable"))

    return sb3_make_vec_env(
        f"unified_manip:{env_id}",  # workers import unified_manip, which registers the IDs
        n_envs=n_envs,
        seed=seed,
        env_kwargs=env_kwargs,
        monitor_dir=str(monitor_dir) if monitor_dir else None,
        # sim_unstable: whether the episode ended because the physics diverged.
        monitor_kwargs={"info_keywords": ("is_success", "sim_unstable")},
        vec_env_cls=SubprocVecEnv if kind == "subproc" else DummyVecEnv,
    )


def _model_kwargs(algo_name: str, params: dict[str, Any], action_dim: int) -> dict[str, Any]:
    algo = get_algo(algo_name)
    kwargs = {k: v for k, v in params.items() if k not in RUN_KEYS}
    if algo.her:
        kwargs["replay_buffer_class"] = algo.buffer_cls()
    if "action_noise_std" in params:
        from stable_baselines3.common.noise import NormalActionNoise

        std = float(params["action_noise_std"])
        kwargs["action_noise"] = NormalActionNoise(np.zeros(action_dim), std * np.ones(action_dim))
    return kwargs


# ---------------------------------------------------------------------- callbacks
def _callbacks(model_total: int, run_dir: Path, params: dict[str, Any], eval_env, algo_name: str, progress: bool,
               resumed_at: int = 0, n_envs: int = 1):
    """``n_envs`` is the number of *training* envs: EvalCallback counts calls of the
    training env's step, each ``n_envs`` env steps, so ``eval_freq`` (env steps) is
    divided by it."""
    from stable_baselines3.common.callbacks import BaseCallback, CallbackList, EvalCallback

    algo = get_algo(algo_name)

    class SuccessRate(BaseCallback):
        """SB3 logs rollout/success_rate only for off-policy algorithms; log it for all."""

        def _on_rollout_end(self) -> None:
            if not algo.off_policy and len(self.model.ep_success_buffer) > 0:
                self.logger.record("rollout/success_rate", float(np.mean(self.model.ep_success_buffer)))

        def _on_step(self) -> bool:
            return True

        def _on_training_end(self) -> None:
            # Off-policy SB3 dumps logs only every log_interval episodes; make sure the
            # last success rate of a run reaches TensorBoard whatever the algorithm.
            if len(self.model.ep_success_buffer) > 0:
                self.logger.record("rollout/success_rate", float(np.mean(self.model.ep_success_buffer)))
                self.logger.dump(self.num_timesteps)

    class Checkpoint(BaseCallback):
        """Saves a resumable checkpoint every ``freq`` env steps (atomically).

        It saves at the end of a rollout, where the replay buffer holds every transition
        counted in ``num_timesteps`` (during ``on_step`` the last one is not stored yet).
        """

        def __init__(self, freq: int):
            super().__init__()
            self.freq = max(int(freq), 1)
            self.last = 0

        def _on_training_start(self) -> None:
            self.last = self.num_timesteps

        def _on_step(self) -> bool:
            return True

        def _on_rollout_end(self) -> None:
            if self.num_timesteps - self.last >= self.freq:
                checkpoints.write(self.model, run_dir, algo.off_policy)
                self.last = self.num_timesteps

    class Progress(BaseCallback):
        """A bar with steps, steps/s, ETA and the latest success rate."""

        def _on_training_start(self) -> None:
            from tqdm import tqdm

            self.bar = tqdm(total=model_total, initial=self.num_timesteps, unit="step", dynamic_ncols=True, disable=not progress)

        def _on_step(self) -> bool:
            self.bar.update(self.num_timesteps - self.bar.n)
            buf = self.model.ep_success_buffer
            if len(buf) and self.n_calls % 50 == 0:
                self.bar.set_postfix(success=f"{np.mean(buf):.2f}", refresh=False)
            return True

        def _on_training_end(self) -> None:
            self.bar.close()

    class SaveBestStats(BaseCallback):
        """Keeps ``best/vecnormalize.pkl`` in step with ``best/best_model.zip``."""

        def _on_step(self) -> bool:
            if self.model.get_vec_normalize_env() is not None:
                (run_dir / "best").mkdir(parents=True, exist_ok=True)
                _save_stats(self.model, run_dir / "best" / "vecnormalize.pkl")
            return True

    evaluation = EvalCallback(
        eval_env,
        callback_on_new_best=SaveBestStats(),
        eval_freq=max(int(params.get("eval_freq", 10_000)) // max(n_envs, 1), 1),
        n_eval_episodes=int(params.get("n_eval_episodes", 20)),
        log_path=str(run_dir / "eval"),
        best_model_save_path=str(run_dir / "best"),
        deterministic=True,
        verbose=0,
    )
    if resumed_at:
        _resume_evaluations(evaluation, run_dir / "eval" / "evaluations.npz", resumed_at)
    return CallbackList([SuccessRate(), Checkpoint(params.get("checkpoint_freq", 10_000)), evaluation, Progress()])


def _resume_evaluations(evaluation, path: Path, upto: int) -> None:
    """Give a resumed run's EvalCallback the evaluations made up to its checkpoint.

    EvalCallback starts with empty lists and rewrites ``evaluations.npz`` from them: a
    resumed run would lose its earlier curve, and its first evaluation would replace the
    best model whatever it scored. Evaluations after ``upto`` (made past the checkpoint
    by the attempt that was cut short) are dropped; they are made again.
    """
    try:
        with np.load(path) as data:
            keep = data["timesteps"] <= upto
            evaluation.evaluations_timesteps = data["timesteps"][keep].tolist()
            evaluation.evaluations_results = data["results"][keep].tolist()
            evaluation.evaluations_length = data["ep_lengths"][keep].tolist()
            if "successes" in data:
                evaluation.evaluations_successes = data["successes"][keep].tolist()
    except (OSError, ValueError, KeyError):  # none yet, or cut off while written: start afresh
        return
    if evaluation.evaluations_results:
        evaluation.best_mean_reward = float(max(np.mean(r) for r in evaluation.evaluations_results))


def _save_stats(model, path: Path) -> None:
    """Save the VecNormalize statistics of ``model``'s env atomically."""
    tmp = path.with_name(path.stem + ".tmp.pkl")
    model.get_vec_normalize_env().save(str(tmp))
    os.replace(tmp, path)


def _normalized(venv, params: dict[str, Any], stats: Path | None, training: bool):
    """Wrap ``venv`` in VecNormalize when the run normalises observations.

    Rewards are left as the task defines them (HER recomputes them from goals); with
    ``stats`` the saved running statistics are loaded, otherwise they start fresh.
    """
    if not params.get("normalize"):
        return venv
    from stable_baselines3.common.vec_env import VecNormalize

    if stats is not None:
        venv = VecNormalize.load(str(stats), venv)
    else:
        venv = VecNormalize(venv, norm_obs=True, norm_reward=False, gamma=float(params.get("gamma", 0.99)))
    venv.training = training
    venv.norm_reward = False
    return venv


# ---------------------------------------------------------------------- train
def _config_document(req: TrainRequest, params: dict[str, Any], argv: list[str] | None, device: str) -> dict[str, Any]:
    return {
        "env": req.env,
        "env_kwargs": req.env_config(),
        "algo": req.algo,
        "steps": req.steps,
        "seed": req.seed,
        "n_envs": req.n_envs,
        "device": device,  # where it started; a resume may run elsewhere (not compared)
        "hyperparameters": params,
        "overrides": list(req.overrides),
        "versions": package_versions(),
        "command": shlex.join(argv) if argv else None,
    }


_COMPARED = ("env", "env_kwargs", "algo", "steps", "seed", "n_envs", "hyperparameters")


def train(
    req: TrainRequest, argv: list[str] | None = None, progress: bool = True, log=print, threads: int | None = None,
    lock_wait_s: float = 0.0,
) -> dict[str, Any]:
    """Train (or resume, or skip if finished) the run ``req`` describes.

    ``threads`` is torch's thread count (default: up to 2). A caller that runs several
    trainings side by side passes 1: oversubscribed OpenMP threads spin and slow every
    run several-fold. The run directory is owned by this process while it trains; if
    another process owns it, this waits up to ``lock_wait_s`` seconds for it to end.

    Returns the final status dict. Raises :class:`TrainError` for bad requests, for a
    run directory another process owns and when no checkpoint of the run loads, and
    :class:`KeyboardInterrupt` after checkpointing when interrupted.
    """
    params = resolve(req.algo, req.env, req.overrides)
    # The device is where a run executes, not what it is: it stays out of the compared
    # hyperparameters, so a run started on one device resumes on another.
    try:
        device = resolve_device(req.device or params.pop("device", "auto"))
    except DeviceError as err:
        raise TrainError(str(err)) from None
    params.pop("device", None)
    run_dir = req.directory
    config = _config_document(req, params, argv, device)
    try:
        with rundir.owned(run_dir, lock_wait_s):  # everything below runs as the directory's only owner
            return _train_owned(req, run_dir, config, params, device, progress, log, threads)
    except RunDirectoryError as err:
        raise TrainError(str(err)) from None


def _train_owned(req: TrainRequest, run_dir: Path, config: dict[str, Any], params: dict[str, Any], device: str,
                 progress: bool, log, threads: int | None) -> dict[str, Any]:
    import shutil

    import torch

    algo = get_algo(req.algo)
    rundir.check_same_run(run_dir, config, _COMPARED)
    if req.restart:
        rundir.clear_outputs(run_dir)
        log(f"{run_dir}: restarting from step 0")
    status = read_status(run_dir)
    if status and status.get("state") == "finished":
        log(f"{run_dir}: already finished at {status['num_timesteps']} steps; nothing to do")
        return status
    # EvalCallback copies the training statistics into the eval env before each evaluation.
    # It is made first: env keyword arguments the task refuses end here, before any file.
    eval_env = _normalized(_checked_env(req), params, None, training=False)
    if not (run_dir / CONFIG).is_file():
        write_atomic(run_dir / CONFIG, yaml.safe_dump(config, sort_keys=False))

    torch.set_num_threads(threads or max(1, min(2, os.cpu_count() or 1)))
    candidates = checkpoints.published(run_dir)
    if not candidates:  # starting (again) from step 0: logs of an aborted attempt would mislead
        for sub in ("monitor", "eval", "best", "tb"):
            shutil.rmtree(run_dir / sub, ignore_errors=True)
    segment = len(list((run_dir / "monitor").glob("seg*"))) if (run_dir / "monitor").is_dir() else 0
    raw_env = make_vec_env(req.env, req.env_config(), req.n_envs, req.seed + 1000 * segment, run_dir / "monitor" / f"seg{segment}", req.vec)
    cls = algo.cls()
    started = time.time()
    elapsed_before = float((status or {}).get("wall_time_s", 0.0))

    def load(ckpt: checkpoints.Checkpoint):
        stats = ckpt.path(checkpoints.VECNORMALIZE)
        if params.get("normalize") and stats is None:
            raise checkpoints.CheckpointError(f"{ckpt.directory}: no observation statistics (vecnormalize) for a normalize run")
        model = cls.load(ckpt.path(checkpoints.MODEL), env=_normalized(raw_env, params, stats, training=True), device=device)
        if model.num_timesteps != ckpt.step:
            raise checkpoints.CheckpointError(f"{ckpt.path(checkpoints.MODEL)}: at step {model.num_timesteps}, the manifest says {ckpt.step}")
        if algo.off_policy:
            checkpoints.restore_replay_buffer(model, ckpt)
        return model

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
            env = _normalized(raw_env, params, None, training=True)
            model = cls(env=env, seed=req.seed, device=device, tensorboard_log=str(run_dir / "tb"), verbose=0,
                        **_model_kwargs(req.algo, params, env.action_space.shape[0]))
        checkpoints.prune(run_dir)  # an unpublished checkpoint of a writer that was killed
        write_status(run_dir, state="running", num_timesteps=int(model.num_timesteps), wall_time_s=elapsed_before)
        remaining = req.steps - model.num_timesteps
        callbacks = _callbacks(req.steps, run_dir, params, eval_env, req.algo, progress, resumed_at=int(model.num_timesteps),
                               n_envs=req.n_envs)
        # Ctrl-C and kill both end in a checkpoint. SIGINT is set explicitly: a process
        # started in the background (or by a parent that ignores it) inherits SIG_IGN.
        previous_handler = signal.signal(signal.SIGTERM, _raise_interrupt)
        previous_int = signal.signal(signal.SIGINT, signal.default_int_handler)
        try:
            if remaining > 0:
                model.learn(total_timesteps=remaining, callback=callbacks, reset_num_timesteps=False, tb_log_name="tb")
        except KeyboardInterrupt:
            checkpoints.write(model, run_dir, algo.off_policy)
            write_status(
                run_dir,
                state="running",
                num_timesteps=int(model.num_timesteps),
                wall_time_s=elapsed_before + time.time() - started,
            )
            log(f"{run_dir}: interrupted at step {model.num_timesteps}; run the same command again to resume")
            raise
        finally:
            signal.signal(signal.SIGTERM, previous_handler)
            signal.signal(signal.SIGINT, previous_int)
        tmp = run_dir / "final_model.tmp.zip"
        model.save(tmp)
        os.replace(tmp, run_dir / "final_model.zip")
        if algo.off_policy:
            tmp = run_dir / "replay_buffer.tmp.pkl"
            model.save_replay_buffer(tmp)
            os.replace(tmp, run_dir / "replay_buffer.pkl")
        if model.get_vec_normalize_env() is not None:
            _save_stats(model, run_dir / "vecnormalize.pkl")
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
        raw_env.close()
        eval_env.close()


def _checked_env(req: TrainRequest):
    """The evaluation env; a task that refuses the env keyword arguments is a TrainError.

    It has the training env's wrapper layers, because EvalCallback copies VecNormalize
    statistics layer by layer and refuses chains that differ: a ``VecMonitor`` over an
    unmonitored env when the training env is the native vector env, else ``Monitor``-ed."""
    from .vector.factory import resolve_vec

    native = resolve_vec(req.vec, req.env, req.n_envs) == "native"
    try:
        if native:
            import gymnasium as gym
            from stable_baselines3.common.vec_env import DummyVecEnv, VecMonitor

            env = VecMonitor(DummyVecEnv([lambda: gym.make(req.env, **req.env_config())]))
            env.seed(req.seed + 10_000)
        else:
            env = make_vec_env(req.env, req.env_config(), 1, req.seed + 10_000, None)
    except (TypeError, ValueError) as err:  # gymnasium appends where it was raised; keep the task's words
        reason = str(err).split(" was raised from the environment creator")[0]
        raise TrainError(f"cannot make {req.env} with {req.env_config()}: {reason}") from None
    return env


def _transitions(model) -> int:
    buffer = model.replay_buffer
    return int(buffer.size() * buffer.n_envs)


def _raise_interrupt(signum, frame):  # pragma: no cover - exercised by the kill test
    raise KeyboardInterrupt


# ---------------------------------------------------------------------- eval
@dataclass(frozen=True)
class EvalResult:
    episodes: int
    successes: int
    success_rate: float
    ci_low: float
    ci_high: float
    mean_return: float
    std_return: float

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def evaluate(
    target: Path,
    episodes: int,
    action_mode: str | None = None,
    reward_type: str | None = None,
    seed: int = 123,
    video: Path | None = None,
    video_episodes: int = 2,
    deterministic: bool = True,
    device: str = "auto",
) -> EvalResult:
    """Evaluate a run directory (its best model if any, else its final one) or a model
    zip inside a run directory. The env defaults to the run's own settings; a model
    cannot be evaluated in an action mode it was not trained in."""
    import gymnasium as gym
    from scipy.stats import binomtest

    if episodes <= 0:
        raise TrainError(f"--episodes must be positive, got {episodes}")
    try:
        device = resolve_device(device)
    except DeviceError as err:
        raise TrainError(str(err)) from None
    if video is not None and Path(video).suffix.lower() not in (".mp4", ".gif"):
        raise TrainError(f"unsupported video format {Path(video).suffix!r}; expected .mp4 or .gif")
    target = Path(target)
    if not target.exists():
        raise TrainError(f"{target} does not exist; expected a run directory or a model .zip inside one")
    run_dir = target if target.is_dir() else target.parent
    while run_dir != run_dir.parent and not (run_dir / CONFIG).is_file():
        run_dir = run_dir.parent
    if not (run_dir / CONFIG).is_file():
        raise TrainError(f"{target} is not inside a unified-manip run directory (no {CONFIG} found)")
    try:
        config = read_config(run_dir)
    except RunDirectoryError as err:
        raise TrainError(str(err)) from None
    env_kwargs = dict(config["env_kwargs"])
    if action_mode is not None and action_mode != env_kwargs["action_mode"]:
        raise TrainError(
            f"the model was trained with action_mode {env_kwargs['action_mode']!r}; it cannot be evaluated "
            f"with action_mode {action_mode!r} (the actions mean different things)"
        )
    if reward_type is not None:
        if reward_type not in REWARD_TYPES:
            raise TrainError(f"unknown reward type {reward_type!r}; expected one of {', '.join(REWARD_TYPES)}")
        env_kwargs["reward_type"] = reward_type
    if target.is_file():
        model_path = target
        if not model_path.suffix == ".zip":
            raise TrainError(f"{target} is not a model; expected a run directory or a model .zip inside one")
    else:
        candidates = [run_dir / "best" / "best_model.zip", run_dir / "final_model.zip"]
        ckpt = checkpoints.newest(run_dir)
        if ckpt:
            candidates.append(ckpt.path(checkpoints.MODEL))
        model_path = next((p for p in candidates if p.is_file()), None)
        if model_path is None:
            raise TrainError(f"{run_dir} has no model yet (no best, final or checkpoint model)")
    cls = get_algo(config["algo"]).cls()
    render = {"render_mode": "rgb_array", "render_width": 320, "render_height": 320} if video else {}
    from stable_baselines3.common.vec_env import DummyVecEnv

    env = gym.make(config["env"], **env_kwargs, **render)
    # HER models need an env to load; give them one over the same instance.
    venv = DummyVecEnv([lambda: env])
    model = cls.load(model_path, env=venv, device=device)
    normalizer = None
    if config["hyperparameters"].get("normalize"):
        normalizer = _normalized(venv, config["hyperparameters"], _stats_for(model_path, run_dir), training=False)
    returns, successes, frames = [], 0, []
    for ep in range(episodes):
        obs, info = env.reset(seed=seed + ep)
        done, total = False, 0.0
        if video and ep < video_episodes:
            frames.append(env.render())
        while not done:
            action, _ = model.predict(normalizer.normalize_obs(obs) if normalizer else obs, deterministic=deterministic)
            obs, reward, terminated, truncated, info = env.step(action)
            total += reward
            done = terminated or truncated
            if video and ep < video_episodes:
                frames.append(env.render())
        returns.append(total)
        successes += int(info.get("is_success", 0.0) > 0.5)
    env.close()
    if video:
        write_video(Path(video), frames, fps=get_task(config["env"]).render_fps)
    ci = binomtest(successes, episodes).proportion_ci(confidence_level=0.95, method="wilson")
    return EvalResult(episodes, successes, successes / episodes, float(ci.low), float(ci.high), float(np.mean(returns)), float(np.std(returns)))


def _stats_for(model_path: Path, run_dir: Path) -> Path:
    """The VecNormalize statistics saved together with ``model_path``."""
    model_path = Path(model_path)
    if model_path.parent.parent.name == checkpoints.CHECKPOINTS:
        candidate = model_path.parent / checkpoints.VECNORMALIZE
    elif model_path.parent.name == checkpoints.CHECKPOINTS:  # the legacy layout
        candidate = model_path.parent / model_path.name.replace("model_", "vecnormalize_").replace(".zip", ".pkl")
    elif model_path.parent.name == "best":
        candidate = model_path.parent / "vecnormalize.pkl"
    else:
        candidate = run_dir / "vecnormalize.pkl"
    if not candidate.is_file():
        raise TrainError(f"{model_path} was trained with normalize: true but {candidate} is missing")
    return candidate


def write_video(path: Path, frames: list[np.ndarray], fps: int) -> None:
    """MP4 (via imageio-ffmpeg) or GIF, chosen by the file suffix."""
    import imageio.v3 as iio

    path.parent.mkdir(parents=True, exist_ok=True)
    suffix = path.suffix.lower()
    if suffix == ".gif":
        iio.imwrite(path, np.stack(frames), duration=1000 / fps, loop=0)
    elif suffix == ".mp4":
        iio.imwrite(path, np.stack(frames), fps=fps, codec="libx264", macro_block_size=1)
    else:
        raise TrainError(f"unsupported video format {path.suffix!r}; expected .mp4 or .gif")
