"""The soak and memory benchmark, at CI size (the full sizes and their figures: README)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

import unified_manip
from benchmarks import gauges, soak

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.robosuite  # a cycle of every family
def test_short_soak_holds_memory_descriptors_and_contexts(tmp_path):
    out = tmp_path / "soak.json"
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "benchmarks.soak",
            "--steps",
            "1000",
            "--frames",
            "10",
            "--cycles",
            "3",
            "--json",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=900,
        cwd=ROOT,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    document = json.loads(out.read_text())
    assert document["command"].endswith("--cycles 3 --json " + str(out))
    rows = document["rows"]
    steps = [r for r in rows if r["part"] == "steps"]
    assert [r["mode"] for r in steps] == list(unified_manip.TASKS[soak.STEP_TASK].action_modes)
    for r in steps:
        assert r["count"] == 1000 and r["episodes"] >= 1000 // 100
        assert r["sim_unstable"] == 0 and r["rss_growth_mb"] < soak.RSS_LIMIT_MB
    frames = [r for r in rows if r["part"] == "frames"]
    assert [r["task"] for r in frames] == list(soak.FRAME_TASKS)
    assert all(r["count"] == 10 and r["rss_growth_mb"] < soak.RSS_LIMIT_MB for r in frames)
    cycles = [r for r in rows if r["part"] == "cycles"]
    assert [r["family"] for r in cycles] == ["arm4", "fetch", "shadow_hand", "robosuite"]
    for r in cycles:
        assert r["after"]["fds"] == r["before"]["fds"], r
        assert r["after"]["gl_contexts"] == r["before"]["gl_contexts"] == 0, r
    assert "| robosuite | 3 |" in proc.stdout
    # Progress bars go to stderr, one per part, and end at their totals.
    assert "soak make/close cycles: 100%" in proc.stderr and "12/12" in proc.stderr, proc.stderr


def test_soak_bad_input_is_one_line_exit_2():
    proc = subprocess.run(
        [sys.executable, "-m", "benchmarks.soak", "--parts", "steps,naps"],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=ROOT,
    )
    assert proc.returncode == 2
    assert (
        proc.stderr.strip() == "python -m benchmarks.soak: error: unknown part 'naps'; expected steps, frames or cycles"
    )


def test_gauges_see_a_live_renderer():
    env = soak._make("UnifiedManip/Arm4Reach-v0", render_mode="rgb_array", render_width=32, render_height=32)
    env.reset(seed=0)
    before = gauges.gl_contexts()
    env.render()
    assert gauges.gl_contexts() == before + 1  # the counter can fail: it sees a context while one lives
    env.close()
    assert gauges.gl_contexts() == before
