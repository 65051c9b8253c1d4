"""Every number the results pages publish in prose was read against the data it cites.

Tables of results are generated when the site is built (``<!-- gen:KIND NAME -->``) or by
a command whose output sits between markers (the README's ``<!-- headline: ... -->`` …
``<!-- end of headline ... -->``), so they cannot drift from ``results.csv``. Prose is
written by hand: a paragraph, list or hand-written table that quotes a measured number
must sit under a marker naming the files it was checked against::

    <!-- checked: results/observation_designs/results.csv results/observation_designs/robustness.csv -->

A marker covers what follows it up to the next heading or the next marker, and the heading
just above it. A published number is a fraction (``0.85``) or a figure with a unit of
measure (``12%``, ``0.4 h``, ``7.6 minutes``, ``45 steps/s``, ``1.5x``, ``6.6 cm``);
package versions and setup counts (``3 seeds``, ``60k steps``) are not. Code blocks and
inline code are not prose. Whoever edits a covered paragraph rereads its numbers against
the named files; this test keeps the claim honest in shape: nothing measured goes
unmarked, and every file a marker names exists.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs" / "results").glob("*.md"))]

NUMBER = re.compile(
    r"(?<![\w.\-/])(?:0\.\d+(?![\w.])"
    r"|\d+(?:[.,]\d+)?\s?(?:%|h\b|hours?\b|minutes?\b|min\b|ms\b|s\b|steps/s\b|cm\b|×|x\b|core-hours))"
)
CHECKED = re.compile(r"<!-- checked: ([^>]+?) -->")
_CODE = re.compile(r"^[ \t]*```.*?^[ \t]*```[ \t]*$", re.S | re.M)
_GENERATED = re.compile(r"<!-- headline:.*?<!-- end of headline[^>]*-->", re.S)
_NOT_PROSE = re.compile(r"`[^`]*`|<!--.*?-->|\]\([^)]*\)", re.S)


def published_blocks(text: str) -> list[tuple[str, list[str] | None]]:
    """The page's blocks (paragraphs, lists, tables, headings) that publish a number, each
    with the sources of the marker covering it (None where none does)."""
    text = _GENERATED.sub("", _CODE.sub("", text))
    blocks = re.split(r"\n[ \t]*\n", text)
    out, sources = [], None
    for i, block in enumerate(blocks):
        if block.lstrip().startswith("#"):
            following = blocks[i + 1] if i + 1 < len(blocks) else ""
            m = CHECKED.search(following)
            sources = m.group(1).split() if m else None
        elif m := CHECKED.search(block):
            sources = m.group(1).split()
        if NUMBER.search(_NOT_PROSE.sub("", block)):
            out.append((block, sources))
    return out


def test_marker_rules_on_a_sample():
    page = "\n\n".join(
        [
            "# Title",
            "Setup: 3 seeds, 60k steps, MuJoCo 3.9, `0.5` in code.",
            "## Result: 0.85",
            "<!-- checked: results/x/results.csv -->",
            "It reached 0.85 in 1.5 h.",
            "<!-- gen:results x -->",
            "```bash\necho 0.99\n```",
            "## Next",
            "Unmarked: 12% faster.",
        ]
    )
    got = [(b.split("\n")[0], s) for b, s in published_blocks(page)]
    assert got == [
        ("## Result: 0.85", ["results/x/results.csv"]),
        ("It reached 0.85 in 1.5 h.", ["results/x/results.csv"]),
        ("Unmarked: 12% faster.", None),
    ]


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_published_numbers_are_marked_checked(page):
    unmarked = [b.strip()[:120] for b, sources in published_blocks(page.read_text()) if sources is None]
    assert not unmarked, (
        f"{page.relative_to(ROOT)}: prose with measured numbers and no '<!-- checked: FILE... -->' "
        f"marker above it (read each number against its file, then name the file): {unmarked}"
    )


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_checked_sources_exist(page):
    named = {s for m in CHECKED.finditer(page.read_text()) for s in m.group(1).split()}
    missing = sorted(s for s in named if not (ROOT / s).exists())
    assert not missing, f"{page.relative_to(ROOT)}: markers name files that do not exist: {missing}"
