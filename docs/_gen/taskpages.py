"""Task pages, the task table, the reward table and the version history, generated from
the registry (:data:`unified_manip.TASKS`), live envs and the configs.

A task page has the sections of :data:`SECTIONS`. The written ones come from the task's
``TaskSpec.doc`` (:mod:`taskdoc`); the action space, the reward designs, the episode end,
the ``gym.make`` keywords and the benchmark rows are generated (:mod:`tasksections`), the
action spaces from an env built in every mode (:mod:`taskspaces`). The animation and its
caption come from ``docs/images/tasks/`` (written by ``render_gifs.py``).
"""

from __future__ import annotations

import json
from pathlib import Path

import taskdoc
import tasksections as gen
import taskspaces

#: Where the committed task frames and animations live, relative to ``docs/``.
FRAMES = "images/tasks"
#: Every task page's sections, in order.
SECTIONS: tuple[str, ...] = (
    "Description",
    "Action space",
    "Observation",
    "Rewards",
    "Starting state",
    "Episode end",
    "Arguments",
    "Version history",
    "Benchmark",
)


def short_id(task_id: str) -> str:
    """``UnifiedManip/Arm4Reach-v0`` -> ``Arm4Reach-v0``."""
    return task_id.split("/", 1)[1]


def page_path(task_id: str) -> str:
    """The task page's path inside ``docs/``."""
    return f"tasks/{short_id(task_id)}.md"


def animations(docs_dir: Path) -> dict[str, dict]:
    """How each committed animation was made (``render_gifs.py``'s record), by task ID."""
    path = docs_dir / FRAMES / "animations.json"
    return json.loads(path.read_text()) if path.is_file() else {}


def picture_name(task_id: str, animation: dict | None) -> str:
    """The file name (no suffix) of the task's animation and frame: its own, or those of
    its previous version where ``render_gifs.py`` found the two episodes identical frame
    for frame and recorded ``"file"``."""
    return (animation or {}).get("file", short_id(task_id))


def _picture(spec, animation: dict | None, has_frame: bool) -> list[str]:
    name = picture_name(spec.id, animation)
    if animation:
        success = animation["first_success_step"]
        outcome = f"success at step {success}" if success else "no success"
        caption = (
            f"One episode (seed 0) of {animation['policy']} in `{animation['action_mode']}`, "
            f"{outcome}, shown in real time."
        )
        return [f"![{name}: {caption}](../{FRAMES}/{name}.gif){{ width=240 }}", "", f"*{caption}*", ""]
    if has_frame:
        return [f"![{name}: its scripted policy at work, seed 0](../{FRAMES}/{name}.png){{ width=320 }}", ""]
    return []


def _distance_text(spec) -> str:
    """The goal distance the success threshold applies to: the task's own wording where
    its distance says what it measures (``|dx|``, a weighted norm), else "goal distance"."""
    describe = getattr(spec.goal_distance, "describe", None)
    return f"goal distance {describe()}" if describe else "goal distance"


def task_page(spec, has_frame: bool, animation: dict | None = None) -> str:
    """One task's page, in Markdown."""
    summary, doc = taskdoc.split(spec.doc)
    live = taskspaces.spaces(spec.id)
    example_mode = next(m for m in ("ee_delta", "native", *spec.action_modes) if m in spec.action_modes)
    intro, notes = taskdoc.modes_intro(doc["action"])
    lines = [f"# {short_id(spec.id)}", "", *_picture(spec, animation, has_frame)]
    lines += [
        "| | |",
        "|---|---|",
        f"| ID | `{spec.id}` |",
        f"| family | `{spec.family}` |",
        f"| action space | {gen.box(live['modes'][example_mode])} in `{example_mode}` ([every mode](#action-space)) |",
        f"| goal size | {spec.goal_dim} |",
        f"| episode length | {spec.max_episode_steps} steps of {live['dt'] * 1000:g} ms |",
        f"| success threshold | {_distance_text(spec)} < {spec.distance_threshold:g} |",
        f"| scripted policy | {'yes' if spec.scripted_policy else 'no'} |",
        "",
        "```python",
        "import gymnasium as gym",
        "import unified_manip  # registers the UnifiedManip/* IDs",
        "",
        f'env = gym.make("{spec.id}",',
        f'               action_mode="{example_mode}", reward_type="sparse")',
        "obs, info = env.reset(seed=0)",
        "```",
        "",
        "## Description",
        "",
        summary,
        "",
        *taskdoc.markdown(doc["description"]),
        "## Action space",
        "",
        f"{intro} The first table reads each mode's `action_space` and `observation` size from an "
        "env built in that mode.",
        "",
        *gen.action_tables(spec.controllers, live),
        "",
        *taskdoc.markdown(notes),
        "## Observation",
        "",
        *taskdoc.markdown(doc["observation"]),
        "## Rewards",
        "",
        f'`info["is_success"]` is 1.0 when the goal distance is below **{spec.distance_threshold:g}** '
        "(`distance_threshold`), at reset and on every step.",
        "",
        *taskdoc.markdown(_relabel(doc["rewards"], "Rewards:", "In the dense designs,")),
        f"The reward designs on this task (term set `{spec.terms.name}`), with the scales of the "
        f"default [`RewardConfig`]({gen.REWARD_CONFIG_API}); `reward_config=` changes them "
        "([reward designs](../concepts/rewards.md)):",
        "",
        *gen.reward_rows(spec.terms),
        "",
        "`compute_reward` returns the same reward for goals and infos, batched, for every design.",
        "",
        "## Starting state",
        "",
        *taskdoc.markdown(taskdoc.strip_label(doc["starting"], "Starting state:")),
        "`env.reset(seed=s)` draws every random quantity from the env's `np_random`, so a seed gives the same episode.",
        "",
        "## Episode end",
        "",
        *gen.episode_end(spec, live),
        "",
        "## Arguments",
        "",
        f'Every keyword of `gym.make("{spec.id}", ...)`, with its default: the fields of '
        f"[`EnvConfig`]({gen.ENV_CONFIG_API}), which checks them before a simulator is built.",
        "",
        *gen.argument_rows(spec, live),
        "",
        *(
            taskdoc.markdown(doc["arguments"])
            or ["Any other keyword raises `TypeError`: this task takes no family options.", ""]
        ),
        "## Version history",
        "",
        taskdoc.version_history(spec.doc),
        "",
        "## Benchmark",
        "",
        *_benchmark(spec.id),
        f"Generated from the task's `TaskSpec` (`unified-manip list --doc {spec.id}` prints its text) "
        "and from envs built in every action mode.",
        "",
    ]
    return "\n".join(lines)


