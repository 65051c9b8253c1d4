"""The action that reaches a recorded next state: how ``convert`` re-executes a step.

From the converted episode's state, each step looks for the action of the new mode whose
step lands the grip site nearest where the recording had it after that step, and the
achieved goal (the object, a door's angle) nearest the recording's. Candidates are
stepped in a *probe*: a second env of the same task and mode, reset with the episode's
seed, into which the converted env's :meth:`~unified_manip.envs.backend.Backend.checkpoint`
is restored before each try. The converted env itself only plays the chosen action, so
its episode replays exactly from its seed and actions.

The search is Gauss–Newton on finite differences over the action's arm entries. It starts
from the best-landing initial guess (the recorded action translated into the mode, and
the open-loop tracker's action) and keeps its gripper entry. Each iteration estimates the
Jacobian of the residual with one probe step per arm entry, takes the damped
least-squares step, and keeps it when the residual falls (halving it up to three times
when not). It stops once the grip site lands within ``accept_cm`` and the goal within as
much.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: ``convert``'s methods, the default first: this search, or its first initial guess played
#: open loop.
METHODS = ("search", "track")

#: A converted step whose grip site lands further than this from the recording (cm) fails
#: the episode.
TOLERANCE_CM = 10.0


@dataclass(frozen=True)
class SearchConfig:
    """How hard ``convert`` searches each step's action.

    Attributes:
        iterations: Gauss–Newton iterations at most per step.
        difference: Finite-difference step, in action units.
        damping: Levenberg damping added to ``JᵀJ``, relative to its largest diagonal entry.
        goal_weight: The achieved goal's weight in the residual, against the grip site's
            (both in the task's units, m for positions).
        velocity_weight: The grip site's velocity's weight in the end-effector modes (s: a
            velocity error of 1 m/s counts as a position error of this many metres). There
            the action commands the site, and a site that lands right but moving wrong
            overshoots the next step. The joint modes match positions only: with a joint
            per action entry, the search bought the velocity with contorted joint targets
            that lost the episode (docs/datasets.md has the measurements).
        accept_cm: A landing this close (grip site and weighted goal, cm) ends the search.
        fallback: Whether an episode the search loses is played again by each initial
            guess open loop, in turn, and the first replay kept is kept. The search is
            greedy, one step ahead: where the mode lags the recording (absolute joint
            targets on Door), it buys each step's landing with motion the next steps
            cannot undo, and the tracker's steadier targets keep what it loses.
        catch_up: Extra steps the search may spend on one recorded step while the grip
            site lags its recorded position by more than ``catch_up_cm``: the converted
            episode follows the recorded path at the pace the mode allows, where the
            mode is slower than the recording's (a capped joint step; a servoed arm
            after Meta-World's mocap hand). ``0``: one step per recorded step.
        catch_up_cm: The lag (cm) beyond which a step is caught up.
        lead_weights: Where the search loses an episode (catching up and in lockstep) in a
            mode that carries a target between steps (``joint_target_delta``,
            ``ee_target_delta``, robosuite's ``joint_velocity``), it tries it again with
            the controller's lead in the residual (its target's offset from the measured
            arm, in full action steps: the same scale in every mode), at each of these
            weights (m per step) in turn. One step ahead, the search can buy each landing
            with a target that runs ever further ahead of the arm, until the arm swings
            after it and leaves the path; the lead's cost holds the target near the arm
            (docs/datasets.md has the measurements). ``()``: no such retries.
    """

    iterations: int = 3
    difference: float = 0.05
    damping: float = 1e-3
    goal_weight: float = 1.0
    velocity_weight: float = 0.04
    accept_cm: float = 0.5
    fallback: bool = True
    catch_up: int = 4
    catch_up_cm: float = 1.0
    lead_weights: tuple[float, ...] = (5e-4, 1.5e-4)

    def __post_init__(self) -> None:
        if self.iterations < 0:
            raise ValueError(f"SearchConfig.iterations must be >= 0, got {self.iterations}")
        for name in ("difference", "damping", "goal_weight", "accept_cm", "catch_up_cm"):
            value = getattr(self, name)
            if not value > 0:
                raise ValueError(f"SearchConfig.{name} must be > 0, got {value}")
        if self.catch_up < 0:
            raise ValueError(f"SearchConfig.catch_up must be >= 0, got {self.catch_up}")
        if not self.velocity_weight >= 0:
            raise ValueError(f"SearchConfig.velocity_weight must be >= 0, got {self.velocity_weight}")
        if not all(w > 0 for w in self.lead_weights):
            raise ValueError(f"SearchConfig.lead_weights must all be > 0, got {self.lead_weights}")


@dataclass(frozen=True)
class Target:
    """Where a recorded step left the simulator, as the search compares it.

    Attributes:
        site: The grip site's position, world frame, m (each arm's in turn).
        velocity: The grip site's linear velocity, world frame, m/s (each arm's in turn).
        goal: The achieved goal.
    """

    site: np.ndarray
    velocity: np.ndarray
    goal: np.ndarray


@dataclass(frozen=True)
class Landing:
    """The chosen action and where its probe step landed.

    Attributes:
        action: The action (float32, in [-1, 1]).
        site_error: The grip site's distance from its target, m.
        goal_error: The achieved goal's distance from its target (the goal's units).
        probes: Probe steps spent.
    """

    action: np.ndarray
    site_error: float
    goal_error: float
    probes: int


class ActionSearch:
    """Searches each step's action in ``probe``, an env of the converted task and mode.

    Args:
        probe: A gymnasium env of this project, made like the converted one; the search
            steps its backend only.
        config: The search's settings.
        lead_weight: The weight of the controller's lead in the residual (0: none; see
            :attr:`SearchConfig.lead_weights`).
    """

    def __init__(self, probe, config: SearchConfig = SearchConfig(), lead_weight: float = 0.0) -> None:
        from unified_manip.envs.controllers.translate import arms

        self.env, self.config = probe, config
        self.backend = probe.unwrapped.backend
        views = arms(self.backend)
        self.rigs = [v.rig for v in views]
        # The action's arm entries: each arm's part but its gripper entry.
        entries, start = [], 0
        for v in views:
            entries.append(start + np.arange(v.control.action_dim - int(v.rig.has_gripper)))
            start += v.control.action_dim
        self.arm = np.concatenate(entries)
        site_mode = hasattr(views[0].control, "site_action_toward")
        self.velocity_weight = config.velocity_weight if site_mode else 0.0
        self.controls = [v.control for v in views]
        if lead_weight and not leads(self.controls):
            raise ValueError(
                f"a lead weight needs a controller that carries a target; {type(self.controls[0]).__name__} does not"
            )
        self.lead_weight = lead_weight
        self.probes = 0

    def start(self, seed: int) -> None:
        """Reset the probe with the episode's seed (the goal, the placements, the held
        rotation: whatever a reset fixes for the episode)."""
        self.env.reset(seed=seed)

    def _land(self, checkpoint, action: np.ndarray, target: Target) -> np.ndarray:
        """The residual after stepping ``action`` from ``checkpoint``: the grip site's
        offset from the target's, then the weighted goal's and arm velocities'."""
        import mujoco

        backend, c = self.backend, self.config
        backend.restore(checkpoint)
        backend.step(action.astype(np.float64))
        self.probes += 1
        achieved = np.asarray(backend.achieved_goal(), dtype=np.float64)  # as the recorded observation read it
        # The sites and velocities as a restored recorded state reads them (mj_step leaves
        # them a substep behind; the probe is restored before its next try anyway).
        mujoco.mj_forward(backend.model, backend.data)
        parts = [
            sites(self.rigs) - target.site,
            c.goal_weight * (achieved - target.goal),
            self.velocity_weight * (site_velocities(self.rigs) - target.velocity),
        ]
        if self.lead_weight:
            parts.append(self.lead_weight * np.concatenate([control.lead() for control in self.controls]))
        return np.concatenate(parts)

    def __call__(self, checkpoint, guesses: list[np.ndarray], target: Target) -> Landing:
        """The action from ``checkpoint`` (the converted env's) that lands nearest
        ``target``, starting from the best of ``guesses``."""
        c = self.config
        self.probes = 0
        arm = self.arm
        landings = [(_as_action(g), self._land(checkpoint, _as_action(g), target)) for g in guesses]
        x, r = min(landings, key=lambda xr: float(xr[1] @ xr[1]))
        site = slice(0, target.site.size)

        accept = c.accept_cm / 100
        goal = slice(site.stop, site.stop + target.goal.size)
        for _ in range(c.iterations):
            if np.linalg.norm(r[site]) < accept and np.linalg.norm(r[goal]) < accept:
                break
            jac = np.empty((r.size, arm.size))
            for j, i in enumerate(arm):
                h = c.difference if x[i] < 1 - c.difference else -c.difference
                probe = x.copy()
                probe[i] += h
                jac[:, j] = (self._land(checkpoint, _as_action(probe), target) - r) / h
            normal = jac.T @ jac
            normal[np.diag_indices(arm.size)] += c.damping * max(float(normal.diagonal().max()), 1e-12)
            delta = np.linalg.solve(normal, -jac.T @ r)
            improved = False
            for scale in (1.0, 0.5, 0.25, 0.125):
                y = x.copy()
                y[arm] += scale * delta
                y = _as_action(y)
                ry = self._land(checkpoint, y, target)
                if ry @ ry < r @ r:
                    x, r, improved = y, ry, True
                    break
            if not improved:
                break
        return Landing(x, float(np.linalg.norm(r[site])), float(np.linalg.norm(r[goal]) / c.goal_weight), self.probes)


def leads(controls) -> bool:
    """Whether every one of ``controls`` carries a target whose lead it can tell."""
    return all(hasattr(control, "lead") for control in controls)


def _as_action(x: np.ndarray) -> np.ndarray:
    """``x`` as the env would take it from a dataset: float32, in [-1, 1]."""
    return np.clip(np.asarray(x, dtype=np.float64), -1.0, 1.0).astype(np.float32)


def sites(rigs) -> np.ndarray:
    """The grip sites' positions of ``rigs``, one after another, world frame, m."""
    return np.concatenate([rig.site_position() for rig in rigs])


def site_velocities(rigs) -> np.ndarray:
    """The grip sites' linear velocities of ``rigs``, one after another, world frame, m/s."""
    import mujoco

    out = np.empty(6)
    velocities = []
    for rig in rigs:
        mujoco.mj_objectVelocity(rig.model, rig.data, mujoco.mjtObj.mjOBJ_SITE, rig.site_id, out, 0)
        velocities.append(out[3:].copy())
    return np.concatenate(velocities)
