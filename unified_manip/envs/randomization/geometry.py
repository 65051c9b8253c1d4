"""What a change of mass, size or shape leaves to derive, done once per draw.

MuJoCo picks a contact's collision function by ``geom_type`` at run time, so a primitive
geom can change between box, cylinder and sphere by writing model fields, without
recompiling (a mesh cannot: its shape is fixed when compiled). What the compiler would
have derived is derived here from the nominal values captured when the env was made:

* each changed geom's bounding sphere (``geom_rbound``) and box (``geom_aabb``), and its
  body's bounding-volume hierarchy (``bvh_aabb``, a box around every geom of the body),
  so that the broad and mid phases still find the contacts of a larger geom;
* each changed body's inertia: a solid's from its shape, size and mass (a uniform
  density), any other body's nominal inertia times its mass ratio;
* a solid's rest height (:class:`~.entities.RestHeight`), so that the task places a
  resized solid on the table rather than inside it;
* MuJoCo's constants of ``qpos0`` (``mj_setConst``), after any change of mass or inertia.

A shape keeps the solid's height: from a box of half-sizes ``(a, b, c)``, a cylinder of
radius ``max(a, b)`` and half-height ``c``, a sphere of radius ``c``.
"""

from __future__ import annotations

from typing import Any, Sequence

import mujoco
import numpy as np

from unified_manip.envs.randomization.entities import Resolved

_SPHERE, _CAPSULE, _ELLIPSOID, _CYLINDER, _BOX = (
    int(mujoco.mjtGeom.mjGEOM_SPHERE),
    int(mujoco.mjtGeom.mjGEOM_CAPSULE),
    int(mujoco.mjtGeom.mjGEOM_ELLIPSOID),
    int(mujoco.mjtGeom.mjGEOM_CYLINDER),
    int(mujoco.mjtGeom.mjGEOM_BOX),
)
#: The primitive geom types, with how many of ``geom_size``'s axes each uses.
PRIMITIVES: dict[int, int] = {_SPHERE: 1, _CAPSULE: 2, _ELLIPSOID: 3, _CYLINDER: 2, _BOX: 3}
_TYPES = {"box": _BOX, "cylinder": _CYLINDER, "sphere": _SPHERE}


def _shaped(size: np.ndarray, gtype: int, shape: str) -> np.ndarray:
    """A ``shape``'s size of the same height and width as a primitive of ``size``."""
    half = _half_height(gtype, size)
    width = float(max(size[0], size[1])) if gtype in (_BOX, _ELLIPSOID) else float(size[0])
    if shape == "box":
        return np.array([width, width, half]) if gtype != _BOX else size.copy()
    if shape == "cylinder":
        return np.array([width, half, 0.0])
    return np.array([half, 0.0, 0.0])


def _half_height(gtype: int, size: np.ndarray) -> float:
    return float({_SPHERE: size[0], _CAPSULE: size[0] + size[1], _CYLINDER: size[1]}.get(gtype, size[2]))


def _bounds(gtype: int, s: np.ndarray) -> tuple[float, np.ndarray]:
    """A primitive's bounding radius and local box half-sizes."""
    if gtype == _SPHERE:
        return float(s[0]), np.array([s[0], s[0], s[0]])
    if gtype == _CAPSULE:
        return float(s[0] + s[1]), np.array([s[0], s[0], s[0] + s[1]])
    if gtype == _CYLINDER:
        return float(np.hypot(s[0], s[1])), np.array([s[0], s[0], s[1]])
    if gtype == _ELLIPSOID:
        return float(max(s)), s[:3].copy()
    return float(np.linalg.norm(s)), s[:3].copy()


def _inertia(gtype: int, s: np.ndarray, mass: float) -> np.ndarray:
    """Principal inertia of a uniform primitive of ``mass``."""
    if gtype == _SPHERE:
        return np.full(3, 0.4 * mass * s[0] ** 2)
    if gtype == _CYLINDER:
        side = mass * (3 * s[0] ** 2 + 4 * s[1] ** 2) / 12
        return np.array([side, side, 0.5 * mass * s[0] ** 2])
    a, b, c = s[:3] ** 2
    return mass / 3 * np.array([b + c, a + c, a + b])


