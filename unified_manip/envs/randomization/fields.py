"""How each field is written: a term resolved on one compiled model.

A :class:`FieldWriter` captures the nominal values of its model entries when the env is
made and writes ``operation(nominal, drawn)`` on every draw, so values never drift from
earlier draws. It also checks, against the model, what the term itself cannot: that the
entity has the part the field needs, that ``add`` keeps the field valid, and that a size
or shape change meets primitive geoms only (a mesh's shape is fixed when the model is
compiled). What a write leaves to derive (bounding volumes, inertia, a solid's rest
height) is done once per draw by :class:`~.geometry.Geometry`.
"""

from __future__ import annotations

import abc

import mujoco
import numpy as np

from unified_manip.envs.randomization.draws import combine, value_bounds
from unified_manip.envs.randomization.entities import Resolved
from unified_manip.envs.randomization.geometry import PRIMITIVES, Geometry
from unified_manip.envs.randomization.terms import FIELD_PARTS, FIELD_WIDTH, POSITIVE, RandomizationTerm

_AFFINE = int(mujoco.mjtBias.mjBIAS_AFFINE)
#: MuJoCo's default geom rgba: a geom with a material and this rgba shows the material's colour.
_DEFAULT_RGBA = (0.5, 0.5, 0.5, 1.0)


class CannotApply(ValueError):
    """A term the task's model cannot take (a part it lacks, a mesh's shape, a range that
    would make it invalid)."""


