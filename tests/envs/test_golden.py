"""Behaviour does not change: every ID x action mode x reward type replays its golden
50-step rollout bit for bit (see ``tests/envs/golden.py``; regenerate with
``python tests/envs/golden.py --write``). The hashes compared are the set of the MuJoCo
installed; every test fails if it has none.

The rollouts are played once, in child processes with generic floating point
(``golden.PORTABLE_ENV``), so the hashes do not depend on the CPU. The cases are dealt
into :data:`PARTS` xdist groups, one child each, so that the README's command
(``--dist loadgroup``) plays them on both workers."""

from __future__ import annotations

import functools
import hashlib

import numpy as np
import pytest
from conftest import ID_MODE_REWARDS
from golden import cases, check_portable, feed, hashes_in_child, key, load_sets, mujoco_version

import unified_manip

SETS = load_sets()
#: The installed MuJoCo's set, or None (then every test here fails, naming the version).
STORED = SETS.get(mujoco_version())
NO_SET = f"no golden set for mujoco {mujoco_version()}: run python tests/envs/golden.py --write"
pytestmark = [pytest.mark.slow, pytest.mark.golden]  # the rollouts take minutes

#: Children that play the rollouts; case i goes to part i % PARTS (every part gets every family).
PARTS = 2


@functools.cache
def played(part: int) -> dict[str, dict[str, str]] | RuntimeError:
    """The hashes of part ``part``'s cases, or the child's error (kept, so that its cases
    fail at once instead of each starting another child)."""
    try:  # the cases of families installed here (an install without an extra deselects the others)
        cases = [c for c in ID_MODE_REWARDS[part::PARTS] if unified_manip.TASKS[c[0]].installed]
        return hashes_in_child([key(*c) for c in cases])
    except RuntimeError as err:
        return err


def test_the_installed_mujoco_has_a_golden_set():
    assert STORED is not None, NO_SET
    assert "3.9.0" in SETS and "3.3.0" in SETS  # both ends of the tested range


#: Extras that pin one MuJoCo release (Meta-World 3.1.1 pins mujoco==3.3.0): their
#: families' cases can be recorded only in that release's set, and only there are they kept.
PINNED_MUJOCO = {"metaworld": "3.3.0"}


def recordable(mujoco: str) -> set[str]:
    """The keys of every registered case that MuJoCo ``mujoco`` can play."""
    return {key(*c) for c in cases() if PINNED_MUJOCO.get(unified_manip.TASKS[c[0]].extra or "", mujoco) == mujoco}


def test_every_registered_case_has_stored_hashes():
    """Every case of every registered ID, the sampled families' too (the rollouts below play
    the contract suites' sample of them; ``golden.py`` plays them all)."""
    for mujoco, stored in SETS.items():
        current = recordable(mujoco)
        assert sorted(current - set(stored)) == [], f"mujoco {mujoco}: run python tests/envs/golden.py --write"
        assert sorted(set(stored) - current) == [], f"mujoco {mujoco}: IDs or modes were removed: bump versions instead"


def test_a_pinned_family_is_recorded_only_on_its_mujoco():
    assert {spec.extra for spec in unified_manip.TASKS.values()} >= set(PINNED_MUJOCO)
    assert all(version in SETS for version in PINNED_MUJOCO.values())
    pinned = {key(*c) for c in cases()} - recordable("3.9.0")
    assert pinned and all(unified_manip.TASKS[k.split("|")[0]].extra == "metaworld" for k in pinned)


@pytest.mark.parametrize(
    "part, case",
    [
        pytest.param(
            i % PARTS,
            c,
            id="-".join(c).replace("UnifiedManip/", ""),
            marks=pytest.mark.xdist_group(f"golden-{i % PARTS}"),
        )
        for i, c in enumerate(ID_MODE_REWARDS)
    ],
)
def test_golden_rollout(part, case):
    assert STORED is not None, NO_SET
    hashes = played(part)
    if isinstance(hashes, RuntimeError):
        raise hashes
    assert hashes[key(*case)] == STORED[key(*case)]


def test_generic_floating_point_is_checked():
    # pytest's own process runs with the CPU's code paths: the check refuses to hash here.
    with pytest.raises(RuntimeError, match="golden rollouts need generic floating point"):
        check_portable()


def _digest(value) -> str:
    h = hashlib.sha256()
    feed(h, value)
    return h.hexdigest()


def test_hashing_is_canonical_and_sees_the_last_bit():
    a = {"b": np.float32(1.5), "a": {"y": True, "x": [1, 2.0]}}
    assert _digest(a) == _digest({"a": {"x": [1.0, np.int64(2)], "y": np.bool_(True)}, "b": 1.5})
    assert _digest(1.0) != _digest(np.nextafter(1.0, 2.0))
    assert _digest(True) != _digest(1.0)
    assert _digest(np.zeros(2)) != _digest(np.zeros((2, 1)))
    with pytest.raises(TypeError, match="cannot hash a value of type object"):
        _digest(object())
