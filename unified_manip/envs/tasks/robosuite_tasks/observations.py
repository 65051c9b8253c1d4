"""robosuite's observation groups: its own observables, one group each, plus the shared
``object_rel`` and ``goal_rel``; the default vector is robosuite's ``robot0_proprio-state``
(then ``robot1_proprio-state`` on the two-arm tasks) then ``object-state``, i.e. those
observables in robosuite's order. The first robot's groups are named without a prefix
(``joint_pos``); a second robot's carry its own (``robot1_joint_pos``)."""

from __future__ import annotations

import re
from typing import Any

import numpy as np

from unified_manip.envs.observations import ObservationGroup as G
from unified_manip.envs.observations import goal_rel_group

#: robosuite's proprioceptive observables (without the ``robot0_`` prefix): group name,
#: units, kind.
PROPRIO: dict[str, tuple[str, str, str]] = {
    "joint_pos": ("joint_pos", "rad", "state"),
    "joint_pos_cos": ("joint_pos_cos", "cos of the joint angles", "state"),
    "joint_pos_sin": ("joint_pos_sin", "sin of the joint angles", "state"),
    "joint_vel": ("joint_vel", "rad/s", "velocity"),
    "joint_acc": ("joint_acc", "rad/s^2", "velocity"),
    "eef_pos": ("ee_pos", "m (end effector, world)", "state"),
    "eef_quat": ("ee_quat", "quaternion (x, y, z, w)", "state"),
    "eef_quat_site": ("ee_quat_site", "quaternion (x, y, z, w) of the grip site", "state"),
    "gripper_qpos": ("gripper", "m (finger joint positions)", "state"),
    "gripper_qvel": ("gripper_vel", "m/s (finger joint velocities)", "velocity"),
    "contact": ("contact", "1 while the wiping tool pushes with more than 1 N (Wipe)", "state"),
}
PROPRIO_MODALITY = re.compile(r"robot(\d+)_proprio")


def _object_group(key: str) -> G:
    kind = "relative" if "_to_" in key else "state"
    units = "quaternion (x, y, z, w)" if key.endswith("_quat") else "rad" if key.endswith("qpos") else "m"
    return G(units, lambda b: b._obs[key], kind)


def _object_rel(b) -> np.ndarray:
    """Object - grip site of each reacher, in turn (3 entries each)."""
    sites = [site for _, site, _ in b._reach]
    return (np.atleast_2d(b.task.object_pos(b._up)) - b.data.site_xpos[sites]).ravel()


def suite_groups(up: Any) -> tuple[dict[str, G], tuple[str, ...]]:
    """``(groups, default)`` of a robosuite env: each active proprio and object observable
    in robosuite's order (the default vector), then ``object_rel`` and ``goal_rel``."""
    groups: dict[str, G] = {}
    for key, obs in up._observables.items():
        if not (obs.is_enabled() and obs.is_active()):
            continue
        robot = PROPRIO_MODALITY.fullmatch(obs.modality)
        if robot:
            prefix = f"robot{robot[1]}_"
            name, units, kind = PROPRIO[key.removeprefix(prefix)]
            groups[name if robot[1] == "0" else prefix + name] = G(units, lambda b, k=key: b._obs[k], kind)
        elif obs.modality == "object":
            groups[key] = _object_group(key)
    default = tuple(groups)
    groups["object_rel"] = G("m (object - grip site)", _object_rel, "relative")
    groups["goal_rel"] = goal_rel_group("goal units (goal - achieved goal)")
    return groups, default
