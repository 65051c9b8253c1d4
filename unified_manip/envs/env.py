"""The one concrete env class: a goal-conditioned Gymnasium env over any backend."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from gymnasium import spaces
from gymnasium_robotics.core import GoalEnv

from unified_manip.envs.cameras import image_sensor, observation_box
from unified_manip.envs.controllers.actions import checked_actions, squared_norm
from unified_manip.envs.observations import build_stream, reattach
from unified_manip.envs.randomization.randomizer import Randomizer, build_randomizer
from unified_manip.envs.registry import get_task
from unified_manip.envs.rewards import info_arrays
from unified_manip.envs.setup import env_setup
from unified_manip.envs.termsets import ACTION_SQ


class UnifiedManipEnv(GoalEnv):
    """A task from any family behind one goal-conditioned interface.

    Build it with ``gym.make("UnifiedManip/<Task>-v0", **kwargs)``; the task's own
    documentation is in ``env.unwrapped.task.doc`` (and ``unified-manip list --doc``).

    Args:
        task_id: The registered ID (filled in by the registration).
        **kwargs: The other keyword arguments of ``gym.make``: the fields of
            :class:`unified_manip.envs.config.EnvConfig` (``action_mode``, ``reward_type``,
            ``observation``, ``randomization``, ... each documented there), and the
            family's own options (e.g. ``robot`` on robosuite tasks), validated by
            :func:`unified_manip.envs.setup.env_setup`.

    Observation:
        ``Dict(observation, achieved_goal, desired_goal)``, all float32 ``Box``, plus
        ``rgb`` (uint8 H x W x 3) and ``depth`` (float32 metres, H x W x 1) when the
        observation design names those image groups.

    Info (at reset and on every step):
        ``is_success`` (1.0 / 0.0), the task's reward inputs (its term set's
        ``info_keys``, ``action_sq`` among them), ``sim_unstable``, plus
        ``reward_terms`` on steps and the action mode's diagnostics (``ik_residual``
        in metres and ``ik_limit_active`` under ``ee_delta``). Under a randomisation
        other than ``none``, ``randomization``: the values in force, at reset and on the
        steps where an ``interval`` term drew.
    """

    metadata = {"render_modes": ["rgb_array", "human"], "render_fps": 25}

    def __init__(self, task_id: str, **kwargs: Any) -> None:
        setup = env_setup(task_id, **kwargs)  # a bad option fails here, before the simulator loads
        self.task = setup.task
        self.config = setup.config
        render_mode = self.config.render_mode
        self.render_mode = render_mode
        self.metadata = {**self.metadata, "render_fps": self.task.render_fps}
        self._terms = self.task.terms
        self.reward_spec = self.config.reward_design(self._terms)
        self._terminations = self._terms.check_terminations(self.config.terminate_on, self.task.id)
        self._threshold = self.task.distance_threshold
        self._backend = setup.build_backend()
        self._randomizer: Randomizer | None = build_randomizer(
            self.config.randomization, self.task.entities, self._backend, self.task.id
        )

        # Size the spaces from one reset of the backend with a throwaway generator.
        self._backend.reset(np.random.default_rng(0))
        self._stream = build_stream(self.config, self._backend, self.task.id)
        self._images = image_sensor(self.config, self.task.cameras, self.task.id)
        obs = self._read()
        obs["observation"] = self._stream.start(obs["observation"], np.random.default_rng(0))
        n = self._backend.action_dim
        self.action_space = spaces.Box(-1.0, 1.0, shape=(n,), dtype=np.float32)
        self.observation_space = spaces.Dict({key: observation_box(key, v) for key, v in obs.items()})
        self._action_shape = (n,)
        layout = getattr(self._backend, "action_layout", "")  # e.g. "2 × (3 + 1)": two arms
        self._action_rule = (
            f"action must have shape {(n,)}{f' ({layout})' if layout else ''} for {self.task.id} "
            f"with action_mode={self.config.action_mode!r}"
        )
        self._last_obs = obs
        self._before: dict[str, float] = {}

    # ------------------------------------------------------------------ Gymnasium API
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed, options=options)
        drawn = None
        if self._randomizer is not None:  # model fields first: the backend's reset places the state in them
            drawn = self._randomizer.reset(self._backend, self.np_random, seeded=seed is not None)
        self._backend.reset(self.np_random)
        obs = self._read()
        obs["observation"] = self._stream.start(obs["observation"], self.np_random)
        self._last_obs = obs
        quantities = self._quantities(unstable=False)
        self._before = quantities
        info = {
            "is_success": self._success(obs),
            **quantities,
            **self._terms.events_at_rest(),
            ACTION_SQ: 0.0,
            "sim_unstable": False,
            **self._backend.extra_info(),
        }
        if drawn is not None:
            info["randomization"] = drawn
        if self.render_mode == "human":
            self.render()
        return obs, info

    def step(self, action):
        action = self._validate_action(action)
        drawn = None if self._randomizer is None else self._randomizer.step(self._backend, self.np_random)
        diagnostics = self._backend.step(action)
        unstable = self._backend.unstable()
        obs = None if unstable else self._read()
        # MuJoCo flags (and resets) a diverged state at the start of its next substep, so
        # the last substep of a step can leave one without a warning: a non-finite
        # observation (it holds the state the goals are read from) is a divergence too.
        if obs is not None and not math.isfinite(obs["observation"].sum()):
            unstable = True
        if unstable:  # a diverged simulator has no meaningful state: keep the last finite observation
            obs = {k: v.copy() for k, v in self._last_obs.items()}
        else:
            obs["observation"] = self._stream.advance(obs["observation"], self.np_random)
        self._last_obs = obs
        quantities = self._quantities(unstable)
        events = self._terms.events_between(self._before, quantities)
        info = {
            **quantities,
            **{k: float(v) for k, v in events.items()},
            ACTION_SQ: squared_norm(action),
            "sim_unstable": unstable,
            **diagnostics,
            **self._backend.extra_info(),
        }
        self._before = quantities
        # Same dtype path as compute_reward, so the two agree bit for bit.
        distance = self.task.goal_distance(
            obs["achieved_goal"].astype(np.float64), obs["desired_goal"].astype(np.float64)
        )
        success = float(distance < self._threshold)
        terms = self.reward_spec.terms_batch(distance, success, info)  # reads the term set's info_keys
        reward_terms = {k: float(v) for k, v in terms.items()}
        reward = float(sum(terms.values()))
        info["is_success"] = success
        info["reward_terms"] = reward_terms
        if drawn is not None:
            info["randomization"] = drawn
        terminated = bool(self.config.terminate_on_success and success > 0.5) or any(
            bool(t.fn(info)) for t in self._terminations
        )
        if self.render_mode == "human":
            self.render()
        return obs, reward, terminated, unstable, info

    def render(self):
        if self.render_mode is None:
            return None
        return self._backend.render()

    def close(self) -> None:
        self._backend.close()
        if self._images is not None:
            self._images.close()

    @property
    def observation_layout(self) -> dict[str, slice]:
        """Each group of the observation design (and ``distractors``), in order, with its
        slice of the ``observation`` vector."""
        return dict(self._stream.layout)

    @property
    def goal_dependent_layout(self) -> dict[str, slice]:
        """The groups of :attr:`observation_layout` that are ``desired_goal`` minus a state
        quantity (``goal_rel``): a replay buffer that relabels goals must move them too."""
        return dict(self._stream.goal_layout)

    def state_observation(self) -> dict[str, np.ndarray]:
        """The state now as the default design shows it, exact (no distractors, noise or
        delay), whatever this env's design: what the tasks' scripted policies read, so that
        demonstrations do not depend on the agent's observation design."""
        b = self._backend
        return {
            "observation": np.asarray(b.observation(), dtype=np.float32),
            "achieved_goal": np.asarray(b.achieved_goal(), dtype=np.float32),
            "desired_goal": np.asarray(b.desired_goal(), dtype=np.float32),
        }

    def randomization_state(self) -> dict[str, float]:
        """The randomised values in force, by ``info["randomization"]`` key (``entity.field``,
        with ``[element]`` for per-element draws and ``[k]`` for the channels of ``rgba`` and
        the axes of ``camera_pose``; a ``shape`` as its index in the term's shapes); empty
        under ``none``."""
        return {} if self._randomizer is None else self._randomizer.state()

    @property
    def randomizer(self) -> Randomizer | None:
        """The env's randomisation terms as they apply to its task (``terms``, and the
        preset terms left out, ``skipped``), or None under ``none``."""
        return self._randomizer

    @property
    def backend(self):
        """The simulator running this env (to read its state; the env steps it)."""
        return self._backend

    # ------------------------------------------------------------------ GoalEnv API
    def compute_reward(self, achieved_goal, desired_goal, info):
        """Reward for goals of shape ``(g,)`` or ``(B, g)``; equals ``step()``'s reward.

        ``info`` is one info dict, or a sequence / object array of ``B`` of them.
        """
        return self.reward_spec.total(*self._reward_inputs(achieved_goal, desired_goal, info))

    def compute_reward_terms(self, achieved_goal, desired_goal, info, raw: bool = False) -> dict[str, np.ndarray]:
        """The reward's terms for goals ``(g,)`` or ``(B, g)``, as ``compute_reward``:
        scaled (they add up to the reward, as ``info["reward_terms"]``) or, with
        ``raw=True``, before their scales."""
        inputs = self._reward_inputs(achieved_goal, desired_goal, info)
        return self.reward_spec.raw_batch(*inputs) if raw else self.reward_spec.terms_batch(*inputs)

    def compute_terminated(self, achieved_goal, desired_goal, info):
        """True on success when ``terminate_on_success`` is set, or where a switched-on
        termination holds (read from ``info``, as ``compute_reward`` reads it)."""
        distance = self.task.goal_distance(achieved_goal, desired_goal)
        ended = np.logical_and(self.config.terminate_on_success, distance < self._threshold)
        if self._terminations:
            ctx = info_arrays(info, np.shape(distance), self._terms.info_keys)
            for t in self._terminations:
                ended = np.logical_or(ended, t.fn(ctx))
        return ended

    def compute_truncated(self, achieved_goal, desired_goal, info):
        """Always False here: the time limit is applied by ``gym.make``'s TimeLimit."""
        return False

    # ------------------------------------------------------------------ pickling
    def __getstate__(self) -> dict[str, Any]:
        if self._randomizer is not None and not self._backend.pickles_model:
            raise TypeError(
                f"{self.task.id} cannot be pickled under randomization: its backend rebuilds a nominal "
                "model when unpickled; make a new env with the same arguments instead"
            )
        state = self.__dict__.copy()
        state["task"] = self.task.id  # specs hold factories; look them up again
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        state["task"] = get_task(state["task"])
        self.__dict__.update(state)
        reattach(self._stream, self._backend)

    # ------------------------------------------------------------------ helpers
    def _validate_action(self, action) -> np.ndarray:
        return checked_actions(action, self._action_shape, self._action_rule)

    def _read(self) -> dict[str, np.ndarray]:
        """The backend's observation dict now, ``observation`` being the design's groups
        before the sensor model (``ObservationStream.start`` / ``advance``)."""
        b = self._backend
        obs = {
            "observation": self._stream.raw(b),
            "achieved_goal": np.asarray(b.achieved_goal(), dtype=np.float32),
            "desired_goal": np.asarray(b.desired_goal(), dtype=np.float32),
        }
        obs.update(b.extra_observations())
        if self._images is not None:
            obs.update(self._images.read(b.model, b.data))
        return obs

    def _quantities(self, unstable: bool) -> dict[str, float]:
        """The term set's inputs now, from the backend's quantities; 0 after a divergence
        (a diverged simulator has no meaningful state)."""
        if unstable:
            return {k: 0.0 for k in self._terms.inputs}
        quantities = self._backend.quantities()
        return {k: float(quantities[k]) for k in self._terms.inputs}

    def _reward_inputs(self, achieved_goal, desired_goal, info):
        """``(distance, success, info arrays)`` for goals ``(g,)`` or ``(B, g)``, in float64
        as ``step()`` computes them, so the two agree bit for bit."""
        distance = self.task.goal_distance(
            np.asarray(achieved_goal, dtype=np.float64), np.asarray(desired_goal, dtype=np.float64)
        )
        success = (distance < self._threshold).astype(np.float64)
        return distance, success, info_arrays(info, np.shape(distance), self._terms.info_keys)

    def _success(self, obs: dict[str, np.ndarray]) -> float:
        d = self.task.goal_distance(obs["achieved_goal"], obs["desired_goal"])
        return float(d < self._threshold)
