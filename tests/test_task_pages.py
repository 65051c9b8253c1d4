"""The generated task pages (``docs/_gen/taskpages.py``): every section, in order, and what
they state checked against envs built here, the README and the committed animations.

Cost: one env per action mode of every task (122 envs, about 15 s on a quiet core), plus
the pages themselves, which read the same spaces from ``.cache/docs/`` or build them once.
"""

from __future__ import annotations

import json
import re
import sys
import warnings
from pathlib import Path

import gymnasium as gym
import pytest

import unified_manip
from unified_manip.envs.config import EnvConfig
from unified_manip.envs.setup import CONFIG_FIELDS

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "docs" / "_gen"))

import taskpages  # noqa: E402
import tasksections  # noqa: E402
import taskspaces  # noqa: E402

#: The pages document every ID, so they need every family installed (the robosuite extra too).
pytestmark = pytest.mark.robosuite

IMAGES = ROOT / "docs" / "images" / "tasks"
GIF_LIMIT = 300_000  # bytes per animation
TOTAL_LIMIT = 8_000_000  # bytes for all of them


@pytest.fixture(scope="module")
def pages() -> dict[str, str]:
    animations = taskpages.animations(ROOT / "docs")
    return {
        task_id: taskpages.task_page(
            spec, taskpages.frame_exists(ROOT / "docs", task_id, animations.get(task_id)), animations.get(task_id)
        )
        for task_id, spec in unified_manip.TASKS.items()
    }


def _section(page: str, title: str) -> str:
    return page.split(f"\n## {title}\n", 1)[1].split("\n## ", 1)[0]


def _rows(text: str) -> list[list[str]]:
    """The cells of every body row of the Markdown tables in ``text`` (no header, no rule)."""
    lines = text.splitlines()
    rows = []
    for i, line in enumerate(lines):
        rule = i + 1 < len(lines) and lines[i + 1].startswith("|-")
        if line.startswith("| ") and not rule:
            rows.append([c.strip() for c in line.strip().strip("|").split(" | ")])
    return rows


def test_every_page_has_every_section_in_order(pages):
    for task_id, page in pages.items():
        headings = re.findall(r"^## (.+)$", page, re.M)
        assert tuple(headings) == taskpages.SECTIONS, (task_id, headings)
        for title in taskpages.SECTIONS:
            assert _section(page, title).strip(), (task_id, title)


