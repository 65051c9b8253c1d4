"""Task pages, the task table, the mode and reward tables and the version history,
generated from the registry (:data:`unified_manip.TASKS`) and the configs.

A task's ``TaskSpec.doc`` is plain text (what ``unified-manip list --doc ID`` prints).
:func:`task_page` turns it into Markdown: its observation tables become Markdown
tables, its action-mode list is rebuilt from the task's controller configs, and its
``Version history:`` paragraph feeds :func:`versions_table`.
"""

from __future__ import annotations

import re
from pathlib import Path

# Paragraph starters in a task doc: a label, optionally with a parenthesis, then a colon
# ("Goal (3,): ...", "Dense reward: ...", "Options: ..."), or a line that opens a
# section without one.
_LABEL = re.compile(r"^[A-Z][A-Za-z ]{0,30}(?: \([^)]*\))?:(?:\s|$)")
_STARTS = ("Observation", "- ")
# A row of an observation table: "    0-3    joint angles j0..j3    rad".
_ROW = re.compile(r"^\s{4}(\d+(?:-\d+)?)\s{2,}(.*?)(?:\s{2,}(\S.*?))?\s*$")

#: Where the committed task frames live, relative to ``docs/``.
FRAMES = "images/tasks"


def short_id(task_id: str) -> str:
    """``UnifiedManip/Arm4Reach-v0`` -> ``Arm4Reach-v0``."""
    return task_id.split("/", 1)[1]


def page_path(task_id: str) -> str:
    """The task page's path inside ``docs/``."""
    return f"tasks/{short_id(task_id)}.md"


def _split_doc(doc: str) -> tuple[str, list[str]]:
    """The doc's first paragraph (its summary) and the remaining lines."""
    lines = doc.strip("\n").splitlines()
    end = next((i for i, line in enumerate(lines) if not line.strip()), len(lines))
    return " ".join(line.strip() for line in lines[:end]), lines[end:]


def _modes_block(lines: list[str]) -> tuple[int, int] | None:
    """``(start, stop)`` of the action-mode list: its "Action modes" header (possibly
    wrapped over several lines), the indented mode rows and the indented
    ``controller_options`` paragraph after them."""
    start = next((i for i, line in enumerate(lines) if line.startswith("Action modes")), None)
    if start is None:
        return None
    i = start
    while i < len(lines) and not lines[i].startswith("    "):
        i += 1
    while i < len(lines) and lines[i].startswith("    "):
        i += 1
    return start, i


def _modes_intro(lines: list[str]) -> str:
    """The "Action modes (...):" header's parenthesis as one sentence."""
    header = []
    for line in lines:
        if line.startswith("    "):
            break
        header.append(line.strip())
    text = " ".join(header).rstrip(":")
    if text.startswith("Action modes (") and text.endswith(")"):
        text = text[len("Action modes (") : -1]
    return text[:1].upper() + text[1:] + "."


def modes_table(controllers) -> str:
    """Markdown: one row per action mode with its config's description and the
    parameters ``controller_options`` may set, with their values for this task."""
    rows = [
        "| mode | the action (`a` in [-1, 1] per joint or axis) | `controller_options` (defaults here) |",
        "|---|---|---|",
    ]
    for mode, config in controllers.items():
        params = ", ".join(f"`{name}={value!r}`" for name, value in config.parameters().items()) or "–"
        rows.append(f"| `{mode}` | {config.describe()} | {params} |")
    return "\n".join(rows)


def _table(rows: list[re.Match]) -> list[str]:
    out = ["| index | content | units |", "|---|---|---|"]
    out += [f"| {m.group(1)} | {m.group(2).strip()} | {(m.group(3) or '').strip()} |" for m in rows]
    return out


def _markdown(lines: list[str]) -> list[str]:
    """Plain doc lines to Markdown: paragraphs (a label starts a new one), list items,
    observation tables from indented rows, other indented blocks as code."""
    out: list[str] = []
    para: list[str] = []

    def flush():
        if para:
            out.extend([" ".join(para), ""])
            para.clear()

    i = 0
    while i < len(lines):
        line = lines[i]
        if not line.strip():
            flush()
            i += 1
        elif line.startswith("    "):
            flush()
            block = []
            while i < len(lines) and lines[i].startswith("    "):
                block.append(lines[i])
                i += 1
            rows = [_ROW.match(b) for b in block if not set(b.strip()) <= set("= ")]
            rows = [r for r in rows if r and r.group(1) != "index"]
            body = [b for b in block if not set(b.strip()) <= set("= ") and "index  content" not in b]
            if rows and len(rows) == len(body):
                out.extend([*_table(rows), ""])
            else:
                out.extend(["```text", *(b[4:] for b in block), "```", ""])
        else:
            stripped = line.strip()
            if _LABEL.match(stripped) or stripped.startswith(_STARTS):
                flush()
            para.append(stripped)
            i += 1
    flush()
    return out


