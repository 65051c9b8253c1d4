"""The run-directory protocol: what a run directory holds and how it is written.

A run directory holds everything about one run::

    config.yaml          resolved hyperparameters, env kwargs, package versions, command
    status.json          {"state": "running" | "finished", "num_timesteps": N, ...}
    monitor/segK/        Monitor CSVs (with is_success) of the K-th start or resume
    tb/                  TensorBoard events
    eval/evaluations.npz periodic evaluation (EvalCallback): returns and successes
    best/best_model.zip  the best evaluated model
    checkpoints/<step>/  the last two resumable checkpoints (model + replay buffer + obs
                         statistics + manifest; see :mod:`unified_manip.training.checkpoints`)
    .lock                held by the process that owns the run (:mod:`unified_manip.training.runlock`)
    final_model.zip      written when the run finishes
    replay_buffer.pkl    off-policy algorithms, written when the run finishes
    vecnormalize.pkl     observation statistics of runs with ``normalize: true`` (final;
                         ``best/vecnormalize.pkl`` belongs to the best model)

``config.yaml`` says what run a directory holds (a different run is refused),
``status.json`` how far it got, and ``.lock`` who works in it now (one process at a
time). The rest (checkpoints, logs, models) belongs to training; :func:`clear_outputs`
removes it for ``--restart``. Every file is written to a temporary name and renamed,
so a kill never leaves a half-written file that is later read as whole.
"""

from __future__ import annotations

import json
import os
import platform
import shlex
import shutil
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator

from unified_manip.training.runlock import LOCK_FILE, DirectoryInUse, DirectoryLock
from unified_manip.training.settings import RunConfig, RunConfigError, split

STATUS = "status.json"
CONFIG = "config.yaml"
#: What a run writes besides config.yaml and the lock (what ``--restart`` removes).
OUTPUTS = (
    "checkpoints",
    "monitor",
    "eval",
    "best",
    "tb",
    "final_model.zip",
    "replay_buffer.pkl",
    "vecnormalize.pkl",
    STATUS,
)


#: The config.yaml keys that must match for a directory to hold the same run (the
#: device is where a run executes, not what it is: a run resumes on another).
COMPARED = ("env", "env_kwargs", "algo", "steps", "seed", "n_envs", "hyperparameters")

#: Run settings that change how fast a run trains, not what it learns, with the value a
#: ``config.yaml`` written before the setting existed ran with. They are not compared
#: (a hyperparameter file may change its default), and a resumed run keeps the value it
#: started with: ``compile_loss`` learned the same as the eager loss
#: (``results/compile_loss_check``), so the shipped TQC recipes turned it on after many
#: committed runs trained without it.
KEPT_ON_RESUME: dict[str, Any] = {"compile_loss": False}


class RunDirectoryError(ValueError):
    """A run directory that cannot be used for this run (one-line error, exit 2)."""


def package_versions() -> dict[str, str]:
    from importlib.metadata import version

    names = (
        "unified_manip",
        "mujoco",
        "gymnasium",
        "gymnasium-robotics",
        "robosuite",
        "metaworld",
        "stable-baselines3",
        "sb3-contrib",
        "torch",
        "numpy",
        "mink",
    )
    out = {"python": platform.python_version()}
    for n in names:
        try:
            out[n] = version(n)
        except Exception:  # pragma: no cover - reported, not fatal
            out[n] = "not installed"
    return out


def config_document(
    req: Any, n_envs: int, params: dict[str, Any], argv: list[str] | None, device: str
) -> dict[str, Any]:
    """The config.yaml of the run ``req`` (a :class:`~unified_manip.training.request.TrainRequest`)
    with ``n_envs`` training envs."""
    return {
        "env": req.env,
        "env_kwargs": req.env_config(),
        "algo": req.algo,
        "steps": req.steps,
        "seed": req.seed,
        "n_envs": n_envs,
        "device": device,  # where it started; a resume may run elsewhere (not compared)
        "hyperparameters": params,
        "overrides": list(req.overrides),
        "versions": package_versions(),
        "command": shlex.join(argv) if argv else None,
    }


def write_atomic(path: Path, text: str) -> None:
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def read_status(run_dir: Path) -> dict[str, Any] | None:
    path = Path(run_dir) / STATUS
    if not path.is_file():
        return None
    return json.loads(path.read_text())


def write_status(run_dir: Path, **status: Any) -> None:
    write_atomic(Path(run_dir) / STATUS, json.dumps({**status, "updated": time.time()}, indent=2))


def read_config(run_dir: Path) -> dict[str, Any]:
    from unified_manip.training.yamlfile import YamlFileError, load_mapping

    try:
        return load_mapping(Path(run_dir) / CONFIG, "a run's settings (written by unified-manip train)")
    except YamlFileError as err:
        raise RunDirectoryError(str(err)) from None


def run_settings(run_dir: Path, config: dict[str, Any]) -> tuple[RunConfig, dict[str, Any]]:
    """``(run settings, the algorithm's keyword arguments)`` a run's ``config.yaml`` (``config``,
    read from ``run_dir``) records: its ``hyperparameters`` with the ``n_envs`` and ``device``
    it ran with. Older files read the same (the keys are the hyperparameter file's)."""
    recorded = {**config.get("hyperparameters", {})}
    for key in ("n_envs", "device"):
        if config.get(key) is not None:
            recorded[key] = config[key]
    try:
        return split(recorded)
    except (RunConfigError, TypeError) as err:
        raise RunDirectoryError(f"{Path(run_dir) / CONFIG}: {err}") from None


