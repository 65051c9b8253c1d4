"""Grid files: which runs a bench trains (``baselines/grids/*.yaml``), fully validated
before any run starts. The file format is described in :mod:`unified_manip.experiments.bench`."""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from unified_manip.envs.config import EnvConfig
from unified_manip.envs.design_names import design_label
from unified_manip.envs.registry import TASKS, get_task
from unified_manip.envs.rewards import validate_reward_type
from unified_manip.envs.task_lists import expand_task_lists
from unified_manip.experiments.cells import in_cell, parse_cell_overrides, parse_only_cells
from unified_manip.experiments.designs import check_design, parse_designs
from unified_manip.experiments.randomizations import check_randomization, grid_randomizations
from unified_manip.experiments.selection import matches, parse_only
from unified_manip.training.algorithms import ALGOS
from unified_manip.training.hyperparams import check_her_warmup, resolve_run
from unified_manip.training.pretrain import check_settings as check_demonstration_settings
from unified_manip.training.request import run_name
from unified_manip.training.yamlfile import YamlFileError, load_mapping

REQUIRED = ("tasks", "action_modes", "reward_types", "algos", "seeds", "steps")
OPTIONAL = (
    "name",
    "description",
    "eval_freq",
    "n_eval_episodes",
    "overrides",
    "n_envs",
    "only",
    "targets",
    "env_kwargs",
    "observations",
    "randomizations",
    "cell_overrides",
)


class GridError(ValueError):
    """A grid file is malformed (reported before any run starts)."""


@dataclass(frozen=True)
class RunSpec:
    task: str
    action_mode: str
    reward_type: str
    algo: str
    seed: int
    steps: int
    overrides: tuple[str, ...]
    n_envs: int | None = None  # None: the hyperparameter file's n_envs, else 1
    env_kwargs: dict[str, Any] = field(default_factory=dict)  # extra gym.make keyword arguments
    observation: str = "default"  # the design's label (design_label); the design is in env_kwargs
    randomization: str = "none"  # the training preset (randomization_label); in env_kwargs unless none

    @property
    def name(self) -> str:
        return run_name(
            self.task, self.action_mode, self.reward_type, self.algo, self.seed, self.observation, self.randomization
        )


@dataclass(frozen=True)
class Grid:
    name: str
    runs: tuple[RunSpec, ...]
    source: dict[str, Any]


def _list(path: Path, doc: dict, key: str, kind: type) -> list:
    value = doc[key]
    if (
        not isinstance(value, list)
        or not value
        or not all(isinstance(v, kind) and not isinstance(v, bool) for v in value)
    ):
        raise GridError(f"{path}: grid key {key!r} must be a non-empty list of {kind.__name__}, got {value!r}")
    return value


