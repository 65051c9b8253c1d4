"""Golden trajectories: the behaviour every refactor must keep, bit for bit.

For every registered ID x action mode x reward type, one 50-step rollout: ``reset(seed=0)``
and 50 seeded random actions (the same actions for the three reward types of an ID and
mode). Four SHA-256 hashes are kept per case, of

* ``obs``: every observation dict (reset's and each step's);
* ``rewards``: the step rewards;
* ``infos``: every info dict (reset's and each step's), nested dicts included;
* ``ends``: each step's ``terminated`` and ``truncated``.

Hashing is canonical: dict keys sorted, every number or array converted to float64
and hashed as its exact bytes with its shape (so float32 and float64 of one value
agree, and 1.0 and 1 agree), bools and strings tagged apart from numbers. A change in
the last bit of any value changes the hash.

The hashes are kept per MuJoCo version (``golden_hashes.json``'s ``"mujoco"``, one set per
release of the supported range that has been recorded): the test compares the set of the
MuJoCo installed, and fails when there is none. numpy and mink do not enter the key: on
MuJoCo 3.9.0, numpy 2.4.6 with mink 1.2.0 (robosuite through uv's override) gave the
hashes numpy 1.26.4 with mink 0.0.5 gave, on all 354 cases.

Commands (run from the repository root, the virtual environment active)::

    python tests/envs/golden.py                    # compare every case, print those that differ
    python tests/envs/golden.py --only Lift        # only cases whose key contains "Lift"
    python tests/envs/golden.py --write            # add cases not stored yet (a new ID or mode,
                                              # or every case of a new MuJoCo version);
                                              # a stored case that differs is reported, kept
    python tests/envs/golden.py --update --only X  # overwrite differing stored cases too

``--update`` is only for a deliberate, documented behaviour change, together with a
version bump of the ID (the old version keeps its hashes; see the README). Cases of IDs
or modes no longer registered are dropped on writing.

Portable floating point: the last bits of a rollout depend on which code paths the CPU
selects at run time: OpenBLAS's kernel (``action @ action``, mink's QP objective,
robosuite's controllers), numpy's SIMD loops, glibc's libm variants (MuJoCo's
``sin``/``exp``) and numba's target (robosuite). Measured on one AMD EPYC (AVX2) machine:
changing only the OpenBLAS kernel changed 342 of the 354 cases, only the libm variant 195.
So the rollouts always run in a child process with every one of those pinned to its
generic x86-64 code (``tests/portable.py``'s ``PORTABLE_ENV``); the CLI re-executes itself that way and the
test starts such a child. The hashes are then the same on any x86-64 CPU with the same
MuJoCo and glibc; another architecture may legitimately differ.
"""

from __future__ import annotations

import gc
import hashlib
import json
import os
import sys
import zlib
from pathlib import Path
from typing import Any, Iterator

os.environ.setdefault("MUJOCO_GL", "egl")

import gymnasium as gym  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tests/, when run as a script
import portable  # noqa: E402
from portable import PORTABLE_ENV, check_portable, is_portable  # noqa: E402

PATH = Path(__file__).with_name("golden_hashes.json")
STEPS = 50
RESET_SEED = 0
FIELDS = ("obs", "rewards", "infos", "ends")


def hashes_in_child(keys: list[str] | None = None, timeout: float = 1800) -> dict[str, dict[str, str]]:
    """The hashes of ``keys`` (all cases if ``None``), played in a child process with
    :data:`PORTABLE_ENV`."""
    cmd = [sys.executable, __file__, "--hashes", *(keys or [])]
    out = portable.run(cmd, timeout)
    if out.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd[1:3])} failed (exit {out.returncode}):\n{out.stderr[-4000:]}")
    return json.loads(out.stdout)


def cases() -> list[tuple[str, str, str]]:
    """Every registered ID x action mode x reward type, in registration order."""
    import unified_manip

    return [
        (tid, mode, reward)
        for tid, spec in unified_manip.TASKS.items()
        for mode in spec.action_modes
        for reward in unified_manip.REWARD_TYPES
    ]


def key(task_id: str, mode: str, reward: str) -> str:
    return f"{task_id}|{mode}|{reward}"


def feed(h: "hashlib._Hash", value: Any) -> None:
    """Add ``value`` to ``h`` canonically (see the module docstring)."""
    if isinstance(value, dict):
        h.update(b"{")
        for k in sorted(value, key=str):
            h.update(b"k" + str(k).encode() + b"\0")
            feed(h, value[k])
        h.update(b"}")
    elif isinstance(value, (list, tuple)):
        h.update(b"[")
        for v in value:
            feed(h, v)
        h.update(b"]")
    elif value is None:
        h.update(b"N")
    elif isinstance(value, str):
        h.update(b"s" + value.encode() + b"\0")
    elif isinstance(value, (bool, np.bool_)):
        h.update(b"?1" if value else b"?0")
    else:
        a = np.asarray(value)
        if a.dtype.kind not in "fiub":
            raise TypeError(f"cannot hash a value of type {type(value).__name__} ({a.dtype})")
        a = np.ascontiguousarray(a, dtype=np.float64)
        h.update(b"f" + repr(a.shape).encode() + a.tobytes())


