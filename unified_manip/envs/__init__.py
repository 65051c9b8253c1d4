"""The env library: every task behind one goal-conditioned Gymnasium interface.

Five concepts, each in its own place:

* a **task** (:class:`~unified_manip.envs.registry.TaskSpec`, registered by its family
  under ``unified_manip.envs.tasks``);
* a **backend** (:class:`~unified_manip.envs.backend.Backend`): what a simulator family
  provides to the one env class, :class:`~unified_manip.envs.env.UnifiedManipEnv`;
* an **action mode**: a controller config (:mod:`unified_manip.envs.controllers`);
* a **reward design** (:mod:`unified_manip.envs.rewards`);
* the env's keyword arguments as one frozen config
  (:class:`~unified_manip.envs.config.EnvConfig`).

``vector`` runs N envs of one task in one call. This layer imports nothing from
training, experiments, tools or the CLI, and needs none of their dependencies.
"""
