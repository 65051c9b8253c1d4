"""Image observations: the ``rgb`` and ``depth`` groups on every family, seeded frames,
the camera and size keywords and their errors, and the fast render settings."""

from __future__ import annotations

import os
import pickle
import subprocess
import sys

import gymnasium as gym
import numpy as np
import pytest

import unified_manip
from unified_manip.envs.cameras import FAST, FULL, ImageSensor, RenderSettings

#: One ID of each family, with a camera other than its default where it has one.
FAMILIES = (
    ("UnifiedManip/Arm4Push-v0", "wrist"),
    ("UnifiedManip/FetchPush-v0", "external_camera_0"),
    ("UnifiedManip/Lift-v0", None),
    ("UnifiedManip/HandReach-v0", None),
    ("UnifiedManip/FrankaKitchen-v0", None),
)


@pytest.mark.parametrize("task_id,camera", FAMILIES)
def test_image_groups_add_rgb_and_depth_keys(task_id, camera):
    env = gym.make(task_id, observation=["default", "rgb", "depth"], camera=camera, image_size=48)
    state = gym.make(task_id)
    assert env.observation_space["rgb"] == gym.spaces.Box(0, 255, (48, 48, 3), np.uint8)
    assert env.observation_space["depth"] == gym.spaces.Box(0.0, np.inf, (48, 48, 1), np.float32)
    obs, _ = env.reset(seed=1)
    reference, _ = state.reset(seed=1)
    for key in ("observation", "achieved_goal", "desired_goal"):  # the state keys are the state env's
        np.testing.assert_array_equal(obs[key], reference[key])
    assert obs["rgb"].std() > 5.0  # a scene, not a blank frame
    # Depth in metres: the scenes are within a few metres of their cameras (the far plane
    # is the background); nothing is behind the camera.
    assert 0.0 < obs["depth"].min() < 3.0 and np.isfinite(obs["depth"]).all()
    obs, *_ = env.step(env.action_space.sample())
    assert env.observation_space.contains(obs)
    env.close()
    state.close()


def test_frames_are_seeded_and_survive_pickling():
    def rollout(env):
        frames = [env.reset(seed=3)[0]["rgb"]]
        env.action_space.seed(3)
        for _ in range(5):
            frames.append(env.step(env.action_space.sample())[0]["rgb"])
        return np.stack(frames)

    kwargs = dict(observation=["joint_pos", "rgb"], image_size=32, action_mode="ee_delta")
    a, b = gym.make("UnifiedManip/Arm4Reach-v0", **kwargs), gym.make("UnifiedManip/Arm4Reach-v0", **kwargs)
    first = rollout(a)
    np.testing.assert_array_equal(first, rollout(b))
    assert not np.array_equal(first[0], first[-1])  # the arm moved in the frames
    clone = pickle.loads(pickle.dumps(a))
    action = a.action_space.sample()
    np.testing.assert_array_equal(a.step(action)[0]["rgb"], clone.step(action)[0]["rgb"])
    for env in (a, b, clone):
        env.close()


def test_the_state_only_design_renders_nothing():
    env = gym.make("UnifiedManip/Arm4Reach-v0")
    assert set(env.observation_space) == {"observation", "achieved_goal", "desired_goal"}
    assert env.unwrapped._images is None


@pytest.mark.parametrize(
    "kwargs,error,message",
    [
        (
            {"observation": ["default", "rgb"], "camera": "wrist_cam"},
            ValueError,
            "unknown camera 'wrist_cam' for UnifiedManip/FetchReach-v0; expected one of 'front', "
            "'head_camera_rgb', 'gripper_camera_rgb', 'external_camera_0'",
        ),
        ({"observation": ["default", "rgb"], "image_size": 0}, ValueError, "image_size must be a positive int"),
        ({"observation": ["default", "depth"], "image_size": -84}, ValueError, "image_size must be a positive int"),
        ({"observation": ["default", "rgb"], "image_size": 8.5}, ValueError, "image_size must be a positive int"),
        ({"observation": ["rgb", "depth"]}, ValueError, "has only image groups; add a preset"),
        ({"camera": 3}, TypeError, "camera must be a camera's name or None, got 3"),
    ],
)
def test_bad_image_options_are_refused(kwargs, error, message):
    with pytest.raises(error) as err:
        gym.make("UnifiedManip/FetchReach-v0", **kwargs)
    assert message in str(err.value) and "\n" not in str(err.value)


def test_no_renderer_is_one_clear_error():
    """GLFW without a display cannot start: the state env still works, the image one says why."""
    code = (
        "import gymnasium as gym, unified_manip\n"
        "gym.make('UnifiedManip/Arm4Reach-v0').reset(seed=0)\n"
        "try:\n"
        "    gym.make('UnifiedManip/Arm4Reach-v0', observation=['default', 'rgb'])\n"
        "except RuntimeError as err:\n"
        "    print(type(err).__name__, err)\n"
    )
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=300, env={**env, "MUJOCO_GL": "glfw"}
    )
    lines = proc.stdout.splitlines()
    assert proc.returncode == 0 and len(lines) == 1, proc.stderr
    assert lines[0].startswith("RendererUnavailable image observations need an OpenGL renderer, and none could start")
    assert lines[0].endswith("set MUJOCO_GL=egl (or osmesa) on a machine that has it")


