"""``unified-manip bench``: a grid of training runs, on this machine or a Ray cluster.

A grid file (``baselines/grids/*.yaml``) lists tasks x action modes x reward types x
algorithms x seeds, the budget and the evaluation schedule::

    name: action_spaces
    tasks: [UnifiedManip/Arm4Reach-v0, UnifiedManip/FetchReach-v0]
    action_modes: all              # or a list; "all" = every mode each task supports
    reward_types: [sparse]
    algos: [sac_her]
    seeds: [0, 1, 2]
    steps: 10000                   # env steps per run, or {default: N, <task ID>: N, ...}
    n_envs: {default: 1, ppo: 8}   # optional: envs per run (or one number), by algorithm
    eval_freq: 1000                # env steps between evaluations
    n_eval_episodes: 20
    overrides: {sac_her: [learning_starts=500]}   # optional, per algorithm
    only:                          # optional: keep just the combinations matching an entry
      - {algo: ppo, reward_type: sparse}
    targets:                       # optional: final success the report checks
      - {task: UnifiedManip/Arm4Reach-v0, action_mode: ee_delta, success: 0.95}

Each run is the ``train`` command's run, in ``<out>/runs/<run name>``. Re-running a bench
skips finished runs and resumes unfinished ones from their checkpoints. One bench at a
time owns ``<out>`` (a second is refused), and the worker that trains a run owns that
run's directory, so a retried run never writes beside an attempt still alive. A run that
crashes is retried up to ``retries`` times and then recorded as failed with its error;
it never blocks the rest. ``<out>/results.csv`` gets one row per *finished* run, and is
rewritten atomically after every run, so it never holds a half-written run.
"""

from __future__ import annotations

import csv
import itertools
import json
import os
import time
import traceback
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

import numpy as np
import yaml

from .config import REWARD_TYPES
from .hyperparams import ALGOS, get_algo, resolve
from .registry import TASKS
from .runlock import DirectoryLock
from .yamlfile import YamlFileError, load_mapping

#: How long a run waits for its directory when another process still owns it (an
#: earlier attempt on a Ray node that has not noticed it was given up on, or a stray
#: ``train``) before it is refused and counted as a failed attempt.
RUN_LOCK_WAIT_S = 60.0

REQUIRED = ("tasks", "action_modes", "reward_types", "algos", "seeds", "steps")
OPTIONAL = ("name", "description", "eval_freq", "n_eval_episodes", "overrides", "n_envs", "only", "targets")
ONLY_KEYS = ("task", "action_mode", "reward_type", "algo")
RESULT_COLUMNS = (
    "run", "task", "action_mode", "reward_type", "algo", "seed", "steps", "final_success_rate",
    "curve", "wall_time_s", "steps_per_s", "versions",
)


class GridError(ValueError):
    """A grid file is malformed (reported before any run starts)."""


class ResultsError(ValueError):
    """A ``results.csv`` that is not a bench's (one-line error)."""


@dataclass(frozen=True)
class RunSpec:
    task: str
    action_mode: str
    reward_type: str
    algo: str
    seed: int
    steps: int
    overrides: tuple[str, ...]
    n_envs: int = 1

    @property
    def name(self) -> str:
        return f"{self.task.split('/')[-1]}__{self.action_mode}__{self.reward_type}__{self.algo}__s{self.seed}"


@dataclass(frozen=True)
class Grid:
    name: str
    runs: tuple[RunSpec, ...]
    source: dict[str, Any]


def _list(path: Path, doc: dict, key: str, kind: type) -> list:
    value = doc[key]
    if not isinstance(value, list) or not value or not all(isinstance(v, kind) and not isinstance(v, bool) for v in value):
        raise GridError(f"{path}: grid key {key!r} must be a non-empty list of {kind.__name__}, got {value!r}")
    return value


