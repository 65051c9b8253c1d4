"""A dataset written under Minari 0.5.3 reads and replays under 0.5.4, and the other way
round (``minari[hdf5]>=0.5.3,<0.6``: numpy 1.26 installs get 0.5.3, numpy 2 ones 0.5.4).

The other version runs in a venv that sees everything installed here but its own Minari,
so only Minari differs between writer and reader: the replay must stay exact, and it names
the Minari version the dataset was recorded under."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from importlib.metadata import version

import pytest
from conftest import ROOT, overlay_venv

from unified_manip.datasets import store

#: Each supported Minari release and the one it is tested against.
OTHER = {"0.5.3": "0.5.4", "0.5.4": "0.5.3"}


def _cli(python: str, *args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.run(
        [python, "-m", "unified_manip.cli", *args], capture_output=True, text=True, env=env, timeout=600
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    return proc


@pytest.mark.slow
def test_a_dataset_crosses_minari_0_5_3_and_0_5_4(tmp_path):
    here = version("minari")
    assert here in OTHER, f"minari {here} is installed: add it to OTHER with the release to test it against"
    other = OTHER[here]
    pythons = {here: sys.executable, other: overlay_venv(tmp_path / "venv", f"minari=={other}")}
    versions_seen = {
        v: subprocess.run([p, "-c", "import minari; print(minari.__version__)"], capture_output=True, text=True)
        for v, p in pythons.items()
    }
    assert {v: proc.stdout.strip() for v, proc in versions_seen.items()} == {here: here, other: other}
    for writer, reader in ((here, other), (other, here)):
        out = tmp_path / f"written-{writer}" / "arm4-v0"
        _cli(pythons[writer], "collect", "--env", "UnifiedManip/Arm4PickAndPlace-v0", "--episodes", "2",
             "--out", str(out), "--no-progress")  # fmt: skip
        meta = json.loads((out / "data" / "metadata.json").read_text())
        assert (meta["minari_version"], meta[store.KEY]["versions"]["minari"]) == (store.MINARI_FORMAT, writer)
        report = tmp_path / f"replayed-{reader}.json"
        _cli(pythons[reader], "replay", str(out), "--json", str(report), "--no-progress")
        got = json.loads(report.read_text())
        assert got["exact"] and len(got["episodes"]) == 2, got
        assert got["version_mismatches"] == [f"minari {writer} (recorded) vs {reader} (here)"]
