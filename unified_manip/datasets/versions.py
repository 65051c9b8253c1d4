"""The versions of the packages a recording depends on, and the differences from them."""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

#: The packages whose version can change a recorded trajectory (or its reading).
PACKAGES: tuple[str, ...] = ("unified_manip", "mujoco", "gymnasium", "gymnasium-robotics", "robosuite", "minari")


def installed() -> dict[str, str]:
    """``{package: version}`` of :data:`PACKAGES` here (``"not installed"`` for a missing one)."""
    out = {}
    for name in PACKAGES:
        try:
            out[name] = version(name)
        except PackageNotFoundError:
            out[name] = "not installed"
    return out


def requirements(versions: dict[str, str]) -> list[str]:
    """pip-style pins of ``versions`` (Minari's ``requirements`` metadata, which its
    ``recover_environment`` checks)."""
    return [f"{name}=={v}" for name, v in versions.items() if v != "not installed" and name != "minari"]


def mismatches(recorded: dict[str, str]) -> list[str]:
    """``"mujoco 3.8.0 (recorded) vs 3.9.0 (here)"`` for each package whose version
    here differs from ``recorded``, in :data:`PACKAGES` order."""
    here = installed()
    return [
        f"{name} {recorded[name]} (recorded) vs {here[name]} (here)"
        for name in PACKAGES
        if name in recorded and recorded[name] != here[name]
    ]
