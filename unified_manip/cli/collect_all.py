"""``unified-manip collect --all``: a dataset of every task with a scripted policy, in
every mode conversion reaches, and of the best trained run under ``results/`` for the
tasks no scripted policy covers."""

from __future__ import annotations

import argparse
from pathlib import Path


def collect_all_command(args: argparse.Namespace) -> int:
    """``collect --all``: :func:`unified_manip.datasets.catalogue.collect_all`, with the
    trained runs under ``results/`` for the tasks the scripted policy does not cover."""
    from unified_manip.datasets import DatasetError
    from unified_manip.datasets.catalogue import collect_all

    fixed = [f"--{k.replace('_', '-')}" for k in ("action_mode", "reward_type", "env_kwarg") if getattr(args, k)]
    if args.policy != "scripted" or fixed:
        raise DatasetError(f"--all chooses the policies and modes itself; drop {', '.join(fixed or ['--policy'])}")
    tasks = [args.env] if args.env else None
    manifest = collect_all(
        Path(args.out), args.episodes or 100, tasks, trained_runs(Path("results")), progress=not args.no_progress
    )
    written = sum(e["state"] == "written" for e in manifest.values())
    print(f"{written} datasets in {args.out}, {len(manifest) - written} skipped (see {args.out}/catalogue.json)")
    return 0


def trained_runs(results: Path) -> dict:
    """``task ID -> (make_policy, source, env kwargs)``: for each task, the finished run under
    ``results`` with a final model and the highest last evaluation (none: models are not
    committed, so a fresh clone has none)."""
    import numpy as np
    import yaml

    best: dict[str, tuple[float, Path, dict]] = {}
    for model in results.glob("*/runs/*/final_model.zip"):
        run = model.parent
        try:
            config = yaml.safe_load((run / "config.yaml").read_text())
            with np.load(run / "eval" / "evaluations.npz") as data:
                success = float(data["successes"][-1].mean())
        except (OSError, KeyError, ValueError, IndexError):
            continue
        if success > best.get(config["env"], (-1.0,))[0]:
            best[config["env"]] = (success, run, config["env_kwargs"])
    if not best:
        return {}
    from unified_manip.training.played import run_policy

    return {task: (run_policy(run), f"run {run} (deterministic)", kw) for task, (_, run, kw) in best.items()}
