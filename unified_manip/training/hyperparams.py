"""Hyperparameters: ``baselines/<algo>.yaml`` files, keyed by task ID, with overrides.

Each file maps task IDs (and ``default``) to a flat mapping of hyperparameters. YAML
anchors and merge keys (``<<: *defaults``) share values; every value is a YAML literal,
nothing is ever evaluated. An entry is the ``default`` entry updated by the task's own.

Keys are either keyword arguments of the algorithm's constructor (checked against the
Stable-Baselines3 signature) or one of :data:`RUN_KEYS`. ``--set key=value`` sets any
such key (``policy_kwargs.net_arch=[64,64]`` reaches into a mapping the entry already
has); the value is parsed as a YAML literal and must have the type the algorithm's
signature (or, inside a mapping, the existing value) allows.
"""

from __future__ import annotations

import copy
import inspect
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

#: Settings of the run rather than of the algorithm.
RUN_KEYS: dict[str, type] = {
    "eval_freq": int,  # env steps between evaluations (EvalCallback)
    "n_eval_episodes": int,  # episodes per evaluation
    "checkpoint_freq": int,  # env steps between resumable checkpoints
    "action_noise_std": float,  # TD3: std of Gaussian exploration noise, in action units
    "normalize": bool,  # running mean/std observation normalisation (VecNormalize), as the zoo's normalize
    "device": str,  # auto | cpu | cuda; --device overrides it (where a run executes, not compared on resume)
    "n_envs": int,  # parallel envs, at least 1; train --n-envs and a grid's n_envs override it
    "demonstrations": int,  # off-policy: episodes of the scripted policy put in the replay buffer first
    "bc_steps": int,  # with demonstrations: actor gradient steps of behaviour cloning on them before training
    "bc_weight": float,  # with demonstrations: weight of a Q-filtered cloning loss in every actor update
    "bc_q_filter": bool,  # with bc_weight: keep the loss only where Q rates the demonstrated action higher (default true)
    "bc_sampled": bool,  # with bc_weight: the loss on a stochastic actor's sampled action, not its mean (default false)
    "offline_steps": int,  # with demonstrations: gradient steps of the algorithm's own update on them alone first
}


def _default_dir() -> Path:
    """``UNIFIED_MANIP_BASELINES`` if set; else the files installed with the package
    (``unified_manip/baselines/`` in a wheel); else the checkout's ``baselines/`` (an
    editable install or a source tree)."""
    if os.environ.get("UNIFIED_MANIP_BASELINES"):
        return Path(os.environ["UNIFIED_MANIP_BASELINES"])
    package = Path(__file__).resolve().parents[1]  # unified_manip/
    installed = package / "baselines"
    return installed if installed.is_dir() else package.parent / "baselines"


#: Where the YAML files live (see :func:`_default_dir`).
DEFAULT_DIR = _default_dir()


@dataclass(frozen=True)
class Algo:
    """One baseline: an SB3 class, with or without hindsight relabelling."""

    name: str
    module: str
    cls_name: str
    her: bool = False
    off_policy: bool = True
    buffer: str = "stable_baselines3:HerReplayBuffer"  # module:class of the HER buffer

    def cls(self):
        import importlib

        return getattr(importlib.import_module(self.module), self.cls_name)

    def buffer_cls(self):
        """The replay buffer class of a HER algorithm."""
        import importlib

        module, name = self.buffer.split(":")
        return getattr(importlib.import_module(module), name)

    def load(self, path, policy: Any = None, **kwargs: Any):
        """``cls().load(path, **kwargs)``, with this project's own classes handed over by
        name instead of unpickled from the file: a model saved before they moved (e.g.
        ``unified_manip.crossq`` to ``unified_manip.training.crossq``) still loads.

        Args:
            path: The model zip.
            policy: The run's ``policy`` hyperparameter (an alias such as
                ``"MultiInputPolicy"``, or a class); None: unpickled from the file.
            **kwargs: ``env``, ``device``, ... as for SB3's ``load``.
        """
        cls = self.cls()
        custom: dict[str, Any] = {}
        if self.module.startswith("unified_manip.") and policy is not None:
            custom["policy_class"] = cls.policy_aliases[policy] if isinstance(policy, str) else policy
        if self.her and self.buffer.startswith("unified_manip."):
            custom["replay_buffer_class"] = self.buffer_cls()
        return cls.load(path, custom_objects=custom or None, **kwargs)


