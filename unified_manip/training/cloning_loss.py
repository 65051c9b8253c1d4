"""A behaviour-cloning loss kept during training, Q-filtered (``bc_weight: λ``).

Nair et al. 2018 ("Overcoming Exploration in Reinforcement Learning with
Demonstrations", section 4) add to each actor update a loss on a batch of demonstrated
transitions, kept only where the critic rates the demonstrated action above the actor's
own (the Q-filter)::

    λ · mean over the batch of 1[Q(s, a_demo) > Q(s, π(s))] · ‖π(s) − a_demo‖²

with π(s) the actor's deterministic action (a stochastic actor's mean action, squashed).
The actor then imitates the scripted policy where the scripted policy is better and is
free to improve on it elsewhere; :mod:`unified_manip.training.pretrain` is the other half of their
method, cloning before training. With ``bc_q_filter: false`` every demonstrated
transition counts (a fixed cloning regulariser, as in TD3+BC, Fujimoto and Gu 2021): for
a critic that rates the actor's own actions above the demonstrated ones almost everywhere,
which is what an untrained critic that the actor maximises tends to do.

With ``bc_sampled: true`` the loss takes the stochastic actor's *sampled* (reparameterised)
action in place of its mean: for a Gaussian before the tanh, the expected squared error is
the mean's squared error plus the variance, so the same weight also pulls the actor's
noise down where the demonstrations act. The mean-action loss leaves that noise to the
entropy bonus, and once the entropy coefficient has fallen near 0 nothing bounds it
(PickPlaceCan-v0, ``docs/results.md``). A deterministic actor (TD3) has no noise to
shrink, so asking it of one is an error.

The loss goes into every actor update of the algorithm, whatever it is (SAC, TQC,
CrossQ, TD3): a step pre-hook on the actor's optimiser adds its gradient to the one the
algorithm's own actor loss left, so each optimiser step follows the sum of the two losses.
Q is the mean over the critic's outputs (critics, or critics × quantiles), evaluated in
inference mode. The demonstrations are the replay buffer's first rows (the run put them
there before any transition of its own), read with the goals they acted for, normalised as
the buffer normalises, and sampled with numpy's global generator as the buffer samples.
"""

from __future__ import annotations

from typing import Any

import numpy as np


class CloningLossError(ValueError):
    """A run asked for the cloning loss and cannot have it."""


def check(bc_weight: float, demonstrations: int, q_filter: bool = True, sampled: bool = False) -> None:
    """Raise :class:`CloningLossError` unless ``bc_weight`` (0: no loss) is 0 or more, the
    run has demonstrations to imitate, and the filter and the sampled action are left
    alone without the loss."""
    for name, changed in (("bc_q_filter=false", not q_filter), ("bc_sampled=true", sampled)):
        if changed and not bc_weight:
            raise CloningLossError(f"{name} changes the cloning loss; set bc_weight above 0 as well")
    if not bc_weight >= 0:
        raise CloningLossError(f"bc_weight must be a loss weight, 0 or more; got {bc_weight}")
    if bc_weight and not demonstrations:
        raise CloningLossError(
            f"bc_weight={bc_weight} imitates the demonstrations; set demonstrations to 1 or more episodes"
        )


def attach(model, transitions: int, steps: int, weight: float, q_filter: bool = True, sampled: bool = False):
    """Add the cloning loss of weight ``weight`` (Q-filtered unless ``q_filter`` is false;
    on the actor's sampled action where ``sampled``, else on its mean) to every later
    actor update of ``model``, on the first ``transitions`` transitions of its replay
    buffer (the demonstrations) for a run of ``steps`` env steps in all.

    Returns the hook's handle (``.remove()`` detaches it). Raises :class:`CloningLossError`
    where the buffer would overwrite the demonstrations before the run ends, or where
    ``sampled`` is asked of a deterministic actor.
    """
    if sampled and not hasattr(model.actor, "action_dist"):
        raise CloningLossError(
            f"bc_sampled=true needs a stochastic actor (SAC, TQC, CrossQ); "
            f"{type(model).__name__}'s actor is deterministic"
        )
    buffer = model.replay_buffer
    rows = transitions // buffer.n_envs
    needed = rows + -(-steps // buffer.n_envs)
    if buffer.buffer_size < needed:
        raise CloningLossError(
            f"bc_weight needs the demonstrations kept in the replay buffer: buffer_size must be at "
            f"least {needed * buffer.n_envs} transitions ({transitions} demonstrated + {steps} "
            f"steps); got {buffer.buffer_size * buffer.n_envs}"
        )
    loss = _Cloning(model, rows, weight, q_filter, sampled)
    return model.actor.optimizer.register_step_pre_hook(lambda optimizer, args, kwargs: loss.backward())


class _Cloning:
    """Adds ``weight`` × the (Q-filtered) cloning loss's gradient to the actor's parameters."""

    def __init__(self, model, rows: int, weight: float, q_filter: bool, sampled: bool = False):
        self.model, self.rows, self.weight, self.q_filter, self.sampled = model, rows, weight, q_filter, sampled

    def backward(self) -> None:
        import torch

        model = self.model
        observations, actions = self._batch()
        mine = model.policy._predict(observations, deterministic=not self.sampled)  # sampled: rsample
        with torch.no_grad():
            better = (
                self._q(observations, actions) > self._q(observations, mine)
                if self.q_filter
                else torch.ones(len(actions), dtype=torch.bool, device=actions.device)
            )
        errors = ((mine - actions) ** 2).sum(dim=1)
        loss = self.weight * (better.float() * errors).mean()
        loss.backward()
        model.logger.record_mean("train/bc_loss", float(loss.item()))
        model.logger.record_mean("train/bc_q_filter", float(better.float().mean().item()))
        model.logger.record_mean("train/bc_error", float(errors.mean().item()))  # unfiltered, unweighted

    def _batch(self) -> tuple[Any, Any]:
        model = self.model
        buffer = model.replay_buffer
        rows = np.random.randint(0, self.rows, size=model.batch_size)
        envs = np.random.randint(0, buffer.n_envs, size=model.batch_size)
        observations = buffer._normalize_obs(
            {key: value[rows, envs] for key, value in buffer.observations.items()}, model._vec_normalize_env
        )  # as the buffer's own samples are
        return (
            {key: buffer.to_torch(value) for key, value in observations.items()},
            buffer.to_torch(buffer.actions[rows, envs]),
        )

    def _q(self, observations, actions):
        import torch

        critic = self.model.critic
        training = critic.training
        critic.set_training_mode(False)  # no batch-norm statistics from these batches (CrossQ)
        try:
            values = critic(observations, actions)
        finally:
            critic.set_training_mode(training)
        values = torch.cat(values, dim=1) if isinstance(values, tuple) else values
        return values.flatten(start_dim=1).mean(dim=1)
