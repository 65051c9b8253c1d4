"""The valve task's observation groups, declared once (no simulator).

Each group reads the backend's current state. The default observation is the
concatenation of :data:`DEFAULT`; the scripted policy finds its entries through
:func:`default_slices`, so the layout is written only here.
"""

from __future__ import annotations

import numpy as np

from unified_manip.envs.observations import ObservationGroup as G
from unified_manip.envs.observations import goal_rel_group

#: Every group, in the order the ``"full"`` preset concatenates them. The shared names
#: (``joint_pos``, ``ee_pos``, ``object_pos``, ``object_rel``, ``goal_rel``, ...) mean what
#: they mean on every family: here the object is the valve's handle and the end effector
#: the fingertip.
GROUPS: dict[str, G] = {
    "joint_pos": G("rad", lambda b: b.data.qpos[b.rig.qpos_adr]),
    "joint_vel": G("rad/s", lambda b: b.data.qvel[b.rig.dof_adr], "velocity"),
    "ee_pos": G("m (fingertip, world)", lambda b: b.data.site_xpos[b.rig.site_id]),
    "object_pos": G("m (handle, world)", lambda b: b.data.site_xpos[b.handle_site]),
    "valve_angle": G("rad, wrapped to [-pi, pi)", lambda b: np.atleast_1d(b.valve_angle())),
    "valve_vel": G("rad/s", lambda b: b.data.qvel[b.valve_dof : b.valve_dof + 1], "velocity"),
    "object_rel": G(
        "m (handle - fingertip)",
        lambda b: b.data.site_xpos[b.handle_site] - b.data.site_xpos[b.rig.site_id],
        "relative",
    ),
    # desired - achieved, as on every family (hindsight relabelling recomputes it so),
    # not wrapped: from -2 pi to 2 pi.
    "goal_rel": goal_rel_group("rad (target - valve angle)"),
}

#: The default observation vector, group by group.
DEFAULT = ("joint_pos", "joint_vel", "ee_pos", "object_pos", "valve_angle", "valve_vel", "object_rel", "goal_rel")
#: Each group's length.
SIZES = {"joint_pos": 2, "joint_vel": 2, "ee_pos": 3, "object_pos": 3, "valve_angle": 1, "valve_vel": 1}
SIZES |= {"object_rel": 3, "goal_rel": 1}


def default_slices() -> dict[str, slice]:
    """Each default group's slice of the default observation vector."""
    out, start = {}, 0
    for name in DEFAULT:
        out[name] = slice(start, start + SIZES[name])
        start += SIZES[name]
    return out
