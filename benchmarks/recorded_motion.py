"""How fast a recording's grip site moves: ``python -m benchmarks.recorded_motion DATASET...``.

Per episode of each dataset: the first step at which it succeeds, and the grip site's
largest move in one step (cm) before that step and after it, read by restoring each
recorded state as ``convert`` does. A converted episode must follow the whole recording
within ``convert``'s tolerance, success or not, so a recording that sweeps on after it
has succeeded is lost by a mode whose step cannot keep up (docs/datasets.md).
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.parser import ToolParser


def motion(path: Path) -> dict[str, Any]:
    """``{"env_id", "action_mode", "episodes": [...]}`` for the dataset at ``path``; an
    episode's ``first_success`` is None where it never succeeds (its ``after`` is then 0)."""
    import gymnasium as gym

    from unified_manip.datasets.steps import recorded_targets
    from unified_manip.datasets.store import metadata, open_dataset

    dataset = open_dataset(path)
    meta = metadata(dataset)
    env = gym.make(meta["env_id"], **meta["env_kwargs"])
    rows = []
    try:
        for ep in dataset.iterate_episodes():
            sites = np.array([t.site for t in recorded_targets(env, ep, meta["env_id"])])
            moves = np.linalg.norm(np.diff(sites, axis=0), axis=1) * 100.0
            hits = np.flatnonzero(np.asarray(ep.infos["is_success"]) > 0.5)
            first = int(hits[0]) if hits.size else None
            split = len(moves) if first is None else first
            rows.append(
                {
                    "episode": int(ep.id),
                    "steps": len(moves),
                    "first_success": first,
                    "max_cm_before": float(moves[:split].max(initial=0.0)),
                    "max_cm_after": float(moves[split:].max(initial=0.0)),
                }
            )
    finally:
        env.close()
    return {"env_id": meta["env_id"], "action_mode": meta["env_kwargs"]["action_mode"], "episodes": rows}


def main(argv: list[str] | None = None) -> None:
    parser = ToolParser("benchmarks.recorded_motion", __doc__)
    parser.add_argument("datasets", nargs="+", help="dataset directories (written by collect or convert)")
    parser.add_argument("--json", required=True, help="write {dataset name: result} here")
    args = parser.parse_args(argv)
    missing = [d for d in args.datasets if not Path(d).is_dir()]
    if missing:
        parser.error(f"no dataset at {missing[0]}; expected a directory written by collect or convert")
    results = {Path(d).name: motion(Path(d)) for d in args.datasets}
    tmp = Path(f"{args.json}.tmp")  # whole or not at all
    tmp.write_text(json.dumps(results, indent=2))
    os.replace(tmp, args.json)
    for name, result in results.items():
        after = [e["max_cm_after"] for e in result["episodes"]]
        print(f"{name}: {len(after)} episodes, after success up to {max(after, default=0):.2f} cm a step")


if __name__ == "__main__":
    main()
