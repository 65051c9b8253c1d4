"""The Meta-World tasks' action modes: ``{mode: controller config}``.

``native`` is Meta-World's own: its Sawyer's hand follows a mocap body welded to it.
The joint and end-effector modes need that weld removed and the arm driven another
way; they are not offered yet."""

from __future__ import annotations

from unified_manip.envs import controllers as ctl

CONTROLLERS = {
    "native": ctl.Native(
        "Meta-World's own: (dx, dy, dz) moves the mocap body the hand is welded to by "
        "1 cm per unit (clipped to the hand's box), and the gripper entry drives the two "
        "fingers' position actuators (+1 closes, -1 opens)"
    ),
}
