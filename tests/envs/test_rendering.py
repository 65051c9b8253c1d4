"""The shared renderer: per-family scene options, robosuite without its collision geoms."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import unified_manip  # noqa: F401  (registers the IDs)
from unified_manip.envs.rendering import Renderer, SceneOptions


def _collision_green(frame: np.ndarray) -> int:
    """Pixels of robosuite's collision colour: its collision geoms are flat green
    (rgba 0, 0.5, 0), shaded by the lights. No visual geom of the Lift scene is green."""
    f = frame.astype(int)
    r, g, b = f[..., 0], f[..., 1], f[..., 2]
    return int(((g > 1.5 * r + 20) & (g > 1.5 * b + 20)).sum())


@pytest.mark.robosuite
def test_robosuite_frames_hide_the_collision_geoms():
    env = gym.make(
        "UnifiedManip/Lift-v0",
        render_mode="rgb_array",
        render_width=160,
        render_height=160,
        observation=["default", "rgb"],
        image_size=96,
    )
    obs, _ = env.reset(seed=0)
    backend = env.unwrapped._backend
    # The same scene with every geom group drawn: the check sees the collision geoms.
    with_collision = Renderer("rgb_array", 160, 160, SceneOptions(camera="frontview"))
    assert _collision_green(with_collision.render(backend.model, backend.data)) > 200
    with_collision.close()
    frame = env.render()
    assert frame.shape == (160, 160, 3) and frame.std() > 5.0
    assert _collision_green(frame) == 0
    assert _collision_green(obs["rgb"]) == 0  # the camera observation too
    env.close()


def test_renderers_of_two_envs_take_turns():
    """Each frame comes from its own GL context, however renders interleave."""
    a = gym.make("UnifiedManip/Arm4Reach-v0", render_mode="rgb_array", render_width=64, render_height=48)
    b = gym.make("UnifiedManip/FetchReach-v0", render_mode="rgb_array", render_width=80, render_height=60)
    a.reset(seed=0)
    b.reset(seed=0)
    first = a.render()
    assert b.render().shape == (60, 80, 3)
    np.testing.assert_array_equal(a.render(), first)
    a.close()
    b.close()


def test_scene_options_are_validated():
    with pytest.raises(ValueError) as err:
        SceneOptions(hidden_geom_groups=(6,))
    assert str(err.value) == "hidden_geom_groups must be in 0..5, got [6]"
    with pytest.raises(ValueError) as err:
        SceneOptions(camera="front", free_camera={"distance": 1.0})
    assert str(err.value) == "give camera (a named camera) or free_camera (the free camera's config), not both"


@pytest.mark.parametrize(
    "task_id",
    ["UnifiedManip/Arm4Reach-v0", "UnifiedManip/Lift-v0", "UnifiedManip/FetchReach-v0", "UnifiedManip/HandReach-v0"],
)
def test_an_env_that_rendered_and_was_never_closed_exits_quietly(task_id):
    import subprocess
    import sys

    code = (
        "import gymnasium as gym, unified_manip\n"
        f"env = gym.make({task_id!r}, render_mode='rgb_array', render_width=64, render_height=64)\n"
        "env.reset(seed=0)\n"
        "print(env.render().shape)"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert (proc.returncode, proc.stdout, proc.stderr) == (0, "(64, 64, 3)\n", "")