ALGOS: dict[str, Algo] = {
    a.name: a
    for a in (
        Algo("ppo", "stable_baselines3", "PPO", off_policy=False),
        Algo("sac", "stable_baselines3", "SAC"),
        Algo("td3", "stable_baselines3", "TD3"),
        Algo("sac_her", "stable_baselines3", "SAC", her=True),
        Algo("tqc_her", "sb3_contrib", "TQC", her=True),
        Algo(
            "crossq_her",
            "unified_manip.training.crossq",
            "CrossQ",
            her=True,
            buffer="unified_manip.training.crossq:CatDictHerReplayBuffer",
        ),
    )
}


class HyperparameterError(ValueError):
    """A hyperparameter file or override is invalid."""


def get_algo(name: str) -> Algo:
    try:
        return ALGOS[name]
    except KeyError:
        raise HyperparameterError(f"unknown algorithm {name!r}; expected one of {', '.join(ALGOS)}") from None


def _allowed_types(annotation: Any) -> tuple[type, ...] | None:
    """Python types a YAML literal may have for a constructor annotation (None: any)."""
    text = annotation if isinstance(annotation, str) else getattr(annotation, "__name__", str(annotation))
    text = str(text)
    found = []
    for token, typ in (("float", float), ("int", int), ("str", str), ("bool", bool), ("dict", dict)):
        if token in text:
            found.append(typ)
    if "tuple" in text or "list" in text:
        found.append(list)
    if "Optional" in text or "None" in text:
        found.append(type(None))
    return tuple(found) or None


def _signature_types(algo: Algo) -> dict[str, tuple[type, ...] | None]:
    params = inspect.signature(algo.cls().__init__).parameters
    # Objects (not YAML literals) and the settings the CLI owns.
    skip = {
        "self",
        "env",
        "replay_buffer_class",
        "action_noise",
        "rollout_buffer_class",
        "rollout_buffer_kwargs",
        "_init_setup_model",
        "device",
        "seed",
        "tensorboard_log",
        "verbose",
    }
    return {k: _allowed_types(p.annotation) for k, p in params.items() if k not in skip}


def _type_ok(value: Any, allowed: tuple[type, ...] | None) -> bool:
    if allowed is None:
        return True
    if isinstance(value, bool):
        return bool in allowed
    if isinstance(value, int) and float in allowed:
        return True
    return isinstance(value, allowed)


def _type_names(allowed: tuple[type, ...]) -> str:
    return " or ".join("null" if t is type(None) else t.__name__ for t in allowed)


def valid_keys(algo: Algo) -> dict[str, tuple[type, ...] | None]:
    """Every key a hyperparameter entry of ``algo`` may hold, with its allowed types."""
    keys = dict(_signature_types(algo))
    keys.update({k: (t,) if t is not float else (float, int) for k, t in RUN_KEYS.items()})
    return keys


def load_file(algo: Algo, directory: Path | None = None) -> dict[str, dict[str, Any]]:
    path = Path(directory or DEFAULT_DIR) / f"{algo.name}.yaml"
    if not path.is_file():
        raise HyperparameterError(f"hyperparameter file {path} not found")
    from unified_manip.training.yamlfile import YamlFileError, key_line, load_mapping

    expected = "a mapping of task IDs with a 'default' entry"
    try:
        data = load_mapping(path, expected)
    except YamlFileError as err:
        raise HyperparameterError(str(err)) from None
    if "default" not in data:
        raise HyperparameterError(f"{path}: expected {expected}; there is no 'default' entry")
    for key, entry in data.items():
        if not isinstance(entry, dict) and (entry is not None or key == "default"):
            raise HyperparameterError(
                f"{path}:{key_line(path, key)}: entry {key!r} must be a mapping of hyperparameters, got {type(entry).__name__}"
            )
        if key != "default" and not _names_a_task(str(key)):
            raise HyperparameterError(
                f"{path}:{key_line(path, key)}: entry {key!r} names no registered task; expected 'default', a task ID "
                f"(e.g. UnifiedManip/Arm4Reach-v0) or '<task ID> <action mode>' (e.g. 'UnifiedManip/Lift-v0 native')"
            )
    return data


def mode_entry(task_id: str, action_mode: str) -> str:
    """The key of the entry that holds ``task_id``'s settings for one action mode only
    (e.g. ``"UnifiedManip/Lift-v0 native"``)."""
    return f"{task_id} {action_mode}"


def split_entry(key: str) -> tuple[str, str | None]:
    """``(task ID, action mode or None)`` of an entry key (the inverse of :func:`mode_entry`)."""
    task_id, _, mode = key.partition(" ")
    return task_id, mode or None


def _names_a_task(key: str) -> bool:
    from unified_manip.envs.registry import TASKS

    task_id, mode = split_entry(key)
    return task_id in TASKS and (mode is None or mode in TASKS[task_id].action_modes)


