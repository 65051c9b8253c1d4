"""``unified-manip robustness BENCH``: every finished run's final policy evaluated again
under observation noise and delay, and on test distributions of domain randomisation
(``default``, ``in-range``, ``extreme``: Packer et al. 2018), without retraining.

Each (run, condition) is evaluated with :func:`~unified_manip.training.evaluation.evaluate`
on the run's ``final_model.zip`` (the policy the run ended with, not its best checkpoint),
its own env settings otherwise, and written to ``BENCH/robustness.csv`` atomically as soon as
it is done, so an interrupted pass resumes where it stopped. The report reads the file
(:func:`robustness_section`). Noise is a standard deviation in each observation group's own
units (metres for positions, radians for joint angles); a condition's noise and delay replace
the run's own, and the rest of its design (groups, distractors) stays. A condition's test
distribution replaces the run's training randomisation
(:func:`~unified_manip.training.evaluation.evaluated_randomization`: the ranges come from
``--randomization`` or the run's own preset); without one the run's own stays. Each row
records the run's training randomisation, the distribution and the randomisation it was
tested under; a ``robustness.csv`` written before these columns reads as ``none``.
"""

from __future__ import annotations

import csv
import os
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Callable

from unified_manip.envs.randomization import TEST_DISTRIBUTIONS, randomization_label
from unified_manip.experiments.factors import SHIFTED, applied_terms
from unified_manip.experiments.results import collect_row
from unified_manip.experiments.selection import matches, parse_only

FILE = "robustness.csv"
COLUMNS = (
    "run",
    "task",
    "action_mode",
    "observation",
    "algo",
    "seed",
    "randomization",
    "noise",
    "delay",
    "distribution",
    "tested",
    "factor",
    "episodes",
    "successes",
    "success_rate",
    "ci_low",
    "ci_high",
)
#: The default conditions: observation noise of 0, 0.5 and 1 cm, and a one-step delay.
NOISES = (0.0, 0.005, 0.01)
DELAYS = (1,)


class RobustnessError(ValueError):
    """A bench directory that cannot be evaluated (one-line error)."""


@dataclass(frozen=True)
class Condition:
    noise: float
    delay: int
    distribution: str = ""  # a test distribution (TEST_DISTRIBUTIONS); "": the run's own randomisation
    factor: str = ""  # one term of the distribution's (``entity.field``) alone; "": all of them

    @property
    def label(self) -> str:
        if self.delay:
            perturbation = f"delay {self.delay}" + (f", noise {self.noise:g}" if self.noise else "")
        else:
            perturbation = f"noise {self.noise:g}"
        if not self.distribution:
            return perturbation
        label = self.distribution + (f": {self.factor} only" if self.factor else "")
        return label + (f", {perturbation}" if self.delay or self.noise else "")

    @property
    def order(self) -> tuple:
        """Where the condition's column goes: by distribution, its factors after it, then no
        delay first, by noise."""
        return (_DISTRIBUTION_ORDER.index(self.distribution), self.factor, self.delay, self.noise)


_DISTRIBUTION_ORDER = ("", *TEST_DISTRIBUTIONS)


def conditions(
    noises: tuple[float, ...] = NOISES, delays: tuple[int, ...] = DELAYS, distributions: tuple[str, ...] = ("",)
) -> list[Condition]:
    """On each test distribution (``""``: the run's own randomisation), each noise level
    without delay, then each delay without noise."""
    bad = [n for n in noises if not n >= 0.0] + [d for d in delays if d < 1]
    if bad:
        raise RobustnessError(f"noise levels must be >= 0 and delays >= 1 step; got {bad[0]!r}")
    unknown = [d for d in distributions if d not in _DISTRIBUTION_ORDER]
    if unknown:
        raise RobustnessError(
            f"unknown test distribution {unknown[0]!r}; expected one of {', '.join(TEST_DISTRIBUTIONS)}"
        )
    return [
        c
        for z in distributions
        for c in [Condition(float(n), 0, z) for n in noises] + [Condition(0.0, int(d), z) for d in delays]
    ]


