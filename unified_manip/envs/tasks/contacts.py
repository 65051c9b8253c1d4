"""Contact queries the families' grasp checks share (on ``mujoco.MjData``)."""

from __future__ import annotations


def touches_both(data, geom: int, left: int, right: int) -> bool:
    """Whether geoms ``left`` and ``right`` (the two fingers) both touch ``geom``."""
    if data.ncon < 2:
        return False
    pairs = data.contact.geom
    other = pairs[(pairs == geom).any(axis=1)].ravel()
    return bool((other == left).any() and (other == right).any())