def load_grid(path: Path) -> Grid:
    """Read and fully validate a grid file; raise :class:`GridError` on any problem."""
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
            "the bench writes to baselines/results/<name>"
        )
    tasks = _list(path, doc, "tasks", str)
    for t in tasks:
        if t not in TASKS:
            raise GridError(f"{path}: unknown task {t!r}; expected one of {', '.join(TASKS)}")
    rewards = _list(path, doc, "reward_types", str)
    for r in rewards:
        if r not in REWARD_TYPES:
            raise GridError(f"{path}: unknown reward type {r!r}; expected one of {', '.join(REWARD_TYPES)}")
    algos = _list(path, doc, "algos", str)
    for a in algos:
        if a not in ALGOS:
            raise GridError(f"{path}: unknown algorithm {a!r}; expected one of {', '.join(ALGOS)}")
    seeds = _list(path, doc, "seeds", int)
    steps = _per_key(path, "steps", doc["steps"], tasks, "tasks")
    modes_value = doc["action_modes"]
    if modes_value != "all":
        modes = _list(path, doc, "action_modes", str)
        for t in tasks:
            unsupported = [m for m in modes if m not in TASKS[t].action_modes]
            if unsupported:
                raise GridError(
                    f"{path}: action mode {unsupported[0]!r} is not supported by {t}; "
                    f"expected one of {', '.join(TASKS[t].action_modes)} (or action_modes: all)"
                )
    overrides = doc.get("overrides") or {}
    if not isinstance(overrides, dict) or any(a not in algos or not isinstance(v, list) for a, v in overrides.items()):
        raise GridError(f"{path}: overrides must map algorithms of the grid to lists of key=value strings")
    run_settings = []
    for key in ("eval_freq", "n_eval_episodes"):
        if key in doc:
            if not isinstance(doc[key], int) or doc[key] <= 0:
                raise GridError(f"{path}: {key} must be a positive integer, got {doc[key]!r}")
            run_settings.append(f"{key}={doc[key]}")
    n_envs = _per_key(path, "n_envs", doc.get("n_envs", 1), algos, "algorithms")
    from .benchmark import TargetError, parse_targets

    try:  # the report marks each target met or missed
        parse_targets(doc.get("targets"), str(path))
    except TargetError as err:
        raise GridError(str(err)) from None
    only = doc.get("only")
    if only is not None:
        if not isinstance(only, list) or not only or not all(isinstance(e, dict) and e for e in only):
            raise GridError(f"{path}: only must be a non-empty list of mappings with keys from {', '.join(ONLY_KEYS)}")
        for entry in only:
            bad = [k for k in entry if k not in ONLY_KEYS]
            if bad:
                raise GridError(f"{path}: unknown key {bad[0]!r} in only; expected {', '.join(ONLY_KEYS)}")
    runs = []
    for t, r, a, s in itertools.product(tasks, rewards, algos, seeds):
        for m in TASKS[t].action_modes if modes_value == "all" else modes:
            combo = {"task": t, "action_mode": m, "reward_type": r, "algo": a}
            if only is not None and not any(all(combo[k] == v for k, v in e.items()) for e in only):
                continue
            sets = tuple(run_settings + list(overrides.get(a, [])))
            try:  # every hyperparameter override is checked before anything starts
                resolve(a, t, sets)
            except ValueError as err:
                raise GridError(f"{path}: {err}") from None
            runs.append(RunSpec(t, m, r, a, s, steps[t], sets, n_envs[a]))
    if not runs:
        raise GridError(f"{path}: the grid selects no runs")
    return Grid(name, tuple(runs), doc)


def _plain_name(name: object) -> bool:
    """A name that stays one directory below where it is joined (no separators, no '..')."""
    return isinstance(name, str) and name not in ("", ".", "..") and not any(c in name for c in "/\\\0")


SELECT_KEYS = ("task", "action_mode", "reward_type", "algo", "seed")


def selected(grid: Grid, select: tuple[str, ...]) -> set[str] | None:
    """Names of the runs matching every ``key=value`` of ``select`` (None: no selection).

    ``unified-manip bench --only algo=ppo`` trains just those runs now; results.csv still
    holds every finished run of the grid, so a grid can be run in the order a study needs.
    """
    if not select:
        return None
    wanted: dict[str, set[str]] = {}
    for item in select:
        key, sep, value = item.partition("=")
        if not sep or key not in SELECT_KEYS or not value:
            raise GridError(f"malformed --only {item!r}; expected KEY=VALUE with KEY one of {', '.join(SELECT_KEYS)}")
        wanted.setdefault(key, set()).add(value)
    names = {r.name for r in grid.runs if all(str(getattr(r, k)) in v for k, v in wanted.items())}
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
        raise GridError(f"{path}: {name} must be a positive integer, got {value!r} (or a mapping of the grid's {what} to one)")
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


