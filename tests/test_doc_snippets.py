"""Every code block of the documentation and the README runs as written.

* **Python blocks** run as scripts, each in its own interpreter, from an empty directory.
  Where a ```` ```text ```` block follows one, it is the block's output and must equal
  what the script prints (the scripts seed what they print).
* **Shell blocks** (```` ```bash ````) run in the ``slow`` tests, from a scratch directory
  that holds the repository's ``baselines/``, a copy of ``datasets/``, a copy of the committed
  results' tables and an empty ``benchmarks/out/``, so nothing is written into the checkout
  (``python -m benchmarks.<name>`` finds the tools through ``PYTHONPATH``). Their budgets are shrunk by the
  substitutions in :data:`BUDGETS` (steps, episodes, repeats), which keep every option the
  reader sees. Every ``unified-manip`` command of every shell block, run or not, is also
  parsed by the real parser in the fast tests, and every grid file it names loads.

A block that cannot run says why in a marker on the line above it, which this file reads:

* ``<!-- snippet: skip (REASON) -->``: not run (an install, a server, hours of training);
  the reason is required.
* ``<!-- snippet: slow (REASON) -->``: a Python block that trains; it runs in the ``slow``
  tests under :data:`BUDGETS`.
* ``<!-- snippet: excerpt PATH -->``: a Python block quoted from a file: it must appear in
  that file verbatim.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
import textwrap
from dataclasses import dataclass
from pathlib import Path

import pytest

import unified_manip

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted(p for p in (ROOT / "docs").rglob("*.md") if "_gen" not in p.parts)]

_FENCE = re.compile(r"^(?P<indent>[ \t]*)```(?P<lang>[\w-]*)[ \t]*$")
_MARKER = re.compile(r"^[ \t]*<!-- snippet: (?P<kind>skip|slow|excerpt)(?: (?P<arg>.*?))? -->[ \t]*$")

#: Substitutions that shrink a block's budget for the slow tests, applied in order to its
#: text: (pattern, replacement, why). They change budgets only (one may add a budget setting the
#: block leaves at its default), never which features run.
BUDGETS: tuple[tuple[str, str, str], ...] = (
    (r"\.learn\([\d_]+\)", ".learn(300)", "a Python block trains 300 steps, not its 10,000"),
    (r"(unified-manip train\b[^\n]*?--steps) \d+", r"\1 300", "train runs 300 steps"),
    (r"--episodes \d+", "--episodes 2", "collect and eval play 2 episodes"),
    (
        r"((?:unified-manip |python -m benchmarks\.)speed\b[^\n]*?)--steps \d+",
        r"\1--steps 50",
        "speed times 50 steps",
    ),
    (r"--repeats \d+", "--repeats 1", "one repeat"),
    (r"--set eval_freq=\d+", "--set eval_freq=150", "evaluate at 150 steps"),
    (r"--set n_eval_episodes=\d+", "--set n_eval_episodes=2", "two evaluation episodes"),
    (
        r"(unified-manip train\b)(?![^\n]*n_eval_episodes)",
        r"\1 --set n_eval_episodes=2",
        "a run's final evaluation plays two episodes, not its 50",
    ),
    (
        r"(unified-manip train\b)(?![^\n]*--n-envs)",
        r"\1 --n-envs 2",
        "two training envs, not a recipe's 8 worker processes",
    ),
    (r"--set demonstrations=\d+", "--set demonstrations=8", "8 scripted demonstrations, one per env"),
)

#: The quickstart's grid runs for real, shrunk: (pattern, replacement) on the grid text.
GRID_BUDGET = (
    (r"steps: \d+", "steps: 300"),
    (r"eval_freq: \d+", "eval_freq: 150"),
    (r"n_eval_episodes: \d+", "n_eval_episodes: 2"),
)


@dataclass(frozen=True)
class Block:
    page: Path
    line: int
    lang: str
    code: str
    marker: tuple[str, str] | None
    output: str | None

    @property
    def id(self) -> str:
        return f"{self.page.relative_to(ROOT)}:{self.line}"


def blocks(page: Path) -> list[Block]:
    """The fenced code blocks of a page, each with the marker above it and, for a block
    followed by a ``text`` block, that block as its output."""
    lines = page.read_text().splitlines()
    raw = []  # (start line index, lang, code)
    i = 0
    while i < len(lines):
        m = _FENCE.match(lines[i])
        if not m or not m["lang"]:
            i += 1
            continue
        j = next(k for k in range(i + 1, len(lines)) if _FENCE.match(lines[k]) and not _FENCE.match(lines[k])["lang"])
        raw.append((i, j, m["lang"], textwrap.dedent("\n".join(lines[i + 1 : j]))))
        i = j + 1
    out = []
    for n, (start, end, lang, code) in enumerate(raw):
        above = next((lines[k] for k in range(start - 1, -1, -1) if lines[k].strip()), "")
        marker = _MARKER.match(above)
        nxt = raw[n + 1] if n + 1 < len(raw) else None
        between = lines[end + 1 : nxt[0]] if nxt else []
        output = nxt[3] if nxt and nxt[2] == "text" and not any(s.strip() for s in between) else None
        out.append(
            Block(page, start + 1, lang, code, (marker["kind"], marker["arg"] or "") if marker else None, output)
        )
    return out


ALL = [b for page in PAGES for b in blocks(page)]
PYTHON = [b for b in ALL if b.lang == "python"]
SHELL = [b for b in ALL if b.lang == "bash"]


def _env() -> dict[str, str]:
    return {**os.environ, "PYTHONPATH": str(ROOT), "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}


def shrink(text: str) -> str:
    for pattern, replacement, _ in BUDGETS:
        text = re.sub(pattern, replacement, text)
    return text


def _run_python(block: Block, cwd: Path, code: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", code], cwd=cwd, env=_env(), capture_output=True, text=True, timeout=600
    )


def test_markers_give_a_reason_or_a_file():
    bad = [
        b.id for b in ALL if b.marker and b.marker[0] in ("skip", "slow") and not re.fullmatch(r"\(.+\)", b.marker[1])
    ]
    bad += [b.id for b in ALL if b.marker and b.marker[0] == "excerpt" and not (ROOT / b.marker[1]).is_file()]
    assert not bad, f"markers without '(reason)' or naming no file: {bad}"


def test_the_pages_hold_the_blocks_this_file_runs():
    # A regression guard on the parser: the quickstart's block and its output are found.
    quick = [b for b in PYTHON if b.page.name == "quickstart.md"]
    assert quick and quick[0].output and quick[0].output.startswith("{'observation': (34,)")
    assert len(PYTHON) >= 12 and len(SHELL) >= 40


@pytest.mark.parametrize("block", [b for b in PYTHON if b.marker is None], ids=lambda b: b.id)
def test_python_block_runs_and_prints_what_the_page_shows(block, tmp_path):
    proc = _run_python(block, tmp_path, block.code)
    assert proc.returncode == 0, f"{block.id} failed:\n{proc.stderr[-3000:]}"
    if block.output is not None:
        assert proc.stdout.strip() == block.output.strip(), f"{block.id} printed:\n{proc.stdout}"


@pytest.mark.parametrize("block", [b for b in PYTHON if b.marker and b.marker[0] == "excerpt"], ids=lambda b: b.id)
def test_quoted_code_is_in_its_file(block):
    source = (ROOT / block.marker[1]).read_text()
    assert block.code.strip() in source, f"{block.id} no longer matches {block.marker[1]}; quote it again"


@pytest.mark.slow
@pytest.mark.parametrize("block", [b for b in PYTHON if b.marker and b.marker[0] == "slow"], ids=lambda b: b.id)
def test_slow_python_block_runs_on_a_small_budget(block, tmp_path):
    code = shrink(block.code)
    assert code != block.code, f"{block.id} is marked slow but no budget substitution applies"
    proc = _run_python(block, tmp_path, code)
    assert proc.returncode == 0, f"{block.id} failed:\n{proc.stderr[-3000:]}"


# -- shell blocks ---------------------------------------------------------------------------


def commands(code: str) -> list[list[str]]:
    """The ``unified-manip`` commands of a shell block, as argument lists (continuations
    joined, comments dropped, ``&&`` chains split, shell variables left as they are)."""
    joined = code.replace("\\\n", " ")
    out = []
    for line in joined.splitlines():
        if "unified-manip" not in line.split("#")[0]:
            continue
        lex = shlex.shlex(line, posix=True, punctuation_chars=";&|")
        lex.whitespace_split = True
        lex.commenters = "#"
        words: list[str] = []
        for token in [*lex, ";"]:
            if token and set(token) <= set(";&|"):
                while words and re.fullmatch(r"\w+=\S*", words[0]):
                    words = words[1:]
                if words[:1] == ["unified-manip"]:
                    out.append(words[1:])
                words = []
            else:
                words.append(token)
    return out


def _parse(argv: list[str]):
    from unified_manip.cli.main import build_parser

    return build_parser().parse_args(argv)


def _needs_robosuite(block: Block) -> bool:
    """Whether a command of ``block`` loads a grid with a robosuite task (loading builds
    the task's backend, so it needs the robosuite extra)."""
    import yaml

    for grid in re.findall(r"baselines/\S+\.yaml", block.code):
        path = ROOT / grid
        if path.is_file() and any(
            unified_manip.TASKS[t].extra
            for t in (yaml.safe_load(path.read_text()) or {}).get("tasks", ())
            if t in unified_manip.TASKS
        ):
            return True
    return False


@pytest.mark.parametrize(
    "block",
    [
        pytest.param(b, marks=[pytest.mark.robosuite] if _needs_robosuite(b) else [], id=b.id)
        for b in SHELL
        if commands(b.code)
    ],
)
def test_every_command_parses_and_its_grids_load(block):
    from unified_manip.experiments.grid import load_grid

    for argv in commands(block.code):
        if any("$" in a or "<" in a for a in argv):
            continue  # a placeholder for the reader to fill (``<grid>``, ``$mode``)
        try:
            args = _parse(argv)
        except SystemExit as e:
            pytest.fail(f"{block.id}: `unified-manip {' '.join(argv)}` does not parse (exit {e.code})")
        grid = getattr(args, "grid", None)
        if grid and str(grid).startswith("baselines/"):
            load_grid(ROOT / grid, datasets=False)


def _workspace(tmp: Path) -> Path:
    """A scratch directory that looks like the checkout to a command: baselines and
    datasets linked, the committed results' tables copied (reports write beside them)."""
    tmp.mkdir()
    (tmp / "baselines").symlink_to(ROOT / "baselines")
    shutil.copytree(ROOT / "datasets", tmp / "datasets")
    for src in (ROOT / "results").glob("*/*"):
        if src.is_file():
            dst = tmp / "results" / src.parent.name / src.name
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dst)
    (tmp / "docs" / "images").mkdir(parents=True)
    (tmp / "benchmarks" / "out").mkdir(parents=True)  # where the measurement tools' figures go
    (tmp / "runs").mkdir()
    return tmp


