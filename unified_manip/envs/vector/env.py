"""The native vector env: N envs of one task stepped in one call, Gymnasium 1.x semantics.

``gym.make_vec("UnifiedManip/<task>-v0", num_envs=N, ...)`` builds it where the task's
family has a :class:`~.batched.BatchedBackend`. Everything outside the family's
simulation is done here, over all N envs at once, with the single env's formulas in
the single env's order, so that env ``i`` reproduces ``gym.make``'s env bit for bit:
action validation and clipping, the ``sim_unstable`` handling, goal distance, success,
reward terms, ``terminated``, the time limit, and the info entries.
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

import numpy as np
from gymnasium import error, spaces
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from unified_manip.envs.cameras import observation_box
from unified_manip.envs.config import EnvConfig
from unified_manip.envs.controllers.actions import checked_actions, squared_norms
from unified_manip.envs.registry import get_task
from unified_manip.envs.rewards import info_arrays
from unified_manip.envs.termsets import ACTION_SQ
from unified_manip.envs.vector import infos as vinfo
from unified_manip.envs.vector.batched import BatchedBackend
from unified_manip.envs.vector.observation_rows import ObservationRows
from unified_manip.envs.vector.randomizer_rows import Drawn, RandomizerRows
from unified_manip.envs.vector.resets import env_seeds, reset_mask, step_resets


class NativeVectorEnv(VectorEnv):
    """N envs of one task under one action mode, as one Gymnasium ``VectorEnv``.

    Args:
        task_id: The registered ID.
        batched: The family's batched backend holding the N simulations.
        config: The validated env options (the same for every env).
        max_episode_steps: The time limit (``truncated``), or None for none.
        autoreset_mode: Gymnasium's ``AutoresetMode`` (default ``NEXT_STEP``, as
            ``SyncVectorEnv``); ``SAME_STEP`` puts ``final_obs`` / ``final_info`` in the
            info; ``DISABLED`` expects ``reset(options={"reset_mask": ...})``.

    Observation: the single env's ``Dict``, batched (float32 ``(N, ...)`` arrays).
    Info: a dict of ``(N,)`` arrays with ``_key`` masks, laid out as ``SyncVectorEnv``
    lays out the single env's info dicts (``is_success``, the reward inputs,
    ``sim_unstable``, the mode's diagnostics and ``reward_terms``).
    """

    metadata: dict[str, Any] = {"render_modes": ["rgb_array"], "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(
        self,
        task_id: str,
        batched: BatchedBackend,
        config: EnvConfig,
        max_episode_steps: int | None,
        autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
    ) -> None:
        self._task_id = get_task(task_id).id
        self.config = config
        self.num_envs = n = batched.num_envs
        self.autoreset_mode = AutoresetMode(autoreset_mode)
        self.metadata = {**self.metadata, "autoreset_mode": self.autoreset_mode, "render_fps": self.task.render_fps}
        self.render_mode = config.render_mode
        self._terms = terms = self.task.terms
        self.reward_spec = config.reward_design(terms)
        self._at_rest = tuple(k for k in terms.info_keys if k not in terms.inputs)
        self._terminations = terms.check_terminations(config.terminate_on, self._task_id)
        self._threshold = self.task.distance_threshold
        self._max_steps = max_episode_steps
        self._batched = batched
        self._rows = ObservationRows(config, self.task, batched, self._task_id)
        self._randomizers = RandomizerRows(config, self.task, batched, self._task_id)
        obs = self._rows.raw(batched.observations())
        obs["observation"] = self._rows.start_all(obs["observation"], np.random.default_rng(0))
        self.single_observation_space = spaces.Dict({key: observation_box(key, v[0]) for key, v in obs.items()})
        self.single_action_space = spaces.Box(-1.0, 1.0, shape=(batched.action_dim,), dtype=np.float32)
        self.observation_space = batch_space(self.single_observation_space, n)
        self.action_space = batch_space(self.single_action_space, n)
        self._action_shape = (n, batched.action_dim)
        self._action_rule = (
            f"actions must have shape {self._action_shape} (one row per env) for {self.task.id} with "
            f"num_envs={n}, action_mode={config.action_mode!r}"
        )
        self._rngs: list[np.random.Generator | None] = [None] * n
        self._last_obs = obs
        self._before = {k: np.zeros(n) for k in terms.inputs}
        self._elapsed = np.zeros(n, dtype=np.int64)
        self._autoreset = np.zeros(n, dtype=bool)
        self._needs_reset = True

    @property
    def task(self):
        """The task's :class:`~unified_manip.envs.registry.TaskSpec` (looked up by ID: specs
        hold factories, so the env pickles the ID)."""
        return get_task(self._task_id)

    # ------------------------------------------------------------------ Gymnasium API
    def reset(self, *, seed: int | Sequence[int | None] | None = None, options: dict | None = None):
        """Reset every env, or those in ``options["reset_mask"]``; env ``i`` is seeded
        with ``seed + i`` (an int), ``seed[i]`` (a list) or not at all (None)."""
        n = self.num_envs
        seeds = env_seeds(seed, n)
        mask = reset_mask(options, n)
        extra: dict[str, Any] = {}
        drawn: Drawn = {}
        for i in np.flatnonzero(mask):
            if seeds[i] is not None or self._rngs[i] is None:
                self._rngs[i], _ = seeding.np_random(seeds[i])
            extra = vinfo.gather(extra, self._reset_one(int(i), seeds[i] is not None, drawn), i, n)
        obs = self._fresh_obs(mask)
        quantities = self._inputs()
        info = vinfo.merge({}, vinfo.reset_info(self._success(obs), quantities, self._at_rest, extra), mask)
        info = self._randomizers.merge(info, drawn)
        for key, value in quantities.items():
            self._before[key][mask] = value[mask]
        self._elapsed[mask] = 0
        self._autoreset[mask] = False
        self._needs_reset = False
        return {k: v.copy() for k, v in obs.items()}, info

    def step(self, actions):
        if self._needs_reset:
            raise error.ResetNeeded("Cannot call step() before calling reset()")
        a = self._validate(actions)
        n = self.num_envs
        resetting = step_resets(self.autoreset_mode, self._autoreset)
        stepping = ~resetting
        drawn = self._randomizers.step(stepping, self._rng)
        diagnostics = self._batched.step(a, np.flatnonzero(stepping)) if stepping.any() else {}
        reset_extra: dict[str, np.ndarray] = {}
        reset_drawn: Drawn = {}
        for i in np.flatnonzero(resetting):
            reset_extra = vinfo.gather(reset_extra, self._reset_one(int(i), False, reset_drawn), i, n)
        obs = self._rows.raw(self._batched.observations())
        # MuJoCo flags (and resets) a diverged state only at the start of its next substep,
        # so a non-finite observation is a divergence too (as in the single env).
        unstable = (self._batched.unstable() | ~np.isfinite(obs["observation"].sum(axis=1))) & stepping
        self._sense(obs, np.flatnonzero(resetting), np.flatnonzero(stepping & ~unstable))
        # A diverged simulator has no meaningful state: keep the last finite observation.
        if unstable.any():
            for key, value in obs.items():
                value[unstable] = self._last_obs[key][unstable]
        quantities = self._inputs()
        # A diverged simulator's quantities read 0, as in the single env.
        stepped = {k: np.where(unstable, 0.0, v) for k, v in quantities.items()}
        ctx = {**stepped, **self._terms.events_between(self._before, stepped), ACTION_SQ: squared_norms(a)}
        # Same dtype path as compute_reward (and the single env), so they agree bit for bit.
        distance = self.task.goal_distance(
            obs["achieved_goal"].astype(np.float64), obs["desired_goal"].astype(np.float64)
        )
        success = (distance < self._threshold).astype(np.float64)
        terms = self.reward_spec.terms_batch(distance, success, ctx)
        reward = sum(terms.values(), np.zeros(n))  # term by term, in order, as the single env
        terminated = (success > 0.5) & self.config.terminate_on_success
        for termination in self._terminations:
            terminated |= termination.fn(ctx)
        self._elapsed[stepping] += 1
        truncated = unstable.copy()
        if self._max_steps is not None:
            truncated |= self._elapsed >= self._max_steps
        step_info = {**ctx, "sim_unstable": unstable, **diagnostics, "is_success": success, "reward_terms": terms}
        self._before = {k: np.where(resetting, quantities[k], stepped[k]) for k in quantities}
        self._elapsed[resetting] = 0  # the step after an episode's end reset it
        reward[resetting] = 0.0
        terminated &= stepping
        truncated &= stepping
        done = terminated | truncated
        info: dict[str, Any] = {}
        if self.autoreset_mode == AutoresetMode.SAME_STEP and done.any():
            final = {int(i): {k: v[i].copy() for k, v in obs.items()} for i in np.flatnonzero(done)}
            info = vinfo.merge(info, {"final_info": step_info}, done)
            info["final_obs"], info["_final_obs"] = vinfo.objects(final, n), done.copy()
            for i in np.flatnonzero(done):
                reset_extra = vinfo.gather(reset_extra, self._reset_one(int(i), False, reset_drawn), i, n)
            fresh = self._rows.raw(self._batched.observations())
            self._sense(fresh, np.flatnonzero(done), ())
            for key, value in obs.items():
                value[done] = fresh[key][done]
            quantities = self._inputs()
            for key, value in quantities.items():
                self._before[key][done] = value[done]
            self._elapsed[done] = 0
            resetting = done
            done = np.zeros(n, dtype=bool)
        info = vinfo.merge(info, step_info, ~resetting)
        info = self._randomizers.merge(info, {i: v for i, v in drawn.items() if not resetting[i]})
        if resetting.any():
            reset_info = vinfo.reset_info(self._success(obs), quantities, self._at_rest, reset_extra)
            info = vinfo.merge(info, reset_info, resetting)
            info = self._randomizers.merge(info, reset_drawn)
        for key, value in obs.items():
            self._last_obs[key] = value.copy()
        self._autoreset = done
        return {k: v.copy() for k, v in obs.items()}, reward, terminated, truncated, info

    def render(self) -> tuple[np.ndarray | None, ...] | None:  # type: ignore[override]  # None per env in human mode
        if self.render_mode is None:
            return None
        return tuple(self._batched.render(i) for i in range(self.num_envs))

    def close_extras(self, **kwargs: Any) -> None:
        self._batched.close()
        self._rows.close()

    # ------------------------------------------------------------------ GoalEnv API, batched
    def compute_reward(self, achieved_goal, desired_goal, info) -> np.ndarray:
        """Reward for goals of shape ``(g,)`` or ``(B, g)``; equals ``step()``'s reward.

        ``info`` is this env's info (a dict of ``(B,)`` arrays), one single-env info
        dict, or a sequence / object array of ``B`` of them (``HerReplayBuffer``).
        """
        achieved_goal = np.asarray(achieved_goal, dtype=np.float64)
        desired_goal = np.asarray(desired_goal, dtype=np.float64)
        distance = self.task.goal_distance(achieved_goal, desired_goal)
        success = (distance < self._threshold).astype(np.float64)
        return self.reward_spec.total(distance, success, self._ctx(info, np.shape(distance)))

    def compute_terminated(self, achieved_goal, desired_goal, info) -> np.ndarray:
        distance = self.task.goal_distance(achieved_goal, desired_goal)
        ended = np.logical_and(self.config.terminate_on_success, distance < self._threshold)
        if self._terminations:
            ctx = self._ctx(info, np.shape(distance))
            for termination in self._terminations:
                ended = np.logical_or(ended, termination.fn(ctx))
        return ended

    def _ctx(self, info, shape: tuple[int, ...]) -> dict[str, np.ndarray]:
        """The reward inputs of ``info``: this env's info (a dict of arrays), one single-env
        info dict, or a sequence / object array of them."""
        keys = self._terms.info_keys
        if isinstance(info, Mapping):
            return {k: np.broadcast_to(np.asarray(info.get(k, 0.0), dtype=np.float64), shape) for k in keys}
        return info_arrays(info, shape, keys)

    # ------------------------------------------------------------------ helpers
    def _reset_one(self, i: int, seeded: bool, drawn: Drawn) -> dict[str, Any]:
        """Reset env ``i`` from its generator, its randomisation first (as the single env);
        its drawn values go to ``drawn[i]``; returns its extra reset info."""
        self._randomizers.reset(i, self._rng(i), seeded, drawn)
        return self._batched.reset(i, self._rng(i))

    def randomization_state(self, index: int) -> dict[str, float]:
        """Env ``index``'s randomised values in force (the single env's
        ``randomization_state()``); empty under ``none``."""
        return self._randomizers.state(index)

    def _validate(self, actions) -> np.ndarray:
        return checked_actions(actions, self._action_shape, self._action_rule)

    def _inputs(self) -> dict[str, np.ndarray]:
        """The term set's inputs of every env, from the batched backend's quantities."""
        quantities = self._batched.quantities()
        return {k: quantities[k] for k in self._terms.inputs}

    def _fresh_obs(self, mask: np.ndarray) -> dict[str, np.ndarray]:
        """The backend's observations where ``mask``, the last ones elsewhere."""
        obs = self._rows.raw(self._batched.observations())
        self._sense(obs, np.flatnonzero(mask), ())
        for key, value in obs.items():
            value[~mask] = self._last_obs[key][~mask]
            self._last_obs[key] = value.copy()
        return obs

    def _sense(
        self, obs: dict[str, np.ndarray], starting: np.ndarray | Sequence[int], advancing: np.ndarray | Sequence[int]
    ) -> None:
        """The sensor model on the rows of envs that start or advance an episode; the
        other rows keep the last observation (see :meth:`ObservationRows.sense`)."""
        obs["observation"] = self._rows.sense(
            obs["observation"], self._last_obs["observation"], starting, advancing, self._rng
        )

    def _rng(self, i: int) -> np.random.Generator:
        rng = self._rngs[i]
        if rng is None:  # every env is reset (and seeded) before its stream starts
            raise RuntimeError(f"env {i} has no generator: reset it first")
        return rng

    @property
    def observation_layout(self) -> dict[str, slice]:
        """Each group of the observation design, in order, with its slice of ``observation``."""
        return self._rows.layout

    @property
    def goal_dependent_layout(self) -> dict[str, slice]:
        """The groups of ``observation_layout`` that depend on the goal (as the single env's)."""
        return self._rows.goal_layout

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._rows.reattach()

    def _success(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        """As the single env's reset: success from the float32 goals."""
        distance = self.task.goal_distance(obs["achieved_goal"], obs["desired_goal"])
        return (distance < self._threshold).astype(np.float64)
