"""Cross-task aggregates per action mode against hand-computed values, and the report's
aggregate sections."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from unified_manip.experiments.aggregates import (
    TAUS,
    curve_auc,
    improvement_intervals,
    iqm_intervals,
    mode_scores,
    performance_profiles,
    probability_of_improvement,
    rank_table,
)
from unified_manip.experiments.report import build_report
from unified_manip.experiments.results import write_results
from unified_manip.experiments.stats import iqm, score_distributions
from unified_manip.experiments.targets import steps_to

# Four runs on two tasks: sorted, 0.1 0.2 0.3 0.4 0.6 0.7 0.8 0.9; the IQM trims two from
# each end (a quarter of 8) and averages 0.3, 0.4, 0.6 and 0.7: 0.5.
TINY = np.array([[0.1, 0.9], [0.2, 0.8], [0.3, 0.7], [0.4, 0.6]])


def test_iqm_of_a_tiny_array_and_its_seeded_interval():
    (point, low, high) = iqm_intervals({"a": TINY})["a"]
    assert math.isclose(point, 0.5)
    assert 0.1 <= low < 0.5 < high <= 0.9
    assert iqm_intervals({"a": TINY})["a"] == (point, low, high)  # the same bootstrap every time
    # One constant score: no spread, the interval is the point.
    assert iqm_intervals({"c": np.full((3, 2), 0.7)})["c"] == pytest.approx((0.7, 0.7, 0.7))


def test_probability_of_improvement_of_two_modes_by_hand():
    # Task 1: x = (1.0, 0.5) against y = (0.5, 0.0): 1>0.5, 1>0, 0.5=0.5 (half), 0.5>0 -> 3.5/4.
    # Task 2: x = (0.2, 0.2) against y = (0.4, 0.1): each 0.2 beats 0.1 only -> 2/4.
    # Averaged over tasks: (0.875 + 0.5) / 2 = 0.6875; the other way 1 - 0.6875.
    x = np.array([[1.0, 0.2], [0.5, 0.2]])
    y = np.array([[0.5, 0.4], [0.0, 0.1]])
    poi = {pair: p for pair, (p, _, _) in improvement_intervals({"x": x, "y": y}).items()}
    assert poi == pytest.approx({("x", "y"): 0.6875, ("y", "x"): 0.3125})


def test_the_numpy_statistic_is_rliables_and_its_interval_is_seeded_and_complementary():
    from rliable import metrics

    rng = np.random.default_rng(0)
    for _ in range(20):  # success rates on a 50-episode grid: ties happen
        x, y = rng.integers(0, 51, size=(3, 4)) / 50, rng.integers(0, 51, size=(5, 4)) / 50
        assert probability_of_improvement(x, y) == pytest.approx(metrics.probability_of_improvement(x, y), abs=1e-12)
    x = np.array([[1.0, 0.2], [0.5, 0.2]])
    y = np.array([[0.5, 0.4], [0.0, 0.1]])
    ci = improvement_intervals({"x": x, "y": y})
    p, low, high = ci[("x", "y")]
    assert p == pytest.approx(0.6875) and 0.0 <= low <= p <= high <= 1.0 and low < high
    assert ci[("y", "x")] == pytest.approx((1 - p, 1 - high, 1 - low))
    assert improvement_intervals({"x": x, "y": y}) == ci  # seeded
    # A mode whose every run beats every run of another: certain, whatever the resample.
    assert improvement_intervals({"a": x + 2.0, "b": y})[("a", "b")] == (1.0, 1.0, 1.0)


def test_the_numpy_iqm_and_score_distributions_are_rliables_to_the_bit():
    """The bootstraps call these thousands of times; rliable's own (scipy's ``trim_mean``
    and an ``np.vectorize`` loop) gave the same bits, slower."""
    from rliable import library as rly
    from rliable import metrics

    rng = np.random.default_rng(0)
    for shape in [(1, 1), (2, 3), (3, 10), (5, 4), (7, 13)]:
        for scores in (rng.random(shape), rng.integers(0, 51, size=shape) / 50):  # ties on a 50-episode grid
            assert iqm(scores) == metrics.aggregate_iqm(scores)
            assert np.array_equal(score_distributions(scores, TAUS), rly.score_distributions(scores, TAUS))


def test_performance_profile_is_the_fraction_of_runs_above_each_threshold():
    taus = np.array([0.0, 0.25, 0.5, 0.85, 1.0])
    profiles, bands = performance_profiles({"a": TINY}, taus)
    # Above 0: all 8; above 0.25: 0.3 0.4 0.6 0.7 0.8 0.9; above 0.5: four; above 0.85: 0.9.
    np.testing.assert_allclose(profiles["a"], [1.0, 6 / 8, 4 / 8, 1 / 8, 0.0])
    assert bands["a"].shape == (2, 5) and np.all(bands["a"][0] <= profiles["a"] + 1e-12)


def test_area_under_a_hand_made_curve_and_steps_to_0_8():
    curve = [[10, 0.0], [20, 0.5], [30, 1.0], [40, 0.9]]
    # Trapezoids: 10*(0+0.5)/2 + 10*(0.5+1)/2 + 10*(1+0.9)/2 = 2.5 + 7.5 + 9.5 = 19.5 over 30 steps.
    assert curve_auc(curve) == pytest.approx(0.65)
    assert steps_to(curve, 0.8) == 30
    assert steps_to([[10, 0.5], [20, 0.79]], 0.8) is None
    assert curve_auc([[50, 0.4]]) == 0.4  # one evaluation: its value
    with pytest.raises(ValueError, match="at least one evaluation point"):
        curve_auc([])


def test_rank_table_ranks_modes_per_task_and_ties_share_their_mean_rank():
    scores = {
        "a": np.array([[1.0, 0.2], [0.8, 0.4]]),  # means 0.9, 0.3 (0.30000000000000004 in floats)
        "b": np.array([[0.5, 0.3], [0.5, 0.3]]),  # means 0.5, 0.3
        "c": np.array([[0.0, 0.9], [0.2, 0.9]]),  # means 0.1, 0.9
    }
    ranks = rank_table(scores)
    assert ranks["a"][0].tolist() == [1, 2.5] and ranks["a"][1] == 1.75
    assert ranks["b"][0].tolist() == [2, 2.5] and ranks["b"][1] == 2.25
    assert ranks["c"][0].tolist() == [3, 1] and ranks["c"][1] == 2.0


def _row(task: str, mode: str, seed: int, curve: list[list[float]]) -> dict:
    return {
        "run": f"{task.split('/')[-1]}__{mode}__sparse__tqc_her__s{seed}",
        "task": task,
        "action_mode": mode,
        "reward_type": "sparse",
        "algo": "tqc_her",
        "seed": seed,
        "steps": int(curve[-1][0]),
        "final_success_rate": curve[-1][1],
        "curve": json.dumps(curve),
        "wall_time_s": 100.0,
        "steps_per_s": 10.0,
        "versions": json.dumps({"mujoco": "3.9.0"}),
    }


ARM, FETCH = "UnifiedManip/Arm4Reach-v0", "UnifiedManip/FetchReach-v0"


def _multi_task_rows() -> list[dict]:
    rows = []
    for seed in range(3):
        rows.append(_row(ARM, "ee_delta", seed, [[500, 0.5], [1000, 0.9 + 0.05 * seed]]))
        rows.append(_row(FETCH, "ee_delta", seed, [[500, 0.8], [1000, 1.0]]))
        rows.append(_row(ARM, "joint_delta", seed, [[500, 0.0], [1000, 0.2 * seed]]))
        rows.append(_row(FETCH, "joint_delta", seed, [[500, 0.1], [1000, 0.5]]))
    rows.append(_row(ARM, "joint_delta", 3, [[500, 0.0], [1000, 0.9]]))  # a fourth seed on one task
    rows.append(_row(ARM, "joint_torque", 0, [[500, 0.0], [1000, 0.1]]))  # a mode on one task only
    return rows


def test_mode_scores_keep_modes_run_on_every_task_and_the_same_runs_per_task(tmp_path):
    write_results(tmp_path, _multi_task_rows())
    from unified_manip.experiments.results import read_results

    s = mode_scores(read_results(tmp_path / "results.csv"))
    assert s.tasks == (ARM, FETCH) and s.modes == ("ee_delta", "joint_delta")
    assert s.left_out == {"joint_torque": (FETCH,)}
    assert s.runs == {"ee_delta": (3, 0), "joint_delta": (3, 1)}  # seed 3 on the arm left out
    np.testing.assert_allclose(s.final["joint_delta"], [[0.0, 0.5], [0.2, 0.5], [0.4, 0.5]])
    # Fetch ee_delta: 0.8 at 500 reaches 0.8; area (0.8 + 1.0) / 2 = 0.9.
    assert s.steps["ee_delta"][1] == [500, 500, 500] and s.auc["ee_delta"][0, 1] == pytest.approx(0.9)


@pytest.mark.slow
def test_a_multi_task_report_writes_the_aggregate_sections_and_figures(tmp_path):
    bench = tmp_path / "bench"
    bench.mkdir()
    write_results(bench, _multi_task_rows())
    out = tmp_path / "report"
    text = build_report(bench / "results.csv", out, command="r", dense_check=False).read_text()
    section = text[text.index("## Aggregates across tasks") :]
    for needle in (
        "### tqc_her, sparse reward",
        "their runs per task: ee_delta 3, joint_delta 3",
        "Left out, as not run on every task: joint_torque (no runs of FetchReach-v0).",
        "lowest seeds kept): joint_delta 1.",
        "**Performance profile**",
        "**Probability of improvement**",
        "**Sample efficiency**",
        "**Rank per task**",
        # ee_delta's 6 finals 0.9 0.95 1.0 1.0 1.0 1.0: scipy's trim_mean cuts int(0.25 * 6) = 1
        # from each end, (0.95 + 1 + 1 + 1) / 4 = 0.9875.
        "| ee_delta | 6 | 0.99 [",
        # P(ee_delta > joint_delta): 1 on both tasks (every ee_delta run beats every joint_delta one).
        "| ee_delta | — | 1.00 [1.00, 1.00] |",
        "| joint_delta | 0.00 [0.00, 0.00] | — |",
        # Steps to 0.8: the arm's ee_delta runs reach it at 1,000, Fetch's at 500; joint_delta never.
        "| ee_delta | 1,000, 1,000, 1,000 | 500, 500, 500 |",
        "| joint_delta | —, —, — | —, —, — |",
        "| ee_delta | 1 (0.95) | 1 (1.00) | 1.00 |",
        "| joint_delta | 2 (0.20) | 2 (0.50) | 2.00 |",
    ):
        assert needle in section, needle
    for name in ("iqm", "profile", "improvement"):
        png = out / f"aggregates_tqc_her_sparse_{name}.png"
        assert png.stat().st_size > 10_000 and f"({png.name})" in section
    # A one-task report has no aggregate section.
    write_results(bench, [r for r in _multi_task_rows() if r["task"] == ARM])
    text = build_report(bench / "results.csv", tmp_path / "one", command="r", dense_check=False).read_text()
    assert "## Aggregates across tasks" not in text


@pytest.mark.slow
def test_with_one_run_per_task_the_aggregates_show_no_interval(tmp_path):
    """A stratified bootstrap of one run per task resamples nothing: its "interval" would be
    the point itself, so the report shows none and says why."""
    bench = tmp_path / "bench"
    bench.mkdir()
    write_results(bench, [r for r in _multi_task_rows() if r["seed"] == 0 and r["action_mode"] != "joint_torque"])
    text = build_report(bench / "results.csv", tmp_path / "report", command="r", dense_check=False).read_text()
    section = text[text.index("## Aggregates across tasks") :]
    assert "with one run per task there is nothing to resample, so no interval is shown ([—])." in section
    assert "| ee_delta | 2 | 0.95 [—] | 0.80 [—] | 1.00 |" in section  # finals 0.9 and 1.0; areas 0.7, 0.9
    assert "| ee_delta | — | 1.00 [—] |" in section


def _design_rows() -> list[dict]:
    """An observation study: two tasks, each in its own action mode, three designs, 2 seeds."""
    rows = []
    for task, mode in ((ARM, "ee_delta"), (FETCH, "native")):
        for design, finals in (("default", (0.9, 1.0)), ("minimal", (0.1, 0.3)), ("default+distractors32", (0.6, 0.8))):
            for seed, final in enumerate(finals):
                row = _row(task, mode, seed, [[500, final / 2], [1000, final]])
                row["observation"] = design
                row["run"] = row["run"].replace("__s", "" if design == "default" else f"__obs-{design}__s")
                rows.append(row)
    return rows


def test_observation_designs_are_compared_per_task_and_pair_with_their_modes(tmp_path):
    write_results(tmp_path, _design_rows())
    from unified_manip.experiments.results import read_results

    rows = read_results(tmp_path / "results.csv")
    s = mode_scores(rows, "observation")
    # Each task ran one action mode, so the tasks are the problems and every design ran on both.
    assert s.tasks == (ARM, FETCH) and s.modes == ("default", "default+distractors32", "minimal")
    np.testing.assert_allclose(s.final["minimal"], [[0.1, 0.1], [0.3, 0.3]])
    # Compared by action mode, every mode misses the other task: nothing to aggregate.
    assert mode_scores(rows, "action_mode").modes == ()
    # Where the other factor varies, each (task, value) pair is a problem of its own.
    mixed = [r for r in rows if r["task"] == ARM] + [
        {**r, "action_mode": "joint_delta"} for r in rows if r["task"] == ARM
    ]
    assert mode_scores(mixed, "observation").tasks == (f"{ARM} (ee_delta)", f"{ARM} (joint_delta)")


@pytest.mark.slow
def test_a_report_of_observation_designs_ranks_and_aggregates_them(tmp_path):
    bench = tmp_path / "bench"
    bench.mkdir()
    write_results(bench, _design_rows())
    out = tmp_path / "report"
    text = build_report(bench / "results.csv", out, command="r", dense_check=False).read_text()
    table = text[text.index("## Final success rate") :]
    assert "| task | algo | action mode | observation | reward |" in table
    assert "| Arm4Reach-v0 | tqc_her | ee_delta | default+distractors32 | sparse | 2 | 0.70 |" in table
    ranking = text[text.index("## Ranking of observation designs") :]
    for needle in (
        "**FetchReach-v0**, tqc_her, native, sparse reward:",
        "| 1 | default | 0.95 | — |",
        "| 2 | default+distractors32 | 0.70 |",
        "| 3 | minimal | 0.20 | 1.00 |",  # both default runs beat both minimal ones
    ):
        assert needle in ranking, needle
    aggregates = text[text.index("### Observation designs: tqc_her, sparse reward") :]
    assert "Observation designs run on all 2 tasks (Arm4Reach-v0, FetchReach-v0)" in aggregates
    assert "| observation design | runs | IQM final success" in aggregates
    assert "| default | — | 1.00 [1.00, 1.00] | 1.00 [1.00, 1.00] |" in aggregates  # P(row > column)
    for name in ("iqm", "profile", "improvement"):
        png = out / f"aggregates_tqc_her_sparse_observation_{name}.png"
        assert png.stat().st_size > 10_000 and f"({png.name})" in aggregates
    assert "## Ranking of action modes" not in text and "### tqc_her, sparse reward" not in text
    assert (out / "Arm4Reach-v0_final.png").stat().st_size > 10_000  # one bar per design