def read_robustness(path: Path) -> list[dict[str, Any]]:
    """The rows of a ``robustness.csv``, typed (none if there is no file)."""
    if not Path(path).is_file():
        return []
    with Path(path).open(newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        r["randomization"] = r.get("randomization") or "none"  # files from before randomisation
        r["distribution"] = r.get("distribution") or ""
        r["tested"] = r.get("tested") or r["randomization"]
        r["factor"] = r.get("factor") or ""  # files from before factors
        for k in ("seed", "delay", "episodes", "successes"):
            r[k] = int(r[k])
        for k in ("noise", "success_rate", "ci_low", "ci_high"):
            r[k] = float(r[k])
    return rows


def _write(path: Path, rows: list[dict[str, Any]]) -> None:
    tmp = path.with_name(path.name + ".tmp")
    with tmp.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS)
        writer.writeheader()
        for row in sorted(rows, key=lambda r: (r["run"], condition_of(r).order, r["tested"])):
            writer.writerow({k: row[k] for k in COLUMNS})
    os.replace(tmp, path)


def evaluate_bench(
    bench: Path,
    wanted: list[Condition],
    episodes: int = 50,
    seed: int = 123,
    progress: Callable[[str], None] | None = None,
    randomization: str | None = None,
    factors: bool = False,
    select: tuple[str, ...] = (),
) -> Path:
    """Evaluate every finished run of ``bench`` under each condition not yet in its
    ``robustness.csv``; return the file's path. ``randomization``: the preset whose ranges
    the test distributions take (default: each run's own training preset). ``factors``:
    also each term of a shifted distribution alone (one factor at a time), every term that
    applies to the run's task, as an extra condition of that distribution (without noise
    or delay). ``select``: ``--only KEY=VALUE`` items; only the runs matching them."""
    from unified_manip.training.evaluation import evaluate, evaluated_randomization
    from unified_manip.training.request import TrainError
    from unified_manip.training.rundir import read_config

    runs_dir = Path(bench) / "runs"
    if not runs_dir.is_dir():
        raise RobustnessError(f"{bench} has no runs/ directory; expected a bench's output directory")
    try:
        wanted_runs = parse_only(select)
    except ValueError as err:
        raise RobustnessError(str(err)) from None
    finished = [(d, row) for d in sorted(runs_dir.iterdir()) if (row := collect_row(d)) is not None]
    if not finished:
        raise RobustnessError(f"{runs_dir} holds no finished run")
    finished = [(d, row) for d, row in finished if matches(row, wanted_runs)]
    if not finished:
        raise RobustnessError(f"--only {' '.join(select)} selects none of the finished runs in {runs_dir}")
    missing = [d.name for d, _ in finished if not (d / "final_model.zip").is_file()]
    if missing:
        raise RobustnessError(
            f"{runs_dir / missing[0]} has no final_model.zip (committed results carry no models); evaluate the "
            "bench directory the runs trained in"
        )
    path = Path(bench) / FILE
    rows = read_robustness(path)
    done = {(r["run"], r["noise"], r["delay"], r["distribution"], r["tested"], r["factor"]) for r in rows}
    todo = []
    for d, row in finished:  # every run's test distributions resolve before any evaluation
        config = read_config(d)
        trained = config["env_kwargs"].get("randomization")
        for c in wanted:
            try:
                tested = evaluated_randomization(trained, randomization, c.distribution or None)
            except TrainError as err:
                raise RobustnessError(f"{d.name}: {err}") from None
            plain = c.distribution in SHIFTED and not c.noise and not c.delay
            alone = applied_terms(config, tested) if factors and plain else ()
            for term in (None, *alone):
                cond = replace(c, factor=term.label) if term else c
                if (d.name, c.noise, c.delay, c.distribution, randomization_label(tested), cond.factor) not in done:
                    todo.append((d, row, cond, tested, term))
    for i, (run_dir, row, c, tested, term) in enumerate(todo, 1):
        if progress:
            progress(f"[{i}/{len(todo)}] {run_dir.name}: {c.label}")
        try:
            result = evaluate(
                run_dir / "final_model.zip",
                episodes,
                seed=seed,
                observation_noise=c.noise,
                observation_delay=c.delay,
                randomization=tested if term is None else (term,),
            )
        except TrainError as err:  # a preset none of whose terms the run's task takes
            raise RobustnessError(f"{run_dir.name}: {err}") from None
        rows.append(
            {
                **{k: row[k] for k in ("run", "task", "action_mode", "observation", "algo", "seed", "randomization")},
                "noise": c.noise,
                "delay": c.delay,
                "distribution": c.distribution,
                "tested": randomization_label(tested),
                "factor": c.factor,
                **{k: getattr(result, k) for k in ("episodes", "successes", "success_rate", "ci_low", "ci_high")},
            }
        )
        _write(path, rows)
    if not path.is_file():
        _write(path, rows)
    return path


def condition_of(row: dict[str, Any]) -> Condition:
    """The condition a row of ``robustness.csv`` was evaluated under."""
    return Condition(row["noise"], row["delay"], row["distribution"], row["factor"])
