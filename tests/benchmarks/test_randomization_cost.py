"""The reset-cost benchmark of the randomisation presets runs end to end (few resets)."""

from __future__ import annotations

import json

from benchmarks import randomization_cost as bench


def test_every_preset_is_timed_against_none_and_the_draw_is_part_of_the_reset(tmp_path, capsys):
    out = tmp_path / "cost.json"
    assert bench.main(["--resets", "40", "--family", "arm4", "--out", str(out)]) == 0
    result = json.loads(out.read_text())
    assert not list(tmp_path.glob("*.partial"))
    row = result["families"]["arm4"]
    assert set(row["ms_per_reset"]) == set(bench.PRESETS)
    assert set(row["overhead"]) == set(bench.PRESETS) - {"none"}
    assert row["overhead"]["all"] > 0  # the arm's reset is cheap beside drawing and writing 12 terms
    # the randomiser's own work is one part of an ``all`` reset, which also resets the simulator
    assert 0 < row["randomiser_ms_all"] < row["ms_per_reset"]["all"]
    assert 0 < row["randomiser_ms_all_alone"] < row["ms_per_reset"]["all"]
    assert result["machine"]["clock"].startswith("time.process_time")
    assert "arm4" in capsys.readouterr().out
