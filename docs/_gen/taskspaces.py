"""Each task's live spaces, per action mode, for its page: the ``Box`` of the action, the
length of the ``observation`` vector, the env step's duration and the observation
groups the task offers, read from envs built with ``gym.make``.

Building every mode of every task takes about 15 s, so the result is cached in
``.cache/docs/task_spaces.json``, keyed by a hash of the env library's source and the
simulators' versions: a change to either builds the envs again.

A family whose extra pins another MuJoCo than the site's (Meta-World's pins 3.3.0) cannot
be built where the site is. Its spaces are measured where it is installed and committed
in ``docs/_gen/pinned_spaces.json`` (``python docs/_gen/taskspaces.py --record metaworld``);
pages of its IDs read them when the family is not installed, and a test compares them
with the live envs where it is.
"""

from __future__ import annotations

import hashlib
import json
import os
import warnings
from importlib.metadata import version
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CACHE = ROOT / ".cache" / "docs" / "task_spaces.json"
#: The packages whose versions can change a space.
PACKAGES = ("mujoco", "gymnasium", "gymnasium-robotics", "robosuite")

#: The committed spaces of the pinned families' IDs, measured where they are installed.
PINNED = Path(__file__).with_name("pinned_spaces.json")
#: The extras a record is kept for.
PINNED_EXTRAS = ("metaworld",)

_memo: dict[str, dict] = {}  # task ID -> measure()
_key: list[str] = []  # the fingerprint the memo was read under


def fingerprint() -> str:
    """A hash of ``unified_manip/envs`` (every file) and :data:`PACKAGES`' versions."""
    digest = hashlib.sha256()
    for path in sorted((ROOT / "unified_manip" / "envs").rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts:
            digest.update(str(path.relative_to(ROOT)).encode())
            digest.update(path.read_bytes())
    for package in PACKAGES:
        digest.update(f"{package}=={version(package)}".encode())
    return digest.hexdigest()[:16]


def measure(task_id: str) -> dict:
    """``{"modes": {mode: {"shape", "low", "high", "observation"}}, "dt", "groups"}`` of
    ``task_id``, from one env per action mode."""
    import gymnasium as gym

    import unified_manip

    spec = unified_manip.TASKS[task_id]
    modes, dt, groups = {}, None, None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for mode in spec.action_modes:
            env = gym.make(task_id, action_mode=mode, disable_env_checker=True)
            try:
                box = env.action_space
                modes[mode] = {
                    "shape": list(box.shape),
                    "low": sorted({float(v) for v in box.low}),
                    "high": sorted({float(v) for v in box.high}),
                    "dtype": str(box.dtype),
                    "observation": int(env.observation_space["observation"].shape[0]),
                }
                dt = env.unwrapped.backend.dt
                groups = list(env.unwrapped.backend.observation_groups())
            finally:
                env.close()
    return {"modes": modes, "dt": dt, "groups": groups}


def recorded(task_id: str) -> dict:
    """The committed :func:`measure` of a pinned family's ID (``KeyError`` naming the command
    that records it)."""
    tasks = json.loads(PINNED.read_text())["tasks"] if PINNED.is_file() else {}
    if task_id not in tasks:
        raise KeyError(f"{task_id} has no recorded spaces: run python docs/_gen/taskspaces.py --record <its extra>")
    return tasks[task_id]


def record(extra: str) -> int:
    """Measure every ID of the families that need ``extra`` (installed here) into :data:`PINNED`."""
    from importlib.metadata import version as installed_version

    import unified_manip

    ids = [tid for tid, spec in unified_manip.TASKS.items() if spec.extra == extra]
    doc = json.loads(PINNED.read_text()) if PINNED.is_file() else {"versions": {}, "tasks": {}}
    doc["versions"][extra] = {p: installed_version(p) for p in ("mujoco", extra)}
    doc["tasks"] = {k: v for k, v in doc["tasks"].items() if unified_manip.TASKS[k].extra != extra}
    doc["tasks"].update({tid: measure(tid) for tid in ids})
    PINNED.write_text(json.dumps(doc, indent=1, sort_keys=True) + "\n")
    print(f"wrote {PINNED}: {len(ids)} IDs of the {extra} extra")
    return 0


def spaces(task_id: str) -> dict:
    """:func:`measure`'s result for ``task_id``, from the cache when it is current, or the
    committed record for a pinned family that is not installed here."""
    import unified_manip

    spec = unified_manip.TASKS[task_id]
    if spec.extra in PINNED_EXTRAS and not spec.installed:
        return recorded(task_id)
    if not _key:
        _key.append(fingerprint())
        try:
            cached = json.loads(CACHE.read_text())
        except (OSError, ValueError):  # none yet, or unreadable: measure again
            cached = {}
        if cached.get("fingerprint") == _key[0]:
            _memo.update(cached["tasks"])
    if task_id not in _memo:
        _memo[task_id] = measure(task_id)
        CACHE.parent.mkdir(parents=True, exist_ok=True)
        tmp = CACHE.with_suffix(f".{os.getpid()}.tmp")  # two builds at once each write whole files
        tmp.write_text(json.dumps({"fingerprint": _key[0], "tasks": _memo}, indent=1))
        tmp.replace(CACHE)
    return _memo[task_id]


if __name__ == "__main__":
    import sys

    if sys.argv[1:2] != ["--record"] or len(sys.argv) != 3 or sys.argv[2] not in PINNED_EXTRAS:
        raise SystemExit(f"usage: python docs/_gen/taskspaces.py --record {{{','.join(PINNED_EXTRAS)}}}")
    sys.exit(record(sys.argv[2]))