class Geometry:
    """The derived fields of one model, from its nominal values (see the module docs).

    Args:
        model: The compiled model, nominal.
        geoms: Every geom a size or shape term may change.
        bodies: Every body a mass term may change.
        solids: The solid entities (one body each, whose inertia follows its shape).
    """

    def __init__(self, model, geoms: Sequence[int], bodies: Sequence[int], solids: Sequence[Resolved]) -> None:
        self._type0 = {int(g): int(model.geom_type[g]) for g in geoms}
        self._size0 = {int(g): model.geom_size[g].copy() for g in geoms}
        self._base = {g: s.copy() for g, s in self._size0.items()}
        self._rule: dict[int, tuple[str, float]] = {g: ("scale", 1.0) for g in self._size0}
        touched = set(int(b) for b in bodies) | {int(model.geom_bodyid[g]) for g in geoms}
        self._mass0 = {b: float(model.body_mass[b]) for b in touched}
        self._inertia0 = {b: model.body_inertia[b].copy() for b in touched}
        self._solid: dict[int, tuple[int, Any, float, float]] = {}  # body -> (geom, rest, z0, half0)
        for s in solids:
            body = int(model.geom_bodyid[s.part("geoms")[0]]) if len(s.part("geoms")) else None
            if body is None:
                continue
            geom = next((int(g) for g in s.part("geoms") if model.geom_contype[g] or model.geom_conaffinity[g]), None)
            if geom is None or int(model.geom_type[geom]) not in PRIMITIVES:
                continue
            self._solid[body] = (geom, s.rest, 0.0, _half_height(int(model.geom_type[geom]), model.geom_size[geom]))
        self._dirty_geoms: set[int] = set()
        self._dirty_bodies: set[int] = set()
        # Each resizable body's geoms, and their centres' distances from its inertial
        # frame (neither is randomised), for its bounding-volume hierarchy.
        self._reach: dict[int, tuple[slice, np.ndarray]] = {}
        for b in {int(model.geom_bodyid[g]) for g in geoms}:
            first, count = int(model.body_geomadr[b]), int(model.body_geomnum[b])
            dist = [float(np.linalg.norm(model.geom_pos[g] - model.body_ipos[b])) for g in range(first, first + count)]
            self._reach[b] = (slice(first, first + count), np.array(dist))

    def capture_rest(self, backend) -> None:
        """Read the nominal rest heights of the solids (once, when the env is made)."""
        for body, (geom, rest, _, half0) in self._solid.items():
            if rest is not None:
                self._solid[body] = (geom, rest, float(rest.get(backend)), half0)

    def set_mass(self, model, bodies: np.ndarray, masses: np.ndarray) -> None:
        model.body_mass[bodies] = masses
        self._dirty_bodies.update(int(b) for b in bodies)

    def set_size(self, model, geoms: np.ndarray, operation: str, values: Sequence[float]) -> None:
        for g, v in zip(geoms, values):
            self._rule[int(g)] = (operation, float(v))
            self._resize(model, int(g))

    def set_shape(self, model, geoms: np.ndarray, shape: str) -> None:
        for g in geoms:
            g = int(g)
            model.geom_type[g] = _TYPES[shape]
            self._base[g] = _shaped(self._size0[g], self._type0[g], shape)
            self._resize(model, g)

    def _resize(self, model, g: int) -> None:
        operation, value = self._rule[g]
        base, used = self._base[g], PRIMITIVES[int(model.geom_type[g])]
        size = base.copy()
        if operation == "scale":
            size[:used] = base[:used] * value
        elif operation == "add":
            size[:used] = base[:used] + value
        else:
            size[:used] = value
        model.geom_size[g] = size
        self._dirty_geoms.add(g)

    def commit(self, model, backend) -> None:
        """Derive what the writes since the last commit changed (see the module docs)."""
        if not self._dirty_geoms and not self._dirty_bodies:
            return
        resized = {int(model.geom_bodyid[g]) for g in self._dirty_geoms}
        for g in self._dirty_geoms:
            rbound, half = _bounds(int(model.geom_type[g]), model.geom_size[g])
            model.geom_rbound[g] = rbound
            model.geom_aabb[g, 3:] = half
        for b in resized:
            self._bvh(model, b)
        for b in self._dirty_bodies | resized:
            solid = self._solid.get(b)
            if solid is not None:
                geom = solid[0]
                model.body_inertia[b] = _inertia(int(model.geom_type[geom]), model.geom_size[geom], model.body_mass[b])
                if solid[1] is not None:
                    height = _half_height(int(model.geom_type[geom]), model.geom_size[geom])
                    solid[1].set(backend, solid[2] + height - solid[3])
            elif self._mass0[b] > 0:
                model.body_inertia[b] = self._inertia0[b] * (model.body_mass[b] / self._mass0[b])
        self._dirty_geoms.clear()
        self._dirty_bodies.clear()

    def _bvh(self, model, body: int) -> None:
        """Every node of the body's hierarchy: a box around all its geoms, in its inertial frame."""
        n = int(model.body_bvhnum[body])
        if n == 0:
            return
        geoms, dist = self._reach[body]
        reach = float(np.max(dist + model.geom_rbound[geoms]))
        adr = int(model.body_bvhadr[body])
        model.bvh_aabb[adr : adr + n, :3] = 0.0
        model.bvh_aabb[adr : adr + n, 3:] = reach