# ---------------------------------------------------------------------- one run
def run_one(spec: RunSpec, out_dir: str, threads: int = 1, device: str | None = None) -> dict[str, Any]:
    """Train one run (resuming if needed) and return its results row. Runs in a worker."""
    from .train import TrainRequest, train

    run_dir = Path(out_dir) / "runs" / spec.name
    req = TrainRequest(
        env=spec.task, action_mode=spec.action_mode, reward_type=spec.reward_type, algo=spec.algo,
        steps=spec.steps, seed=spec.seed, n_envs=spec.n_envs, run_dir=run_dir, overrides=spec.overrides, device=device,
    )
    train(req, argv=None, progress=False, log=lambda msg: None, threads=threads, lock_wait_s=RUN_LOCK_WAIT_S)
    row = collect_row(run_dir)
    if row is None:
        raise RuntimeError(f"{run_dir} did not finish")
    return row


def collect_row(run_dir: Path) -> dict[str, Any] | None:
    """The results row of a finished run, or ``None`` if it is not finished."""
    from .train import CONFIG, read_status

    run_dir = Path(run_dir)
    status = read_status(run_dir)
    if not status or status.get("state") != "finished" or not (run_dir / "final_model.zip").is_file():
        return None
    config = yaml.safe_load((run_dir / CONFIG).read_text())
    evaluations = np.load(run_dir / "eval" / "evaluations.npz")
    steps = evaluations["timesteps"].tolist()
    success = evaluations["successes"].mean(axis=1).tolist() if "successes" in evaluations else [float("nan")] * len(steps)
    wall = float(status.get("wall_time_s", float("nan")))
    return {
        "run": run_dir.name,
        "task": config["env"],
        "action_mode": config["env_kwargs"]["action_mode"],
        "reward_type": config["env_kwargs"]["reward_type"],
        "algo": config["algo"],
        "seed": config["seed"],
        "steps": config["steps"],
        "final_success_rate": success[-1] if success else float("nan"),
        "curve": json.dumps([[int(t), float(s)] for t, s in zip(steps, success)]),
        "wall_time_s": wall,
        "steps_per_s": status["num_timesteps"] / wall if wall and wall == wall else float("nan"),
        "versions": json.dumps(config["versions"], sort_keys=True),
    }


def write_results(out_dir: Path, rows: list[dict[str, Any]]) -> Path:
    """Write ``results.csv`` (one row per finished run) atomically."""
    path = Path(out_dir) / "results.csv"
    tmp = path.with_name("results.csv.tmp")
    with tmp.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=RESULT_COLUMNS)
        writer.writeheader()
        for row in sorted(rows, key=lambda r: r["run"]):
            writer.writerow({k: row[k] for k in RESULT_COLUMNS})
    os.replace(tmp, path)
    return path


def read_results(path: Path) -> list[dict[str, Any]]:
    """The rows of a bench's ``results.csv``, typed.

    Raises:
        ResultsError: the file lacks the bench's columns or holds a value of the wrong
            type (the message names the file and line).
    """
    with Path(path).open(newline="") as f:
        reader = csv.DictReader(f)
        missing = [c for c in RESULT_COLUMNS if c not in (reader.fieldnames or ())]
        if missing:
            raise ResultsError(f"{path}: not a bench's results.csv; missing column(s) {', '.join(missing)}")
        rows = list(reader)
    for line, r in enumerate(rows, start=2):
        try:
            r["seed"] = int(r["seed"])
            r["steps"] = int(r["steps"])
            for k in ("final_success_rate", "wall_time_s", "steps_per_s"):
                r[k] = float(r[k])
            r["curve"] = json.loads(r["curve"])
            r["versions"] = json.loads(r["versions"])
        except (TypeError, ValueError) as err:
            raise ResultsError(f"{path}:{line}: malformed row ({err})") from None
    return rows


# ---------------------------------------------------------------------- executors
def _local_executor(workers: int):
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    return ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"), initializer=_ignore_sigint)


