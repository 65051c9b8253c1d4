"""The optional dependency groups ("extras") and the one-line error for a missing one.

``pip install unified_manip`` is the env library alone (MuJoCo, Gymnasium,
gymnasium-robotics, mink): every family but robosuite's. robosuite, training, reports,
Ray, the zoo and datasets each come with an extra, e.g. ``pip install "unified_manip[train]"``;
``[all]`` has them all. A task whose family needs an extra names it in
:attr:`~unified_manip.envs.registry.TaskSpec.extra`, and ``gym.make`` of it without the
extra raises :class:`MissingExtra`.
"""

from __future__ import annotations

import importlib.util

#: Each extra and the modules that tell whether it is installed.
EXTRAS: dict[str, tuple[str, ...]] = {
    "train": ("torch", "stable_baselines3", "sb3_contrib", "tensorboard"),
    "bench": ("matplotlib", "pandas", "rliable", "scipy", "tensorboard"),
    "ray": ("ray",),
    "zoo": ("rl_zoo3",),
    "datasets": ("minari", "h5py"),
    "robosuite": ("robosuite", "h5py"),
    "metaworld": ("metaworld",),
    "fast-camera": ("fast_simplification",),
}


class MissingExtra(ImportError):
    """What was asked for needs an extra that is not installed."""


def missing_modules(extra: str) -> list[str]:
    """The modules of ``extra`` that cannot be imported here (none: it is installed)."""
    if extra not in EXTRAS:
        raise ValueError(f"unknown extra {extra!r}; expected one of {', '.join(EXTRAS)}")
    return [m for m in EXTRAS[extra] if not _installed(m)]


def _installed(module: str) -> bool:
    # A directory of that name in the working directory (Ray's /tmp/ray, say) is a
    # namespace package to the import system, with no origin: it is not the package.
    spec = importlib.util.find_spec(module)
    return spec is not None and spec.origin is not None


def require(*extras: str, what: str) -> None:
    """Raise :class:`MissingExtra` naming the first missing extra and its install line.

    Args:
        *extras: The extras ``what`` needs, e.g. ``"train", "bench"``.
        what: What needs them, as the message should name it (``"unified-manip train"``).
    """
    for extra in extras:
        absent = missing_modules(extra)
        if absent:
            raise MissingExtra(
                f'{what} needs the {extra} extra: pip install "unified_manip[{extra}]" (missing: {", ".join(absent)})'
            )
