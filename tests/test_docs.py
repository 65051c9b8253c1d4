"""The documentation: the site builds with ``mkdocs build --strict``, its generated pages
hold what they are generated from, and the README stays a landing page."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from wheel_install import build_wheel, no_checkout_env, wheel_venv

import unified_manip

ROOT = Path(__file__).resolve().parents[1]
README_LIMIT = 12 * 1024


def test_readme_is_a_landing_page_of_at_most_12_kb():
    size = (ROOT / "README.md").stat().st_size
    assert size <= README_LIMIT, f"README.md is {size} bytes; move detail into docs/"


# One worker builds the site (minutes) for every test that reads it.
pytestmark = pytest.mark.xdist_group("docs")


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """The site, built as a reader of a clone would: ``mkdocs build --strict`` from the
    repository's root, with the package installed from a wheel (not editable), so the
    source tree imports as laid out (import path = file path). The example family's
    source is on the path, as its own install would put it."""
    tmp = tmp_path_factory.mktemp("site")
    python = wheel_venv(build_wheel(tmp / "wheel"), tmp / "venv", ROOT / "examples" / "valve_family")
    env = {**no_checkout_env(), "NO_MKDOCS_2_WARNING": "1"}
    make = "import gymnasium as gym, unified_manip; print(unified_manip.__file__); gym.make('{}').reset(seed=0)"
    for task_id in ("UnifiedManip/Arm4Reach-v0", "UnifiedManip/ValveTurn-v0"):
        proc = subprocess.run(
            [python, "-c", make.format(task_id)], cwd=ROOT, capture_output=True, text=True, timeout=300, env=env
        )
        assert proc.returncode == 0, proc.stderr[-3000:]
        assert proc.stdout.strip() == str(ROOT / "unified_manip" / "__init__.py")  # the tree shadows the wheel
    out = tmp / "html"
    proc = subprocess.run(
        [python, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=900,
        env=env,
    )
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-4000:]
    return out


@pytest.mark.slow
def test_every_registered_task_has_a_page_with_its_animation_sections_and_modes(site):
    index = (site / "tasks" / "index.html").read_text()
    sys.path.insert(0, str(ROOT / "docs" / "_gen"))
    import taskpages

    animations = taskpages.animations(ROOT / "docs")
    for task_id, spec in unified_manip.TASKS.items():
        name = task_id.split("/", 1)[1]
        picture = taskpages.picture_name(task_id, animations[task_id])  # its own, or its previous version's
        page = (site / "tasks" / name / "index.html").read_text()
        assert f"images/tasks/{picture}.gif" in page, name
        assert (site / "images" / "tasks" / f"{picture}.gif").is_file(), name
        assert f'src="../images/tasks/{picture}.png"' in index, name  # the index's thumbnail
        for section in ("action-space", "rewards", "starting-state", "episode-end", "arguments", "benchmark"):
            assert f'id="{section}"' in page, (name, section)
        assert 'href="../../reference/api/envs/#unified_manip.envs.config.EnvConfig"' in page, name
        for mode in spec.action_modes:
            assert f"<code>{mode}</code>" in page, (name, mode)


@pytest.mark.slow
def test_the_home_page_opens_with_code_and_the_headline_results(site):
    page = (site / "index.html").read_text()
    body = page.split("<h1", 1)[1]
    assert body.index("UnifiedManip/Arm4Reach-v0") < body.index('id="headline-results"') < body.index('id="why"')
    from unified_manip.experiments.headline import headline_table

    headline = headline_table(ROOT / "results" / "action_spaces_families").splitlines()[0]
    assert headline.split(" (", 1)[0] in page and 'href="tasks/FetchPush-v0/"' in page


@pytest.mark.slow
def test_the_command_reference_lists_every_subcommand(site):
    from unified_manip.cli.main import build_parser

    page = (site / "reference" / "cli" / "index.html").read_text()
    subparsers = next(a for a in build_parser()._actions if a.choices and isinstance(a.choices, dict))
    for name in subparsers.choices:
        assert f'id="{name}"' in page, name


@pytest.mark.slow
def test_the_api_reference_is_rendered_from_the_docstrings(site):
    page = (site / "reference" / "api" / "envs" / "index.html").read_text()
    assert "EnvConfig" in page and "UnifiedManipEnv" in page and "doc-heading" in page


def _table_rows(text: str) -> list[dict[str, str]]:
    """The rows of the first Markdown table in ``text``, each as ``{header: cell}``."""
    lines = [line for line in text.splitlines() if line.startswith("|")]
    split = [[c.strip() for c in line.strip("|").split("|")] for line in lines]
    return [dict(zip(split[0], cells)) for cells in split[2:]]


def _setting(row: dict[str, str], mode: str) -> tuple[str, str, str, str, str, str]:
    return (
        row["task"],
        row["algo"],
        row[mode].strip("`"),
        row.get("observation", "default"),
        row.get("randomization", "none"),
        row["reward"],
    )


def _report_rows(report: Path) -> dict[tuple[str, str, str, str, str, str], str]:
    """``(task, algo, mode, observation, randomization, reward) -> "mean [lo, hi]"`` from a committed
    report's "Final success rate" table."""
    text = report.read_text().split("## Final success rate", 1)[1].split("\n## ", 1)[0]
    rows = {}
    for row in _table_rows(text):
        interval = row["interval"].split(" (", 1)[0]
        interval = f" {interval}" if interval.startswith("[") else ""
        rows[_setting(row, "action mode")] = row["mean"] + interval
    return rows