def _ignore_sigint() -> None:
    """Idle pool workers ignore Ctrl-C (the bench handles it); ``train`` turns it back on
    while a run learns, so a running run still checkpoints and stops."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)


def run_grid(
    grid: Grid,
    out_dir: Path,
    executor: str = "local",
    workers: int | None = None,
    address: str | None = None,
    retries: int = 1,
    progress: bool = True,
    command: str | None = None,
    on_event: Callable[[str, RunSpec], None] | None = None,
    device: str | None = None,
    select: tuple[str, ...] = (),
) -> dict[str, Any]:
    """Run every run of ``grid`` that is not finished yet; return a summary.

    ``device`` (auto, cpu or cuda) applies to every run; it is checked here, before any
    run starts, so ``cuda`` without a GPU fails once and not once per run.

    Raises :class:`~unified_manip.runlock.DirectoryInUse` if another bench owns ``out_dir``.
    """
    if device is not None:
        from .devices import DeviceError, resolve_device

        try:
            resolve_device(device)
        except DeviceError as err:
            raise GridError(str(err)) from None
    out_dir = Path(out_dir).resolve()
    with DirectoryLock(out_dir, "bench directory"):
        return _run_owned(grid, out_dir, executor, workers, address, retries, progress, command, on_event, device,
                          selected(grid, select))


def _run_owned(grid: Grid, out_dir: Path, executor: str, workers: int | None, address: str | None, retries: int,
               progress: bool, command: str | None, on_event, device: str | None,
               chosen: set[str] | None = None) -> dict[str, Any]:
    (out_dir / "grid.yaml").write_text(yaml.safe_dump(grid.source, sort_keys=False))
    if command:
        (out_dir / "command.txt").write_text(command + "\n")
    rows = {r["run"]: r for r in (collect_row(out_dir / "runs" / s.name) for s in grid.runs) if r}
    todo = [s for s in grid.runs if s.name not in rows and (chosen is None or s.name in chosen)]
    failures: dict[str, str] = {}
    attempts = {s.name: 0 for s in todo}
    write_results(out_dir, list(rows.values()))
    workers = workers or max(1, os.cpu_count() or 1)

    from tqdm import tqdm

    bar = tqdm(total=len(grid.runs), initial=len(rows), unit="run", desc=grid.name, disable=not progress, dynamic_ncols=True)
    started = time.time()

    def done(spec: RunSpec, row: dict | None, error: str | None) -> bool:
        """Record a finished attempt; return True if the run should be retried."""
        attempts[spec.name] += 1
        if row is not None:
            rows[spec.name] = row
            failures.pop(spec.name, None)
            write_results(out_dir, list(rows.values()))
            bar.update(1)
            if on_event:
                on_event("finished", spec)
            return False
        failures[spec.name] = error or "unknown error"
        _record_failure(out_dir, spec, failures[spec.name], attempts[spec.name])
        if on_event:
            on_event("failed", spec)
        return attempts[spec.name] <= retries

    def postfix(running: int) -> None:
        bar.set_postfix(running=running, failed=len(failures), refresh=True)

    if executor == "local":
        pool = _local_executor(workers)
        try:
            queue = list(todo)
            futures = {}
            while queue or futures:
                while queue and len(futures) < workers:
                    spec = queue.pop(0)
                    futures[pool.submit(run_one, spec, str(out_dir), 1, device)] = spec
                postfix(len(futures))
                from concurrent.futures import FIRST_COMPLETED, wait

                finished, _ = wait(list(futures), return_when=FIRST_COMPLETED)
                for fut in finished:
                    spec = futures.pop(fut)
                    try:
                        retry = done(spec, fut.result(), None)
                    except Exception as err:  # a crashed run must not stop the grid
                        retry = done(spec, None, "".join(traceback.format_exception_only(type(err), err)).strip())
                    if retry:
                        queue.append(spec)
        finally:
            pool.shutdown(cancel_futures=True)
    elif executor == "ray":
        import ray

        if not ray.is_initialized():
            ray.init(address=address, include_dashboard=False, log_to_driver=False, configure_logging=False)
        remote = ray.remote(num_cpus=1, max_retries=0)(run_one)
        queue = list(todo)
        pending = {}
        while queue or pending:
            while queue and len(pending) < workers:
                spec = queue.pop(0)
                pending[remote.remote(spec, str(out_dir), 1, device)] = spec
            postfix(len(pending))
            ready, _ = ray.wait(list(pending), num_returns=1)
            for ref in ready:
                spec = pending.pop(ref)
                try:
                    retry = done(spec, ray.get(ref), None)
                except Exception as err:
                    cause = getattr(err, "cause", None) or err
                    retry = done(spec, None, f"{type(cause).__name__}: {cause}".splitlines()[0])
                if retry:
                    queue.append(spec)
    else:
        raise GridError(f"unknown executor {executor!r}; expected 'local' or 'ray'")
    postfix(0)
    bar.close()
    return {
        "runs": len(grid.runs),
        "finished": len(rows),
        "failed": sorted(failures),
        "wall_time_s": time.time() - started,
        "results": str(out_dir / "results.csv"),
    }


def _record_failure(out_dir: Path, spec: RunSpec, error: str, attempt: int) -> None:
    with (Path(out_dir) / "failures.jsonl").open("a") as f:
        f.write(json.dumps({"run": spec.name, "attempt": attempt, "error": error, "time": time.time()}) + "\n")
