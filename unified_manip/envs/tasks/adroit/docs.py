"""The Adroit tasks' documentation pages (``unified-manip list --doc``)."""

from __future__ import annotations

from unified_manip.envs.controllers.docs import modes_section
from unified_manip.envs.tasks.adroit.controllers import CONTROLLERS

_MODES = f"""Action modes (one entry in [-1, 1] per actuator, upstream's order: the arm's
joints, then WRJ1, WRJ0, FFJ3-1, MFJ3-1, RFJ3-1, LFJ4-1, THJ4-0; q is the actuated
joint's position, and the range is the positions its servo can hold, within the
joint's range):
{modes_section(CONTROLLERS)}
The joint modes command the position the joint settles at: on the arm, whose servo
gain (500) is not its stiffness (200), ctrl = 0.4 target. Other modes raise
ValueError: the actuators are position servos (no torque interface), and the end-effector
modes' one gripper entry has no counterpart among the hand's 24 finger actuators."""

RELOCATE_DOC = f"""AdroitRelocate: pick up a ball from the table with the Adroit arm and hand
(a Shadow hand on a 6-joint arm: 3 slides and 3 rotations) and carry it to a target in
the air (gymnasium-robotics AdroitHandRelocate-v1).

Starting state: the ball at x in [-0.15, 0.15], y in [-0.15, 0.3] m on the table; the
target at x, y in [-0.2, 0.2], z in [0.15, 0.35] m (upstream's reset).

Success (upstream's "success"): goal (3,), achieved = the ball's centre, desired = the
target, m; distance < 0.1 m. Sparse reward = success - 1 (upstream's sparse reward is 10 / -0.1). 200 steps
of 10 ms.

Observation (39,): upstream's vector without its two goal-relative parts (palm -
target, ball - target: hindsight relabelling would leave them stale), with the palm's
and the ball's positions in their place:
    0-29   arm and hand joint positions (upstream's qpos[:30])      m, rad
    30-32  palm - ball (upstream's)                                 m
    33-35  palm position (site S_grasp)                             m
    36-38  ball position                                            m
The simulator state (``get_state``) does not hold the target or the ball's start: upstream
keeps them in the model (``site_pos``, ``body_pos``), which pickling keeps.

{_MODES}

Rewards: term set "grasp": reach = 1 - tanh(5 |palm - ball|), place = 5 lifted
(1 - tanh(5 d)) with lifted 1 while the ball is off the table (centre above z = 0.04 m,
upstream's dense reward's check), success bonus 10; dense_penalized adds -0.01 sum(a^2)
and -10 on the step the ball drops back.

Version history: v0 initial (over AdroitHandRelocate-v1, gymnasium-robotics 1.4.2).
"""

DOOR_DOC = f"""AdroitDoor: undo the latch and swing the door open with the Adroit arm and hand
(a Shadow hand on a 4-joint arm: 1 slide and 3 rotations; gymnasium-robotics
AdroitHandDoor-v1).

Starting state: the door's frame at x in [-0.3, -0.2], y in [0.25, 0.35], z in
[0.252, 0.35] m (upstream's reset).

Success: goal (1,), achieved = the door hinge's angle, desired = fully open, 1.57 rad
(the hinge's upper limit; the same every episode); |angle - 1.57| <
0.22 rad, i.e. angle > 1.35 rad while the hinge is within its range [0, 1.57]:
upstream's "success" (angle >= 1.35). Sparse reward = success - 1 (upstream's sparse
reward is 10 / -0.1). 200 steps of 10 ms.

Observation (40,): upstream's vector, with the arm's first joint (ARTz), which upstream
leaves out:
    0-27   arm and hand joint positions (qpos[:28])                  m, rad
    28     latch angle                                              rad
    29     door hinge angle                                         rad
    30-32  palm position (site S_grasp)                             m
    33-35  handle position (site S_handle)                          m
    36-38  palm - handle                                            m
    39     door open: +1 beyond 1 rad, else -1 (upstream's)         -
The simulator state (``get_state``) does not hold the door's placement: upstream keeps
it in the model (``body_pos``), which pickling keeps.

{_MODES}

Rewards: term set "push": reach = 1 - tanh(5 |palm - handle|), place = 5 (1 - tanh(5
d)) with d the hinge's distance from open, rad, success bonus 10; no grasp check (as
robosuite's Door), so dense_penalized adds only -0.01 sum(a^2).

Version history: v0 initial (over AdroitHandDoor-v1, gymnasium-robotics 1.4.2).
"""
