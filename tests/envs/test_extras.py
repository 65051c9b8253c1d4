"""A task whose family needs an extra (robosuite's) says which, in one line, when the
extra is missing: ``gym.make``, ``gym.make_vec`` and the upstream env alike.

Where robosuite is installed, these tests hide it (``sys.modules["robosuite"] = None``,
which Python's import system reads as "not installed"); on an install without it (the
fast CI leg) they see the real absence."""

from __future__ import annotations

import sys

import gymnasium as gym
import pytest

import unified_manip
from unified_manip.extras import EXTRAS, MissingExtra

MESSAGE = 'UnifiedManip/Lift-v0 needs the robosuite extra: pip install "unified_manip[robosuite]" (missing: robosuite)'


@pytest.fixture
def no_robosuite(monkeypatch):
    monkeypatch.setitem(sys.modules, "robosuite", None)


def test_only_the_robosuite_and_metaworld_families_need_an_extra():
    extras = {spec.family: spec.extra for spec in unified_manip.TASKS.values()}
    assert {family: extra for family, extra in extras.items() if extra} == {
        "robosuite": "robosuite",
        "metaworld": "metaworld",
    }
    assert {"arm4", "fetch", "shadow_hand", "adroit", "robosuite", "metaworld"} <= extras.keys()
    assert EXTRAS["robosuite"] == ("robosuite", "h5py")
    assert EXTRAS["metaworld"] == ("metaworld",)


def test_the_metaworld_extra_is_not_in_all():
    """Meta-World 3.1.1 pins mujoco==3.3.0: in ``all``, it would hold every install there."""
    import tomllib
    from pathlib import Path

    extras = tomllib.loads((Path(__file__).parents[2] / "pyproject.toml").read_text())["project"][
        "optional-dependencies"
    ]
    assert extras["metaworld"] == ["metaworld==3.1.1"]
    assert "metaworld" not in extras["all"][0]


def test_making_a_metaworld_id_without_the_extra_names_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "metaworld", None)
    assert not unified_manip.TASKS["UnifiedManip/MetaWorldReach-v0"].installed
    with pytest.raises(MissingExtra) as err:
        gym.make("UnifiedManip/MetaWorldReach-v0")
    assert str(err.value) == (
        'UnifiedManip/MetaWorldReach-v0 needs the metaworld extra: pip install "unified_manip[metaworld]" '
        "(missing: metaworld)"
    )


@pytest.mark.filterwarnings("ignore:.*no native vector env")
def test_making_a_robosuite_id_without_the_extra_names_it(no_robosuite):
    spec = unified_manip.TASKS["UnifiedManip/Lift-v0"]
    assert not spec.installed
    for make in (
        lambda: gym.make("UnifiedManip/Lift-v0"),
        lambda: gym.make("UnifiedManip/Lift-v0", action_mode="ee_delta", reward_type="dense"),
        lambda: gym.make_vec("UnifiedManip/Lift-v0", num_envs=2),
        spec.build_upstream,
    ):
        with pytest.raises(MissingExtra) as err:
            make()
        assert str(err.value) == MESSAGE
    # The other families need nothing beyond the base install.
    env = gym.make("UnifiedManip/Arm4Reach-v0")
    env.reset(seed=0)
    env.close()


def test_an_unknown_extra_is_refused():
    spec = unified_manip.TASKS["UnifiedManip/Arm4Reach-v0"]
    with pytest.raises(
        ValueError,
        match="unknown extra 'robosuit'; expected one of train, bench, ray, zoo, datasets, robosuite, metaworld, fast-camera",
    ):
        type(spec)(**{**spec.__dict__, "extra": "robosuit"})
