"""``camera_meshes="decimated"``: observation cameras drawing simplified meshes, cached on
disk, while the physics and ``render()`` stay the full env's."""

from __future__ import annotations

import sys

import gymnasium as gym
import numpy as np
import pytest

from unified_manip.envs import mesh_lod
from unified_manip.envs.config import EnvConfig
from unified_manip.extras import MissingExtra

#: Fetch: 18 meshes, about 34k faces, and no extra beyond the base install.
TASK = "UnifiedManip/FetchPickAndPlace-v0"


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv(mesh_lod.CACHE_ENV, str(tmp_path))
    return tmp_path / "meshes"


def test_decimated_frames_are_close_the_physics_and_render_unchanged(cache):
    kwargs = dict(observation=["default", "rgb"], image_size=48, render_mode="rgb_array", render_width=48)
    full = gym.make(TASK, **kwargs, render_height=48)
    lod = gym.make(TASK, **kwargs, render_height=48, camera_meshes="decimated")
    a, _ = full.reset(seed=0)
    b, _ = lod.reset(seed=0)
    for key in ("observation", "achieved_goal", "desired_goal"):
        np.testing.assert_array_equal(a[key], b[key])
    change = np.abs(a["rgb"].astype(int) - b["rgb"])
    # The cheap meshes change a few pixels a little: measured mean 2.6/255 at 84 px.
    assert 0.0 < change.mean() < 6.0, change.mean()
    np.testing.assert_array_equal(full.render(), lod.render())  # render() keeps the full meshes
    model = lod.unwrapped.backend.model
    before = {name: getattr(model, name).copy() for name in mesh_lod.MESH_FIELDS}
    with mesh_lod.decimated_meshes(model):
        assert model.mesh_facenum.sum() < 0.2 * before["mesh_facenum"].sum()
    for name, values in before.items():  # restored bit for bit
        np.testing.assert_array_equal(getattr(model, name), values)
    full.close()
    lod.close()


def _sphere(n: int = 24) -> tuple[np.ndarray, np.ndarray]:
    """A UV sphere of about 2 n^2 faces."""
    theta, phi = np.meshgrid(np.linspace(0.1, np.pi - 0.1, n), np.linspace(0, 2 * np.pi, n, endpoint=False))
    vert = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], -1).reshape(-1, 3)
    i = np.arange(n - 1)[None, :] + n * np.arange(n)[:, None]  # (phi, theta) grid index
    j = (i + n) % (n * n)
    face = np.concatenate([np.stack([i, j, i + 1], -1), np.stack([j, j + 1, i + 1], -1)]).reshape(-1, 3)
    return vert.astype(np.float32), face.astype(np.int32)


def test_simplified_meshes_are_cached_and_reused(cache):
    vert, face = _sphere()
    first = mesh_lod.cached_mesh(vert, face, vert, None, 0.9)
    assert len(first["face"]) < 0.2 * len(face)
    files = list(cache.iterdir())
    assert [f.suffix for f in files] == [".npz"]  # one mesh, no temporary file left
    # The second call reads the file: an edit to the stored vertices comes back.
    stored = dict(np.load(files[0]))
    stored["vert"] = stored["vert"] + 1.0
    np.savez(files[0], **stored)
    again = mesh_lod.cached_mesh(vert, face, vert, None, 0.9)
    np.testing.assert_array_equal(again["vert"], first["vert"] + 1.0)
    # Another reduction is another entry.
    mesh_lod.cached_mesh(vert, face, vert, None, 0.5)
    assert len(list(cache.iterdir())) == 2


def test_camera_meshes_is_validated_and_names_its_extra(monkeypatch):
    with pytest.raises(ValueError) as err:
        EnvConfig(camera_meshes="fast")
    assert str(err.value) == "unknown camera_meshes 'fast'; expected one of 'full', 'decimated'"
    monkeypatch.setitem(sys.modules, "fast_simplification", None)  # not installed, to Python
    with pytest.raises(MissingExtra) as err:
        gym.make(TASK, observation=["default", "rgb"], camera_meshes="decimated")
    assert str(err.value) == (
        "camera_meshes='decimated' needs the fast-camera extra: "
        'pip install "unified_manip[fast-camera]" (missing: fast_simplification)'
    )
    gym.make(TASK, camera_meshes="decimated").close()  # no camera: nothing to simplify
