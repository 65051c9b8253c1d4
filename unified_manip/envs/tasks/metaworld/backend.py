"""The Meta-World backend: upstream's env object (its model, its seeded reset, its
observation and its own success and reward) under ``native`` or, on an actuated copy of
its model (:mod:`.rig`), the joint and end-effector modes, with the goals of :mod:`.tasks`."""

from __future__ import annotations

from typing import Any, Mapping

import mujoco
import numpy as np

from unified_manip.envs.backend import Backend
from unified_manip.envs.config import EnvConfig
from unified_manip.envs.controllers import ControllerConfig
from unified_manip.envs.observations import ObservationGroup
from unified_manip.envs.physics import bad_state_warnings
from unified_manip.envs.rendering import Renderer
from unified_manip.envs.tasks.metaworld import observations as obs_
from unified_manip.envs.tasks.metaworld.cameras import SCENE
from unified_manip.envs.tasks.metaworld.rig import MetaWorldRig, actuated_model
from unified_manip.envs.tasks.metaworld.tasks import TASKS, MetaWorldTask
from unified_manip.envs.tasks.upstream import pickle_upstream, unpickle_upstream

#: Meta-World's observation of this step and its copy of the last step's (the frame stack).
CURR, PREV = slice(0, 18), slice(18, 36)

#: The robot's bodies: the ones whose name starts with these (Meta-World's Sawyer).
_ROBOT_PREFIXES = (
    "right_",
    "hand",
    "rightclaw",
    "leftclaw",
    "rightpad",
    "leftpad",
    "base",
    "pedestal",
    "head",
    "screen",
)


def make_upstream(env_name: str):
    """Meta-World's env of ``env_name`` as this family runs it: the goal shown (its
    multi-task benchmarks' ``partially_observable=False``), and every reset drawing a new
    object and target placement from the env's ``np_random`` (``seeded_rand_vec``)
    rather than a frozen one of a benchmark's 50 tasks."""
    import metaworld

    up = metaworld.ALL_V3_ENVIRONMENTS[env_name]()
    up._partially_observable = False
    del up.sawyer_observation_space  # a cached property of the observability
    up._freeze_rand_vec = False
    up.seeded_rand_vec = True
    up._set_task_called = True
    up.max_path_length = np.iinfo(np.int64).max  # the TimeLimit ends episodes, not a raise
    return up