def test_generated_result_tables_equal_the_committed_reports():
    sys.path.insert(0, str(ROOT / "docs" / "_gen"))
    import resultpages

    checked = 0
    for results in sorted((ROOT / "results").glob("*/results.csv")):
        report = results.parent / "report" / "report.md"
        if not report.is_file():
            continue
        expected = _report_rows(report)
        got = {}
        for row in _table_rows(resultpages.final_table([results])):
            got.setdefault(_setting(row, "mode"), []).append(row["final success [interval]"].split(" (", 1)[0])
        for key, value in expected.items():
            assert value in got.get(key, []), (results.parent.name, key, value, got.get(key))
            checked += 1
    assert checked >= 40


def test_the_catalogue_table_sums_each_task_and_the_whole_set(tmp_path):
    """``gen:catalogue``: ``collect --all``'s costs per task and in all, from its catalogue."""
    import json

    sys.path.insert(0, str(ROOT / "docs" / "_gen"))
    import resultpages

    arm, hand = "UnifiedManip/Arm4Push-v0", "UnifiedManip/HandReach-v0"
    entries = {
        "a": {"task": arm, "mode": "ee_delta", "state": "written", "bytes": 2_000_000, "wall_s": 60.0, "cpu_s": 30.0},
        "b": {
            "task": arm,
            "mode": "joint_delta",
            "state": "skipped",
            "converted": "23/49",
            "wall_s": 30.0,
            "cpu_s": 6.0,
        },
        "c": {"task": hand, "mode": "trained", "state": "skipped", "reason": "no run"},
    }
    (tmp_path / "catalogue.json").write_text(json.dumps(entries))
    lines = resultpages.catalogue_table(tmp_path).splitlines()
    assert lines[2] == "| Arm4Push-v0 | 1: `ee_delta` | `joint_delta` 23/49 | 2 MB | 1.5 min | 0.6 min |"
    assert lines[3] == "| HandReach-v0 | 0: – | `trained`: no run | 0 MB | 0.0 min | 0.0 min |"
    assert lines[5].startswith("**The whole set: 1 datasets of 3 tried, 0.00 GB, 0.03 h wall (0.01 h CPU)**")


