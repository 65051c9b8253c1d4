"""Action modes as controller configs, one implementation each, over per-family rigs.

* :mod:`.configs`: one frozen config dataclass per mode (what a family declares);
* :mod:`.joint` and :mod:`.ee`: the implementations (imported when a config is built);
* :mod:`.rig`: the rig interface and :class:`~.rig.MujocoRig`;
* :mod:`.composite`: one controller per rig under one action (two arms);
* :mod:`.ik`: mink differential IK;
* :mod:`.docs`: the mode tables of the task pages and the README, from the configs.

Importing this package imports only the configs (no simulator).
"""

from unified_manip.envs.controllers.configs import (
    COMMAND_KINDS,
    ControllerConfig,
    EEDelta,
    EETargetDelta,
    IntegratedJointVelocity,
    JointDelta,
    JointPosition,
    JointTargetDelta,
    JointTorque,
    JointVelocity,
    Native,
)

__all__ = [
    "COMMAND_KINDS",
    "ControllerConfig",
    "EEDelta",
    "EETargetDelta",
    "IntegratedJointVelocity",
    "JointDelta",
    "JointPosition",
    "JointTargetDelta",
    "JointTorque",
    "JointVelocity",
    "Native",
]
