"""Summarise the MT10 grid's datasets as they were made, one entry per ID and mode.

``make_datasets.sh`` leaves one JSON per mode beside each dataset: ``collect``'s counts
for the recorded modes, ``convert``'s per-episode measurements for the joint modes. This
reads them for the v1 and v2 IDs of each task and writes the summary that
``results/action_spaces_mt10/datasets.json`` holds, so that datasets made again can be
read against the recorded ones::

    python baselines/grids/studies/datasets_summary.py --v1 data_v1 --v2 data \\
        --tasks Push,PickPlace,DoorOpen --out remade.json

Counts of kept episodes are those ``convert`` wrote; ``kept_by`` counts the kept
episodes by the way each was replayed; the tracking error is the mean over every
episode tried; an episode "left the path" when its tracking first went past the
tolerance.
"""

from __future__ import annotations

import argparse
import json
from collections import Counter
from pathlib import Path
from statistics import fmean

from unified_manip.cli.output import write_json
from unified_manip.datasets.convert import EpisodeConversion

MODES = ("ee_delta", "native", "joint_delta", "joint_target_delta")


def recorded(doc: dict) -> dict:
    """A collected mode: how many episodes were kept of how many played."""
    return {"recorded": doc["episodes"], "played": doc["played"], "success_rate": doc["success_rate"]}


def converted(doc: dict) -> dict:
    """A converted mode: what ``convert`` kept, and how."""
    episodes = [EpisodeConversion(**e) for e in doc["episodes"]]
    return {
        "kept": doc["kept"],
        "episodes": len(episodes),
        "method": doc["method"],
        "tolerance_cm": doc["tolerance_cm"],
        "kept_by": dict(Counter(e.replayed_by for e in episodes if e.kept).most_common()),
        "tracking_error_mean_cm": fmean(e.tracking_error_mean_cm for e in episodes),
        "left_the_path": sum(e.first_step_off is not None for e in episodes),
    }


def summarise(folder: Path) -> dict:
    """Every mode's entry for the datasets under ``folder``; modes without a JSON are
    left out (a mode that was not collected)."""
    out = {}
    for mode in MODES:
        path = folder / f"{mode}.json"
        if not path.exists():
            continue
        doc = json.loads(path.read_text())
        out[mode] = converted(doc) if "kept" in doc else recorded(doc)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--v1", type=Path, required=True, help="the v1 datasets' folder")
    parser.add_argument("--v2", type=Path, required=True, help="the v2 datasets' folder")
    parser.add_argument("--tasks", required=True, help="comma-separated, e.g. Push,DoorOpen")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    doc = {}
    for task in args.tasks.split(","):
        for version, root in (("v1", args.v1), ("v2", args.v2)):
            folder = root / f"MetaWorld{task}-{version}"
            if not folder.is_dir():
                parser.error(f"no datasets for {task} {version}: expected {folder}")
            doc[f"UnifiedManip/MetaWorld{task}-{version}"] = summarise(folder)
    write_json(args.out, doc)


if __name__ == "__main__":
    main()
