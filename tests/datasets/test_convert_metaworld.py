"""``convert`` on Meta-World (its servoed Sawyer on MuJoCo 3.3.0), where the one-step
search in a target mode runs the target away from the arm: the retry with the target's
lead in the residual keeps what the search loses. Real Meta-World, no mocks."""

from __future__ import annotations

import warnings

import pytest

from unified_manip.datasets.convert import convert
from unified_manip.datasets.policies import scripted
from unified_manip.datasets.recording import collect
from unified_manip.datasets.replay import replay

pytestmark = pytest.mark.metaworld  # needs the metaworld extra


def test_the_lead_weighted_retry_keeps_a_push_the_search_loses(tmp_path):
    """MetaWorldPush-v1's first successful scripted episode, recorded in ee_delta (the
    scripted native actions translated live), into joint_target_delta: the search loses it
    catching up and in lockstep, and the retry at the first lead weight keeps it, within 1
    cm of the recorded path on average, in a dataset that replays exactly from its
    actions. (Without the retries, the open-loop guesses lose it too.)"""
    source = tmp_path / "push-ee-v0"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # Meta-World's policies warn that their gains clip
        kwargs = {"action_mode": "ee_delta", "reward_type": "sparse"}
        collect(
            "UnifiedManip/MetaWorldPush-v1",
            kwargs,
            scripted,
            "scripted",
            "scripted",
            1,
            source,
            only_successful=True,
            progress=False,
        )
        report = convert(source, "joint_target_delta", tmp_path / "push-target-v0", progress=False)
    (episode,) = report.episodes
    assert episode.replayed_by == "search, lead 0.0005"
    assert episode.kept and episode.tracking_error_mean_cm < 1.0
    assert replay(tmp_path / "push-target-v0", from_actions=True, progress=False).exact
