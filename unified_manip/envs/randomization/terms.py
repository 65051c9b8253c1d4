"""One randomisation term: which entity, which field, how it is drawn and when.

A :class:`RandomizationTerm` is a frozen config that checks itself when built, so a bad
field, distribution, operation, mode or range fails with a message naming the valid
choices before any simulator is loaded. What depends on the task (the entity's name, the
field's nominal values) is checked when the env is made
(:class:`~unified_manip.envs.randomization.randomizer.Randomizer`).

The fields, the model arrays they write and what they apply to:

============== ========================================== ==================
field          model array                                entity part
============== ========================================== ==================
size           ``geom_size`` (every axis by one factor)   geoms
mass           ``body_mass`` (``body_inertia`` follows)   bodies
friction       ``geom_friction[:, 0]`` (sliding)          geoms
damping        ``dof_damping``                            joints
armature       ``dof_armature``                           joints
actuator_gain  ``actuator_gainprm[:, 0]`` (a position     actuators
               servo's ``biasprm[:, 1]`` follows)
rgba           ``mat_rgba`` / ``geom_rgba`` (r, g, b)     geoms
light          ``light_diffuse`` (one brightness)         lights
camera_pose    ``cam_pos`` (x, y, z offsets, m)           cameras
shape          ``geom_type`` among :data:`SHAPES`         a solid's geoms
============== ========================================== ==================
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields
from typing import Any, Mapping

#: The fields a term may randomise, with the entity part each writes.
FIELD_PARTS: dict[str, str] = {
    "size": "geoms",
    "mass": "bodies",
    "friction": "geoms",
    "damping": "joints",
    "armature": "joints",
    "actuator_gain": "actuators",
    "rgba": "geoms",
    "light": "lights",
    "camera_pose": "cameras",
    "shape": "geoms",
}
FIELDS: tuple[str, ...] = tuple(FIELD_PARTS)
DISTRIBUTIONS: tuple[str, ...] = ("uniform", "log_uniform", "gaussian")
OPERATIONS: tuple[str, ...] = ("abs", "scale", "add")
#: ``startup``: drawn at the first reset and at every reset given a seed, kept otherwise;
#: ``reset``: drawn at every reset; ``interval``: drawn every ``every`` steps.
MODES: tuple[str, ...] = ("startup", "reset", "interval")
#: The primitive shapes a ``shape`` term chooses among.
SHAPES: tuple[str, ...] = ("box", "cylinder", "sphere")

#: Each field's operations (a camera's pose is offset, never set to one value for all).
FIELD_OPERATIONS: dict[str, tuple[str, ...]] = {f: OPERATIONS for f in FIELDS} | {
    "camera_pose": ("add",),
    "shape": ("abs",),
}
#: How many values one draw of a field holds (r, g, b; x, y, z; else one).
FIELD_WIDTH: dict[str, int] = {f: 1 for f in FIELDS} | {"rgba": 3, "camera_pose": 3}
#: The fields whose value must stay above 0 (``True``) or at least 0 (``False``). Colours
#: and brightness are clipped instead (to [0, 1] and to >= 0), so an offset may reach past them.
POSITIVE: dict[str, bool] = {
    "size": True,
    "mass": True,
    "actuator_gain": True,
    "friction": False,
    "damping": False,
    "armature": False,
}


def choices(values) -> str:
    """``'a', 'b', 'c'``: the valid choices in an error message."""
    return ", ".join(repr(v) for v in values)


def _pick(name: str, value: Any, valid: tuple[str, ...], what: str = "") -> None:
    if value not in valid:
        raise ValueError(f"unknown {name} {value!r}{what}; expected one of {choices(valid)}")


@dataclass(frozen=True)
class RandomizationTerm:
    """One randomised model field of one named entity.

    Attributes:
        entity: The entity's name, as the task's family names it (``object``, ``table``,
            ``robot``, ``light``, ``camera``; ``env.unwrapped.task.entities``).
        field: One of :data:`FIELDS`.
        range: ``(low, high)`` of the draw, in the field's units for ``abs`` and ``add``
            and as a factor for ``scale``; for ``gaussian``, ``(mean, std)``. Unused by
            ``shape``.
        distribution: ``uniform``, ``log_uniform`` (uniform in log space: factors) or
            ``gaussian``.
        operation: ``abs`` (the value replaces the nominal one), ``scale`` (multiplies
            it) or ``add`` (is added to it). Always from the nominal values captured when
            the env was made, never from an earlier draw.
        mode: ``startup``, ``reset`` or ``interval`` (:data:`MODES`).
        every: With ``interval``: draw every this many steps of an episode.
        exclude: ``(low, high)`` inside ``range`` that draws avoid (uniform and
            log-uniform only): the extreme test distributions draw beyond the training
            range this way.
        shared: One draw for every element of the entity (``True``) or one per element
            (each joint its own damping).
        shapes: With ``shape``: the shapes drawn among, uniformly.
    """

    entity: str
    field: str
    range: tuple[float, float] = (1.0, 1.0)
    distribution: str = "uniform"
    operation: str = "scale"
    mode: str = "reset"
    every: int = 0
    exclude: tuple[float, float] | None = None
    shared: bool = True
    shapes: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not isinstance(self.entity, str) or not self.entity:
            raise TypeError(f"a randomization term's entity must be a name, got {self.entity!r}")
        _pick("randomization field", self.field, FIELDS)
        _pick("distribution", self.distribution, DISTRIBUTIONS)
        _pick("mode", self.mode, MODES)
        _pick("operation", self.operation, FIELD_OPERATIONS[self.field], f" for field {self.field!r}")
        object.__setattr__(self, "range", _pair("range", self.range))
        if self.mode == "interval":
            if isinstance(self.every, bool) or not isinstance(self.every, int) or self.every < 1:
                raise ValueError(f"mode 'interval' needs every >= 1 (steps between draws), got every={self.every!r}")
        elif self.every:
            raise ValueError(f"every={self.every!r} is for mode 'interval' only; this term's mode is {self.mode!r}")
        if self.field == "shape":
            self._check_shapes()
            return
        if self.shapes:
            raise ValueError(f"shapes are for field 'shape' only; this term's field is {self.field!r}")
        low, high = self.range
        if self.distribution == "gaussian":
            if high < 0:
                raise ValueError(f"a gaussian range is (mean, std) with std >= 0; got {self.range}")
        elif low > high:
            raise ValueError(f"range {self.range} is inverted; expected (low, high) with low <= high")
        if self.distribution == "log_uniform" and low <= 0:
            raise ValueError(f"a log_uniform range must be above 0; got {self.range}")
        if self.exclude is not None:
            self._check_exclude()
        self._check_valid_values()

    def _check_shapes(self) -> None:
        shapes = tuple(self.shapes)
        object.__setattr__(self, "shapes", shapes)
        if not shapes:
            raise ValueError(f"a 'shape' term needs shapes, some of {choices(SHAPES)}")
        for shape in shapes:
            _pick("shape", shape, SHAPES)
        if self.mode == "interval":
            raise ValueError("a 'shape' term draws at construction or reset; expected mode 'startup' or 'reset'")
        if self.exclude is not None:
            raise ValueError("a 'shape' term draws among its shapes; it takes no exclude")

    def _check_exclude(self) -> None:
        exclude = _pair("exclude", self.exclude)
        object.__setattr__(self, "exclude", exclude)
        if self.distribution == "gaussian":
            raise ValueError("exclude needs distribution 'uniform' or 'log_uniform', not 'gaussian'")
        (low, high), (x0, x1) = self.range, exclude
        if not low <= x0 <= x1 <= high:
            raise ValueError(f"exclude {self.exclude} must lie inside range {self.range}")
        if x0 == low and x1 == high:
            raise ValueError(f"exclude {self.exclude} covers all of range {self.range}")

    def _check_valid_values(self) -> None:
        """A range that would make the model invalid, where the nominal value does not
        matter (``abs`` and ``scale``; ``add`` is checked against the nominal values)."""
        if self.field not in POSITIVE or self.operation == "add":
            return
        low = self.range[0] if self.distribution != "gaussian" else -math.inf
        strict = POSITIVE[self.field]
        if (strict and low <= 0) or (not strict and low < 0):
            bound = "above 0" if strict else "at least 0"
            what = "values" if self.operation == "abs" else "factors"
            hint = " (a gaussian is unbounded: use uniform or log_uniform)" if self.distribution == "gaussian" else ""
            raise ValueError(
                f"{self.entity}.{self.field}: range {self.range} gives {what} below the valid ones; "
                f"{self.field} must stay {bound}{hint}"
            )

    @property
    def label(self) -> str:
        """``entity.field``: the term's key in ``info["randomization"]``."""
        return f"{self.entity}.{self.field}"

    def as_dict(self) -> dict[str, Any]:
        """The term as plain values (JSON), which :func:`term_from` reads back."""
        out = asdict(self)
        out["range"] = list(self.range)
        out["exclude"] = None if self.exclude is None else list(self.exclude)
        out["shapes"] = list(self.shapes)
        return out


def _pair(name: str, value: Any) -> tuple[float, float]:
    try:
        low, high = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a pair of numbers (low, high), got {value!r}") from None
    if not (math.isfinite(low) and math.isfinite(high)):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return low, high


_TERM_FIELDS = tuple(f.name for f in fields(RandomizationTerm))


def term_from(value: RandomizationTerm | Mapping[str, Any]) -> RandomizationTerm:
    """A term from itself or from a mapping of its fields (YAML, JSON, ``as_dict``)."""
    if isinstance(value, RandomizationTerm):
        return value
    if not isinstance(value, Mapping):
        raise TypeError(f"a randomization term must be a RandomizationTerm or a mapping, got {value!r}")
    unknown = [k for k in value if k not in _TERM_FIELDS]
    if unknown:
        raise ValueError(f"unknown randomization term key {unknown[0]!r}; expected some of {choices(_TERM_FIELDS)}")
    kwargs = dict(value)
    for key in ("range", "exclude", "shapes"):
        if isinstance(kwargs.get(key), list):
            kwargs[key] = tuple(kwargs[key])
    return RandomizationTerm(**kwargs)