def _joint_dofs(model, joints: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each joint's dof addresses, and the joint each dof belongs to (its row)."""
    width = {0: 6, 1: 3, 2: 1, 3: 1}  # free, ball, slide, hinge
    dofs: list[int] = []
    rows: list[int] = []
    for row, j in enumerate(joints):
        n = width[int(model.jnt_type[j])]
        dofs.extend(range(int(model.jnt_dofadr[j]), int(model.jnt_dofadr[j]) + n))
        rows.extend([row] * n)
    return np.array(dofs, dtype=np.int64), np.array(rows, dtype=np.int64)


class FieldWriter(abc.ABC):
    """One term on one model: ``write(model, values, geometry)`` from its nominal values.

    Attributes:
        term: The term.
        elements: The names of the entries one per-element draw covers (info keys).
        needs_const: The write changes mass or inertia, so MuJoCo's derived constants
            (``mj_setConst``) must be recomputed.
    """

    needs_const = False

    def __init__(self, term: RandomizationTerm, entity: Resolved, model, task_id: str) -> None:
        self.term = term
        part = FIELD_PARTS[term.field]
        self.ids = entity.part(part)
        if not len(self.ids):
            raise CannotApply(
                f"{task_id}: entity {entity.name!r} has no {part}, which field {term.field!r} needs; {_has(entity)}"
            )
        self.elements = [self._name(model, part, int(i)) for i in self.ids]
        self.nominal = self._capture(model)

    @staticmethod
    def _name(model, part: str, i: int) -> str:
        view = getattr(
            model, {"bodies": "body", "geoms": "geom", "joints": "joint", "actuators": "actuator"}.get(part, part[:-1])
        )
        return view(i).name or f"{part[:-1]}{i}"

    @property
    def count(self) -> int:
        """Rows of one draw: 1 when the term is shared, else one per element."""
        return 1 if self.term.shared else len(self.elements)

    @abc.abstractmethod
    def _capture(self, model) -> np.ndarray:
        """The nominal values of the entries this writer changes, ``(elements, width)``."""

    def _check_add(self, nominal: np.ndarray, task_id: str) -> None:
        """``add`` must keep the field valid from its smallest nominal value."""
        field = self.term.field
        if field not in POSITIVE or self.term.operation != "add":
            return
        low = value_bounds(self.term)[0] + float(np.min(nominal))
        if (POSITIVE[field] and low <= 0) or low < 0:
            raise CannotApply(
                f"{task_id}: {self.term.label} add range {self.term.range} takes the smallest nominal "
                f"{float(np.min(nominal)):.4g} to {low:.4g}; {field} must stay "
                f"{'above 0' if POSITIVE[field] else 'at least 0'}"
            )

    def values(self, values: np.ndarray) -> np.ndarray:
        """The new values of every element, ``(elements, width)``, from a draw."""
        return combine(self.term.operation, self.nominal, values)

    @abc.abstractmethod
    def write(self, model, values: np.ndarray, geometry: Geometry) -> None:
        """Write ``values`` (from :meth:`values`) into ``model``; note in ``geometry`` what
        the change leaves to derive."""


def _has(entity: Resolved) -> str:
    parts = [p for p, ids in entity.ids.items() if len(ids)]
    return f"it has {', '.join(parts)}" if parts else "it matches nothing in this model"


class BodyMass(FieldWriter):
    needs_const = True

    def _capture(self, model) -> np.ndarray:
        return model.body_mass[self.ids].copy()[:, None]

    def write(self, model, values, geometry) -> None:
        geometry.set_mass(model, self.ids, self.values(values)[:, 0])


class GeomSize(FieldWriter):
    """Every axis of each geom's size by one value; the base is the geom's current
    shape's size (its nominal one unless a ``shape`` term changed it)."""

    needs_const = True

    def _capture(self, model) -> np.ndarray:
        bad = [n for n, g in zip(self.elements, self.ids) if int(model.geom_type[g]) not in PRIMITIVES]
        if bad:
            raise CannotApply(
                f"{self.term.label}: geom {bad[0]!r} is a mesh or plane, whose size is fixed when the "
                "model is compiled; size applies to primitive geoms (box, cylinder, sphere, capsule, ellipsoid)"
            )
        used = [model.geom_size[g, : PRIMITIVES[int(model.geom_type[g])]] for g in self.ids]
        return np.array([[float(np.min(u))] for u in used])  # the smallest half-size, for the add check

    def write(self, model, values, geometry) -> None:
        drawn = values[:, 0].tolist()
        geometry.set_size(model, self.ids, self.term.operation, drawn * len(self.ids) if len(drawn) == 1 else drawn)


class GeomShape(FieldWriter):
    needs_const = True

    def __init__(self, term, entity, model, task_id) -> None:
        super().__init__(term, entity, model, task_id)
        if not entity.solid:
            raise CannotApply(
                f"{task_id}: entity {entity.name!r} is not a primitive solid the family lets change shape "
                "(a mesh or a body of several parts); shape applies to the objects families mark as solid"
            )
        barred = [s for s in term.shapes if s not in entity.shapes]
        if barred:
            raise CannotApply(
                f"{task_id}: entity {entity.name!r} cannot become a {barred[0]}; it takes {', '.join(entity.shapes)}"
            )

    def _capture(self, model) -> np.ndarray:
        bad = [n for n, g in zip(self.elements, self.ids) if int(model.geom_type[g]) not in PRIMITIVES]
        if bad:
            raise CannotApply(f"{self.term.label}: geom {bad[0]!r} is a mesh, whose shape is fixed when compiled")
        return np.zeros((1, 1))

    @property
    def count(self) -> int:
        return 1

    def write(self, model, values, geometry) -> None:
        geometry.set_shape(model, self.ids, self.term.shapes[int(values[0, 0])])


class GeomFriction(FieldWriter):
    def _capture(self, model) -> np.ndarray:
        return model.geom_friction[self.ids, :1].copy()

    def write(self, model, values, geometry) -> None:
        model.geom_friction[self.ids, 0] = np.maximum(self.values(values)[:, 0], 0.0)


class JointDofs(FieldWriter):
    """``damping`` / ``armature``: one value per joint, on each of its dofs."""

    def __init__(self, term, entity, model, task_id) -> None:
        self._array = "dof_damping" if term.field == "damping" else "dof_armature"
        self.needs_const = term.field == "armature"
        super().__init__(term, entity, model, task_id)

    def _capture(self, model) -> np.ndarray:
        self._dofs, self._rows = _joint_dofs(model, self.ids)
        return getattr(model, self._array)[self._dofs].copy()[:, None]

    def values(self, values: np.ndarray) -> np.ndarray:
        per_dof = values if len(values) == 1 else values[self._rows]
        return combine(self.term.operation, self.nominal, per_dof)

    def write(self, model, values, geometry) -> None:
        getattr(model, self._array)[self._dofs] = np.maximum(self.values(values)[:, 0], 0.0)


class ActuatorGain(FieldWriter):
    """The gain ``kp``; on a position servo (affine bias ``-kp q``) the bias follows."""

    def _capture(self, model) -> np.ndarray:
        gain = model.actuator_gainprm[self.ids, 0].copy()
        self._servo = (model.actuator_biastype[self.ids] == _AFFINE) & (model.actuator_biasprm[self.ids, 1] == -gain)
        return gain[:, None]

    def write(self, model, values, geometry) -> None:
        kp = self.values(values)[:, 0]
        model.actuator_gainprm[self.ids, 0] = kp
        servo = self.ids[self._servo]
        model.actuator_biasprm[servo, 1] = -kp[self._servo]


class Rgba(FieldWriter):
    """Red, green, blue of each geom's material where it shows one, else of the geom."""

    def _capture(self, model) -> np.ndarray:
        targets: list[tuple[str, int]] = []
        for g in self.ids:
            mat = int(model.geom_matid[g])
            target = ("mat", mat) if mat >= 0 and tuple(model.geom_rgba[g]) == _DEFAULT_RGBA else ("geom", int(g))
            if target not in targets:
                targets.append(target)
        self._mats = np.array([i for kind, i in targets if kind == "mat"], dtype=np.int64)
        self._geoms = np.array([i for kind, i in targets if kind == "geom"], dtype=np.int64)
        self.elements = [f"{kind}{i}" for kind, i in targets]
        return np.concatenate((model.mat_rgba[self._mats, :3], model.geom_rgba[self._geoms, :3]))

    def write(self, model, values, geometry) -> None:
        rgb = np.minimum(np.maximum(self.values(values), 0.0), 1.0)
        k = len(self._mats)
        model.mat_rgba[self._mats, :3] = rgb[:k]
        model.geom_rgba[self._geoms, :3] = rgb[k:]


class LightBrightness(FieldWriter):
    def _capture(self, model) -> np.ndarray:
        return model.light_diffuse[self.ids].copy()

    def write(self, model, values, geometry) -> None:
        model.light_diffuse[self.ids] = np.maximum(self.values(values), 0.0)


class CameraPose(FieldWriter):
    def _capture(self, model) -> np.ndarray:
        return model.cam_pos[self.ids].copy()

    def write(self, model, values, geometry) -> None:
        model.cam_pos[self.ids] = self.values(values)


WRITERS: dict[str, type[FieldWriter]] = {
    "mass": BodyMass,
    "size": GeomSize,
    "shape": GeomShape,
    "friction": GeomFriction,
    "damping": JointDofs,
    "armature": JointDofs,
    "actuator_gain": ActuatorGain,
    "rgba": Rgba,
    "light": LightBrightness,
    "camera_pose": CameraPose,
}
assert set(WRITERS) == set(FIELD_WIDTH)


def writer(term: RandomizationTerm, entity: Resolved, model, task_id: str) -> FieldWriter:
    """The term's writer on ``model``, checked against it (:class:`CannotApply`)."""
    w = WRITERS[term.field](term, entity, model, task_id)
    w._check_add(w.nominal, task_id)
    return w
