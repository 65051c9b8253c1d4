"""The one abstract base: what a simulator family provides to the shared env.

A *backend* owns one simulator instance for one task and one action mode. The shared
:class:`unified_manip.envs.env.UnifiedManipEnv` turns it into a goal-conditioned Gymnasium
env; it never looks at which simulator it is talking to. A family (the 4-DOF arm,
gymnasium-robotics, robosuite) implements this class once and builds one instance per
env from the validated :class:`~unified_manip.envs.config.EnvConfig`.
"""

from __future__ import annotations

import abc
import copy
from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

from unified_manip.envs.observations import ObservationGroup


@dataclass(frozen=True)
class Checkpoint:
    """What a backend's next steps depend on (:meth:`Backend.checkpoint`).

    Attributes:
        data: A copy of the simulator's whole ``MjData``: the state, the controls, the
            solver's warm start and every derived quantity, so stepping on from it is bit
            for bit stepping on from where it was taken.
        memory: The controller's memory between steps (:mod:`~unified_manip.envs.controllers.memory`).
        family: What else a family's next step reads (e.g. robosuite's gripper
            smoothing), in the family's own form; ``None`` for most.
    """

    data: Any
    memory: tuple[dict[str, np.ndarray], ...]
    family: Any = None


class Backend(abc.ABC):
    """A simulator running one task under one action mode.

    Attributes:
        action_dim: Length of the ``Box(-1, 1)`` action vector for the chosen mode.
        dt: Simulated seconds per env step.
        model: The simulator's ``mujoco.MjModel`` (every family runs on MuJoCo).
        data: Its ``mujoco.MjData``, which the env steps.
        pickles_model: Pickling keeps the model as it is (randomised fields included);
            False for a backend that rebuilds its simulator when unpickled.
        action_layout: The action's parts in words where it has several, e.g.
            ``"2 × (3 + 1)"`` (two arms); a wrong-shaped action's error names it.
    """

    pickles_model: bool = True
    action_layout: str = ""
    action_dim: int
    dt: float
    model: Any
    data: Any

    @abc.abstractmethod
    def reset(self, np_random: np.random.Generator) -> None:
        """Start an episode: sample the initial state and the goal from ``np_random``.

        All randomness must come from ``np_random`` so that seeded resets are
        reproducible bit for bit.
        """

    @abc.abstractmethod
    def step(self, action: np.ndarray) -> dict[str, Any]:
        """Apply a validated, clipped action and advance the simulation one env step.

        Args:
            action: float64 array of shape ``(action_dim,)`` with values in [-1, 1].

        Returns:
            Diagnostics to merge into ``info`` (e.g. IK residuals under ``ee_delta``).
        """

    @abc.abstractmethod
    def observation(self) -> np.ndarray:
        """The flat observation vector (any float dtype; the env casts to float32)."""

    @abc.abstractmethod
    def observation_groups(self) -> Mapping[str, ObservationGroup]:
        """The named groups this task can put in the observation vector, in the order
        the ``"full"`` preset concatenates them (:mod:`unified_manip.envs.observations`)."""

    @abc.abstractmethod
    def default_observation(self) -> tuple[str, ...]:
        """The groups whose concatenation is :meth:`observation`, exactly, in order."""

    @abc.abstractmethod
    def achieved_goal(self) -> np.ndarray:
        """The part of the state the goal is compared against."""

    @abc.abstractmethod
    def desired_goal(self) -> np.ndarray:
        """The goal sampled at the last reset."""

    @abc.abstractmethod
    def quantities(self) -> Mapping[str, float]:
        """The task's named per-step quantities now, as floats: at least every input of the
        task's term set (:attr:`TaskSpec.terms <unified_manip.envs.registry.TaskSpec.terms>`),
        which the env copies into ``info`` for the reward terms. They must not depend on the
        goal, so that hindsight relabelling recomputes the reward exactly."""

    @abc.abstractmethod
    def unstable(self) -> bool:
        """True if the physics diverged during the last step (warning or NaN state)."""

    @abc.abstractmethod
    def render(self) -> np.ndarray | None:
        """An RGB frame for ``rgb_array``, or ``None`` after drawing for ``human``."""

    def extra_info(self) -> dict[str, Any]:
        """Task-specific keys to add to ``info`` at reset and on every step."""
        return {}

    def extra_observations(self) -> dict[str, np.ndarray]:
        """Extra observation-dict entries (e.g. camera images); empty by default."""
        return {}

    def close(self) -> None:
        """Release simulator and renderer resources."""

    def get_state(self) -> np.ndarray:
        """The simulator's full physics state: MuJoCo's ``mj_getState`` with
        ``mjSTATE_FULLPHYSICS`` (time, ``qpos``, ``qvel``, actuator activations, history and
        plugin state) of the backend's ``model`` and ``data``, as a float64 vector. Every
        family here runs on MuJoCo (robosuite's ``sim.get_state().flatten()`` is a subset
        of it), so this one definition serves them all."""
        import mujoco

        spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        state = np.empty(mujoco.mj_stateSize(self.model, spec))
        mujoco.mj_getState(self.model, self.data, state, spec)
        return state

    def set_state(self, state: np.ndarray) -> None:
        """Restore a state from :meth:`get_state` (``ValueError`` for one of another size).

        Only the physics is restored: the goal, the controller's own memory and any cached
        observation stay as they are, so step the env to read an observation of it. A
        state other than the current one is followed by ``mj_forward``, which recomputes
        the derived quantities (site positions, velocities) from it. Restoring the state
        the simulator already holds changes nothing: upstream code that reads the derived
        quantities ``mj_step`` left (Fetch's mocap control reads the grip site as of the
        last substep) then continues bit for bit."""
        import mujoco

        spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        size = mujoco.mj_stateSize(self.model, spec)
        state = np.asarray(state, dtype=np.float64)
        if state.shape != (size,):
            raise ValueError(f"a simulator state of this env has shape ({size},); got {state.shape}")
        if np.array_equal(state, self.get_state()):
            return
        mujoco.mj_setState(self.model, self.data, state, spec)
        mujoco.mj_forward(self.model, self.data)

    def checkpoint(self) -> Checkpoint:
        """Everything the physics of the next steps depends on: the simulator's ``MjData``
        and the shared controller's memory. :meth:`restore` puts it back into this backend
        or into another of the same task and action mode reset with the same seed (its
        model then equals this one), which then steps on bit for bit as this one would
        (to rounding on MuJoCo 3.3.0); ``unified-manip convert`` tries actions so. A family whose next physics step also
        reads memory of its own adds it here."""
        from unified_manip.envs.controllers.memory import remember

        return Checkpoint(copy.copy(self.data), remember(getattr(self, "control", None)))

    def restore(self, checkpoint: Checkpoint) -> None:
        """Put back a :meth:`checkpoint` of this backend or of another of the same task
        and mode. Caches of the last step's observation stay as they are: step to read."""
        import mujoco

        from unified_manip.envs.controllers.memory import recall

        if hasattr(mujoco, "mj_copyData"):
            mujoco.mj_copyData(self.data, self.model, checkpoint.data)
        else:  # MuJoCo 3.3.0 binds no in-place copy: the integration state, derived quantities recomputed
            # (the steps after it then agree to rounding, not bit for bit)
            spec = mujoco.mjtState.mjSTATE_INTEGRATION
            state = np.empty(mujoco.mj_stateSize(self.model, spec))
            mujoco.mj_getState(self.model, checkpoint.data, state, spec)
            mujoco.mj_setState(self.model, self.data, state, spec)
            mujoco.mj_forward(self.model, self.data)
        recall(getattr(self, "control", None), checkpoint.memory)
