"""Vector envs: N envs of one task stepped in one call.

``gym.make_vec("UnifiedManip/<task>-v0", num_envs=N, action_mode=..., reward_type=...)``
returns a :class:`~unified_manip.envs.vector.env.NativeVectorEnv` for families with a batched
backend (the 4-DOF arm), and Gymnasium's ``SyncVectorEnv`` with a one-line notice for
the others. :class:`~unified_manip.training.sb3_vec_env.NativeSB3VecEnv` gives the native env
Stable-Baselines3's ``VecEnv`` interface.

=================  =============================================================
module             concept
=================  =============================================================
``pool``           the persistent physics thread pool
``batched``        ``BatchedBackend``: what a family provides to run natively
``arm4``           the 4-DOF arm, N at a time (controls and observations as arrays)
``infos``          info dicts of arrays in Gymnasium's layout
``env``            ``NativeVectorEnv``: the Gymnasium vector env
``factory``        ``make_vector_env``: the ``vector_entry_point``, and the fallback
=================  =============================================================
"""

from unified_manip.envs.vector.factory import VectorFallbackWarning, make_vector_env, native_support

__all__ = ["VectorFallbackWarning", "make_vector_env", "native_support"]