def version_history(doc: str) -> str:
    """The doc's ``Version history:`` paragraph, without its label."""
    lines = doc.strip("\n").splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("Version history:"))
    text = []
    for line in lines[start:]:
        if not line.strip():
            break
        text.append(line.strip())
    return " ".join(text)[len("Version history:") :].strip()


def _without_history(lines: list[str]) -> list[str]:
    start = next((i for i, line in enumerate(lines) if line.startswith("Version history:")), len(lines))
    stop = start
    while stop < len(lines) and lines[stop].strip():
        stop += 1
    return lines[:start] + lines[stop:]


def task_page(spec, has_frame: bool) -> str:
    """One task's page, in Markdown."""
    summary, rest = _split_doc(spec.doc)
    rest = _without_history(rest)
    block = _modes_block(rest)
    example_mode = "ee_delta" if "ee_delta" in spec.action_modes else spec.action_modes[0]
    lines = [f"# {short_id(spec.id)}", "", summary, ""]
    if has_frame:
        lines += [
            f"![{short_id(spec.id)}: its scripted policy at work, seed 0](../{FRAMES}/{short_id(spec.id)}.png)"
            "{ width=320 }",
            "",
        ]
    lines += [
        "| | |",
        "|---|---|",
        f"| ID | `{spec.id}` |",
        f"| family | `{spec.family}` |",
        f"| reward term set | `{spec.terms.name}` ([reward designs](../concepts/rewards.md)) |",
        f"| goal size | {spec.goal_dim} |",
        f"| episode length | {spec.max_episode_steps} steps |",
        f"| success threshold | goal distance < {spec.distance_threshold:g} |",
        f"| scripted policy | {'yes' if spec.scripted_policy else 'no'} |",
        "",
        "```python",
        "import gymnasium as gym",
        "import unified_manip  # registers the UnifiedManip/* IDs",
        "",
        f'env = gym.make("{spec.id}",',
        f'               action_mode="{example_mode}", reward_type="sparse")',
        "```",
        "",
        "## Description",
        "",
    ]
    if block is None:
        lines += _markdown(rest)
    else:
        start, stop = block
        lines += _markdown(rest[:start])
        lines += ["## Action modes", "", _modes_intro(rest[start:stop]), "", modes_table(spec.controllers), ""]
        after = _markdown(rest[stop:])
        if after:
            lines += ["## Details", "", *after]
    lines += [
        "## Version history",
        "",
        version_history(spec.doc),
        "",
        f"Generated from the task's `TaskSpec` (`unified-manip list --doc {spec.id}` prints the same text).",
        "",
    ]
    return "\n".join(lines)


def task_table(tasks) -> str:
    """Markdown: every registered ID with its family, sizes and modes, linked to its page."""
    rows = ["| ID | family | goal size | episode steps | action modes |", "|---|---|---:|---:|---|"]
    for spec in tasks.values():
        name = short_id(spec.id)
        modes = ", ".join(f"`{m}`" for m in spec.action_modes)
        rows.append(f"| [{name}]({name}.md) | `{spec.family}` | {spec.goal_dim} | {spec.max_episode_steps} | {modes} |")
    return "\n".join(rows)


def versions_table(tasks) -> str:
    """Markdown: each registered ID's version history, from its doc."""
    rows = ["| ID | version history |", "|---|---|"]
    for spec in tasks.values():
        rows.append(f"| [{short_id(spec.id)}](tasks/{short_id(spec.id)}.md) | {version_history(spec.doc)} |")
    return "\n".join(rows)


def frame_exists(docs_dir: Path, task_id: str) -> bool:
    return (docs_dir / FRAMES / f"{short_id(task_id)}.png").is_file()


def _term_formula(fn) -> str:
    """A reward term's function, written out."""
    if hasattr(fn, "gain"):  # rewards.Shaped
        x = "d_goal" if fn.of == "distance" else fn.of
        shaped = f"1 - tanh({fn.gain:g} · {x})"
        return f"{fn.gate} · ({shaped})" if fn.gate else shaped
    known = {"sparse": "success - 1", "success_bonus": "success", "action_penalty": "-Σa² (`action_sq`)"}
    name = getattr(fn, "__name__", "")
    if name in known:
        return known[name]
    doc = (getattr(fn, "__doc__", None) or repr(fn)).strip().splitlines()[0]
    return doc.split(":")[0].strip("`. ")  # a term set's own term: its docstring's formula


def reward_table(reward_types, term_sets) -> str:
    """Markdown: the terms of every reward design for every term set, with the default
    ``RewardConfig``'s scales, built by the term sets' own ``design``."""
    rows = ['| `reward_type` | term set | terms (`info["reward_terms"]` key: scale × term) |', "|---|---|---|"]
    for reward_type in reward_types:
        for term_set in term_sets:
            spec = term_set.design(reward_type)
            terms = "; ".join(f"`{t.name}`: {t.scale:g} × ({_term_formula(t.fn)})" for t in spec.terms)
            rows.append(f"| `{reward_type}` | `{term_set.name}` | {terms} |")
            if reward_type == "sparse":
                rows[-1] = f"| `{reward_type}` | every term set | {terms} |"
                break
    return "\n".join(rows)
