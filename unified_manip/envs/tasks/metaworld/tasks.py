"""The 50 Meta-World tasks as goal tasks: what each one's goals are (numpy only).

Meta-World's envs are not goal-conditioned, but every one samples a target,
``_target_pos``, and calls a step a success when a point of the scene is close enough
to it (:mod:`.goals`). Here the desired goal is that target and the achieved goal that
point, so ``is_success`` is Meta-World's own ``success`` (``info["native_success"]``)
for 48 of the 50 tasks. The two stick tasks also ask for a condition that is not a
point's distance (the stick held, or inserted in the handle); their ``is_success`` is
the distance part alone, and ``native_success`` has the rest.

:data:`TASKS` holds them in Meta-World's own order (``metaworld.ALL_V3_ENVIRONMENTS``,
which a test compares), without importing Meta-World.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from unified_manip.envs.tasks.metaworld.goals import (
    ALONG_X,
    ALONG_Y,
    ALONG_Z,
    EUCLIDEAN,
    HORIZONTAL,
    Hooked,
    Short,
    Weighted,
)


@dataclass(frozen=True)
class Point:
    """Where a task's achieved goal is read.

    Attributes:
        source: ``"object"`` (Meta-World's first object position, its observation's
            ``[4:7]``), ``"second_object"`` (``[11:14]``), ``"tcp"`` (the point between
            the two fingertips, Meta-World's ``tcp_center``) or ``"site"`` (a site of the
            model).
        site: The site's name, for ``"site"``.
        offset: Added to the position, m (Meta-World's faucet handle).
    """

    source: str
    site: str | None = None
    offset: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def read(self, b) -> np.ndarray:
        if self.source == "object":
            p = b.upstream_obs[4:7]
        elif self.source == "second_object":
            p = b.upstream_obs[11:14]
        elif self.source == "tcp":
            p = b.tcp()
        else:
            p = b.data.site_xpos[b.site[self.site]]
        return p + np.asarray(self.offset) if any(self.offset) else p.copy()


OBJECT, SECOND_OBJECT, TCP = Point("object"), Point("second_object"), Point("tcp")


@dataclass(frozen=True)
class MetaWorldTask:
    """One Meta-World task's goal.

    Attributes:
        env_name: Meta-World's name, e.g. ``"door-open-v3"``.
        point: Where the achieved goal is read.
        what: What that point is, for the task page.
        distance: The goal distance (:mod:`.goals`), batched.
        threshold: Success when ``distance < threshold`` (Meta-World's radius).
        terms: The gripper term set of the dense rewards (``reach``, ``push``, ``grasp``).
        exact: Whether ``distance < threshold`` is all of Meta-World's success.
        note: What Meta-World's success adds when it is not (the task page says it).
        target_z: The desired goal's height in place of the target's, m, where Meta-World's
            success reads one (the basketball's: just above the hoop).
    """

    env_name: str
    point: Point
    what: str
    distance: Callable[[np.ndarray, np.ndarray], np.ndarray]
    threshold: float
    terms: str
    exact: bool = True
    note: str = ""
    target_z: float | None = None

    def desired(self, target: np.ndarray) -> np.ndarray:
        """The desired goal of Meta-World's target ``target``."""
        goal = np.array(target, dtype=np.float64)
        if self.target_z is not None:
            goal[2] = self.target_z
        return goal

    @property
    def name(self) -> str:
        """The ID's name: ``door-open-v3`` -> ``MetaWorldDoorOpen``."""
        return "MetaWorld" + "".join(w.capitalize() for w in self.env_name.removesuffix("-v3").split("-"))


def _t(env_name, point, what, distance, threshold, terms, **kw) -> MetaWorldTask:
    return MetaWorldTask(env_name, point, what, distance, threshold, terms, **kw)


#: The lever's radius, m: its tip is 2 r sin(e / 2) from the target at an angle error e,
#: so Meta-World's success, e <= pi/24, is this distance or less.
LEVER_RADIUS = 0.2
LEVER_CHORD = 2.0 * LEVER_RADIUS * math.sin(math.pi / 48.0)

_STICK_NOTE = "Meta-World's success also asks for {}: is_success is the distance part alone"

_TABLE = (
    _t("assembly-v3", Point("site", "RoundNut"), "the nut's centre (site RoundNut)", Hooked(0.02), 0.02, "grasp"),
    _t("basketball-v3", OBJECT, "the ball", Weighted((1.0, 1.0, 2.0)), 0.08, "grasp", target_z=0.3),
    _t("bin-picking-v3", OBJECT, "the cube", EUCLIDEAN, 0.05, "grasp"),
    _t("box-close-v3", OBJECT, "the lid", EUCLIDEAN, 0.08, "grasp"),
    _t("button-press-topdown-v3", OBJECT, "the button's face", ALONG_Z, 0.024, "push"),
    _t("button-press-topdown-wall-v3", OBJECT, "the button's face", ALONG_Z, 0.024, "push"),
    _t("button-press-v3", OBJECT, "the button's face", ALONG_Y, 0.02, "push"),
    _t("button-press-wall-v3", OBJECT, "the button's face", ALONG_Y, 0.03, "push"),
    _t("coffee-button-v3", OBJECT, "the machine's button", ALONG_Y, 0.02, "push"),
    _t("coffee-pull-v3", OBJECT, "the mug", EUCLIDEAN, 0.07, "push"),
    _t("coffee-push-v3", OBJECT, "the mug", EUCLIDEAN, 0.07, "push"),
    _t("dial-turn-v3", OBJECT, "the dial's rim point", EUCLIDEAN, 0.07, "push"),
    _t("disassemble-v3", OBJECT, "the nut's handle", Short(2), 1e-6, "grasp"),
    _t("door-close-v3", OBJECT, "the door's handle", EUCLIDEAN, 0.08, "push"),
    _t("door-lock-v3", OBJECT, "the lock's knob", ALONG_Z, 0.02, "push"),
    _t("door-open-v3", OBJECT, "the door's handle", ALONG_X, 0.08, "push"),
    _t("door-unlock-v3", OBJECT, "the lock's knob", ALONG_X, 0.02, "push"),
    _t("hand-insert-v3", OBJECT, "the block", EUCLIDEAN, 0.05, "push"),
    _t("drawer-close-v3", OBJECT, "the drawer's handle", EUCLIDEAN, 0.065, "push"),
    _t("drawer-open-v3", OBJECT, "the drawer's handle", EUCLIDEAN, 0.03, "push"),
    _t(
        "faucet-open-v3", Point("object", offset=(-0.04, 0.0, 0.03)), "the faucet's handle end", EUCLIDEAN, 0.07, "push"
    ),
    _t("faucet-close-v3", OBJECT, "the faucet's handle end", EUCLIDEAN, 0.07, "push"),
    _t("hammer-v3", SECOND_OBJECT, "the nail (body nail_link)", Short(1), 0.01, "grasp"),
    _t("handle-press-side-v3", OBJECT, "the handle's end", ALONG_Z, 0.02, "push"),
    _t("handle-press-v3", OBJECT, "the handle's end", ALONG_Z, 0.02, "push"),
    _t("handle-pull-side-v3", OBJECT, "the handle's end", EUCLIDEAN, 0.08, "push"),
    _t("handle-pull-v3", OBJECT, "the handle's end", ALONG_Z, 0.05, "push"),
    _t("lever-pull-v3", OBJECT, "the lever's tip (site leverStart)", EUCLIDEAN, LEVER_CHORD, "push"),
    _t("pick-place-wall-v3", OBJECT, "the puck", EUCLIDEAN, 0.07, "grasp"),
    _t("pick-out-of-hole-v3", OBJECT, "the peg", EUCLIDEAN, 0.07, "grasp"),
    _t("pick-place-v3", OBJECT, "the puck", EUCLIDEAN, 0.07, "grasp"),
    _t("plate-slide-v3", OBJECT, "the plate", EUCLIDEAN, 0.07, "push"),
    _t("plate-slide-side-v3", OBJECT, "the plate", EUCLIDEAN, 0.07, "push"),
    _t("plate-slide-back-v3", OBJECT, "the plate", EUCLIDEAN, 0.07, "push"),
    _t("plate-slide-back-side-v3", OBJECT, "the plate", EUCLIDEAN, 0.07, "push"),
    _t("peg-insert-side-v3", Point("site", "pegHead"), "the peg's head", Weighted((1.0, 2.0, 2.0)), 0.07, "grasp"),
    _t("peg-unplug-side-v3", OBJECT, "the plug", EUCLIDEAN, 0.07, "grasp"),
    _t("soccer-v3", OBJECT, "the ball", EUCLIDEAN, 0.07, "push"),
    _t(
        "stick-push-v3",
        SECOND_OBJECT,
        "the thermos",
        EUCLIDEAN,
        0.12,
        "grasp",
        exact=False,
        note=_STICK_NOTE.format("the stick held (both pads on it, fingers open, lifted 1 cm)"),
    ),
    _t(
        "stick-pull-v3",
        SECOND_OBJECT,
        "the thermos's handle",
        EUCLIDEAN,
        0.12,
        "grasp",
        exact=False,
        note=_STICK_NOTE.format("the stick's end inserted in the handle"),
    ),
    _t("push-v3", OBJECT, "the puck", EUCLIDEAN, 0.05, "push"),
    _t("push-wall-v3", OBJECT, "the puck", EUCLIDEAN, 0.07, "push"),
    _t("push-back-v3", OBJECT, "the puck", EUCLIDEAN, 0.07, "push"),
    _t("reach-v3", TCP, "the fingertips' midpoint", EUCLIDEAN, 0.05, "reach"),
    _t("reach-wall-v3", TCP, "the fingertips' midpoint", EUCLIDEAN, 0.05, "reach"),
    _t("shelf-place-v3", OBJECT, "the block", EUCLIDEAN, 0.07, "grasp"),
    _t("sweep-into-v3", OBJECT, "the puck", HORIZONTAL, 0.05, "push"),
    _t("sweep-v3", OBJECT, "the puck", EUCLIDEAN, 0.05, "push"),
    _t("window-open-v3", OBJECT, "the window's handle", ALONG_X, 0.05, "push"),
    _t("window-close-v3", OBJECT, "the window's handle", ALONG_X, 0.05, "push"),
)

#: Every task by Meta-World's name, in Meta-World's order.
TASKS: dict[str, MetaWorldTask] = {t.env_name: t for t in _TABLE}