@pytest.mark.parametrize(
    "kind,section,empty",
    [
        ("robustness", "## Robustness of the final policies", ("benchmark", "no robustness.csv")),
        ("factors", "## One factor at a time", ("observation_designs", "no one-factor rows")),
    ],
)
def test_the_robustness_and_factors_markers_repeat_the_committed_report(kind, section, empty):
    """``gen:robustness`` and ``gen:factors``: each task's table is the report's, to the
    digit, and its figure is the report's figure (the whole distributions' and the factors
    alone); a results directory without such rows is refused."""
    sys.path.insert(0, str(ROOT / "docs" / "_gen"))
    import resultpages

    from unified_manip.experiments.robustness import read_robustness

    committed = [
        p.parent
        for p in sorted((ROOT / "results").glob("*/robustness.csv"))
        if kind == "robustness" or any(r["factor"] for r in read_robustness(p))
    ]
    assert committed, f"some committed results have {kind} rows"
    for path in committed:
        page = getattr(resultpages, kind)(path, path.name, depth=1)
        report = (path / "report" / "report.md").read_text().split(section, 1)[1]
        tables = re.findall(r"\*\*[^*]+\*\*:\n\n((?:\|.*\n)+)", page + "\n")
        figures = re.findall(rf"\(\.\./assets/results/[^/]+/([^)]+_{kind}\.png)\)", page)
        assert tables and len(figures) == len(tables)
        assert all(table in report for table in tables)
        assert all((path / "report" / figure).is_file() for figure in figures), figures
    with pytest.raises(ValueError, match=empty[1]):
        getattr(resultpages, kind)(ROOT / "results" / empty[0], empty[0], depth=1)


def test_the_readme_benchmark_table_equals_the_committed_results():
    """Every row of the README's benchmark table: its seeds' mean and range, recomputed from
    the committed ``results/benchmark*/results.csv``."""
    from collections import defaultdict

    from unified_manip.experiments.results import read_results

    finals = defaultdict(list)
    for path in sorted((ROOT / "results").glob("benchmark*/results.csv")):
        for r in read_results(path):
            demos = bool(r.get("demonstrations") and r["demonstrations"]["episodes"])
            finals[(r["task"].split("/")[-1], r["action_mode"], demos, r["steps"])].append(r["final_success_rate"])
    text = (ROOT / "README.md").read_text().split("## Benchmark", 1)[1].split("\n## ", 1)[0]
    rows = _table_rows(text)
    assert len(rows) >= 10
    for row in rows:
        key = (row["task"], row["mode"], "demos" in row["recipe"], int(row["budget"].rstrip("k")) * 1000)
        values = finals[key]
        assert len(values) == int(row["seeds"]), (key, values)
        assert row["final success"] == f"{np.mean(values):.2f} [{min(values):.2f}, {max(values):.2f}]", (key, values)


def test_the_readme_observation_table_equals_the_committed_results():
    """Every row of the README's observation-design table: final success from
    ``results.csv``, and the same policies under 1 cm of noise and a one-step delay from
    ``robustness.csv``, each as the seeds' mean and range."""
    from collections import defaultdict

    from unified_manip.experiments.results import read_results
    from unified_manip.experiments.robustness import read_robustness

    study = ROOT / "results" / "observation_designs"
    task = "UnifiedManip/Arm4PickAndPlace-v0"
    values: dict[tuple[str, str], list[float]] = defaultdict(list)
    for r in read_results(study / "results.csv"):
        if r["task"] == task:
            values[(r["observation"], "final success")].append(r["final_success_rate"])
    for r in read_robustness(study / "robustness.csv"):
        column = {(0.01, 0): "under 1 cm of noise", (0.0, 1): "1-step delay"}.get((r["noise"], r["delay"]))
        if r["task"] == task and column:
            values[(r["observation"], column)].append(r["success_rate"])
    text = (ROOT / "README.md").read_text().split("## Observation designs", 1)[1].split("\n## ", 1)[0]
    rows = _table_rows(text)
    assert len(rows) == 5
    for row in rows:
        design = row["design (Arm4PickAndPlace-v0)"].strip("`")
        for column in ("final success", "under 1 cm of noise", "1-step delay"):
            v = values[(design, column)]
            assert len(v) == 3, (design, column, v)
            assert row[column] == f"{np.mean(v):.2f} [{min(v):.2f}, {max(v):.2f}]", (design, column, v)
