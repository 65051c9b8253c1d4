"""``unified-manip aggregate``: the cross-task aggregates of several benches joined, over
the modes every task ran, and one-line errors for what cannot be joined."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from unified_manip.cli import main

ROOT = Path(__file__).resolve().parents[2]
#: Two committed cloning benches on different tasks: the arm's 8 modes, Lift's 6.
ARM = ROOT / "results" / "bc_arm4pnp_n100" / "results.csv"
LIFT = ROOT / "results" / "bc_lift_search_n100" / "results.csv"


def _table(text: str) -> dict[str, str]:
    """The IQM table's rows, by mode."""
    start = text.index("| action mode | runs | IQM final success")
    rows = text[start:].split("\n\n")[0].splitlines()[2:]
    return {r.split("|")[1].strip(): r for r in rows}


@pytest.mark.slow
def test_two_benches_join_into_one_aggregate_over_their_common_modes(tmp_path, capsys):
    out = tmp_path / "agg"
    assert main(["aggregate", str(ARM), str(LIFT), "--out", str(out)]) == 0
    assert capsys.readouterr().out.strip() == f"wrote {out / 'aggregate.md'}"
    text = (out / "aggregate.md").read_text()
    assert text.startswith("# Aggregate: bc_arm4pnp_n100 + bc_lift_search_n100\n")
    # Each bench's own commands, then where each task's runs come from.
    assert "make_datasets.sh Arm4PickAndPlace-v0" in text and "make_datasets.sh Lift-v0" in text
    assert f"| `{ARM}` | Arm4PickAndPlace-v0 | 24 | 50,000 gradient steps | 0, 1, 2 |" in text
    assert f"| `{LIFT}` | Lift-v0 | 18 | 50,000 gradient steps | 0, 1, 2 |" in text
    assert "Action modes run on all 2 tasks (Arm4PickAndPlace-v0, Lift-v0)" in text
    # Lift's bench has no joint_torque or native runs: the two are named, not aggregated.
    assert "Left out, as not run on every task: joint_torque (no runs of Lift-v0); native (no runs of Lift-v0)." in text
    table = _table(text)
    modes = {"ee_delta", "ee_target_delta", "joint_delta", "joint_position", "joint_target_delta", "joint_velocity"}
    assert set(table) == modes
    assert all(f"| {m} | 6 | " in table[m] for m in modes)  # 3 seeds on each of 2 tasks
    # joint_position cloned to 0 on both tasks: 6 runs at 0.
    assert "| joint_position | 6 | 0.00 [0.00, 0.00] |" in table["joint_position"]
    for name in ("iqm", "profile", "improvement"):
        png = out / f"aggregates_bc_sparse_{name}.png"
        assert png.stat().st_size > 10_000 and f"({png.name})" in text


def _bench(root: Path, name: str, source: Path) -> Path:
    (root / name).mkdir(parents=True)
    return Path(shutil.copy(source, root / name / "results.csv"))


@pytest.mark.parametrize(
    "case, needle",
    [
        ("a run in two files", "is also in"),
        ("the same file twice", "the same results.csv twice"),
        ("one task", "no aggregate: no algorithm and reward has two action modes"),
        ("a missing file", "not found; expected a bench's results.csv"),
    ],
)
def test_what_cannot_be_joined_is_a_one_line_error(case, needle, tmp_path, capsys):
    arm = _bench(tmp_path, "a", ARM)
    argv = {
        "a run in two files": [str(arm), str(_bench(tmp_path, "b", ARM))],
        "the same file twice": [str(arm), str(tmp_path / "a" / ".." / "a" / "results.csv")],
        "one task": [str(arm)],
        "a missing file": [str(arm), str(tmp_path / "nope" / "results.csv")],
    }[case]
    with pytest.raises(SystemExit) as exit_:
        main(["aggregate", *argv, "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert exit_.value.code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith("unified-manip aggregate: error: ") and needle in err, err
    if case == "a run in two files":  # names the run and both files
        assert "Arm4PickAndPlace-v0__" in err and str(arm) in err and str(tmp_path / "b") in err
    assert not (tmp_path / "out" / "aggregate.md").exists()
