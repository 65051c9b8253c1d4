"""A bench's ``results.csv``: one row per finished run, written atomically after every
run, and read back typed (for ``unified-manip report``)."""

from __future__ import annotations

import csv
import json
import os
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from unified_manip.envs.design_names import design_label
from unified_manip.envs.randomization.presets import randomization_label
from unified_manip.training.rundir import CONFIG, read_status
from unified_manip.training.settings import demonstration_record

RESULT_COLUMNS = (
    "run",
    "task",
    "action_mode",
    "reward_type",
    "algo",
    "seed",
    "steps",
    "final_success_rate",
    "curve",
    "wall_time_s",
    "steps_per_s",
    "versions",
)
#: Written by the bench, absent from older files: the run's ``demonstrations.json``
#: (episodes, transitions, success of the scripted episodes it started with, and its
#: demonstration settings under their hyperparameter names), JSON or "". Read back with
#: every setting under its own name (older records' names are mapped, defaults filled in).
#: ``observation``: the run's observation design (``design_label``); "" in older
#: files, which is the default design. ``randomization``: the run's training
#: randomisation (``randomization_label``); "" in older files, which is ``none``.
OPTIONAL_COLUMNS = ("demonstrations", "observation", "randomization")


#: A setting's key: what its runs share besides the task and the seed. Reports group by it.
SETTING = ("algo", "action_mode", "reward_type", "observation", "randomization")


def budget_unit(row: dict[str, Any]) -> str:
    """What a run's ``steps`` counts: gradient steps for behaviour cloning (``bc``), else env steps."""
    return "gradient steps" if row["algo"] == "bc" else "environment steps"


def steps_label(rows: Any) -> str:
    """The x axis of success against steps over these result rows: their one budget unit,
    or both when behaviour cloning is drawn beside RL."""
    units = sorted({budget_unit(r) for r in rows})
    return units[0] if len(units) == 1 else "environment steps (RL) or gradient steps (bc)"


def setting_key(row: dict[str, Any]) -> tuple[str, str, str, str, str]:
    """A row's (algo, action mode, reward type, observation design, training randomisation),
    as :data:`SETTING`."""
    return (
        row["algo"],
        row["action_mode"],
        row["reward_type"],
        row.get("observation") or "default",
        row.get("randomization") or "none",
    )


def setting_label(key: tuple[str, str, str, str, str]) -> str:
    """``mode / reward / algo``, with the design after the mode unless it is the default,
    and the training randomisation last unless it is ``none``."""
    algo, mode, reward, observation, randomization = key
    design = "" if observation == "default" else f" / {observation}"
    rand = "" if randomization == "none" else f" / randomization {randomization}"
    return f"{mode}{design} / {reward} / {algo}{rand}"


class ResultsError(ValueError):
    """A ``results.csv`` that is not a bench's (one-line error)."""


def collect_row(run_dir: Path) -> dict[str, Any] | None:
    """The results row of a finished run, or ``None`` if it is not finished.

    ``status.json`` says ``finished`` only once everything else is written (it is written
    last, atomically), so it alone decides. The models are not needed: committed results
    carry none (git ignores them), and a fresh clone's ``--collect`` keeps their rows."""
    run_dir = Path(run_dir)
    status = read_status(run_dir)
    if not status or status.get("state") != "finished":
        return None
    config = yaml.safe_load((run_dir / CONFIG).read_text())
    evaluations = np.load(run_dir / "eval" / "evaluations.npz")
    steps = evaluations["timesteps"].tolist()
    success = (
        evaluations["successes"].mean(axis=1).tolist() if "successes" in evaluations else [float("nan")] * len(steps)
    )
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
        "demonstrations": _demonstrations(run_dir),
        "observation": design_label(config["env_kwargs"]),
        "randomization": randomization_label(config["env_kwargs"].get("randomization")),
    }


def _demonstrations(run_dir: Path) -> str:
    path = run_dir / "demonstrations.json"
    return json.dumps(json.loads(path.read_text()), sort_keys=True) if path.is_file() else ""


def write_results(out_dir: Path, rows: list[dict[str, Any]]) -> Path:
    """Write ``results.csv`` (one row per finished run) atomically."""
    path = Path(out_dir) / "results.csv"
    tmp = path.with_name("results.csv.tmp")
    with tmp.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=RESULT_COLUMNS + OPTIONAL_COLUMNS)
        writer.writeheader()
        for row in sorted(rows, key=lambda r: r["run"]):
            writer.writerow({**{k: row[k] for k in RESULT_COLUMNS}, **{k: row.get(k) or "" for k in OPTIONAL_COLUMNS}})
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
            record = json.loads(r.get("demonstrations") or "null")
            r["demonstrations"] = demonstration_record(record) if record else None
            r["observation"] = r.get("observation") or "default"
            r["randomization"] = r.get("randomization") or "none"
        except (TypeError, ValueError) as err:
            raise ResultsError(f"{path}:{line}: malformed row ({err})") from None
    return rows
