"""mkdocs hooks: the pages, tables and figures generated from the code and the committed
results each time the site is built (``mkdocs build --strict``).

* ``on_config``: one nav entry per registered task, under "Tasks".
* ``on_files``: the generated pages (``tasks/<ID>.md``, ``reference/cli.md``) and the
  committed report figures of ``results/<name>/report/*.png`` as site files.
* ``on_page_content``: the docstrings' Sphinx roles (``:class:`~a.b.C```) shown as plain
  code (``C``), as Sphinx would show them.
* ``on_page_markdown``: a marker ``<!-- gen:KIND ARG... -->`` in a written page is
  replaced by what ``KIND`` generates (see :data:`MARKERS`).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

from mkdocs.structure.files import File, Files

sys.path.insert(0, str(Path(__file__).resolve().parent))
# The checkout's root, last (an installed unified_manip still comes first): the measurement
# tools (benchmarks/), not installed, render the conversion table's results page.
sys.path.append(str(Path(__file__).resolve().parents[2]))

import clipage  # noqa: E402
import mode_table  # noqa: E402
import resultpages  # noqa: E402
import taskpages  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
RESULTS = ROOT / "results"
_MARKER = re.compile(r"^([ \t]*)<!-- gen:([a-z-]+)((?: [^ >]+)*) -->[ \t]*$", re.M)


def _tasks():
    import unified_manip

    return unified_manip.TASKS


def on_config(config):
    for entry in config["nav"]:
        if isinstance(entry, dict) and "Tasks" in entry:
            entry["Tasks"] += [{taskpages.short_id(t): taskpages.page_path(t)} for t in _tasks()]
    return config


def on_files(files: Files, config) -> Files:
    docs_dir = Path(config["docs_dir"])
    animations = taskpages.animations(docs_dir)
    for task_id, spec in _tasks().items():
        animation = animations.get(task_id)
        page = taskpages.task_page(spec, taskpages.frame_exists(docs_dir, task_id, animation), animation)
        files.append(File.generated(config, taskpages.page_path(task_id), content=page))
    from unified_manip.cli.main import build_parser

    files.append(File.generated(config, "reference/cli.md", content=clipage.cli_reference(build_parser())))
    for png in sorted(RESULTS.glob("*/report/*.png")):
        name = png.parent.parent.name
        files.append(File.generated(config, f"{resultpages.ASSETS}/{name}/{png.name}", abs_src_path=str(png)))
    return files


def _reward_table() -> str:
    from unified_manip.envs.registry import TASKS
    from unified_manip.envs.rewards import REWARD_TYPES

    term_sets = {spec.terms.name: spec.terms for spec in TASKS.values()}
    return taskpages.reward_table(REWARD_TYPES, tuple(term_sets.values()))


def _experiment(name: str) -> Path:
    path = RESULTS / name
    if not path.is_dir():
        raise ValueError(f"no committed experiment {path}")
    return path


def _expand(kind: str, args: list[str], depth: int) -> str:
    if kind == "mode-table":
        return mode_table.mode_table()
    if kind == "reward-table":
        return _reward_table()
    if kind == "task-table":
        return taskpages.task_table(_tasks(), taskpages.animations(ROOT / "docs"))
    if kind == "versions":
        return taskpages.versions_table(_tasks())
    if kind == "results":
        return resultpages.final_table([_experiment(a) / "results.csv" for a in args])
    if kind == "targets":
        return resultpages.targets_table(_experiment(args[0]))
    if kind == "figures":
        return resultpages.figures(_experiment(args[0]), args[0], depth)
    if kind == "robustness":
        return resultpages.robustness(_experiment(args[0]), args[0], depth)
    if kind == "factors":
        return resultpages.factors(_experiment(args[0]), args[0], depth)
    if kind == "catalogue":
        return resultpages.catalogue_table(_experiment(args[0]))
    if kind == "conversion":
        return resultpages.conversion_tables(_experiment(args[0]))
    if kind == "headline":
        from unified_manip.experiments.headline import headline_table

        return headline_table(_experiment(args[0]))
    if kind == "benchmark-summary":
        import tasksections

        return tasksections.benchmark_summary(_tasks())
    if kind == "command":
        return resultpages.command(_experiment(args[0]))
    raise ValueError(f"unknown marker gen:{kind}")


#: The markers a written page may hold.
MARKERS = (
    "mode-table",
    "reward-table",
    "task-table",
    "versions",
    "results NAME...",
    "targets NAME",
    "figures NAME",
    "command NAME",
    "catalogue NAME",
    "conversion NAME",
    "robustness NAME",
    "factors NAME",
    "headline NAME",
    "benchmark-summary",
)


def on_page_markdown(markdown: str, page, config, files) -> str:
    depth = page.file.src_uri.count("/")

    def expand(m: re.Match) -> str:
        indent = m.group(1)
        text = _expand(m.group(2), m.group(3).split(), depth)
        return "\n".join(indent + line if line else line for line in text.splitlines())

    return _MARKER.sub(expand, markdown)


_ROLE = re.compile(r":(?:class|data|meth|func|attr|mod|exc|obj):<code>(~?)([\w.]+)</code>")


def on_page_content(html: str, page, config, files) -> str:
    return _ROLE.sub(lambda m: f"<code>{m.group(2).rsplit('.', 1)[-1] if m.group(1) else m.group(2)}</code>", html)
