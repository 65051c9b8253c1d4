"""Training: Stable-Baselines3 runs on any registered ID.

Run settings and hyperparameter files (``hyperparams``, ``request``, ``devices``), the
algorithms' extras (``crossq``, ``replay_buffers``, ``her``), the envs of a run
(``run_envs``), callbacks, ``train`` and ``evaluation``, the run directory and its
checkpoints (``rundir``, ``runlock``, ``checkpoints``) and the demonstration levers
(``demonstrations``, ``pretrain``, ``offline``, ``cloning_loss``). The layer imports the
env library only; experiments, tools and the CLI sit above it.

For plain Stable-Baselines3 scripts it exports :class:`GoalRelHerReplayBuffer`, a drop-in
for SB3's ``HerReplayBuffer`` that relabels the goal-dependent observation groups too
(:mod:`unified_manip.training.her`); it is imported on first use, so importing a module of
this package does not import SB3.
"""

from __future__ import annotations

from typing import Any

__all__ = ["GoalRelHerReplayBuffer"]


def __getattr__(name: str) -> Any:
    if name == "GoalRelHerReplayBuffer":
        from unified_manip.training.her import GoalRelHerReplayBuffer

        return GoalRelHerReplayBuffer
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
