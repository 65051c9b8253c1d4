"""Named entities: the parts of a task's model that randomisation terms address.

A family names its entities once (``unified_manip/envs/tasks/<family>/entities.py``, given
to its specs as ``TaskSpec.entities``), as it names its cameras: ``object``, ``table``,
``robot``, ``light``, ``camera``, each an :class:`Entity` of name patterns for the model's
bodies, geoms, joints, actuators, lights and cameras. The patterns are matched in full
(``re.fullmatch``) against the names in the backend's compiled model when the env is
made (:func:`resolve`), so one entity can cover every task and action mode of a family
(Fetch has its arm servos only outside ``native``). An entity none of whose patterns
matches anything is absent from that task (Reach tasks have no ``object``).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping

import numpy as np

#: The model parts an entity may name, and MuJoCo's object type of each.
PARTS: tuple[str, ...] = ("bodies", "geoms", "joints", "actuators", "lights", "cameras")


@dataclass(frozen=True)
class RestHeight:
    """Where the task places a solid at reset, so that a resized one rests on the table
    instead of starting inside it: ``get(backend)`` reads the height its centre is placed
    at, ``set(backend, z)`` changes it for the next reset. Module-level functions (picklable).
    """

    get: Callable[[Any], float]
    set: Callable[[Any, float], None]


@dataclass(frozen=True)
class Entity:
    """One named part of a task's model, as name patterns (``re.fullmatch``; empty: none).

    Attributes:
        bodies, geoms, joints, actuators, lights, cameras: Patterns of the model's names
            (an unnamed geom goes by its body's name, an unnamed light by ``""``).
        solid: The entity is one body whose collision geom is a primitive solid resting
            on the table (a cube): ``size`` keeps it resting there and ``shape`` may turn
            it into another primitive. Its inertia follows its mass, size and shape.
        shapes: The shapes the task can take (a pushed object stays a box: a round one
            rolls off the pusher's line); a preset's ``shape`` term keeps these.
        rest: How the task places the solid at reset (see :class:`RestHeight`), or None.
        doc: One line for the documentation.
    """

    bodies: str = ""
    geoms: str = ""
    joints: str = ""
    actuators: str = ""
    lights: str = ""
    cameras: str = ""
    solid: bool = False
    shapes: tuple[str, ...] = ("box", "cylinder", "sphere")
    rest: RestHeight | None = None
    doc: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        for part in PARTS:
            try:
                re.compile(getattr(self, part))
            except re.error as err:
                raise ValueError(f"entity pattern {part}={getattr(self, part)!r} is not a regular expression: {err}")


@dataclass(frozen=True)
class Resolved:
    """An entity's ids in one compiled model, one int array per part (:data:`PARTS`)."""

    name: str
    ids: Mapping[str, np.ndarray]
    solid: bool = False
    rest: RestHeight | None = None
    shapes: tuple[str, ...] = ()

    def part(self, name: str) -> np.ndarray:
        return self.ids[name]

    @property
    def empty(self) -> bool:
        return not any(len(v) for v in self.ids.values())


def _names(model, part: str) -> list[str]:
    count = {
        "bodies": model.nbody,
        "geoms": model.ngeom,
        "joints": model.njnt,
        "actuators": model.nu,
        "lights": model.nlight,
        "cameras": model.ncam,
    }[part]
    view = {
        "bodies": model.body,
        "geoms": model.geom,
        "joints": model.joint,
        "actuators": model.actuator,
        "lights": model.light,
        "cameras": model.camera,
    }[part]
    return [view(i).name for i in range(count)]


def resolve(name: str, entity: Entity, model) -> Resolved:
    """The ids of ``entity``'s parts in ``model`` (empty arrays where nothing matches).

    An unnamed geom is matched by its body's name (Fetch's table top has no name)."""
    ids = {}
    for part in PARTS:
        pattern = getattr(entity, part)
        if not pattern:
            ids[part] = np.zeros(0, dtype=np.int64)
            continue
        names = _names(model, part)
        if part == "geoms":
            bodies = _names(model, "bodies")
            names = [n or bodies[model.geom_bodyid[i]] for i, n in enumerate(names)]
        regex = re.compile(pattern)
        ids[part] = np.array([i for i, n in enumerate(names) if regex.fullmatch(n)], dtype=np.int64)
    return Resolved(name, ids, entity.solid, entity.rest, tuple(entity.shapes))