class MetaWorldBackend(Backend):
    """One Meta-World task under ``native`` (Meta-World's mocap end-effector delta and
    gripper) or a joint mode (the actuated copy's servos, :mod:`.rig`).

    Args:
        config: The validated env config (``options`` must be empty).
        controller: The action mode's controller config.
        task: The task's Meta-World name, e.g. ``"door-open-v3"``.
        wrist_damping: The wrists' joint damping on the actuated copy, N m s/rad (None:
            the model's 10, version 0; :data:`.specs.WRIST_DAMPING`).
        joint_observation: Whether the joint modes' default observation appends the robot's
            joints (:data:`.observations.JOINT_MODE_EXTRA`; version 2 on,
            :data:`.specs.JOINT_OBSERVATION`).

    Attributes:
        upstream_obs: Meta-World's observation of the last step (39: hand, gripper,
            objects, the same of the step before, the goal), clipped as upstream clips it.
        site: Site ids by name (what :class:`~.tasks.Point` reads).
    """

    def __init__(
        self,
        config: EnvConfig,
        controller: ControllerConfig,
        task: str,
        wrist_damping: float | None = None,
        joint_observation: bool = False,
    ) -> None:
        if config.options:
            raise TypeError(f"Meta-World tasks take no extra options, got {sorted(config.options)}")
        up = make_upstream(task)
        up.mujoco_renderer = None  # we render with our own renderer (see render())
        self._up = up
        self.task_name = task
        self.task: MetaWorldTask = TASKS[task]
        self.model, self.data = up.model, up.data
        m = up.model
        self.site = {} if self.task.point.site is None else {self.task.point.site: m.site(self.task.point.site).id}
        self._fingers = (m.site("rightEndEffector").id, m.site("leftEndEffector").id)
        self._pads = (m.geom("leftpad_geom").id, m.geom("rightpad_geom").id)
        names = [m.body(i).name for i in range(m.nbody)]
        self._robot_bodies = np.array([n.startswith(_ROBOT_PREFIXES) for n in names])
        space = up.sawyer_observation_space
        self._low, self._high = space.low, space.high
        self.dt = up.dt
        self.action_dim = 4
        self._native = config.action_mode == "native"
        self._joint_obs = joint_observation and controller.space == "joint"
        if not self._native:  # the other modes run on the actuated copy (.rig)
            model = actuated_model(up.model_name, wrist_damping)
            self._upstream_pair = (up.model, up.data)  # where upstream's reset moves the hand
            self._joint_pair = (model, mujoco.MjData(model))
            self.rig = MetaWorldRig(*self._joint_pair, up.dt)
            self.control = controller.build(self.rig)
            self.action_dim = self.control.action_dim
            self._use(self._joint_pair)
        self._unstable = False
        self.native_success = 0.0
        self.native_reward = 0.0
        self.upstream_obs = np.zeros(39)
        self._renderer = Renderer(config.render_mode, config.render_width, config.render_height, SCENE)

    # -------------------------------------------------------------- episode
    def reset(self, np_random: np.random.Generator) -> None:
        """Upstream's reset, drawn from ``np_random``: ``mj_resetData``, then its
        ``reset_model`` (the hand brought to its start over 50 steps, one draw of the
        object and target placement from its ``_random_reset_space``). Upstream's own
        ``reset`` runs ``reset_model`` twice and keeps the second draw; one is enough."""
        up = self._up
        up._np_random = np_random
        if not self._native:
            self._use(self._upstream_pair)
        mujoco.mj_resetData(up.model, up.data)
        up.curr_path_length = 0
        obs = up.reset_model()
        if not self._native:
            self._to_joint_pair()
            obs = up._get_obs()
        obs[PREV] = obs[CURR]  # upstream's reset: the frame stack starts with two copies
        up._prev_obs = obs[CURR].copy()
        self.upstream_obs = np.clip(obs, self._low, self._high)
        self.native_success = 0.0
        self.native_reward = 0.0
        self._unstable = False

    def step(self, action: np.ndarray) -> dict[str, Any]:
        """Upstream's ``step``, without its path-length check, on the action as float32
        (upstream's action space's dtype, which its arithmetic then keeps)."""
        up = self._up
        action = action.astype(np.float32)
        before = bad_state_warnings(self.data)
        diagnostics = {}
        if self._native:
            up.set_xyz_action(action[:3])
            up.do_simulation([action[-1], -action[-1]], n_frames=up.frame_skip)
        else:
            diagnostics = self.control(action)
            mujoco.mj_step(self.model, self.data, nstep=up.frame_skip)
            mujoco.mj_rnePostConstraint(self.model, self.data)
            # Meta-World's reward reads its action's last entry as the grip effort (+1 closes).
            action = np.array([0.0, 0.0, 0.0, -action[-1]], dtype=np.float32)
        up.curr_path_length += 1
        for site in up._target_site_config:
            up._set_pos_site(*site)
        mujoco.mj_forward(self.model, self.data)
        self._unstable = bad_state_warnings(self.data) > before
        self.upstream_obs = np.clip(up._get_obs(), self._low, self._high)
        reward, info = up.evaluate_state(self.upstream_obs, action)
        self.native_reward, self.native_success = float(reward), float(info["success"])
        return diagnostics

    def _use(self, pair) -> None:
        """Point the backend and upstream's env at ``(model, data)``, upstream's live views
        into its data included (:func:`data_views`)."""
        up = self._up
        views = data_views(up)
        up.model, up.data = self.model, self.data = pair
        repoint(up, views)

    def _to_joint_pair(self) -> None:
        """After upstream's reset on its own model: the actuated copy takes its placements
        (the model fields its reset moves), state and finger controls; servos hold the pose."""
        (um, ud), (jm, jd) = self._upstream_pair, self._joint_pair
        for field in ("body_pos", "body_quat", "site_pos", "site_quat", "geom_pos", "geom_quat"):
            getattr(jm, field)[:] = getattr(um, field)
        mujoco.mj_resetData(jm, jd)
        jd.time = ud.time
        jd.qpos[:], jd.qvel[:], jd.mocap_pos[:], jd.mocap_quat[:] = ud.qpos, ud.qvel, ud.mocap_pos, ud.mocap_quat
        jd.ctrl[self.rig.gripper_ids] = ud.ctrl
        mujoco.mj_forward(jm, jd)
        self._use(self._joint_pair)
        self.rig.hold_rotation()
        self.control.reset()

    def unstable(self) -> bool:
        return self._unstable

    @property
    def upstream(self):
        """Meta-World's env object this backend steps (to read; the backend steps it)."""
        return self._up

    # -------------------------------------------------------------- readings
    def tcp(self) -> np.ndarray:
        """The point between the two fingertips (upstream's ``tcp_center``), m."""
        x = self.data.site_xpos
        return (x[self._fingers[0]] + x[self._fingers[1]]) / 2.0

    def pads_on_one_body(self) -> bool:
        return obs_.pads_touch_one_body(self.model, self.data, self._pads, self._robot_bodies)

    def observation_groups(self) -> Mapping[str, ObservationGroup]:
        return obs_.GROUPS

    def default_observation(self) -> tuple[str, ...]:
        return obs_.DEFAULT + obs_.JOINT_MODE_EXTRA if self._joint_obs else obs_.DEFAULT

    def observation(self) -> np.ndarray:
        obs = self.upstream_obs[: obs_.OBSERVATION_SIZE]
        if not self._joint_obs:
            return obs.copy()
        d, n = self.data, obs_.ROBOT_JOINTS
        return np.concatenate((obs, d.qpos[:n], d.qvel[:n]))

    def achieved_goal(self) -> np.ndarray:
        return self.task.point.read(self)

    def desired_goal(self) -> np.ndarray:
        return self.task.desired(self._up._target_pos)

    def quantities(self) -> dict[str, float]:
        return obs_.quantities(self)

    def extra_info(self) -> dict[str, Any]:
        """Meta-World's own ``success`` and reward of the last step (0 at reset)."""
        return {"native_success": self.native_success, "native_reward": self.native_reward}

    # -------------------------------------------------------------- rendering
    def render(self) -> np.ndarray | None:
        return self._renderer.render(self.model, self.data)

    def close(self) -> None:
        self._renderer.close()

    # -------------------------------------------------------------- pickling
    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        for key in ("model", "data"):
            del state[key]
        state["_up"] = pickle_upstream(self._up)
        state["_views"] = data_views(self._up)
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        up = state["_up"] = unpickle_upstream(state["_up"])
        views = state.pop("_views")
        self.__dict__.update(state)
        repoint(up, views)
        self.model, self.data = up.model, up.data


