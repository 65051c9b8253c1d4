"""``unified-manip plot``: one figure over several benches, a panel per task, drawn from the
committed benchmark results; seeds evaluated at different steps are aligned, not dropped."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from unified_manip.cli import main
from unified_manip.experiments.figures import curve_band
from unified_manip.experiments.results import read_results
from unified_manip.experiments.scaling import labelled_sizes, points

ROOT = Path(__file__).resolve().parents[2]
BENCHES = [ROOT / "results" / name / "results.csv" for name in ("benchmark_arm", "benchmark_robosuite")]


def _tasks(paths) -> list[str]:
    """Every task of the files, in the order they first appear."""
    return list(dict.fromkeys(r["task"] for p in paths for r in read_results(p)))


def test_the_figure_has_one_panel_per_task_of_every_file(tmp_path, capsys):
    out = tmp_path / "figures" / "overview.png"
    assert main(["plot", *map(str, BENCHES), "--out", str(out), "--columns", "3"]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    names = [t.split("/")[-1] for t in _tasks(BENCHES)]
    assert len(names) >= 2
    assert capsys.readouterr().out.strip() == f"wrote {out} ({len(names)} panels: {', '.join(names)})"


def test_tasks_picks_the_panels_and_their_order(tmp_path, capsys):
    tasks = _tasks(BENCHES)
    picked = [tasks[-1], tasks[0]]
    out = tmp_path / "o.svg"
    assert main(["plot", *map(str, BENCHES), "--out", str(out), "--tasks", ",".join(picked)]) == 0
    assert out.read_text().lstrip().startswith("<?xml")
    assert f"(2 panels: {picked[0].split('/')[-1]}, {picked[1].split('/')[-1]})" in capsys.readouterr().out


def test_a_task_without_runs_in_the_files_is_one_line_naming_those_it_holds(tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["plot", str(BENCHES[0]), "--out", str(tmp_path / "o.png"), "--tasks", "UnifiedManip/FetchReach-v0"])
    err = capsys.readouterr().err
    assert exit_.value.code == 2 and err.count("\n") == 1, err
    assert err.startswith("unified-manip plot: error: no finished runs of UnifiedManip/FetchReach-v0 in ")
    assert err.strip().endswith("the files hold runs of " + ", ".join(_tasks(BENCHES[:1])))
    assert not (tmp_path / "o.png").exists()


def test_seeds_evaluated_at_different_steps_are_read_at_each_others_steps():
    a = {"curve": [[10, 0.0], [30, 1.0]]}
    b = {"curve": [[10, 1.0], [20, 1.0], [40, 0.0]]}  # runs past a's last evaluation
    steps, mean, low, high = curve_band([a, b])
    assert steps.tolist() == [10, 20, 30]  # the range both cover
    np.testing.assert_allclose(mean, [0.5, 0.75, 0.75])  # a at 20 is 0.5; b at 30 is 0.5
    assert np.all(low <= mean) and np.all(mean <= high)


def test_one_seed_has_no_band_and_the_same_steps():
    steps, mean, low, high = curve_band([{"curve": [[10, 0.2], [20, 0.4]]}])
    assert steps.tolist() == [10, 20] and mean.tolist() == [0.2, 0.4]
    assert np.isnan(low).all() and np.isnan(high).all()


CLONING = [ROOT / "results" / name / "results.csv" for name in ("bc_arm4pnp_pilot", "bc_arm4pnp_n400")]


def test_against_demonstrations_draws_final_success_over_dataset_sizes(tmp_path, capsys):
    out = tmp_path / "sizes.png"
    assert main(["plot", *map(str, CLONING), "--against", "demonstrations", "--out", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert capsys.readouterr().out.strip() == f"wrote {out} (1 panels: Arm4PickAndPlace-v0)"


def test_points_group_final_success_by_setting_and_demonstration_episodes():
    def row(mode, episodes, final, algo="bc"):
        demos = {"episodes": episodes} if episodes else None
        return {"action_mode": mode, "reward_type": "sparse", "algo": algo, "demonstrations": demos,
                "final_success_rate": final}  # fmt: skip

    rows = [row("ee_delta", 25, 0.1), row("ee_delta", 25, 0.3), row("ee_delta", 400, 0.9), row("joint_delta", 25, 0.0)]
    rows.append(row("ee_delta", 0, 0.5, algo="tqc_her"))  # no demonstrations: at 0
    assert points(rows) == {
        ("ee_delta", "sparse", "bc"): {25: [0.1, 0.3], 400: [0.9]},
        ("joint_delta", "sparse", "bc"): {25: [0.0]},
        ("ee_delta", "sparse", "tqc_her"): {0: [0.5]},
    }


def test_close_dataset_sizes_share_one_tick_label():
    """Lift's converted datasets keep 8, 10, 39, 43, 154 and 167 of 25, 100 and 400 episodes."""
    sizes = [8, 10, 25, 39, 43, 100, 154, 167, 400]
    assert labelled_sizes(sizes, log=True) == [8, 25, 39, 100, 154, 400]
    assert labelled_sizes([0, 10, 25, 100, 400], log=False) == [0, 25, 100, 400]
    assert labelled_sizes([25, 100, 400], log=True) == [25, 100, 400]