def load_grid(path: Path, *, datasets: bool = True) -> Grid:
    """Read and fully validate a grid file; raise :class:`GridError` on any problem.

    ``datasets=False`` reads the grid of runs already trained (a committed experiment, a
    bench's ``--collect``): everything is checked but that the demonstration datasets it
    names are on this machine."""
    path = Path(path)
    if not path.is_file():
        raise GridError(f"grid file {path} not found")
    try:
        doc = load_mapping(path, f"a mapping with keys {', '.join(REQUIRED)}")
    except YamlFileError as err:
        raise GridError(str(err)) from None
    missing = [k for k in REQUIRED if k not in doc]
    if missing:
        raise GridError(f"{path}: missing grid key(s) {', '.join(missing)}; required: {', '.join(REQUIRED)}")
    unknown = [k for k in doc if k not in REQUIRED + OPTIONAL]
    if unknown:
        raise GridError(
            f"{path}: unknown grid key(s) {', '.join(map(repr, unknown))}; expected {', '.join(REQUIRED + OPTIONAL)}"
        )
    name = doc.get("name", path.stem)
    if not _plain_name(name):
        raise GridError(
            f"{path}: name {name!r} must be a plain directory name (no '/', '\\', '..' or absolute path): "
            "the bench writes to results/<name>"
        )
    try:  # a named list (metaworld:MT10) stands for its IDs
        tasks = expand_task_lists(_list(path, doc, "tasks", str))
    except ValueError as err:
        raise GridError(f"{path}: {err}") from None
    _check(path, get_task, tasks)  # the registry's and EnvConfig's own checks and words
    rewards = _list(path, doc, "reward_types", str)
    _check(path, validate_reward_type, rewards)
    algos = _list(path, doc, "algos", str)
    for a in algos:
        if a not in ALGOS:
            raise GridError(f"{path}: unknown algorithm {a!r}; expected one of {', '.join(ALGOS)}")
    seeds = _list(path, doc, "seeds", int)
    steps = _per_key(path, "steps", doc["steps"], tasks, "tasks")
    modes_value = doc["action_modes"]
    if modes_value != "all":
        modes = _list(path, doc, "action_modes", str)
        try:
            for t, m in itertools.product(tasks, modes):
                TASKS[t].check_choices(m, rewards[0])
        except ValueError as err:
            raise GridError(f"{path}: {err} (or action_modes: all)") from None
    overrides = doc.get("overrides") or {}
    if not isinstance(overrides, dict) or any(a not in algos or not isinstance(v, list) for a, v in overrides.items()):
        raise GridError(f"{path}: overrides must map algorithms of the grid to lists of key=value strings")
    run_settings = []
    for key in ("eval_freq", "n_eval_episodes"):
        if key in doc:
            if not isinstance(doc[key], int) or doc[key] <= 0:
                raise GridError(f"{path}: {key} must be a positive integer, got {doc[key]!r}")
            run_settings.append(f"{key}={doc[key]}")
    # Not given: each run takes its hyperparameter file's n_envs (else 1).
    n_envs = _per_key(path, "n_envs", doc["n_envs"], algos, "algorithms") if "n_envs" in doc else dict.fromkeys(algos)
    from unified_manip.experiments.targets import TargetError, parse_targets

    try:  # the report marks each target met or missed
        parse_targets(doc.get("targets"), str(path))
    except TargetError as err:
        raise GridError(str(err)) from None
    env_kwargs = _env_kwargs(path, doc.get("env_kwargs", {}))
    try:
        observations = parse_designs(doc.get("observations", ["default"]))
    except ValueError as err:
        raise GridError(f"{path}: {err}") from None
    try:
        randomizations = grid_randomizations(doc, env_kwargs)
    except ValueError as err:
        raise GridError(f"{path}: {err}") from None
    try:
        only = parse_only_cells(doc.get("only"))
        cell_overrides = parse_cell_overrides(doc.get("cell_overrides", []))
    except ValueError as err:
        raise GridError(f"{path}: {err}") from None
    runs = []
    used: set[int] = set()  # the cell_overrides entries that match a run
    checked: set[tuple[str, str]] = set()
    for t, r, a, s, o, z in itertools.product(tasks, rewards, algos, seeds, observations, randomizations):
        for m in TASKS[t].action_modes if modes_value == "all" else modes:
            combo = {"task": t, "action_mode": m, "reward_type": r, "algo": a}
            if only is not None and not any(in_cell(combo, e) for e in only):
                continue
            sets = tuple(run_settings + list(overrides.get(a, [])))
            matching = [i for i, (cell, _) in enumerate(cell_overrides) if in_cell(combo, cell)]
            used.update(matching)
            sets += tuple(v for i in matching for v in cell_overrides[i][1])
            kwargs = {**env_kwargs, **o, **({"randomization": z} if z != "none" and "randomizations" in doc else {})}
            try:  # every hyperparameter override is checked before anything starts
                resolved = resolve_run(a, t, sets, action_mode=m)
                run = replace(resolved.run, n_envs=n_envs[a] or resolved.run.n_envs)
                check_her_warmup(a, resolved.algo_kwargs, run, TASKS[t].max_episode_steps)
                check_demonstration_settings(
                    t, m, ALGOS[a].off_policy, run, {"action_mode": m, "reward_type": r, **kwargs}, datasets=datasets
                )
                options = env_kwargs.get("controller_options")
                EnvConfig(action_mode=m, controller_options=options).mode_config(TASKS[t].controllers)
                if (t, design_label(o)) not in checked:  # the task's groups (one backend per task)
                    check_design(t, m, o)
                    checked.add((t, design_label(o)))
                if (t, z) not in checked:  # a preset with no term the task takes fails here, not in a run
                    check_randomization(t, m, kwargs.get("randomization", "none"))
                    checked.add((t, z))
            except (TypeError, ValueError) as err:
                raise GridError(f"{path}: {err}") from None
            runs.append(RunSpec(t, m, r, a, s, steps[t], sets, n_envs[a], kwargs, design_label(kwargs), z))
    if not runs:
        raise GridError(f"{path}: the grid selects no runs")
    unused = [cell for i, (cell, _) in enumerate(cell_overrides) if i not in used]
    if unused:
        raise GridError(
            f"{path}: cell_overrides entry {unused[0]} matches no run of the grid (its tasks: {', '.join(tasks)})"
        )
    return Grid(name, tuple(runs), doc)