def _space(task_id: str, mode: str) -> tuple[str, int, float]:
    """The ``Box`` as the page writes it, the ``observation`` size and the step duration
    of ``task_id`` in ``mode``: from an env built here or, for a pinned family that cannot
    be installed here, its committed record (which test_metaworld.py compares with the
    live envs where it is installed)."""
    spec = unified_manip.TASKS[task_id]
    if not spec.installed and spec.extra in taskspaces.PINNED_EXTRAS:
        rec = taskspaces.recorded(task_id)
        m = rec["modes"][mode]
        box = f"`Box({min(m['low'])}, {max(m['high'])}, {tuple(m['shape'])}, {m['dtype']})`"
        return box, m["observation"], rec["dt"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        env = gym.make(task_id, action_mode=mode, disable_env_checker=True)
    box = env.action_space
    out = (
        f"`Box({box.low.min()}, {box.high.max()}, {box.shape}, {box.dtype})`",
        env.observation_space["observation"].shape[0],
        env.unwrapped.backend.dt,
    )
    env.close()
    return out


def test_the_action_spaces_and_episode_length_on_the_pages_are_the_live_envs(pages):
    """Every mode of every task, built here: the page's ``Box`` and ``observation`` size
    are the env's, and the episode end names its time limit and step duration."""
    checked = 0
    for task_id, spec in unified_manip.TASKS.items():
        page = pages[task_id]
        table = {r[0].strip("`"): r for r in _rows(_section(page, "Action space")) if len(r) == 4}
        assert set(table) >= set(spec.action_modes), task_id
        for mode in spec.action_modes:
            expected, size, dt = _space(task_id, mode)
            assert table[mode][1] == expected, (task_id, mode, table[mode][1], expected)
            assert table[mode][3] == str(size), (task_id, mode)
            checked += 1
        steps = spec.max_episode_steps
        assert f"after **{steps} steps** of {dt * 1000:g} ms" in _section(page, "Episode end"), task_id
    assert checked == sum(len(s.action_modes) for s in unified_manip.TASKS.values()) > 100


def test_the_reward_rows_are_the_envs_reward_designs(pages):
    """One task per term set: each ``reward_type`` row names the terms and scales
    of the reward design an env built with it uses, and the threshold is the task's."""
    seen = set()
    for task_id, spec in unified_manip.TASKS.items():
        if spec.terms.name in seen or spec.family == "robosuite":
            continue
        seen.add(spec.terms.name)
        rewards = _section(pages[task_id], "Rewards")
        assert f"below **{spec.distance_threshold:g}**" in rewards
        rows = {r[0].strip("`"): r[1] for r in _rows(rewards)}
        for reward_type in ("sparse", "dense", "dense_penalized"):
            env = gym.make(task_id, reward_type=reward_type, disable_env_checker=True)
            terms = re.findall(r"`(\w+)`: ([\d.]+) ×", rows[reward_type])
            assert terms == [(t.name, f"{t.scale:g}") for t in env.unwrapped.reward_spec.terms], (task_id, reward_type)
            env.close()
    assert (
        seen
        == {s.terms.name for s in unified_manip.TASKS.values() if s.family != "robosuite"}
        >= {"reach", "push", "grasp"}
    )


def test_the_arguments_are_every_gym_make_keyword_with_its_default(pages):
    """Every ``EnvConfig`` keyword is on every page with its default, and each default
    passed to ``gym.make`` by name is accepted as it is."""
    defaults = EnvConfig()
    for task_id, page in pages.items():
        rows = {r[0].strip("`"): r for r in _rows(_section(page, "Arguments"))}
        assert set(rows) == set(CONFIG_FIELDS), task_id
        for name in CONFIG_FIELDS:
            assert rows[name][1] == f"`{getattr(defaults, name)!r}`", (task_id, name)
        assert "../reference/api/envs.md#unified_manip.envs.config.EnvConfig" in _section(page, "Arguments")
    task = "UnifiedManip/Arm4Reach-v0"
    env = gym.make(task, **{name: getattr(defaults, name) for name in CONFIG_FIELDS}, disable_env_checker=True)
    assert env.unwrapped.config == EnvConfig()
    env.close()


def test_a_page_that_lists_no_family_options_means_none_are_taken(pages):
    for task_id, page in pages.items():
        if "this task takes no family options" not in page:
            assert unified_manip.TASKS[task_id].family == "robosuite", task_id
            continue
        if unified_manip.TASKS[task_id].installed:  # a pinned family not installed here: its page's text alone
            with pytest.raises(TypeError, match="take no extra options"):
                gym.make(task_id, robot="Panda", disable_env_checker=True)


def test_the_home_pages_benchmark_rows_equal_the_readmes():
    """The generated summary (the same rows as each task page's) against the README's
    written table, which ``test_docs`` recomputes from the committed results."""
    summary = {
        (r[0].split("]")[0][1:], r[1].strip("`"), "demos" in r[2], r[3]): (r[4], r[5])
        for r in _rows(tasksections.benchmark_summary(unified_manip.TASKS))
    }
    readme = (ROOT / "README.md").read_text().split("## Benchmark", 1)[1].split("\n## ", 1)[0]
    rows = _rows(readme)
    assert len(rows) >= 10
    for task, mode, recipe, budget, seeds, final, *_ in rows:
        assert summary[(task, mode.strip("`"), "demos" in recipe, budget)] == (seeds, final), (task, mode, budget)


def test_the_benchmark_section_links_the_benchmark_or_says_the_task_has_no_row(pages):
    for task_id, page in pages.items():
        section = _section(page, "Benchmark")
        assert "../results/benchmark.md" in section
        has_rows = bool(tasksections.benchmark_rows(task_id))
        assert ("is not in the [benchmark]" in section) != has_rows, task_id


def test_every_task_has_a_small_animation_recorded_and_shown(pages):
    from PIL import Image

    record = json.loads((IMAGES / "animations.json").read_text())
    sizes = {}  # by file: a version whose episode is its previous version's shares its file
    for task_id, page in pages.items():
        name = taskpages.picture_name(task_id, record[task_id])
        path = IMAGES / f"{name}.gif"
        size = sizes[name] = path.stat().st_size
        assert size <= GIF_LIMIT, (name, size)
        with Image.open(path) as gif:
            assert gif.format == "GIF" and 160 <= gif.width <= 240 and gif.n_frames > 5, name
            assert gif.n_frames == record[task_id]["frames"], name
        assert f"](../images/tasks/{name}.gif)" in page, name
        assert record[task_id]["policy"] in page, name
    assert sum(sizes.values()) <= TOTAL_LIMIT


def test_generated_pages_hold_no_internal_references(pages):
    text = "\n".join(pages.values()) + tasksections.benchmark_summary(unified_manip.TASKS)
    assert not re.search(r"\bissue \d+|design document", text, re.I)
