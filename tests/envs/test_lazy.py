"""Lazy re-exports: a family package's names import its simulator on first use, and a
missing simulator reads as a missing attribute to code that probes every module."""

from __future__ import annotations

import io
import pickle

import pytest

from unified_manip.envs.lazy import reexport


def test_a_submodule_that_cannot_import_is_a_missing_attribute_naming_why():
    getattr_, _ = reexport("unified_manip.envs", ("no_such_simulator_module",))
    with pytest.raises(AttributeError, match="No module named 'unified_manip.envs.no_such_simulator_module'"):
        getattr_("SomeBackend")


def test_private_names_import_nothing():
    getattr_, _ = reexport("unified_manip.envs", ("no_such_simulator_module",))
    with pytest.raises(AttributeError, match="^_reduce$"):
        getattr_("_reduce")


def test_pickle_can_search_every_module_for_a_function_without_a_module():
    """pickle's whichmodule looks a name up in every imported module (torch.compile's
    cache pickles so): the family packages must answer, not import a simulator and fail."""
    import unified_manip.envs.tasks.robosuite_tasks  # noqa: F401 (a package with re-exports)

    def orphan():
        return None

    orphan.__module__ = None
    orphan.__qualname__ = "not_a_name_anywhere"
    with pytest.raises(pickle.PicklingError):  # the pure-Python pickler lets other errors through
        pickle._Pickler(io.BytesIO()).dump(orphan)