def test_every_family_names_its_cameras_and_the_free_views_match_upstream():
    from gymnasium_robotics.envs.fetch.fetch_env import DEFAULT_CAMERA_CONFIG as FETCH
    from gymnasium_robotics.envs.shadow_dexterous_hand.hand_env import DEFAULT_CAMERA_CONFIG as HAND

    from unified_manip.envs.tasks.fetch.cameras import FREE_CAMERA as FETCH_OURS
    from unified_manip.envs.tasks.shadow_hand.cameras import FREE_CAMERA as HAND_OURS

    assert all(spec.cameras for spec in unified_manip.TASKS.values())
    for ours, upstream in ((FETCH_OURS, FETCH), (HAND_OURS, HAND)):
        assert set(ours) == set(upstream)
        for key, value in upstream.items():
            np.testing.assert_array_equal(ours[key], value)


def test_render_settings_are_validated():
    with pytest.raises(ValueError) as err:
        RenderSettings(multisamples=-1)
    assert str(err.value) == "multisamples must be an int >= 0 or None, got -1"


def test_fast_settings_differ_from_the_full_look_only_in_rendering():
    """The same state drawn with the fast and the full settings: frames differ (shadows,
    antialiasing), and the full settings give render()'s look at the same camera."""
    env = gym.make("UnifiedManip/Arm4Push-v0", render_mode="rgb_array", render_width=64, render_height=64)
    env.reset(seed=0)
    backend = env.unwrapped.backend
    camera = env.unwrapped.task.cameras["front"]
    assert camera.settings == FAST
    fast = ImageSensor(("rgb",), camera, 64)
    full = ImageSensor(("rgb",), type(camera)(camera.scene, FULL), 64)
    a = fast.read(backend.model, backend.data)["rgb"]
    b = full.read(backend.model, backend.data)["rgb"]
    assert np.abs(a.astype(int) - b).mean() > 1.0
    people = env.render()
    assert np.abs(people.astype(int) - b).mean() < np.abs(people.astype(int) - a).mean()
    fast.close()
    full.close()
    env.close()


@pytest.mark.parametrize("task_id", ["UnifiedManip/Arm4Reach-v0", "UnifiedManip/FetchReach-v0"])
def test_the_vector_env_serves_the_single_envs_frames(task_id):
    """Bit for bit, across episode ends (SAME_STEP puts the final frames in the info)."""
    from gymnasium.vector import AutoresetMode
    from test_vector import assert_same, pair

    from unified_manip.envs.vector.env import NativeVectorEnv

    kwargs = dict(observation=["joint_pos", "rgb", "depth"], image_size=20, max_episode_steps=3)
    native, reference = pair(task_id, 3, AutoresetMode.SAME_STEP, **kwargs)
    assert isinstance(native, NativeVectorEnv)
    assert native.single_observation_space == reference.single_observation_space
    rng = np.random.default_rng(0)
    assert_same(native.reset(seed=5), reference.reset(seed=5))
    for k in range(7):
        actions = rng.uniform(-1, 1, native.action_space.shape).astype(np.float32)
        out = native.step(actions)
        assert_same(out, reference.step(actions), f"step {k}")
    assert out[0]["rgb"].shape == (3, 20, 20, 3)
    native.close()
    reference.close()


@pytest.mark.robosuite
@pytest.mark.parametrize("camera,drawn,hidden", [("agentview", 1, 0), ("agentview_collision", 0, 1)])
def test_robosuite_cameras_draw_visual_meshes_or_collision_geoms(camera, drawn, hidden):
    """``agentview`` draws robosuite's visual geoms (group 1); ``agentview_collision`` the
    same view with the collision geoms (group 0) instead, for speed. (Group 2 holds a few
    markers both draw.)"""
    import mujoco

    env = gym.make("UnifiedManip/Lift-v0", observation=["default", "rgb"], camera=camera, image_size=48)
    obs, _ = env.reset(seed=0)
    assert obs["rgb"].shape == (48, 48, 3) and obs["rgb"].dtype == np.uint8
    model = env.unwrapped.backend.model
    scene = env.unwrapped._images._renderer.scene  # the scene of the frame just drawn
    geoms = [scene.geoms[i] for i in range(scene.ngeom)]
    groups = {int(model.geom_group[g.objid]) for g in geoms if g.objtype == mujoco.mjtObj.mjOBJ_GEOM}
    env.close()
    assert drawn in groups and hidden not in groups, groups
