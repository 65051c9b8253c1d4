"""Ctrl-C in a long command: exit status 130, one line on stderr, no traceback, and no
file left half-written. Each command runs as a real process and gets a real SIGINT once it
is simulating (it has mapped MuJoCo's library, which the command line itself never loads).

``train`` and ``bench`` have their own tests of the same contract, with what they keep:
``tests/training/test_train.py::test_interrupted_or_killed_run_resumes`` (a checkpoint a
resumed run continues from) and ``tests/experiments/test_bench.py::
test_killed_bench_resumes_with_exactly_one_complete_row_per_run`` (finished rows kept).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from unified_manip.cli.interrupts import noting_ctrl_c
from unified_manip.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def dataset(tmp_path_factory) -> Path:
    """20 scripted Arm4PickAndPlace-v0 episodes: enough that replaying or converting them
    takes many seconds."""
    out = tmp_path_factory.mktemp("data") / "arm-pick-v0"
    argv = ["collect", "--env", "UnifiedManip/Arm4PickAndPlace-v0", "--episodes", "20", "--out", str(out)]
    assert main([*argv, "--no-progress"]) == 0
    return out


@pytest.fixture(scope="module")
def bench(tmp_path_factory) -> Path:
    """A bench directory with one finished 300-step sac_her run of Arm4Reach-v0."""
    bench = tmp_path_factory.mktemp("bench")
    run = bench / "runs" / "Arm4Reach-v0__ee_delta__sparse__sac_her__s0"
    sets = ["learning_starts=100", "batch_size=64", "buffer_size=10000", "eval_freq=300", "n_eval_episodes=1"]
    argv = ["train", "--env", "UnifiedManip/Arm4Reach-v0", "--action-mode", "ee_delta", "--algo", "sac_her"]
    argv += ["--steps", "300", "--run-dir", str(run), "--no-progress"] + [a for s in sets for a in ("--set", s)]
    assert main(argv) == 0
    return bench


def _simulating(pid: int) -> bool:
    try:
        return "libmujoco" in Path(f"/proc/{pid}/maps").read_text()
    except FileNotFoundError:
        return False


def interrupt(argv: list[str], cwd: Path, after: float = 1.0) -> tuple[int, str, str]:
    """Run ``unified-manip ARGV``, send SIGINT ``after`` seconds after MuJoCo's library is
    mapped (1 s: well inside the work), and return its exit status, stdout and stderr."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "unified_manip.cli", *argv],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
        # Ctrl-C's default, even where this suite runs as a background job (which starts
        # with SIGINT ignored, and Python then installs no KeyboardInterrupt handler).
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    deadline = time.monotonic() + 300
    while not _simulating(proc.pid):
        assert proc.poll() is None, f"ended before it simulated: {proc.communicate()}"
        assert time.monotonic() < deadline, "never started simulating"
        time.sleep(0.05)
    time.sleep(after)
    assert proc.poll() is None, f"finished before the interrupt: {proc.communicate()}"
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    return proc.returncode, out, err


def assert_one_line(command: str, code: int, err: str) -> None:
    assert code == 130, err
    assert "Traceback" not in err, err
    assert err.strip().splitlines()[-1] == f"unified-manip {command}: interrupted", err


def test_collect(tmp_path):
    out = tmp_path / "big-v0"
    argv = ["collect", "--env", "UnifiedManip/Arm4Reach-v0", "--episodes", "100000", "--out", str(out)]
    code, _, err = interrupt([*argv, "--json", str(tmp_path / "c.json"), "--no-progress"], tmp_path)
    assert_one_line("collect", code, err)
    assert os.listdir(tmp_path) == []  # no dataset, no summary, no temporary


def test_convert(dataset, tmp_path):
    out = tmp_path / "arm-pick-joint-v0"
    argv = ["convert", str(dataset), "--action-mode", "joint_delta", "--out", str(out), "--no-progress"]
    code, _, err = interrupt([*argv, "--json", str(tmp_path / "c.json")], tmp_path)
    assert_one_line("convert", code, err)
    assert os.listdir(tmp_path) == []


def test_replay(dataset, tmp_path):
    video, summary = tmp_path / "replay.mp4", tmp_path / "r.json"
    argv = ["replay", str(dataset), "--video", str(video), "--json", str(summary), "--no-progress"]
    code, _, err = interrupt(argv, tmp_path)
    assert_one_line("replay", code, err)
    assert os.listdir(tmp_path) == []  # no partial video


def test_eval(bench, tmp_path):
    run = next((bench / "runs").iterdir())
    video, summary = tmp_path / "eval.mp4", tmp_path / "e.json"
    argv = ["eval", str(run), "--episodes", "100000", "--video", str(video), "--json", str(summary)]
    code, _, err = interrupt(argv, tmp_path)
    assert_one_line("eval", code, err)
    assert os.listdir(tmp_path) == []


def test_robustness(bench, tmp_path):
    before = sorted(p.relative_to(bench) for p in bench.rglob("*"))
    code, _, err = interrupt(["robustness", str(bench), "--episodes", "100000", "--no-progress"], tmp_path)
    assert_one_line("robustness", code, err)
    # No robustness.csv until a condition is complete, and nothing else touched.
    assert sorted(p.relative_to(bench) for p in bench.rglob("*")) == before


@pytest.mark.parametrize("after", [0.0, 0.02, 0.04, 0.06, 0.08])
def test_robustness_while_mujoco_imports(bench, tmp_path, after):
    """The signal lands while MuJoCo's bindings import: inside a C extension's
    initialisation (which turns it into ``ImportError``), a ctypes call (``ArgumentError``)
    or code the bindings run through ``PyRun_String`` (after which CPython would end the
    process by SIGINT, not with the status returned)."""
    code, _, err = interrupt(["robustness", str(bench), "--no-progress"], tmp_path, after=after)
    assert_one_line("robustness", code, err)


class _HalfBuilt:
    """An object whose finaliser fails, as a GL context the signal cut off half-built."""

    def __del__(self):
        raise AttributeError("'GLContext' object has no attribute '_context'")


def test_a_finaliser_failing_after_the_signal_prints_nothing(monkeypatch):
    """What the interrupt leaves half-built fails quietly when freed, and only after the
    signal: before it, and once the command is done, such errors go to the hook as usual
    (Python's default hook prints them with a traceback)."""
    reported = []
    monkeypatch.setattr(sys, "unraisablehook", reported.append)
    with noting_ctrl_c() as ctrl_c:
        _HalfBuilt()
        assert len(reported) == 1
        with pytest.raises(KeyboardInterrupt):
            ctrl_c(signal.SIGINT, None)  # the handler the signal calls
        _HalfBuilt()
        assert len(reported) == 1
    _HalfBuilt()
    assert len(reported) == 2 and "_context" in str(reported[-1].exc_value)
