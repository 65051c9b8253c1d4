"""A scripted policy in ``joint_delta`` (and ``native``): put the fingertip behind the
handle, seen from the way the valve must turn, and push it round the valve's axis.

It thinks in fingertip targets and turns each into joint angles by the two-link finger's
closed-form inverse kinematics, so it needs no end-effector action mode. It is memoryless
(it reads only the default observation), so it works from any state.
"""

from __future__ import annotations

import math

import numpy as np

from unified_manip_valve.observations import default_slices
from unified_manip_valve.scene import HANDLE_RADIUS, LINKS, VALVE_AXIS, wrap
from unified_manip_valve.specs import CONTROLLERS

#: Fingertip radius + handle radius + 8 mm: the tip stands this far behind the handle.
BEHIND = 0.03
#: The tip pushes from this far behind the handle's centre (1 mm into it), m.
CONTACT = 0.021
#: How far ahead of the handle the pushing tip aims, rad of valve turn.
LEAD = 0.35
#: The tip counts as in place within this distance of its waypoint, m.
NEAR = 0.012
#: The tip comes in to the handle from this far outside the rim, m.
STAGING = 0.035
#: Close enough: stop within this angle of the target (inside the success threshold), rad.
HOLD = 0.08
#: The fingertip moves at most this far toward its target per step, m.
STEP = 0.01
#: The ``joint_delta`` step at ``|a| = 1``, rad.
MAX_DELTA = CONTROLLERS["joint_delta"].max_delta

_S = default_slices()


def finger_ik(target: np.ndarray) -> np.ndarray:
    """Joint angles that put the fingertip at ``target`` (x, y), elbow bent to negative j1
    (the posture at reset); a target out of reach gives the nearest stretched posture."""
    l1, l2 = LINKS
    x, y = target
    c = np.clip((x * x + y * y - l1 * l1 - l2 * l2) / (2 * l1 * l2), -1.0, 1.0)
    q1 = -math.acos(c)
    q0 = math.atan2(y, x) - math.atan2(l2 * math.sin(q1), l1 + l2 * math.cos(q1))
    return np.array([q0, q1])


def _rim(angle: float) -> tuple[np.ndarray, np.ndarray]:
    """The handle's position at valve angle ``angle``, and the unit vector from the axis to it."""
    radial = np.array([math.cos(angle), math.sin(angle)])
    return VALVE_AXIS + HANDLE_RADIUS * radial, radial


def fingertip_target(tip: np.ndarray, angle: float, error: float) -> np.ndarray:
    """Where the fingertip goes next, from where it is relative to the handle.

    In the handle's frame (``along``: the way the valve must turn; ``out``: away from the
    axis), the tip pushes when it is just behind the handle; backs straight out when it is
    next to the handle on the other side; comes straight in when it is behind the handle
    and outside the rim; and otherwise goes to ``STAGING`` m outside the rim, behind the
    handle. Within ``HOLD`` of the target it stays where it is."""
    direction = 1.0 if error > 0 else -1.0
    handle, radial = _rim(angle)
    tangent = direction * np.array([-radial[1], radial[0]])
    along, out = float((tip - handle) @ tangent), float((tip - handle) @ radial)
    if abs(error) < HOLD:
        return tip
    if -BEHIND - 0.01 < along < 0.0 and abs(out) < 0.015:  # in contact, or nearly: push
        # To where the tip touches the handle once it is turned LEAD further (the target, if nearer).
        ahead, ahead_radial = _rim(angle + direction * min(LEAD, abs(error)))
        return ahead - CONTACT * direction * np.array([-ahead_radial[1], ahead_radial[0]])
    if along >= 0.0 and np.linalg.norm(tip - handle) < BEHIND + NEAR:  # on the wrong side: straight out
        return tip + STAGING * radial
    if abs(along + BEHIND) < 2 * NEAR and -0.01 <= out < STAGING + NEAR:  # behind and outside: come in
        return handle - BEHIND * tangent
    return handle - BEHIND * tangent + STAGING * radial


def turn_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """The ``joint_delta`` action that moves the fingertip at most ``STEP`` m straight
    toward this step's target (a straight line in the plane, not in joint space)."""
    o = obs["observation"]
    tip = o[_S["ee_pos"]][:2]
    error = float(wrap(o[_S["goal_rel"]][0]))  # goal_rel is not wrapped
    move = fingertip_target(tip, float(o[_S["valve_angle"]][0]), error) - tip
    move *= min(1.0, STEP / max(float(np.linalg.norm(move)), 1e-9))
    return np.clip((finger_ik(tip + move) - o[_S["joint_pos"]]) / MAX_DELTA, -1.0, 1.0).astype(np.float32)


def success_rate(seeds, action_mode: str = "joint_delta") -> float:
    """The share of seeded episodes that end in success under :func:`turn_policy`."""
    import gymnasium as gym

    env = gym.make("UnifiedManip/ValveTurn-v0", action_mode=action_mode)
    successes = 0.0
    for seed in seeds:
        obs, info = env.reset(seed=seed)
        for _ in range(env.spec.max_episode_steps):
            obs, _, _, _, info = env.step(turn_policy(obs))
        successes += info["is_success"]
    env.close()
    return successes / len(seeds)


if __name__ == "__main__":  # python -m unified_manip_valve.policy [EPISODES [FIRST_SEED]]
    import sys

    n, first = (int(a) for a in (sys.argv[1:] + ["200", "0"][len(sys.argv) - 1 :])[:2])
    print(f"success {success_rate(range(first, first + n)):.3f} over {n} episodes, seeds {first}-{first + n - 1}")
