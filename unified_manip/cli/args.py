"""Argument types and the parser class shared by the ``unified-manip`` subcommands."""

from __future__ import annotations

import argparse

from unified_manip.envs.randomization import TEST_DISTRIBUTIONS
from unified_manip.envs.registry import get_task


class Parser(argparse.ArgumentParser):
    """argparse, but errors are one line naming the valid choices, exit code 2."""

    def error(self, message: str) -> None:  # noqa: D102
        self.exit(2, f"{self.prog}: error: {message}\n")


def task_id(value: str) -> str:
    """One registered ID, checked by the registry (whose error lists the IDs, and any
    family plugin that failed to load)."""
    try:
        return get_task(value).id
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None


def task_ids(value: str | None) -> list[str] | None:
    if value is None:
        return None
    ids = [v.strip() for v in value.split(",") if v.strip()]
    for v in ids:
        try:
            get_task(v)  # the registry's error
        except ValueError as err:
            raise argparse.ArgumentTypeError(str(err)) from None
    return ids


def positive_int(value: str) -> int:
    try:
        n = int(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value!r}") from None
    if n <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value!r}")
    return n


def randomization_preset(value: str) -> str:
    """A ``randomization`` preset (``none``, ``dynamics``, ``objects``, ``visual``, ``all``,
    joined by ``+``, each optionally ``:extreme`` or ``:in-range``), as run names spell it."""
    from unified_manip.envs.randomization import preset_terms, randomization_label

    try:
        preset_terms(value)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err).replace(", or a list of terms", "")) from None
    return randomization_label(value)


def env_kwarg(value: str) -> tuple[str, object]:
    import yaml

    if "=" not in value:
        raise argparse.ArgumentTypeError(f"expected key=value, got {value!r}")
    key, raw = value.split("=", 1)
    try:
        return key, yaml.safe_load(raw)
    except yaml.YAMLError:
        raise argparse.ArgumentTypeError(f"{value!r}: {raw!r} is not a YAML literal") from None


def figure_path(value: str) -> str:
    """A figure's output path; its suffix picks the format."""
    from pathlib import Path

    from unified_manip.experiments.plot import FIGURE_SUFFIXES

    if Path(value).suffix.lower() not in FIGURE_SUFFIXES:
        raise argparse.ArgumentTypeError(
            f"expected a figure path ending in {', '.join(FIGURE_SUFFIXES)}; got {value!r}"
        )
    return value


def add_test_distribution(p: argparse.ArgumentParser, several: bool = False) -> None:
    """``--randomization`` and ``--test-distribution`` of ``eval`` (one distribution) and
    ``robustness`` (``several``)."""
    p.add_argument(
        "--randomization",
        type=randomization_preset,
        metavar="PRESET",
        help="the preset whose ranges the test distributions take (none, dynamics, objects, visual or all, "
        "joined by '+'); default: the run's own training randomization. Without --test-distribution, "
        "the randomization to evaluate under, as given (a ':extreme' suffix included)",
    )
    p.add_argument(
        "--test-distribution",
        choices=TEST_DISTRIBUTIONS,
        nargs="+" if several else None,
        help="evaluate on the nominal task (default), on the preset's training ranges (in-range) or on ranges "
        "beyond them (extreme); "
        + ("each one given is a condition" if several else "default: the run's own training distribution"),
    )
