"""The 4-DOF arm family: the arm first proposed for these comparisons, its model corrected.

The model (``assets/arm4.xml``) keeps the proposed kinematic layout: a yaw joint ``j0``
on a base 0.42 m above the floor, three pitch joints ``j1``-``j3`` on links of 0.30,
0.25 and 0.10 m, and a two-finger gripper. The corrections: angles in radians,
joint damping and armature, force-limited actuators, gravity compensation on the arm
links, and fingers that reach past the palm so a top-down grasp closes on the cube.

The table top is at z = 0.42 m; the cube (5 cm, 0.1 kg) rests with its centre at
z = 0.445 m. Control runs at 50 Hz (10 substeps of 2 ms). The ``native`` mode of this
family is ``joint_delta``, as first proposed.

Modules: :mod:`.scene` (geometry, observation layout), :mod:`.goals` (reset
distributions), :mod:`.controllers` (the action modes), :mod:`.backend` (the MuJoCo backend; imports MuJoCo),
:mod:`.policies` (scripted policies), :mod:`.docs` (task documentation) and
:mod:`.specs` (the task specs). The names these modules define can also be imported
from this package (``from unified_manip.envs.tasks.arm4 import Arm4Backend``), as when the
family was one module; they are imported on first access.
"""

from unified_manip.envs.lazy import reexport
from unified_manip.envs.tasks.arm4.specs import SPECS

__all__ = ["SPECS"]

__getattr__, __dir__ = reexport(__name__, ("scene", "goals", "controllers", "backend", "policies", "docs", "specs"))
