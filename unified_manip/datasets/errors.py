"""The one error of the dataset tools: a one-line message naming what was expected."""

from __future__ import annotations


class DatasetError(ValueError):
    """A dataset, or a request about one, that cannot be used (the CLI exits 2 with it)."""
