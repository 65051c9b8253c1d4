"""The robosuite family (robosuite 1.5.2): Lift, Stack, PickPlaceCan/Milk/Bread/Cereal,
NutAssemblyRound/Square, Door, Wipe and ToolHang; with two arms, TwoArmLift and
TwoArmHandover (one rig and one controller of the mode per arm, their actions side by
side: :mod:`unified_manip.envs.controllers.composite`).

The backend owns one real robosuite env, built with ``robosuite.make`` exactly as a
robosuite user would (:func:`make_upstream`), and drives its ``step``/``reset``.

* **Seeding.** robosuite draws every random number of a reset (object placement, the
  robot's initial-joint noise) from one ``numpy.random.Generator``, ``env.rng``, which
  its placement samplers and robots share by reference. At every reset the backend
  draws a 63-bit seed from the env's ``np_random`` and sets ``env.rng``'s bit-generator
  state *in place* to ``default_rng(seed)``'s, then runs robosuite's reset; the desired
  goal is then drawn from ``np_random``. Same seed, same episode, on any instance.
* **One model.** robosuite samples a few model properties while building the model
  (Lift's cube size); the env is built with ``seed=0`` so every instance has the same
  model. With soft resets those properties stay fixed for the env's lifetime.
* **Fast resets.** The env is built with ``hard_reset=False`` (robosuite resets the
  existing simulator instead of recompiling the model: ~360 resets/s here instead of
  ~5/s). With the in-place reseeding above this is exactly as deterministic.
* **Pickling.** robosuite envs hold closures and their pickles are ~170 MB, so a
  backend pickles as its config, the reset seed and goal of the current episode and
  the actions played since; unpickling rebuilds the env and replays them, which is
  exact because the rollouts are deterministic (and costs one step per step replayed).
* **Rendering** (``render_mode="rgb_array"``) uses the shared
  :class:`unified_manip.envs.rendering.Renderer` on robosuite's model and data
  (``MUJOCO_GL=egl`` headless), from robosuite's ``frontview`` camera; image
  observations (``observation=[..., "rgb"]``) use the cameras of :mod:`.cameras`
  (``agentview`` by default). Both hide the collision geoms (group 0) as robosuite's
  own renderer does.

Modules: :mod:`.options` (the ``robot`` option), :mod:`.cameras` (the image cameras), :mod:`.suite`
(``robosuite.make`` and controller configs; imports robosuite), :mod:`.goals` and :mod:`.more_goals` (how each
env becomes a goal task) and :mod:`.two_arm_goals`, :mod:`.backend`, :mod:`.policies` and :mod:`.more_policies`, :mod:`.docs` and
:mod:`.more_docs` (with :mod:`.doc_parts`), :mod:`.specs`. Their names can also be imported from this package
(``from unified_manip.envs.tasks import robosuite_tasks as rt; rt.UPSTREAM_KWARGS``), as when
the family was one module; they are imported on first access.
"""

from unified_manip.envs.lazy import reexport
from unified_manip.envs.tasks.robosuite_tasks.specs import SPECS

__all__ = ["SPECS"]

__getattr__, __dir__ = reexport(
    __name__,
    (
        "options",
        "controllers",
        "rig",
        "suite",
        "goals",
        "two_arm_goals",
        "more_goals",
        "backend",
        "policies",
        "more_policies",
        "two_arm_policies",
        "doc_parts",
        "docs",
        "more_docs",
        "two_arm_docs",
        "specs",
    ),
)
