"""Hyperparameters: ``baselines/<algo>.yaml`` files, keyed by task ID, with overrides.

Each file maps task IDs (and ``default``) to a flat mapping of hyperparameters. YAML
anchors and merge keys (``<<: *defaults``) share values; every value is a YAML literal,
nothing is ever evaluated. An entry is the ``default`` entry updated by the task's own.

Keys are either keyword arguments of the algorithm's constructor (checked against the
Stable-Baselines3 signature) or run settings (:class:`~unified_manip.training.settings.RunConfig`,
which checks its own). :func:`resolve_run` builds both, once. ``--set key=value`` sets any
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

from unified_manip.training.settings import KEYS as SETTING_KEYS
from unified_manip.training.settings import RunConfig, RunConfigError, check_setting, split


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
        # Behaviour cloning of a dataset (TD3's actor; --steps are gradient steps): unified_manip.training.bc.
        Algo("bc", "stable_baselines3", "TD3"),
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
    keys.update(dict.fromkeys(SETTING_KEYS))  # RunConfig checks its own (check_setting)
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
    """The hyperparameters for ``task_id``, one flat mapping: default entry, task entry,
    the task's entry for ``action_mode`` (where the file has one: a recipe that holds in
    some modes only), then overrides. Every value is checked where it is given: an error
    names the file and entry (or the ``--set``) and the key."""
    algo = get_algo(algo_name)
    path = Path(directory or DEFAULT_DIR) / f"{algo.name}.yaml"
    data = load_file(algo, directory)
    keys = valid_keys(algo)
    params: dict[str, Any] = {}
    entries = ["default", task_id] + ([mode_entry(task_id, action_mode)] if action_mode is not None else [])
    for entry in entries:
        given = copy.deepcopy(data.get(entry) or {})
        for key, value in given.items():
            where = f"{path}: {entry}"
            if key not in keys:
                raise HyperparameterError(
                    f"{where}: unknown hyperparameter {key!r} for {algo.cls_name}; expected one of {', '.join(sorted(keys))}"
                )
            if key in SETTING_KEYS:
                _check_setting(where, key, value)
            elif not _type_ok(value, keys[key]):
                raise HyperparameterError(f"{where}: {key} must be {_type_names(keys[key])}, got {value!r}")
        params.update(given)
    for item in overrides:
        apply_override(params, item, keys)
    return params


@dataclass(frozen=True)
class Resolved:
    """A run's hyperparameters, resolved once (:func:`resolve_run`).

    Attributes:
        hyperparameters: The flat mapping as given (what ``config.yaml`` records).
        run: The run settings among them, defaults filled in.
        algo_kwargs: The rest: the algorithm's keyword arguments.
    """

    hyperparameters: dict[str, Any]
    run: RunConfig
    algo_kwargs: dict[str, Any]


def resolve_run(
    algo_name: str,
    task_id: str,
    overrides: tuple[str, ...] = (),
    directory: Path | None = None,
    action_mode: str | None = None,
) -> Resolved:
    """:func:`resolve`'s mapping, split into the :class:`RunConfig` and the algorithm's keyword arguments."""
    params = resolve(algo_name, task_id, overrides, directory, action_mode)
    run, algo_kwargs = split(params)
    return Resolved(params, run, algo_kwargs)


def _check_setting(where: str, key: str, value: Any) -> None:
    try:
        check_setting(key, value)
    except RunConfigError as err:
        raise HyperparameterError(f"{where}: {err}") from None


def check_her_warmup(algo_name: str, algo_kwargs: dict[str, Any], run: RunConfig, episode_steps: int) -> None:
    """Raise :class:`HyperparameterError` if a HER run would start training before any
    episode has ended: HER draws its goals from finished episodes, and SB3 stops the run
    there with a traceback. The ``run.n_envs`` envs of a vector env end their first
    episodes together, at step ``n_envs * episode_steps``; demonstrations put finished
    episodes in first."""
    algo = get_algo(algo_name)
    if not algo.her or run.demos.demonstrations:
        return
    n_envs = run.n_envs
    starts = algo_kwargs.get("learning_starts", inspect.signature(algo.cls()).parameters["learning_starts"].default)
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
    if len(path) == 1 and top in SETTING_KEYS:
        _check_setting(f"--set {item!r}", top, value)
        params[top] = value
        return
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