def rollout(task_id: str, mode: str, reward: str) -> Iterator[tuple[str, Any]]:
    """``(field, value)`` pairs of one golden rollout, in order."""
    env = gym.make(task_id, action_mode=mode, reward_type=reward)
    try:
        rng = np.random.default_rng(zlib.crc32(f"{task_id}|{mode}".encode()))
        actions = rng.uniform(-1.0, 1.0, size=(STEPS,) + env.action_space.shape).astype(np.float32)
        obs, info = env.reset(seed=RESET_SEED)
        yield "obs", obs
        yield "infos", info
        for a in actions:
            obs, r, terminated, truncated, info = env.step(a)
            yield "obs", obs
            yield "rewards", r
            yield "infos", info
            yield "ends", (terminated, truncated)
            if terminated or truncated:
                obs, info = env.reset()
                yield "obs", obs
                yield "infos", info
    finally:
        env.close()
        gc.collect()  # robosuite's envs hold reference cycles: free each before the next


def hashes(task_id: str, mode: str, reward: str) -> dict[str, str]:
    """The four hashes of one case."""
    h = {f: hashlib.sha256() for f in FIELDS}
    for field, value in rollout(task_id, mode, reward):
        feed(h[field], value)
    return {f: h[f].hexdigest() for f in FIELDS}


def mujoco_version() -> str:
    """The installed MuJoCo's version: the key of its golden set."""
    from importlib.metadata import version

    return version("mujoco")


def load_sets() -> dict[str, dict[str, dict[str, str]]]:
    """Every stored set: ``{mujoco version: {case key: hashes}}``."""
    return json.loads(PATH.read_text())["mujoco"] if PATH.exists() else {}


def main(argv: list[str]) -> int:
    if not is_portable():  # re-run this command with generic floating point
        os.execve(sys.executable, [sys.executable, __file__, *argv], {**os.environ, **PORTABLE_ENV})
    check_portable()
    if argv[:1] == ["--hashes"]:  # hashes_in_child's end: JSON of the named (or all) cases
        wanted = set(argv[1:])
        todo = [c for c in cases() if not wanted or key(*c) in wanted]
        if wanted - {key(*c) for c in todo}:
            raise SystemExit(f"unknown golden cases: {sorted(wanted - {key(*c) for c in todo})}")
        json.dump({key(*c): hashes(*c) for c in todo}, sys.stdout)
        return 0
    write, update = "--write" in argv, "--update" in argv
    only = argv[argv.index("--only") + 1] if "--only" in argv else ""
    sets = load_sets()
    mujoco = mujoco_version()
    stored = sets.get(mujoco, {})
    import unified_manip

    matching = [c for c in cases() if only in key(*c)]
    todo = [c for c in matching if unified_manip.TASKS[c[0]].installed]
    if len(todo) < len(matching):  # a family whose extra is absent cannot play its cases
        absent = sorted(
            {unified_manip.TASKS[c[0]].extra for c in matching} - {unified_manip.TASKS[c[0]].extra for c in todo}
        )
        print(f"not played: {len(matching) - len(todo)} cases of extras not installed here ({', '.join(absent)})")
    if not todo:
        raise SystemExit(f"no installed case's key contains {only!r} (keys are ID|action mode|reward type)")
    added, differ = [], []
    for case in todo:
        k = key(*case)
        got = hashes(*case)
        if k not in stored:
            added.append(k)
            print(f"new     {k}", flush=True)
        elif stored[k] != got:
            differ.append(k)
            print(f"differs {k}", flush=True)
            if not update:
                continue
        stored[k] = got
    if write or update:
        current = {key(*c) for c in cases()}
        dropped = sorted(set(stored) - current)
        sets[mujoco] = {k: v for k, v in stored.items() if k in current}
        doc = {
            "about": "Golden-trajectory hashes per MuJoCo version: see tests/envs/golden.py for what they cover "
            "and how to regenerate them.",
            "steps": STEPS,
            "mujoco": sets,
        }
        PATH.write_text(json.dumps(doc, indent=1, sort_keys=True) + "\n")
        print(
            f"wrote {PATH} (mujoco {mujoco}): {len(added)} added, {len(differ) if update else 0} updated, "
            f"{len(dropped)} dropped"
        )
        return 1 if differ and not update else 0
    print(f"mujoco {mujoco}: {len(todo) - len(differ) - len(added)}/{len(todo)} cases match, {len(added)} not stored")
    return 1 if differ or added else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
