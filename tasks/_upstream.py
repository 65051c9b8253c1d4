"""Kept for old imports: these helpers live in :mod:`unified_manip.tasks.upstream`."""

from .upstream import pickle_upstream, unpickle_upstream, upstream_reset

__all__ = ["pickle_upstream", "unpickle_upstream", "upstream_reset"]
