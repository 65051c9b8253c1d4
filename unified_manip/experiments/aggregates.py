"""Cross-task aggregates per action mode, with rliable (Agarwal et al. 2021).

A bench that runs several action modes on several tasks asks which mode is better across
tasks, not on one. Following rliable, each mode's runs form a ``runs x tasks`` matrix of
scores (success rates, already on a common 0-1 scale), and:

* :func:`iqm_intervals`: the interquartile mean over all runs of all tasks, with a
  stratified bootstrap interval (runs resampled within each task);
* :func:`performance_profiles`: the fraction of runs whose score exceeds each threshold,
  with its stratified bootstrap band;
* :func:`improvement_intervals`: P(X > Y) of each mode over each other, the Mann-Whitney
  probability within each task averaged over tasks;
* :func:`curve_auc` and :func:`~unified_manip.experiments.targets.steps_to`: sample
  efficiency from each run's evaluation curve;
* :func:`rank_table`: each mode's rank by mean final success on each task.

rliable's bootstraps draw from numpy's global generator; each one here is seeded
(:func:`~unified_manip.experiments.stats.seeded_global_numpy`), so a report is the same
every time it is made.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass
from typing import Any

import numpy as np

from unified_manip.experiments.stats import CONFIDENCE, iqm, score_distributions, seeded_global_numpy
from unified_manip.experiments.targets import steps_to

#: Success a run must reach for the "steps to" sample-efficiency column.
STEPS_THRESHOLD = 0.8
#: Bootstrap resamples of every aggregate interval, and the seed they are drawn with.
REPS = 2000
SEED = 0
#: Fewest runs of every mode on every task for an aggregate interval: a stratified bootstrap
#: resamples runs within each task, so with one run per task it has nothing to resample.
MIN_RUNS_PER_TASK_FOR_CI = 2
#: Thresholds the performance profiles are evaluated at.
TAUS = np.linspace(0.0, 1.0, 41)


@dataclass(frozen=True)
class ModeScores:
    """One setting's (algorithm and reward) runs, by action mode, over the tasks every
    included mode was run on.

    ``final[mode]`` and ``auc[mode]`` are ``runs x tasks`` arrays (column ``j`` is
    ``tasks[j]``; rows are runs in seed order, as many per task as the mode's fewest on any
    task); ``steps[mode][j]`` holds each of those runs' steps to :data:`STEPS_THRESHOLD`
    (None where never reached). ``runs[mode]`` is (runs per task, runs left out beyond that
    on tasks with more); ``left_out`` names the modes missing from some task, and which.
    """

    tasks: tuple[str, ...]
    modes: tuple[str, ...]
    final: dict[str, np.ndarray]
    auc: dict[str, np.ndarray]
    steps: dict[str, list[list[int | None]]]
    runs: dict[str, tuple[int, int]]
    left_out: dict[str, tuple[str, ...]]


def curve_auc(curve: list[list[float]]) -> float:
    """Normalised area under a run's evaluation curve: the trapezoid area between its first
    and last evaluation divided by the steps between them, i.e. the mean success over the
    steps evaluated (in [0, 1]); the one value of a one-point curve."""
    from scipy.integrate import trapezoid

    points = np.asarray(curve, dtype=float).reshape(-1, 2)
    if len(points) == 0:
        raise ValueError("curve_auc needs at least one evaluation point, got an empty curve")
    if len(points) == 1:
        return float(points[0, 1])
    return float(trapezoid(points[:, 1], points[:, 0]) / (points[-1, 0] - points[0, 0]))


def settings(rows: list[dict[str, Any]]) -> dict[tuple[str, str], list[dict[str, Any]]]:
    """Result rows by (algorithm, reward type), the settings aggregates are made within."""
    out: dict[tuple[str, str], list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        out[(r["algo"], r["reward_type"])].append(r)
    return dict(sorted(out.items()))


#: What an aggregate compares, and what else tells its problems apart besides the task.
FACTORS = {"action_mode": "observation", "observation": "action_mode"}


def mode_scores(rows: list[dict[str, Any]], factor: str = "action_mode") -> ModeScores:
    """The score matrices of one setting's rows (see :class:`ModeScores`), comparing the
    values of ``factor`` (a key of :data:`FACTORS`). Its problems are the tasks; where the
    rows' other factor varies within a task, each (task, other factor) pair is a problem of its own,
    named ``"<task> (<value>)"``: observation designs on tasks run in different action modes.
    Rows of several training randomisations make each (problem, randomisation) a problem of
    its own, ``"<task> [randomization <preset>]"``."""
    other = FACTORS[factor]
    values: dict[str, set[str]] = defaultdict(set)
    for r in rows:
        values[r["task"]].add(r.get(other) or "default")
    split = any(len(v) > 1 for v in values.values())
    randomized = len({r.get("randomization") or "none" for r in rows}) > 1

    def problem(r: dict[str, Any]) -> str:
        name = f"{r['task']} ({r.get(other) or 'default'})" if split else r["task"]
        return f"{name} [randomization {r.get('randomization') or 'none'}]" if randomized else name

    cells: dict[str, dict[str, list[dict[str, Any]]]] = defaultdict(lambda: defaultdict(list))
    for r in rows:
        cells[r.get(factor) or "default"][problem(r)].append(r)
    tasks = tuple(sorted({problem(r) for r in rows}))
    left_out = {m: tuple(t for t in tasks if t not in by_task) for m, by_task in cells.items()}
    left_out = {m: missing for m, missing in sorted(left_out.items()) if missing}
    modes = tuple(sorted(m for m in cells if m not in left_out))
    final, auc, steps, kept = {}, {}, {}, {}
    for m in modes:
        n = min(len(cells[m][t]) for t in tasks)
        runs = [sorted(cells[m][t], key=lambda r: r["seed"])[:n] for t in tasks]
        final[m] = np.array([[r["final_success_rate"] for r in col] for col in runs]).T
        auc[m] = np.array([[curve_auc(r["curve"]) for r in col] for col in runs]).T
        steps[m] = [[steps_to(r["curve"], STEPS_THRESHOLD) for r in col] for col in runs]
        kept[m] = (n, sum(len(cells[m][t]) - n for t in tasks))
    return ModeScores(tasks, modes, final, auc, steps, kept, left_out)


def iqm_intervals(scores: dict[str, np.ndarray], seed: int = SEED) -> dict[str, tuple[float, float, float]]:
    """``mode -> (IQM, low, high)``: rliable's interquartile mean over all runs and tasks,
    with its 95% stratified-bootstrap interval."""
    from rliable import library as rly

    with seeded_global_numpy(seed):
        point, interval = rly.get_interval_estimates(
            scores, lambda s: np.array([iqm(s)]), reps=REPS, confidence_interval_size=CONFIDENCE
        )
    return {m: (float(point[m][0]), float(interval[m][0, 0]), float(interval[m][1, 0])) for m in scores}


def performance_profiles(
    scores: dict[str, np.ndarray], taus: np.ndarray = TAUS, seed: int = SEED
) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """rliable's score distributions: ``mode -> fraction of runs scoring above each tau``,
    and ``mode -> (2, len(taus))`` 95% stratified-bootstrap bands."""
    from rliable import library as rly

    with seeded_global_numpy(seed):
        return rly.create_performance_profile(
            scores, taus, custom_profile_func=score_distributions, reps=REPS, confidence_interval_size=CONFIDENCE
        )


def probability_of_improvement(x: np.ndarray, y: np.ndarray) -> float:
    """rliable's ``metrics.probability_of_improvement`` (runs x tasks arrays: the
    Mann-Whitney U statistic of each task over its run pairs, ties half, averaged over
    tasks), in numpy: rliable's calls scipy once per task, which made 2,000 bootstrap
    resamples of 28 mode pairs take minutes."""
    greater = (x[:, None, :] > y[None, :, :]).mean(axis=(0, 1))
    ties = (x[:, None, :] == y[None, :, :]).mean(axis=(0, 1))
    return float(np.mean(greater + 0.5 * ties))


def improvement_intervals(
    scores: dict[str, np.ndarray], seed: int = SEED
) -> dict[tuple[str, str], tuple[float, float, float]]:
    """``(x, y) -> (P(X > Y), low, high)``: :func:`probability_of_improvement` with rliable's 95%
    stratified-bootstrap interval (each mode's runs resampled within each task). Each
    unordered pair is bootstrapped once; ``(y, x)`` is its complement, ``1 - p`` with the
    interval ``[1 - high, 1 - low]``, as ties count half."""
    from rliable import library as rly

    names = list(scores)
    pairs = {f"{x},{y}": (scores[x], scores[y]) for i, x in enumerate(names) for y in names[i + 1 :]}
    if not pairs:
        return {}
    with seeded_global_numpy(seed):
        point, interval = rly.get_interval_estimates(
            pairs, probability_of_improvement, reps=REPS, confidence_interval_size=CONFIDENCE
        )
    out: dict[tuple[str, str], tuple[float, float, float]] = {}
    for key in pairs:
        x, y = key.split(",")
        # rliable gives each estimate and bound as a one-element array.
        p, low, high = (float(np.asarray(v).item()) for v in (point[key], interval[key][0], interval[key][1]))
        out[(x, y)] = (p, low, high)
        out[(y, x)] = (1.0 - p, 1.0 - high, 1.0 - low)
    return out


def rank_table(scores: dict[str, np.ndarray]) -> dict[str, tuple[np.ndarray, float]]:
    """``mode -> (rank on each task, mean rank)``: rank 1 has the highest mean final success
    on that task; tied modes share the mean of their ranks."""
    from scipy.stats import rankdata

    modes = list(scores)
    # Rounded: means equal in exact arithmetic can differ in the last bit ((0.2 + 0.4) / 2
    # against 0.3) and must tie.
    means = np.round([scores[m].mean(axis=0) for m in modes], 9)  # modes x tasks
    ranks = np.column_stack([rankdata(-means[:, j], method="average") for j in range(means.shape[1])])
    return {m: (ranks[i], float(ranks[i].mean())) for i, m in enumerate(modes)}
