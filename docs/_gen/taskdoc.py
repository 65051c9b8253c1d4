"""A task's ``TaskSpec.doc`` (plain text, what ``unified-manip list --doc ID`` prints),
split into the sections of its page and turned into Markdown.

The doc is paragraphs separated by blank lines. Its first paragraph is the summary. Each
later paragraph belongs to the section its first words name (:data:`ROUTES`), or to the
description when they name none. A label line inside a paragraph ("Goal (3,): ...")
opens that label's section; the action-mode list keeps what follows it up to the next
blank line (the notes on the modes).
"""

from __future__ import annotations

import re

#: Paragraph openings and the page section they belong to, checked in order.
ROUTES: tuple[tuple[str, str], ...] = (
    ("Starting state:", "starting"),
    ("Success:", "rewards"),
    ("Native success", "rewards"),
    ("Rewards:", "rewards"),
    ("Info adds", "rewards"),
    ("Observation", "observation"),
    ("Goal (", "observation"),
    ("Object state", "observation"),
    ("Action modes", "action"),
    ("Options:", "arguments"),
    ("Version history:", "history"),
)

#: The sections a doc feeds, in page order (the others are generated).
SECTIONS: tuple[str, ...] = ("description", "action", "observation", "rewards", "starting", "arguments", "history")

# Paragraph starters in a task doc: a label, optionally with a parenthesis, then a colon
# ("Goal (3,): ...", "Options: ..."), or a list item.
_LABEL = re.compile(r"^[A-Z][A-Za-z ]{0,30}(?: \([^)]*\))?:(?:\s|$)")
# A row of an observation table: "    0-3    joint angles j0..j3    rad".
_ROW = re.compile(r"^\s{4}(\d+(?:-\d+)?)\s{2,}(.*?)(?:\s{2,}(\S.*?))?\s*$")


def route(line: str) -> str | None:
    """The section a paragraph opening with ``line`` belongs to, or ``None``."""
    return next((section for prefix, section in ROUTES if line.startswith(prefix)), None)


def split(doc: str) -> tuple[str, dict[str, list[str]]]:
    """The summary (the first paragraph, on one line) and each section's plain lines."""
    lines = doc.strip("\n").splitlines()
    end = next((i for i, line in enumerate(lines) if not line.strip()), len(lines))
    summary = " ".join(line.strip() for line in lines[:end])
    sections: dict[str, list[str]] = {name: [] for name in SECTIONS}
    current, fresh = "description", True
    for line in lines[end:]:
        if not line.strip():
            fresh = True
            sections[current].append("")
            continue
        target = None if line.startswith(" ") else route(line)
        if fresh:
            current = target or "description"
        elif target and current != "action":
            current = target
        fresh = False
        sections[current].append(line)
    return summary, sections


def strip_label(lines: list[str], label: str) -> list[str]:
    """``lines`` without ``label`` at the start of their first line, which then starts
    with a capital."""
    if lines and lines[0].startswith(label):
        first = lines[0][len(label) :].strip()
        return [first[:1].upper() + first[1:], *lines[1:]]
    return lines


def modes_intro(lines: list[str]) -> tuple[str, list[str]]:
    """The "Action modes (...):" header's parenthesis as one sentence, and the lines after
    the indented mode rows (the notes on the modes)."""
    header, i = [], 0
    while i < len(lines) and not lines[i].startswith("    "):
        header.append(lines[i].strip())
        i += 1
    while i < len(lines) and lines[i].startswith("    "):
        i += 1
    text = " ".join(header).rstrip(":")
    if text.startswith("Action modes (") and text.endswith(")"):
        text = text[len("Action modes (") : -1]
    return text[:1].upper() + text[1:] + ".", lines[i:]


def _table(rows: list[re.Match]) -> list[str]:
    out = ["| index | content | units |", "|---|---|---|"]
    out += [f"| {m.group(1)} | {m.group(2).strip()} | {(m.group(3) or '').strip()} |" for m in rows]
    return out


def markdown(lines: list[str]) -> list[str]:
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
            if _LABEL.match(stripped) or stripped.startswith("- "):
                flush()
            para.append(stripped)
            i += 1
    flush()
    return out


def version_history(doc: str) -> str:
    """The doc's ``Version history:`` paragraph, without its label."""
    _, sections = split(doc)
    text = " ".join(line.strip() for line in sections["history"] if line.strip())
    return text[len("Version history:") :].strip()
