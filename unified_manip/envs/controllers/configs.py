"""Action modes as frozen config dataclasses (ManiSkill's controller configs).

A family declares ``{mode: config}``; the config names its one implementation
(:attr:`ControllerConfig.controller`, a ``"module:Class"`` imported on first build)
and holds the mode's parameters. The implementation drives any family through the
family's *rig* (:mod:`unified_manip.envs.controllers.rig`): joint and actuator indices,
ranges, the grip site and how a command reaches the actuators. Configs import nothing
heavy, so families declare them at registration without loading a simulator.

Every config describes itself in one line (:meth:`ControllerConfig.describe`): the
``unified-manip list --doc`` pages and the README's mode table are generated from it.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, fields
from typing import Any, ClassVar

import numpy as np

from unified_manip.envs.lazy import resolve

#: What a controller sends to the rig: joint position targets, joint torques or joint
#: velocities. The rig configures its actuators for it once, when the env is built.
COMMAND_KINDS: tuple[str, ...] = ("position", "torque", "velocity")

_PACKAGE = "unified_manip.envs.controllers"


def _positive(owner: str, name: str, value: Any) -> None:
    try:
        array = np.asarray(value, dtype=float)
        ok = array.size > 0 and bool(np.all(np.isfinite(array))) and not np.any(array <= 0)
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"{owner}.{name} must be positive, got {value!r}")


def _rad(value: float) -> str:
    return f"{value:g} rad"


def _metres(value: float) -> str:
    return f"{value * 100:g} cm" if value < 1 else f"{value:g} m"


@dataclass(frozen=True)
class ControllerConfig(ABC):
    """Base of the action-mode configs.

    Class attributes:
        controller: ``"module:Class"`` of the implementation, built as
            ``Class(config, rig)``; ``None`` for ``native`` (the family's own).
        command: The :data:`COMMAND_KINDS` entry the controller sends to the rig.
        space: ``"joint"`` or ``"ee"``: what the action commands (``"native"``: the
            source's own controller).
    """

    controller: ClassVar[str | None] = None
    command: ClassVar[str] = "position"
    space: ClassVar[str] = "joint"

    def build(self, rig):
        """The controller of this mode on ``rig``."""
        if self.controller is None:
            raise ValueError(f"{type(self).__name__} is the family's own controller; the backend drives it")
        return resolve(self.controller)(self, rig)

    def parameters(self) -> dict:
        """The parameters ``controller_options`` may set, with their values here; empty for
        ``native`` (the family's own controller) and for a config without fields."""
        return {} if self.controller is None else {f.name: getattr(self, f.name) for f in fields(self)}

    @abstractmethod
    def describe(self) -> str:
        """What the arm part of the action means, in one line."""


@dataclass(frozen=True)
class JointTorque(ControllerConfig):
    """``joint_torque``: torque ``a * limit`` per joint, from the rig's torque limits."""

    controller: ClassVar[str] = f"{_PACKAGE}.joint:JointTorqueController"
    command: ClassVar[str] = "torque"

    def describe(self) -> str:
        return "torque `a * τ_max` per joint (the actuators' torque limits), gravity compensated"


@dataclass(frozen=True)
class JointPosition(ControllerConfig):
    """``joint_position``: absolute targets, ``[-1, 1]`` mapped onto each joint's range.

    Attributes:
        band: ``None`` (the default): the whole command range. A half-width in rad (one
            for every joint, or one per joint): ``[-1, 1]`` maps onto
            ``q_reset ± band`` instead, the posture the episode started in plus or minus
            ``band``, clipped to the range: a smaller action box around the postures a
            task uses.
    """

    controller: ClassVar[str] = f"{_PACKAGE}.joint:JointPositionController"
    band: float | tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        if self.band is not None:
            _positive("JointPosition", "band", self.band)

    def build(self, rig):
        if self.band is None:
            return super().build(rig)
        return resolve(f"{_PACKAGE}.joint:JointPositionBandController")(self, rig)

    def describe(self) -> str:
        if self.band is None:
            return "absolute target, `[-1, 1]` mapped onto each joint's command range"
        return f"absolute target `q_reset + a * {self.band}` rad (the posture at reset), clipped to the range"


@dataclass(frozen=True)
class JointDelta(ControllerConfig):
    """``joint_delta``: target ``q + a * max_delta``, relative to the *measured* ``q``.

    Attributes:
        max_delta: Target change at ``|a| = 1``, rad; or ``"half_range"``: half of each
            joint's command range (upstream Shadow Hand's ``relative_control``).
        clip: Clip the target to the joints' command ranges. robosuite's own
            ``JOINT_POSITION`` delta input does not, and its tasks keep that.
    """

    controller: ClassVar[str] = f"{_PACKAGE}.joint:JointDeltaController"
    max_delta: float | str = 0.05
    clip: bool = True

    def __post_init__(self) -> None:
        if self.max_delta != "half_range":
            _positive("JointDelta", "max_delta", self.max_delta)

    def describe(self) -> str:
        step = "half the joint's command range" if isinstance(self.max_delta, str) else _rad(self.max_delta)
        clip = ", clipped to the range" if self.clip else ", not clipped"
        return f"target `q + a * {step}`, relative to the measured `q`{clip}"


@dataclass(frozen=True)
class JointTargetDelta(ControllerConfig):
    """``joint_target_delta``: target ``previous target + a * max_delta``: a constant
    action accumulates the target instead of re-anchoring on the measured ``q``
    (ManiSkill's ``pd_joint_target_delta_pos``). At reset the target is the measured ``q``.

    Attributes:
        max_delta: Target change at ``|a| = 1``, rad.
    """

    controller: ClassVar[str] = f"{_PACKAGE}.joint:JointTargetDeltaController"
    max_delta: float = 0.05

    def __post_init__(self) -> None:
        _positive("JointTargetDelta", "max_delta", self.max_delta)

    def describe(self) -> str:
        return (
            f"target `previous target + a * {_rad(self.max_delta)}` (the measured `q` at reset), clipped to the range"
        )


@dataclass(frozen=True)
class JointVelocity(ControllerConfig):
    """``joint_velocity``: velocity servos tracking ``a * max_velocity``.

    Attributes:
        max_velocity: Joint speed at ``|a| = 1``, rad/s (scalar or per joint).
        kv: Velocity-servo gain, N m s / rad (scalar or per joint).
    """

    controller: ClassVar[str] = f"{_PACKAGE}.joint:JointVelocityController"
    command: ClassVar[str] = "velocity"
    max_velocity: float | tuple[float, ...] = 1.0
    kv: float | tuple[float, ...] = 20.0

    def __post_init__(self) -> None:
        _positive("JointVelocity", "max_velocity", self.max_velocity)
        _positive("JointVelocity", "kv", self.kv)

    def describe(self) -> str:
        return f"target speed `a * {np.max(self.max_velocity):g} rad/s`, velocity servos"


@dataclass(frozen=True)
class IntegratedJointVelocity(ControllerConfig):
    """``joint_velocity`` where the simulator has no working velocity control: the
    command is integrated into a position target, ``target += a * max_velocity * dt``,
    kept within ``max_lead`` of the measured position (no wind-up) and the joint range.
    robosuite 1.5.2's ``JOINT_VELOCITY`` controller raises ``AttributeError``.

    Attributes:
        max_velocity: Joint speed at ``|a| = 1``, rad/s.
        max_lead: How far the target may lead the measured position, rad.
    """

    controller: ClassVar[str] = f"{_PACKAGE}.joint:IntegratedJointVelocityController"
    max_velocity: float = 1.0
    max_lead: float = 0.1

    def __post_init__(self) -> None:
        _positive("IntegratedJointVelocity", "max_velocity", self.max_velocity)
        _positive("IntegratedJointVelocity", "max_lead", self.max_lead)

    def describe(self) -> str:
        return (
            f"speed `a * {self.max_velocity:g} rad/s` integrated into a position target, "
            f"kept within {_rad(self.max_lead)} of `q` (no working velocity controller)"
        )


@dataclass(frozen=True)
class EEDelta(ControllerConfig):
    """``ee_delta``: grip-site target ``p + a[:3] * step`` from the *measured* site,
    solved to joint targets by mink differential IK (the rig holds the orientation).

    Attributes:
        step: Grip-site displacement at ``|a| = 1``, m per env step.
        orientation_cost: Weight of the held orientation against position in the IK.
        iterations: Gauss-Newton steps of the IK per env step.
        yield_residual: If set, a solution leaving more position error than this (m) is
            solved again with ``yield_orientation_cost``, so the gripper tilts to reach.
        yield_orientation_cost: The orientation weight of that second solve.
    """

    controller: ClassVar[str] = f"{_PACKAGE}.ee:EEDeltaController"
    space: ClassVar[str] = "ee"
    step: float = 0.05
    orientation_cost: float = 0.1
    iterations: int = 2
    yield_residual: float | None = None
    yield_orientation_cost: float = 0.01

    def __post_init__(self) -> None:
        name = type(self).__name__
        _positive(name, "step", self.step)
        if self.orientation_cost < 0:
            raise ValueError(f"{name}.orientation_cost must be >= 0, got {self.orientation_cost!r}")
        if not isinstance(self.iterations, int) or self.iterations <= 0:
            raise ValueError(f"{name}.iterations must be a positive int, got {self.iterations!r}")
        if self.yield_residual is not None:
            _positive(name, "yield_residual", self.yield_residual)

    def _ik(self) -> str:
        text = f"mink IK (orientation cost {self.orientation_cost:g}"
        if self.yield_residual is not None:
            text += (
                f"; re-solved with {self.yield_orientation_cost:g} where the residual exceeds "
                f"{_metres(self.yield_residual)}, so the gripper tilts to reach"
            )
        return text + ")"

    def describe(self) -> str:
        return f"grip-site target `p + a[:3] * {_metres(self.step)}` from the measured site, {self._ik()}"


@dataclass(frozen=True)
class EETargetDelta(EEDelta):
    """``ee_target_delta``: grip-site target ``previous target + a[:3] * step``: a
    constant action accumulates the target instead of re-anchoring on the measured site
    (ManiSkill's ``pd_ee_target_delta_pos``). At reset the target is the site's position.
    The target is not bounded: beyond the arm's reach the IK residual grows."""

    controller: ClassVar[str] = f"{_PACKAGE}.ee:EETargetDeltaController"

    def describe(self) -> str:
        return f"grip-site target `previous target + a[:3] * {_metres(self.step)}` (the site at reset), {self._ik()}"


@dataclass(frozen=True)
class Native(ControllerConfig):
    """``native``: the source's own controller, driven by the family's backend.

    Attributes:
        description: What the source's controller does with the action.
    """

    space: ClassVar[str] = "native"
    description: str = "the source's own controller"

    def describe(self) -> str:
        return self.description