def _quick_grid(page: Path, tmp: Path) -> None:
    """The quickstart's grid, written out from its page and shrunk by :data:`GRID_BUDGET`."""
    text = page.read_text()
    m = re.search(r"```yaml\n(.*?)```", text, re.S)
    grid = m.group(1)
    for pattern, replacement in GRID_BUDGET:
        grid = re.sub(pattern, replacement, grid)
    (tmp / "quick.yaml").write_text(grid)


SHELL_PAGES = sorted({b.page for b in SHELL if b.marker is None})


@pytest.mark.slow
@pytest.mark.parametrize("page", SHELL_PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_shell_blocks_run_on_a_small_budget(page, tmp_path):
    """A page's shell blocks, in order, in one scratch directory: a block may use what an
    earlier one made (the quickstart's run directory, a dataset collected above)."""
    ws = _workspace(tmp_path / "ws")
    if page.name == "quickstart.md":
        _quick_grid(page, ws)
    bindir = tmp_path / "bin"
    bindir.mkdir()
    (bindir / "unified-manip").write_text(f'#!/bin/sh\nexec {sys.executable} -m unified_manip.cli "$@"\n')
    (bindir / "unified-manip").chmod(0o755)
    env = {**_env(), "PATH": f"{bindir}:{os.environ['PATH']}"}
    for block in [b for b in SHELL if b.page == page and b.marker is None]:
        script = "set -e\n" + shrink(block.code.replace("\\\n", " "))
        proc = subprocess.run(["bash", "-c", script], cwd=ws, env=env, capture_output=True, text=True, timeout=900)
        assert proc.returncode == 0, f"{block.id} failed:\n{script}\n{proc.stdout[-2000:]}\n{proc.stderr[-3000:]}"