def kept_settings(run_dir: Path) -> dict[str, Any]:
    """The :data:`KEPT_ON_RESUME` settings the run in ``run_dir`` started with (an older
    ``config.yaml`` without one ran with its old default); empty for a new directory."""
    if not (Path(run_dir) / CONFIG).is_file():
        return {}
    stored = read_config(run_dir).get("hyperparameters") or {}
    return {key: stored.get(key, old) for key, old in KEPT_ON_RESUME.items()}


def _comparable(config: dict[str, Any], key: str) -> Any:
    value = config.get(key)
    if key == "hyperparameters" and isinstance(value, dict):
        return {k: v for k, v in value.items() if k not in KEPT_ON_RESUME}
    return value


def check_same_run(run_dir: Path, config: dict[str, Any], compared: tuple[str, ...]) -> None:
    """Refuse a directory whose ``config.yaml`` differs from ``config`` in a ``compared`` key
    (the :data:`KEPT_ON_RESUME` settings aside)."""
    if (Path(run_dir) / CONFIG).is_file():
        stored = read_config(run_dir)
        diff = [k for k in compared if _comparable(stored, k) != _comparable(config, k)]
        if diff:
            raise RunDirectoryError(
                f"{run_dir} holds a different run (it differs in {', '.join(diff)}); choose another --run-dir"
            )


def clear_outputs(run_dir: Path) -> None:
    """Remove everything the run wrote but its config.yaml (and the lock)."""
    for name in OUTPUTS:
        path = Path(run_dir) / name
        shutil.rmtree(path) if path.is_dir() else path.unlink(missing_ok=True)


@contextmanager
def owned(run_dir: Path, wait_s: float = 0.0) -> Iterator[Path]:
    """Own ``run_dir`` (created if missing) for the duration of the ``with`` block.

    A file, a directory of other files, or one that another process owns (after
    waiting ``wait_s`` seconds for it) is refused with :class:`RunDirectoryError`. A
    directory made here that holds nothing but the lock when the block fails is removed
    again, so a refused request leaves nothing behind.
    """
    run_dir = Path(run_dir)
    if run_dir.exists() and not run_dir.is_dir():
        raise RunDirectoryError(f"{run_dir} is a file; expected a run directory (choose another --run-dir)")
    if run_dir.is_dir() and not (run_dir / CONFIG).is_file() and any(p.name != LOCK_FILE for p in run_dir.iterdir()):
        raise RunDirectoryError(f"{run_dir} exists and is not a unified-manip run directory; choose another --run-dir")
    created = not run_dir.exists()
    lock = DirectoryLock(run_dir, "run directory")
    try:
        lock.acquire(wait_s=wait_s)
    except DirectoryInUse as err:
        raise RunDirectoryError(str(err)) from None
    try:
        yield run_dir
    except BaseException:
        if created and [p.name for p in run_dir.iterdir()] == [LOCK_FILE]:
            lock.path.unlink()
            run_dir.rmdir()
        raise
    finally:
        lock.release()


def write_final(run_dir: Path, model, off_policy: bool) -> None:
    """The finished run's files: model, replay buffer (off-policy) and observation
    statistics (normalize runs), each written atomically."""
    tmp = run_dir / "final_model.tmp.zip"
    model.save(tmp)
    os.replace(tmp, run_dir / "final_model.zip")
    if off_policy:
        tmp = run_dir / "replay_buffer.tmp.pkl"
        model.save_replay_buffer(tmp)
        os.replace(tmp, run_dir / "replay_buffer.pkl")
    if model.get_vec_normalize_env() is not None:
        from unified_manip.training.run_envs import save_stats

        save_stats(model, run_dir / "vecnormalize.pkl")


def containing(target: Path) -> Path:
    """The run directory ``target`` (a run directory or a file inside one) belongs to."""
    target = Path(target)
    if not target.exists():
        raise RunDirectoryError(f"{target} does not exist; expected a run directory or a model .zip inside one")
    run_dir = target if target.is_dir() else target.parent
    while run_dir != run_dir.parent and not (run_dir / CONFIG).is_file():
        run_dir = run_dir.parent
    if not (run_dir / CONFIG).is_file():
        raise RunDirectoryError(f"{target} is not inside a unified-manip run directory (no {CONFIG} found)")
    return run_dir


def model_to_evaluate(target: Path, run_dir: Path) -> Path:
    """``target`` if it is a model .zip, else the run's best, final or newest checkpoint model."""
    from unified_manip.training import checkpoints

    if target.is_file():
        if not target.suffix == ".zip":
            raise RunDirectoryError(f"{target} is not a model; expected a run directory or a model .zip inside one")
        return target
    candidates = [run_dir / "best" / "best_model.zip", run_dir / "final_model.zip"]
    ckpt = checkpoints.newest(run_dir)
    if ckpt:
        candidates.append(ckpt.path(checkpoints.MODEL))
    model_path = next((p for p in candidates if p.is_file()), None)
    if model_path is None:
        raise RunDirectoryError(f"{run_dir} has no model yet (no best, final or checkpoint model)")
    return model_path


def stats_for(model_path: Path, run_dir: Path) -> Path:
    """The VecNormalize statistics saved together with ``model_path``."""
    from unified_manip.training import checkpoints

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
        raise RunDirectoryError(f"{model_path} was trained with normalize: true but {candidate} is missing")
    return candidate
