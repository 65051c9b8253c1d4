"""The valve scene's geometry, timing and reset distributions (no simulator).

``valve.xml`` holds the same geometry; :class:`~unified_manip_valve.backend.ValveBackend`
checks that the two agree when it loads the model.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

ASSET = Path(__file__).with_name("valve.xml")

#: Physics substeps of 2 ms per env step (50 Hz control).
SUBSTEPS = 10
#: The finger's link lengths, m; its base is the world origin.
LINKS = (0.14, 0.14)
#: The valve's axis (x, y), m, and the handle's distance from it, m.
VALVE_AXIS = np.array([0.16, 0.0])
HANDLE_RADIUS = 0.05
#: The finger's joint angles at reset, rad (fingertip at about (0.13, 0.10) m, clear of the
#: valve), before a uniform perturbation of +-``HOME_NOISE`` rad.
HOME_Q = np.array([1.6, -1.9])
HOME_NOISE = 0.1
#: How far the goal is turned from the valve's angle at reset, rad (either way).
TURN_LOW, TURN_HIGH = 0.5, 1.5


def wrap(angle):
    """``angle`` wrapped to ``[-pi, pi)``, rad (arrays element-wise)."""
    return np.remainder(np.asarray(angle, dtype=np.float64) + math.pi, 2 * math.pi) - math.pi


def sample_episode(rng: np.random.Generator) -> tuple[np.ndarray, float, float]:
    """The finger's joint angles, the valve's angle and the goal angle at reset (rad)."""
    q = HOME_Q + rng.uniform(-HOME_NOISE, HOME_NOISE, size=2)
    valve = rng.uniform(-math.pi, math.pi)
    turn = rng.uniform(TURN_LOW, TURN_HIGH) * rng.choice((-1.0, 1.0))
    return q, valve, float(wrap(valve + turn))