def resolve(
    algo_name: str,
    task_id: str,
    overrides: tuple[str, ...] = (),
    directory: Path | None = None,
    action_mode: str | None = None,
) -> dict[str, Any]:
    """The hyperparameters for ``task_id``: default entry, task entry, the task's entry for
    ``action_mode`` (where the file has one: a recipe that holds in some modes only), then
    overrides."""
    algo = get_algo(algo_name)
    data = load_file(algo, directory)
    params = copy.deepcopy(data["default"])
    params.update(copy.deepcopy(data.get(task_id) or {}))
    if action_mode is not None:
        params.update(copy.deepcopy(data.get(mode_entry(task_id, action_mode)) or {}))
    keys = valid_keys(algo)
    for key, value in params.items():
        if key not in keys:
            raise HyperparameterError(
                f"{algo.name}.yaml: unknown hyperparameter {key!r} for {algo.cls_name}; expected one of {', '.join(sorted(keys))}"
            )
        if not _type_ok(value, keys[key]):
            raise HyperparameterError(f"{algo.name}.yaml: {key} must be {_type_names(keys[key])}, got {value!r}")
    for item in overrides:
        apply_override(params, item, keys)
    if "n_envs" in params and params["n_envs"] < 1:
        raise HyperparameterError(f"{algo.name}.yaml: n_envs must be at least 1, got {params['n_envs']!r}")
    return params


def check_her_warmup(algo_name: str, params: dict[str, Any], n_envs: int, episode_steps: int) -> None:
    """Raise :class:`HyperparameterError` if a HER run would start training before any
    episode has ended: HER draws its goals from finished episodes, and SB3 stops the run
    there with a traceback. The envs of a vector env end their first episodes together,
    at step ``n_envs * episode_steps``; demonstrations put finished episodes in first."""
    algo = get_algo(algo_name)
    if not algo.her or params.get("demonstrations", 0):
        return
    starts = params.get("learning_starts", inspect.signature(algo.cls()).parameters["learning_starts"].default)
    first_update = (starts // n_envs + 1) * n_envs  # SB3 trains once num_timesteps > learning_starts
    first_end = n_envs * episode_steps
    if first_update < first_end:
        raise HyperparameterError(
            f"learning_starts={starts} starts training at step {first_update}, before the first episodes end at step "
            f"{first_end} ({n_envs} envs x {episode_steps} steps), and HER samples goals from finished episodes only; "
            f"set learning_starts to {first_end} or more, or add demonstrations"
        )


def apply_override(params: dict[str, Any], item: str, keys: dict[str, tuple[type, ...] | None]) -> None:
    """Apply one ``key=value`` (``a.b=value`` for nested keys) to ``params`` in place."""
    if "=" not in item or item.startswith("="):
        raise HyperparameterError(f"malformed --set {item!r}; expected key=value, e.g. learning_rate=0.0003")
    key, raw = item.split("=", 1)
    try:
        value = yaml.safe_load(raw) if raw.strip() else None
    except yaml.YAMLError:
        raise HyperparameterError(f"malformed --set {item!r}: {raw!r} is not a YAML literal") from None
    if isinstance(value, str):  # PyYAML reads 3e-4 (no dot) as a string
        try:
            value = float(value)
        except ValueError:
            pass
    path = key.strip().split(".")
    top = path[0]
    if top not in keys:
        raise HyperparameterError(
            f"unknown hyperparameter {top!r} in --set {item!r}; expected one of {', '.join(sorted(keys))}"
        )
    if len(path) == 1:
        allowed = keys.get(top)
        if not _type_ok(value, allowed):
            raise HyperparameterError(
                f"--set {item!r}: {top} must be {_type_names(allowed)}, got {type(value).__name__}"
            )
        params[top] = value
        return
    target = params.get(top)
    for part in path[1:-1]:
        if not isinstance(target, dict) or part not in target:
            raise HyperparameterError(f"unknown hyperparameter {key!r} in --set {item!r}")
        target = target[part]
    leaf = path[-1]
    if not isinstance(target, dict) or leaf not in target:
        known = ", ".join(f"{'.'.join(path[:-1])}.{k}" for k in target) if isinstance(target, dict) else "none"
        raise HyperparameterError(f"unknown hyperparameter {key!r} in --set {item!r}; expected one of {known}")
    old = target[leaf]
    allowed = (float, int) if isinstance(old, float) else (type(old),)
    if old is not None and not _type_ok(value, allowed):
        raise HyperparameterError(f"--set {item!r}: {key} must be {_type_names(allowed)}, got {type(value).__name__}")
    target[leaf] = value
