"""Behaviour cloning of the actor on the demonstrations, before the off-policy updates.

The hyperparameter ``bc_steps: N`` (with ``demonstrations``) takes N gradient steps of the
actor on batches sampled from the replay buffer right after the demonstrations filled it,
so before the agent has stored an episode of its own: the first rollouts then come from
a policy that already imitates the scripted one instead of from a random one. It is the
pretraining half of Nair et al. 2018 ("Overcoming Exploration in Reinforcement Learning
with Demonstrations"), without their behaviour-cloning loss during training; the critic
is not pretrained.

The loss is the policy's own: the negative log-likelihood of the demonstrated actions
under a stochastic actor (SAC, TQC, CrossQ: a tanh-squashed Gaussian, so the actor's
standard deviation shrinks to fit the demonstrations too; see :data:`EDGE`), the squared error of a
deterministic actor's action (TD3). Batches come through the buffer's ``sample``
(a normalising run's statistics start from the demonstrations, see
:func:`seed_statistics`) with the goals the demonstrations acted
for: a HER buffer relabels none of them here, as a demonstrated action toward one goal
is no example of acting toward another.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from unified_manip.training.settings import RunConfig


class PretrainError(ValueError):
    """Behaviour cloning was asked of a run that cannot do it."""


def check(bc_steps: int, demonstrations: int) -> None:
    """Raise :class:`PretrainError` unless ``bc_steps`` (0: none) is a number of steps 0
    or more and the run has demonstrations to clone."""
    if bc_steps < 0:
        raise PretrainError(f"bc_steps must be a number of gradient steps, 0 or more; got {bc_steps}")
    if bc_steps and not demonstrations:
        raise PretrainError(f"bc_steps={bc_steps} clones the demonstrations; set demonstrations to 1 or more episodes")


def check_settings(
    task_id: str,
    action_mode: str,
    off_policy: bool,
    run: RunConfig,
    env_config: dict[str, Any] | None = None,
    *,
    datasets: bool = True,
) -> None:
    """Raise a ``ValueError`` unless a run with settings ``run`` can take the
    demonstrations (:func:`unified_manip.training.demonstrations.check`), the cloning it asks for
    (before training, and the loss during it: :func:`unified_manip.training.cloning_loss.check`) and
    the offline steps (:func:`unified_manip.training.offline.check`):
    what ``train`` and a grid's loading both check before anything starts. Demonstrations
    from a dataset must match the run's env keyword arguments ``env_config`` (default: its
    action mode, sparse reward; :func:`unified_manip.training.dataset_demonstrations.check`),
    unless ``datasets`` is false: the settings of runs already trained elsewhere, read for
    what they were, need not find their datasets on this machine."""
    from unified_manip.training.cloning_loss import check as check_cloning_loss
    from unified_manip.training.demonstrations import check as check_demonstrations
    from unified_manip.training.offline import check as check_offline

    episodes = run.demos.demonstrations
    check_demonstrations(task_id, action_mode, off_policy, episodes)
    if isinstance(episodes, str) and datasets:
        from unified_manip.training.dataset_demonstrations import check as check_dataset

        config = env_config or {"action_mode": action_mode, "reward_type": "sparse"}
        check_dataset(episodes, task_id, config, run.n_envs)
    check(run.demos.bc_steps, episodes)
    check_offline(run.offline.offline_steps, episodes)
    loss = run.cloning_loss
    check_cloning_loss(loss.bc_weight, episodes, loss.bc_q_filter, loss.bc_sampled)


#: Demonstrated actions at the edge of the box (a gripper's -1 or +1) are fitted as this
#: much inside it by a squashed Gaussian: the inverse tanh of 1 is float32's limit (8.3),
#: and fitting that left the gripper's standard deviation at its cap (e^2) and its mean
#: action 0.37 off the demonstrated one; at 0.99 (2.6) they are 1.0 and 0.13 (2,000 steps,
#: two Arm4PickAndPlace-v0 demonstrations in joint_position).
EDGE = 0.99


def _loss(actor, observations, actions):
    import torch.nn.functional as F

    if hasattr(actor, "action_dist"):  # stochastic: the squashed Gaussian's log-likelihood
        mean, log_std, kwargs = actor.get_action_dist_params(observations)
        dist = actor.action_dist.proba_distribution(mean, log_std, **kwargs)
        return -dist.log_prob(actions.clamp(-EDGE, EDGE)).mean()
    return F.mse_loss(actor(observations), actions)


def seed_statistics(model) -> None:
    """Start a normalising run's observation statistics (its ``VecNormalize``; nothing
    where the run does not normalise) from the demonstrated observations in its replay
    buffer, so what is fitted before the first rollout (:func:`behaviour_clone`,
    :func:`unified_manip.training.offline.learn_offline`) sees inputs normalised as its first
    rollouts' will be; the agent's own observations then update them as usual. Unseeded
    they are the identity until the first rollout, and the fitted networks would face
    other inputs from their first update on. Call it once, after the demonstrations are
    stored and before either."""
    venv, buffer = model._vec_normalize_env, model.replay_buffer
    if venv is None or not venv.norm_obs:
        return
    rows = buffer.size()
    pairs = (
        [(venv.obs_rms[k], buffer.observations[k]) for k in venv.norm_obs_keys]
        if isinstance(venv.obs_rms, dict)
        else [(venv.obs_rms, buffer.observations)]
    )
    for stats, values in pairs:  # stored as (rows, n_envs, ...)
        stats.update(values[:rows].reshape(-1, *values.shape[2:]))


def behaviour_clone(model, steps: int) -> dict[str, Any]:
    """Fit ``model.actor`` to the actions in ``model.replay_buffer`` for ``steps`` gradient
    steps of ``model.batch_size`` with the actor's own optimiser (a normalising run calls
    :func:`seed_statistics` first).

    Returns ``{"steps", "loss_first", "loss_last"}``: the loss of the first and of the
    last batch (each averaged over the batch).
    """
    buffer = model.replay_buffer
    her_ratio = getattr(buffer, "her_ratio", None)
    if her_ratio is not None:  # the goals the demonstrations acted for, none relabelled
        buffer.her_ratio = 0.0
    model.policy.set_training_mode(True)
    losses = []
    try:
        for _ in range(steps):
            batch = buffer.sample(model.batch_size, env=model._vec_normalize_env)
            loss = _loss(model.actor, batch.observations, batch.actions)
            model.actor.optimizer.zero_grad()
            loss.backward()
            model.actor.optimizer.step()
            losses.append(float(loss.item()))
    finally:
        model.policy.set_training_mode(False)
        if her_ratio is not None:
            buffer.her_ratio = her_ratio
    if hasattr(model, "actor_target"):  # TD3 acts on its target actor's next actions: start it equal
        model.actor_target.load_state_dict(model.actor.state_dict())
    return {"steps": steps, "loss_first": losses[0] if losses else None, "loss_last": losses[-1] if losses else None}
