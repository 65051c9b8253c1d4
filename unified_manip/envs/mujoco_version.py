"""The MuJoCo versions the families run on, checked before the first env is built, and
the API differences within that range this package meets.

MuJoCo 3.10 changed ``mj_fullM``'s signature (robosuite 1.5.2's controllers call the old
one), 3.11 removed ``MjData.qM`` (robosuite), and from 3.12 comparing MuJoCo's enums with
numpy integers is False (the joint-type checks of robosuite 1.5.2 and gymnasium-robotics
1.4.2 fail). Below 3.3.0, robosuite does not install. :func:`check_mujoco` reads the
installed version from the package metadata, without importing MuJoCo, so an unsupported
one is refused in one line naming the range instead of failing mid-step upstream.
"""

from __future__ import annotations

import functools
import re
from importlib.metadata import PackageNotFoundError, version
from typing import Any

#: The supported range, as ``pyproject.toml`` requires it (tests/envs/test_mujoco_version.py).
SUPPORTED = ">=3.3.0,<3.10"
_LOWEST = (3, 3, 0)
_FIRST_UNSUPPORTED = (3, 10)


class UnsupportedMuJoCo(RuntimeError):
    """The installed MuJoCo is outside :data:`SUPPORTED` (or absent)."""


def supported(mujoco_version: str) -> bool:
    """Whether ``mujoco_version`` (``"3.9.0"``, ``"3.12.0.dev1"``) is in :data:`SUPPORTED`."""
    match = re.match(r"(\d+)\.(\d+)(?:\.(\d+))?", mujoco_version)
    if match is None:
        return False
    release = tuple(int(part or 0) for part in match.groups())
    return _LOWEST <= release < _FIRST_UNSUPPORTED


def check_mujoco(mujoco_version: str | None = None) -> None:
    """Raise :class:`UnsupportedMuJoCo` unless ``mujoco_version`` (default: the installed
    one) is supported; the message is one line naming the range and the fix."""
    if mujoco_version is None:
        mujoco_version = _installed()
    if mujoco_version is None or not supported(mujoco_version):
        found = "no mujoco is installed" if mujoco_version is None else f"mujoco {mujoco_version} is installed"
        raise UnsupportedMuJoCo(
            f"{found}, but unified_manip supports mujoco{SUPPORTED} "
            f'(the families\' upstreams break on 3.10 and later): pip install "mujoco{SUPPORTED}"'
        )


@functools.cache
def _installed() -> str | None:
    try:
        return version("mujoco")
    except PackageNotFoundError:
        return None


def delete_element(spec: Any, element: Any) -> None:
    """Remove ``element`` (a body, an equality, ...) from the ``mujoco.MjSpec`` ``spec``.

    MuJoCo 3.9.0 has ``spec.delete(element)``; 3.3.0 has ``spec.detach_body(body)`` for a
    body and ``element.delete()`` for the other elements instead."""
    if hasattr(spec, "delete"):
        spec.delete(element)
    elif hasattr(spec, "detach_body") and element.__class__.__name__ == "MjsBody":
        spec.detach_body(element)
    else:
        element.delete()


def set_to_position(actuator: Any, kp: float, kv: float = 0.0) -> None:
    """Make the ``mujoco.MjsActuator`` a position servo: force ``kp * (ctrl - q) - kv * qdot``.

    ``actuator.set_to_position(kp=..., kv=...)`` where it exists (MuJoCo 3.9.0); on 3.3.0
    the same fields set by hand (fixed gain ``kp``, affine bias ``(0, -kp, -kv)``)."""
    if hasattr(actuator, "set_to_position"):
        actuator.set_to_position(kp=kp, kv=kv)
        return
    import mujoco

    actuator.gaintype = mujoco.mjtGain.mjGAIN_FIXED
    actuator.gainprm[0] = kp
    actuator.biastype = mujoco.mjtBias.mjBIAS_AFFINE
    actuator.biasprm[1] = -kp
    actuator.biasprm[2] = -kv