def _relabel(lines: list[str], label: str, words: str) -> list[str]:
    """``lines`` with ``label`` at the start of any line replaced by ``words``."""
    return [words + line[len(label) :] if line.startswith(label) else line for line in lines]


def _benchmark(task_id: str) -> list[str]:
    rows = gen.benchmark_rows(task_id)
    if not rows:
        return [f"{short_id(task_id)} is not in the [benchmark](../results/benchmark.md) yet.", ""]
    return [
        "Sparse reward with HER, 50 deterministic evaluation episodes every 10k steps; final success is "
        "the mean over seeds with the seeds' range below 5 seeds "
        "([the benchmark, its recipe and curves](../results/benchmark.md)):",
        "",
        *rows,
        "",
    ]


def task_table(tasks, animations: dict[str, dict] | None = None) -> str:
    """Markdown: every registered ID with a thumbnail (:func:`picture_name`), its family,
    sizes and modes, linked to its page."""
    from unified_manip.envs.config import ACTION_MODES

    animations = animations or {}
    rows = ["| | ID | family | goal size | episode steps | action modes |", "|---|---|---|---:|---:|---|"]
    for spec in tasks.values():
        name = short_id(spec.id)
        every = set(spec.action_modes) == set(ACTION_MODES)
        modes = "every mode" if every else ", ".join(f"`{m}`" for m in spec.action_modes)
        picture = picture_name(spec.id, animations.get(spec.id))
        thumb = f"[![{name}](../{FRAMES}/{picture}.png){{ width=96 }}]({name}.md)"
        rows.append(
            f"| {thumb} | [{name}]({name}.md) | `{spec.family}` | {spec.goal_dim} | {spec.max_episode_steps} | {modes} |"
        )
    return "\n".join(rows)


def versions_table(tasks) -> str:
    """Markdown: each registered ID's version history, from its doc."""
    rows = ["| ID | version history |", "|---|---|"]
    for spec in tasks.values():
        rows.append(f"| [{short_id(spec.id)}](tasks/{short_id(spec.id)}.md) | {taskdoc.version_history(spec.doc)} |")
    return "\n".join(rows)


def frame_exists(docs_dir: Path, task_id: str, animation: dict | None = None) -> bool:
    return (docs_dir / FRAMES / f"{picture_name(task_id, animation)}.png").is_file()


def reward_table(reward_types, term_sets) -> str:
    """Markdown: the terms of every reward design for every term set, with the default
    ``RewardConfig``'s scales, built by the term sets' own ``design``."""
    rows = ['| `reward_type` | term set | terms (`info["reward_terms"]` key: scale × term) |', "|---|---|---|"]
    for reward_type in reward_types:
        for term_set in term_sets:
            spec = term_set.design(reward_type)
            terms = "; ".join(f"`{t.name}`: {t.scale:g} × ({gen.term_formula(t.fn)})" for t in spec.terms)
            rows.append(f"| `{reward_type}` | `{term_set.name}` | {terms} |")
            if reward_type == "sparse":
                rows[-1] = f"| `{reward_type}` | every term set | {terms} |"
                break
    return "\n".join(rows)
