"""Decimated visual meshes for observation cameras (``camera_meshes="decimated"``).

Software rendering (EGL on llvmpipe) spends a small frame on vertex work: robosuite's Lift
draws about 182k mesh faces for an 84 px image. :func:`decimated_meshes` simplifies a
compiled ``MjModel``'s large meshes in place, to about 5% of their faces
(`fast-simplification <https://github.com/pyvista/fast-simplification>`_, an optional
dependency: the ``fast-camera`` extra), for as long as an observation camera's GL context
is built (it uploads the meshes then), and restores them bit for bit: the physics, the
poses and any randomised colours stay the env's, and ``render()`` keeps the full meshes.

Each simplified mesh is cached on disk (:func:`cache_dir`), keyed by a hash of its
compiled vertices, faces and texture-coordinate faces and the reduction, and written
atomically, so the cost (about a second for Lift) is paid once per machine.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import tempfile
from pathlib import Path
from typing import Any, Iterator

import numpy as np

from unified_manip.extras import require

#: The fraction of a mesh's faces removed (``target_reduction`` of fast-simplification).
REDUCTION = 0.95
#: Meshes with fewer faces are kept whole: they cost little and lose shape first.
MIN_FACES = 200
#: Bumped when the cached arrays change meaning.
CACHE_VERSION = 1
#: Environment variable naming the cache folder (its ``meshes/`` subfolder is used).
CACHE_ENV = "UNIFIED_MANIP_CACHE"


def cache_dir() -> Path:
    """Where simplified meshes are kept: ``$UNIFIED_MANIP_CACHE/meshes``, else the user's
    cache folder (platformdirs' ``user_cache_dir``, or ``~/.cache/unified_manip``)."""
    root = os.environ.get(CACHE_ENV)
    if root:
        return Path(root) / "meshes"
    try:
        from platformdirs import user_cache_dir
    except ImportError:
        return Path.home() / ".cache" / "unified_manip" / "meshes"
    return Path(user_cache_dir("unified_manip")) / "meshes"


def require_simplifier() -> None:
    """:class:`~unified_manip.extras.MissingExtra` in one line unless fast-simplification
    is installed (the ``fast-camera`` extra)."""
    require("fast-camera", what="camera_meshes='decimated'")


def _simplify(vert: np.ndarray, face: np.ndarray, reduction: float) -> tuple[np.ndarray, np.ndarray]:
    require_simplifier()
    import fast_simplification

    points, faces = fast_simplification.simplify(
        np.ascontiguousarray(vert, np.float32), np.ascontiguousarray(face, np.int32), reduction
    )
    return np.asarray(points, np.float32), np.asarray(faces, np.int32)


def _nearest(points: np.ndarray, to: np.ndarray, chunk: int = 256) -> np.ndarray:
    """Index in ``to`` of each point's nearest neighbour."""
    out = np.empty(len(points), np.int64)
    for start in range(0, len(points), chunk):
        d = ((points[start : start + chunk, None, :] - to[None, :, :]) ** 2).sum(-1)
        out[start : start + chunk] = d.argmin(1)
    return out


def simplified_mesh(
    vert: np.ndarray, face: np.ndarray, normal: np.ndarray, facetexcoord: np.ndarray | None, reduction: float
) -> dict[str, np.ndarray]:
    """One mesh with about ``1 - reduction`` of its faces.

    Args:
        vert, face: The mesh's vertices and faces (vertex indices).
        normal: A normal per vertex.
        facetexcoord: For a textured mesh, its faces' texture-coordinate indices, else None.
        reduction: The fraction of faces to remove.

    Returns:
        The new ``vert``, ``face`` and ``normal`` arrays and, for a textured mesh,
        ``facetexcoord``: each new vertex takes the normal and texture coordinate of its
        nearest old vertex (which keeps the model's creases; smoothing the new mesh's own
        normals changed more pixels).
    """
    new_vert, new_face = _simplify(vert, face, reduction)
    nearest = _nearest(new_vert, vert)
    out = {"vert": new_vert, "face": new_face, "normal": np.asarray(normal, np.float32)[nearest]}
    if facetexcoord is not None:
        texcoord_of = np.zeros(len(vert), np.int32)
        texcoord_of[face.ravel()] = facetexcoord.ravel()
        out["facetexcoord"] = texcoord_of[nearest][new_face]
    return out


def _key(arrays: tuple[np.ndarray | None, ...], reduction: float) -> str:
    h = hashlib.sha256(f"v{CACHE_VERSION} r{reduction!r}".encode())
    for array in (a if a is not None else np.empty(0, np.int32) for a in arrays):
        h.update(np.ascontiguousarray(array).tobytes())
        h.update(str(array.shape).encode())
    return h.hexdigest()[:32]


def cached_mesh(
    vert: np.ndarray, face: np.ndarray, normal: np.ndarray, facetexcoord: np.ndarray | None, reduction: float
) -> dict[str, np.ndarray]:
    """:func:`simplified_mesh`, read from :func:`cache_dir` when there, else computed and
    written there atomically (a temporary file renamed into place)."""
    folder = cache_dir()
    path = folder / f"{_key((vert, face, normal, facetexcoord), reduction)}.npz"
    if path.exists():
        with np.load(path) as stored:
            return {k: stored[k] for k in stored.files}
    mesh = simplified_mesh(vert, face, normal, facetexcoord, reduction)
    folder.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=folder, suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            np.savez(f, **mesh)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise
    return mesh


#: The model's arrays :func:`decimated_meshes` writes, and restores.
MESH_FIELDS: tuple[str, ...] = (
    "mesh_vert",
    "mesh_vertnum",
    "mesh_normal",
    "mesh_normalnum",
    "mesh_face",
    "mesh_facenormal",
    "mesh_facenum",
    "mesh_facetexcoord",
)


@contextlib.contextmanager
def decimated_meshes(model: Any, reduction: float = REDUCTION) -> Iterator[Any]:
    """``model`` with its meshes of :data:`MIN_FACES` faces or more simplified in place
    (fewer vertices, faces and normals within each mesh's own slots), for as long as the
    ``with`` block runs; :data:`MESH_FIELDS` are restored bit for bit after, even on an
    error.

    Build a GL context (``mujoco.Renderer``) inside the block: it uploads the meshes then,
    and keeps them. No physics step may run inside it.
    """
    saved = {name: getattr(model, name).copy() for name in MESH_FIELDS}
    try:
        _simplify_in_place(model, reduction)
        yield model
    finally:
        for name, values in saved.items():
            getattr(model, name)[...] = values


def _simplify_in_place(model: Any, reduction: float) -> None:
    for i in range(model.nmesh):
        n_face = int(model.mesh_facenum[i])
        if n_face < MIN_FACES:
            continue
        va, vn = int(model.mesh_vertadr[i]), int(model.mesh_vertnum[i])
        fa, na = int(model.mesh_faceadr[i]), int(model.mesh_normaladr[i])
        face = model.mesh_face[fa : fa + n_face].copy()
        textured = model.mesh_texcoordadr[i] >= 0
        facetexcoord = model.mesh_facetexcoord[fa : fa + n_face].copy() if textured else None
        vert = model.mesh_vert[va : va + vn].copy()
        normal = np.zeros_like(vert)  # one per vertex: the last face corner's wins
        normal[face.ravel()] = model.mesh_normal[na + model.mesh_facenormal[fa : fa + n_face].ravel()]
        mesh = cached_mesh(vert, face, normal, facetexcoord, reduction)
        nv, nf = len(mesh["vert"]), len(mesh["face"])
        if nf == 0 or nv > vn or nv > model.mesh_normalnum[i] or nf > n_face:
            continue  # nothing left, or no room in the mesh's slots: keep it whole
        model.mesh_vert[va : va + nv] = mesh["vert"]
        model.mesh_vertnum[i] = nv
        model.mesh_normal[na : na + nv] = mesh["normal"]
        model.mesh_normalnum[i] = nv
        model.mesh_face[fa : fa + nf] = mesh["face"]
        model.mesh_facenormal[fa : fa + nf] = mesh["face"]
        model.mesh_facenum[i] = nf
        if textured:
            model.mesh_facetexcoord[fa : fa + nf] = mesh["facetexcoord"]
