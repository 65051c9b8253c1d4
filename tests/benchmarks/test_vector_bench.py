"""The vector-env throughput benchmark runs end to end (tiny sizes) and reports every kind."""

from __future__ import annotations

import json

from benchmarks import vector_bench as bench


def test_benchmark_runs_every_kind(tmp_path, capsys):
    out = tmp_path / "bench.json"
    argv = [
        "--modes",
        "joint_position",
        "--num-envs",
        "2",
        "--threads",
        "2",
        "--steps",
        "40",
        "--rounds",
        "1",
        "--physics",
        "--json",
        str(out),
    ]
    assert bench.main(argv) == 0
    (row,) = json.loads(out.read_text())
    assert row["num_envs"] == 2 and row["raw_limit"] == 2 * row["raw_one_thread"] > 0
    assert all(row[kind] > 0 for kind in bench.KINDS)
    assert set(row["physics"]) == {"thread pool", "mujoco.rollout"}
    printed = capsys.readouterr().out
    assert "| joint_position | 2 | 2 |" in printed and "native / raw limit" in printed and "pool / rollout" in printed


def test_benchmark_bad_input_is_one_line(capsys):
    assert bench.main(["--modes", "fly", "--steps", "10"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: --modes must be from") and "\n" not in err
    assert bench.main(["--kinds", "native,gpu"]) == 2
    assert "unknown kinds ['gpu']" in capsys.readouterr().err
