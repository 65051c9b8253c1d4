"""The command-line reference, generated from the real ``argparse`` parser."""

from __future__ import annotations

import argparse


def _subcommands(parser: argparse.ArgumentParser) -> list[tuple[str, str, argparse.ArgumentParser]]:
    """``(name, help, parser)`` of each subcommand, in the order they were added."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            helps = {a.dest: (a.help or "").replace("%%", "%") for a in action._choices_actions}
            return [(name, helps.get(name, ""), sub) for name, sub in action.choices.items()]
    return []


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _arguments(parser: argparse.ArgumentParser) -> list[str]:
    rows = ["| argument | default | what it does |", "|---|---|---|"]
    for action in parser._actions:
        if isinstance(action, argparse._HelpAction) or action.help == argparse.SUPPRESS:
            continue
        if action.option_strings:
            metavar = action.metavar or (action.dest.upper() if action.nargs != 0 else "")
            if isinstance(metavar, tuple):
                metavar = " ".join(metavar)
            name = ", ".join(f"`{o}{' ' + metavar if metavar else ''}`" for o in action.option_strings)
        else:
            name = f"`{action.metavar or action.dest}`"
        if action.choices and not isinstance(action.choices, dict) and len(action.choices) <= 12:
            choices = " Choices: " + ", ".join(f"`{c}`" for c in action.choices) + "."
        else:
            choices = ""
        default = action.default
        shown = "–" if default in (None, argparse.SUPPRESS, False) or action.required else f"`{default}`"
        help_text = (action.help or "") % {"default": default, "prog": parser.prog} if action.help else ""
        rows.append(f"| {name} | {_cell(shown)} | {_cell(help_text + choices)} |")
    return rows


def cli_reference(parser: argparse.ArgumentParser) -> str:
    """Markdown: the program's usage, then one section per subcommand with its usage and
    a table of its arguments."""
    prog = parser.prog
    lines = [
        "# Command line",
        "",
        f"`{prog}` is installed with the package. This page is generated from its `argparse` parser "
        "when the site is built, so it lists exactly what the installed command accepts; "
        f"`{prog} COMMAND --help` prints the same.",
        "",
        "| command | what it does |",
        "|---|---|",
    ]
    subs = _subcommands(parser)
    lines += [f"| [`{name}`](#{name}) | {_cell(help_)} |" for name, help_, _ in subs]
    lines.append("")
    for name, help_, sub in subs:
        usage = sub.format_usage().strip()
        lines += [f"## {name}", "", help_[:1].upper() + help_[1:] + ".", "", "```text", usage, "```", ""]
        if sub.description:
            lines += [sub.description, ""]
        lines += _arguments(sub) + [""]
    return "\n".join(lines)
