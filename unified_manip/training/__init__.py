"""Training: Stable-Baselines3 runs on any registered ID.

Run settings and hyperparameter files (``hyperparams``, ``request``, ``devices``), the
algorithms' extras (``crossq``, ``replay_buffers``), the envs of a run (``run_envs``),
callbacks, ``train`` and ``evaluation``, the run directory and its checkpoints
(``rundir``, ``runlock``, ``checkpoints``) and the demonstration levers
(``demonstrations``, ``pretrain``, ``offline``, ``cloning_loss``). The layer imports the
env library only; experiments, tools and the CLI sit above it.
"""
