"""Upstream's noisy observation and joint-velocity control, from precomputed addresses.

gymnasium-robotics' ``FrankaRobot._get_obs`` looks every robot joint up by name on every
step (``robot_get_obs``), about as long as the rest of the step's Python. This reads the
same entries by address and adds the same noise, drawn from the same generator in the same
order, so the observation and ``native``'s servo targets are upstream's bit for bit (the
tests compare them with ``FrankaKitchen-v1``'s):

* the robot's 9 joint positions and velocities, each plus ``robot_noise_ratio`` times its
  amplitude times ``U(-1, 1)``;
* the kitchen's 21 ``qpos`` and 20 ``qvel``, plus ``object_noise_ratio`` times upstream's
  amplitudes (``robot_pos_noise_amp[8:]``, ``robot_vel_noise_amp[9:]``: its indexing) times
  ``U(-1, 1)``;
* ``native``: the servo targets ``clip(q_obs + clip(2 a, velocity bounds) dt, position
  bounds)`` from the last observation's noisy ``q_obs``.
"""

from __future__ import annotations

from typing import Any

import numpy as np


class KitchenReadout:
    """The observation and ``native`` control of one upstream ``KitchenEnv`` (its
    ``robot_env`` holds the robot's configuration: noise amplitudes, bounds, ``dt``).

    Attributes:
        last_q: The robot's noisy joint positions of the last observation.
    """

    def __init__(self, up: Any) -> None:
        robot = up.robot_env
        m = robot.model
        joints = [j for j in range(m.njnt) if m.joint(j).name.startswith("robot")]  # upstream's filter
        self._qadr, self._dadr = m.jnt_qposadr[joints].copy(), m.jnt_dofadr[joints].copy()
        n = len(joints)
        self._q_noise = robot.robot_noise_ratio * robot.robot_pos_noise_amp[:n]
        self._v_noise = robot.robot_noise_ratio * robot.robot_vel_noise_amp[:n]
        self._kitchen_q = slice(n, m.nq)
        self._kitchen_v = slice(n, m.nv)
        self._kq_noise = up.object_noise_ratio * robot.robot_pos_noise_amp[n - 1 :]
        self._kv_noise = up.object_noise_ratio * robot.robot_vel_noise_amp[n:]
        self._act_mid, self._act_rng = robot.act_mid.copy(), robot.act_rng.copy()
        self._vel_bound = robot.robot_vel_bound[:n].copy()
        self._pos_bound = robot.robot_pos_bound[:n].copy()
        self._dt = robot.dt
        self.last_q = np.zeros(n)

    def observation(self, data: Any, rng: np.random.Generator) -> np.ndarray:
        """Upstream's 59-entry observation now, its noise drawn from ``rng``."""
        q, v = data.qpos[self._qadr], data.qvel[self._dadr]  # copies (fancy indexing)
        q += self._q_noise * rng.uniform(low=-1.0, high=1.0, size=q.shape)
        v += self._v_noise * rng.uniform(low=-1.0, high=1.0, size=v.shape)
        self.last_q = q
        kq, kv = data.qpos[self._kitchen_q].copy(), data.qvel[self._kitchen_v].copy()
        kq += self._kq_noise * rng.uniform(low=-1.0, high=1.0, size=kq.shape)
        kv += self._kv_noise * rng.uniform(low=-1.0, high=1.0, size=kv.shape)
        return np.concatenate((q, v, kq, kv))

    def controls(self, action: np.ndarray) -> np.ndarray:
        """``native``'s servo targets for a clipped ``action`` (upstream's ``FrankaRobot.step``)."""
        velocity = np.clip(self._act_mid + action * self._act_rng, self._vel_bound[:, 0], self._vel_bound[:, 1])
        return np.clip(self.last_q + velocity * self._dt, self._pos_bound[:, 0], self._pos_bound[:, 1])