#: What the run itself sets, so a grid's env_kwargs may not.
_RUN_ENV_KEYS = ("action_mode", "reward_type", "render_mode")


def _env_kwargs(path: Path, value: Any) -> dict[str, Any]:
    """A grid's ``env_kwargs``: extra ``gym.make`` keyword arguments for every run (the
    zoo's ``env_kwargs``), e.g. ``{controller_options: {band: 0.75}}``."""
    if not isinstance(value, dict) or not all(isinstance(k, str) for k in value):
        raise GridError(f"{path}: env_kwargs must be a mapping of gym.make keyword arguments, got {value!r}")
    fixed = [k for k in value if k in _RUN_ENV_KEYS]
    if fixed:
        raise GridError(f"{path}: env_kwargs may not set {fixed[0]!r}; the grid's own keys choose it")
    return dict(value)


def _check(path: Path, check, values: list) -> None:
    try:
        for value in values:
            check(value)
    except ValueError as err:
        raise GridError(f"{path}: {err}") from None


def _plain_name(name: object) -> bool:
    """A name that stays one directory below where it is joined (no separators, no '..')."""
    return isinstance(name, str) and name not in ("", ".", "..") and not any(c in name for c in "/\\\0")


def selected(grid: Grid, select: tuple[str, ...]) -> set[str] | None:
    """Names of the runs matching every ``key=value`` of ``select`` (None: no selection).

    ``unified-manip bench --only algo=ppo`` trains just those runs now; results.csv still
    holds every finished run of the grid, so a grid can be run in the order a study needs.
    """
    if not select:
        return None
    try:
        wanted = parse_only(select)
    except ValueError as err:
        raise GridError(str(err)) from None
    names = {r.name for r in grid.runs if matches(vars(r), wanted)}
    if not names:
        raise GridError(f"--only {' '.join(select)} selects none of the grid's {len(grid.runs)} runs")
    return names


def _per_key(path: Path, name: str, value: Any, keys: list[str], what: str) -> dict[str, int]:
    """A positive integer for every key: one for all, or a mapping of keys (and ``default``).

    ``steps`` is keyed by task ID, ``n_envs`` by algorithm (PPO with parallel envs beside
    single-env SAC in one grid)."""

    def positive(v: Any) -> bool:
        return isinstance(v, int) and not isinstance(v, bool) and v > 0

    if positive(value):
        return {k: value for k in keys}
    if not isinstance(value, dict):
        raise GridError(
            f"{path}: {name} must be a positive integer, got {value!r} (or a mapping of the grid's {what} to one)"
        )
    unknown = [k for k in value if k != "default" and k not in keys]
    if unknown:
        raise GridError(f"{path}: {name} names {unknown[0]!r}, which is not one of the grid's {what} (or 'default')")
    bad = [k for k, v in value.items() if not positive(v)]
    if bad:
        raise GridError(f"{path}: {name} for {bad[0]!r} must be a positive integer, got {value[bad[0]]!r}")
    missing = [k for k in keys if k not in value and "default" not in value]
    if missing:
        raise GridError(f"{path}: {name} gives no value for {missing[0]!r}; add it or a 'default'")
    return {k: value.get(k, value.get("default")) for k in keys}
