"""The agent's own updates on the demonstrations alone, before the first rollout (``offline_steps: N``).

With ``demonstrations``, ``offline_steps: N`` takes N gradient steps of the algorithm's
own update (SB3's ``train``: critic, actor, entropy coefficient and target networks, as in
training) on batches from a replay buffer that holds nothing but the demonstrations, HER
relabelling them as it will during training. The first rollouts then come from an agent
whose critic has already been fitted to successful episodes, instead of from a random
one. It is the pre-training phase of DQfD (Hester et al. 2018, "Deep Q-learning from
Demonstrations"), there on demonstrations alone before any interaction, here for an
actor-critic.

It is the lever the Q-filtered cloning loss asked for (:mod:`unified_manip.training.cloning_loss`):
on an untrained critic, which rates the actor's own actions above the demonstrated ones
almost everywhere, the Q-filter let through 9% of the demonstrated transitions. With
``bc_weight`` the cloning loss is in every actor update of these N steps too, and the
record says what fraction the filter passes at the end of them. ``bc_steps`` (the actor
alone, :mod:`unified_manip.training.pretrain`) runs first where both are asked for.
"""

from __future__ import annotations

from typing import Any


class OfflineError(ValueError):
    """Offline steps were asked of a run that cannot take them."""


def check(offline_steps: int, demonstrations: int) -> None:
    """Raise :class:`OfflineError` unless ``offline_steps`` (0: none) is a number of steps
    0 or more and the run has demonstrations to learn from."""
    if offline_steps < 0:
        raise OfflineError(f"offline_steps must be a number of gradient steps, 0 or more; got {offline_steps}")
    if offline_steps and not demonstrations:
        raise OfflineError(
            f"offline_steps={offline_steps} learns from the demonstrations alone; set demonstrations "
            "to 1 or more episodes"
        )


#: Logged by the update (and by the cloning loss), recorded at the first and last step.
RECORDED = (
    "train/critic_loss",
    "train/actor_loss",
    "train/ent_coef",
    "train/bc_loss",
    "train/bc_q_filter",
    "train/bc_error",
)


#: Updates between progress-bar refreshes (the update itself runs in chunks of this many).
#: Each chunk is one ``train`` call: SAC's and TQC's ``target_update_interval`` counts
#: within a call, so above 1 (every shipped entry has 1) a chunk's first step also
#: updates the targets; TD3's and CrossQ's ``policy_delay`` count over all updates.
CHUNK = 250


def _chunks(steps: int) -> list[int]:
    """``steps`` split so that the first and the last step each stand alone (their losses
    are the record's ``first`` and ``last``) and the rest come in chunks of :data:`CHUNK`."""
    if steps < 3:
        return [1] * steps
    middle = [CHUNK] * ((steps - 2) // CHUNK) + ([(steps - 2) % CHUNK] if (steps - 2) % CHUNK else [])
    return [1, *middle, 1]


def learn_offline(model, steps: int, progress: bool = False) -> dict[str, Any]:
    """Take ``steps`` gradient steps of ``model.train`` with the model's batch size on what
    its replay buffer holds now (the demonstrations: see the module docstring), with a
    progress bar if ``progress``.

    Returns ``{"steps", "first", "last"}``: the values :data:`RECORDED` that the update
    logged at its first and at its last step (a name the algorithm does not log is left
    out; the critic loss of a step is the mean over its batch).
    """
    from stable_baselines3.common.logger import Logger
    from tqdm import tqdm

    # learn() has not set a logger up yet; this one keeps the values in memory only, and
    # learn() replaces it with the run's own (no custom logger was set).
    model._logger = Logger(folder=None, output_formats=[])
    seen = []
    with tqdm(total=steps, desc="offline steps", unit="update", disable=not progress, dynamic_ncols=True) as bar:
        for chunk in _chunks(steps):
            model.train(gradient_steps=chunk, batch_size=model.batch_size)
            seen.append(
                {
                    name: float(model.logger.name_to_value[name])
                    for name in RECORDED
                    if name in model.logger.name_to_value
                }
            )
            model.logger.dump()  # the next chunk's values alone
            bar.update(chunk)
    return {"steps": steps, "first": seen[0] if seen else {}, "last": seen[-1] if seen else {}}
