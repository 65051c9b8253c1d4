"""Callables and module attributes that import their code on first use.

``import unified_manip`` registers every task without importing any simulator: a
:class:`~unified_manip.envs.registry.TaskSpec` names its backend as a :class:`Lazy`
``"module:attribute"`` target, imported by the first ``gym.make`` of one of the
family's IDs. :func:`reexport` keeps a family package's old module-level names
importable from the package (``from unified_manip.envs.tasks.arm4 import Arm4Backend``)
without importing its simulator when only the package is imported.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping


def resolve(target: str) -> Any:
    """The attribute named by ``"package.module:attribute"``, importing the module."""
    module, sep, name = target.partition(":")
    if not sep or not module or not name:
        raise ValueError(f"expected 'module:attribute', got {target!r}")
    return getattr(importlib.import_module(module), name)


@dataclass(frozen=True)
class Lazy:
    """``resolve(target)(*args, *call_args, **kwargs, **call_kwargs)``, imported on call.

    Picklable and comparable, unlike a closure; ``functools.partial`` of a class would
    import the class's module when the partial is built.

    Attributes:
        target: ``"package.module:attribute"`` of the callable.
        args: Positional arguments bound before the call's own.
        kwargs: Keyword arguments bound (the call's own take precedence).
    """

    target: str
    args: tuple[Any, ...] = ()
    kwargs: Mapping[str, Any] = field(default_factory=dict)

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return resolve(self.target)(*self.args, *args, **{**self.kwargs, **kwargs})


def lazy(target: str, *args: Any, **kwargs: Any) -> Lazy:
    """``Lazy(target, args, kwargs)``: the lazy counterpart of ``functools.partial``."""
    return Lazy(target, tuple(args), dict(kwargs))


def reexport(package: str, submodules: tuple[str, ...]) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """Module ``__getattr__`` and ``__dir__`` that find a missing attribute of ``package``
    in its ``submodules`` (imported in order, on first access).

    Use in a package's ``__init__``::

        __getattr__, __dir__ = reexport(__name__, ("backend", "policies"))
    """

    def __getattr__(name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        for sub in submodules:
            try:
                module = importlib.import_module(f"{package}.{sub}")
            except ImportError as err:
                # An AttributeError, as for any missing name: code that probes every module
                # for a name (pickle's whichmodule, which torch.compile's cache runs) must
                # not fail because a family's simulator is not installed.
                raise AttributeError(f"module {package!r} has no attribute {name!r} here: {err}") from err
            if name in vars(module):
                return vars(module)[name]
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__() -> list[str]:
        names = set(vars(importlib.import_module(package)))
        for sub in submodules:
            names.update(vars(importlib.import_module(f"{package}.{sub}")))
        return sorted(names)

    return __getattr__, __dir__
