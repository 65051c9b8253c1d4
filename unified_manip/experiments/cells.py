"""A grid's cells: its ``only`` and ``cell_overrides`` entries, which pick runs by task,
action mode, reward type and algorithm (the keys of one cell of the grid's table)."""

from __future__ import annotations

from typing import Any

#: The keys a cell entry may name.
CELL_KEYS = ("task", "action_mode", "reward_type", "algo")


def in_cell(combo: dict[str, str], cell: dict[str, Any]) -> bool:
    """Whether a run's ``combo`` (its values of :data:`CELL_KEYS`) has every value ``cell`` names."""
    return all(combo[k] == v for k, v in cell.items())


def _check_keys(cell: dict[str, Any], where: str, more: str) -> None:
    bad = [k for k in cell if k not in CELL_KEYS]
    if bad:
        raise ValueError(f"unknown key {bad[0]!r} in {where}; expected {', '.join(CELL_KEYS)}{more}")


def parse_only_cells(value: Any) -> list[dict[str, Any]] | None:
    """``only``: the cells whose runs the grid keeps (None: every run).

    Raises:
        ValueError: not a non-empty list of mappings with keys of :data:`CELL_KEYS`.
    """
    if value is None:
        return None
    if not isinstance(value, list) or not value or not all(isinstance(e, dict) and e for e in value):
        raise ValueError(f"only must be a non-empty list of mappings with keys from {', '.join(CELL_KEYS)}")
    for entry in value:
        _check_keys(entry, "only", "")
    return value


def parse_cell_overrides(entries: Any) -> list[tuple[dict[str, Any], list[str]]]:
    """``cell_overrides``: ``[{task: ..., action_mode: ..., set: [key=value, ...]}, ...]`` as
    ``(cell, settings)`` pairs: settings for the runs of the cell, applied after ``overrides``.

    Raises:
        ValueError: an entry of another shape, or with a key outside :data:`CELL_KEYS`.
    """
    shape = f"a list of mappings with 'set' (a list of key=value strings) and keys from {', '.join(CELL_KEYS)}"
    if not isinstance(entries, list):
        raise ValueError(f"cell_overrides must be {shape}")
    out = []
    for entry in entries:
        values = entry.get("set") if isinstance(entry, dict) else None
        if not isinstance(values, list) or not all(isinstance(v, str) for v in values):
            raise ValueError(f"cell_overrides must be {shape}, got {entry!r}")
        cell = {k: v for k, v in entry.items() if k != "set"}
        _check_keys(cell, "cell_overrides", " and set")
        out.append((cell, values))
    return out