def repoint(up, views: list[tuple[str, str, int, tuple[int, ...]]]) -> None:
    """Make the attributes :func:`data_views` listed views into ``up.data`` again."""
    for attr, field, start, shape in views:
        flat = getattr(up.data, field).reshape(-1)
        setattr(up, attr, flat[start : start + int(np.prod(shape))].reshape(shape))


def data_views(up) -> list[tuple[str, str, int, tuple[int, ...]]]:
    """The attributes of ``up`` that are views into its ``MjData``'s arrays, as ``(attribute,
    field, first flat index, shape)``. Meta-World keeps some (``init_left_pad`` is
    ``get_body_com("leftpad")``, the pad's live position; basketball's ``_target_pos`` is a
    site's): its rewards read them as live, and pickling would freeze copies of them."""
    data = up.data
    fields = {name: getattr(data, name) for name in dir(data) if not name.startswith("_")}
    fields = {name: a for name, a in fields.items() if isinstance(a, np.ndarray) and a.size}
    views = []
    for attr, value in vars(up).items():
        if not isinstance(value, np.ndarray) or value.base is None:
            continue
        for field, array in fields.items():
            if np.shares_memory(value, array) and value.flags.c_contiguous:
                offset = value.__array_interface__["data"][0] - array.__array_interface__["data"][0]
                views.append((attr, field, offset // array.itemsize, value.shape))
                break
    return views
