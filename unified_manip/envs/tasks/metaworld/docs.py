"""The Meta-World tasks' documentation pages (``unified-manip list --doc``), one per task,
written from its goal (:mod:`.tasks`)."""

from __future__ import annotations

from unified_manip.envs.controllers.docs import modes_section
from unified_manip.envs.tasks.gripper_terms import GRIPPER_TERM_SETS
from unified_manip.envs.tasks.metaworld.benchmarks import LISTS
from unified_manip.envs.tasks.metaworld.controllers import CONTROLLERS
from unified_manip.envs.tasks.metaworld.tasks import MetaWorldTask

#: Steps per episode (Meta-World's ``max_path_length``) and seconds per step.
MAX_STEPS, STEP_SECONDS = 500, 0.0125

_OBSERVATION = """Observation {size}: Meta-World's own observation without its goal (the last
3 numbers, here desired_goal), so that concat(observation, desired_goal) is Meta-World's
39-number vector with the goal shown:
    0-2    hand position (body "hand")                                m
    3      gripper opening: fingers' distance / 0.1 m, in [0, 1]       -
    4-17   objects: position and quaternion of up to two objects      m, -
           (zeros where the task has fewer)
    18-35  the same 18 numbers of the step before (Meta-World's frame stack)
{joints}The simulator state (``get_state``) does not hold the target or the objects' start:
Meta-World keeps them in the env and the model, which pickling keeps."""

_INFO = """Info adds ``native_success`` (Meta-World's own ``success``, 1.0/0.0) and
``native_reward`` (Meta-World's dense reward of the step, in [0, 10]). That reward is not a
reward_type here: it reads the target inside terms of each task's own shape (tolerance
margins from the episode's start), which hindsight relabelling cannot recompute from
the goals and the step's quantities."""


_JOINT_MODES = """The joint and end-effector modes run on a copy of Meta-World's model with the mocap weld
removed, gravity compensation on the arm, a force-limited position servo on each arm joint
(gains 1000, 1000, 500, 500, 100, 100, 100 N m/rad, critically damped at the rest pose; the
Sawyer's torque limits 80, 80, 40, 40, 9, 9, 9 N m) and an armature of 0.1 kg m^2 on the
arm joints (the model's are 0, on which the servos diverge). Meta-World's reset still
brings the hand to its start with the mocap, on its own model; the copy takes that state.
The end-effector modes' grip site is Meta-World's site endEffector, on the hand 5 mm above
the fingertips' midpoint; mink's IK holds the hand's rotation at the episode's start. In
those modes native_reward reads the gripper entry as Meta-World's grip effort."""


def _desired(task: MetaWorldTask) -> str:
    if task.target_z is None:
        return "Meta-World's target (_target_pos)"
    return f"Meta-World's target (_target_pos) at height {task.target_z:g} m, as its success reads it"


def _lists(task: MetaWorldTask) -> str:
    """The task lists paragraph: Meta-World's benchmark lists, and which hold the task."""
    names = ", ".join(f"metaworld:{name}" for name in LISTS)
    member = [name for name, tasks in LISTS.items() if task.env_name in tasks]
    return f"""Task lists: in Meta-World's {", ".join(member)}. A bench grid's tasks may name a
list in place of its IDs: {names}."""


_JOINTS = """In the joint modes, as on Fetch, the robot's joints follow:
    36-44  the 7 arm joints (right_j0 to right_j6), the 2 finger slides  rad, m
    45-53  their velocities                                           rad/s, m/s
"""

_HISTORY = """Version history: v0 initial (over Meta-World 3.1.1, MuJoCo 3.3.0). v1: in the joint and
end-effector modes, the wrists' (right_j4 to right_j6) joint damping is 1 N m s/rad, not
the model's 10: with the 9 N m limit, 10 held a wrist to 0.9 rad/s, so the hand left the
line the IK planned on fast moves. native is unchanged. v2: the joint modes observe the
robot's joints and their velocities (18 more numbers), as Fetch's joint modes do; v1's
joint-mode policies saw only the hand, so the arm's posture was hidden from them. The
other modes are unchanged."""


def task_doc(task: MetaWorldTask, wrist_damping: float | None, joint_observation: bool) -> str:
    """The page of one task whose version damps the wrists with ``wrist_damping`` N m s/rad
    (None: the model's, as every other arm joint) and, with ``joint_observation``, shows
    the joint modes the robot's joints."""
    damping = (
        "10 N m s/rad (the model's)"
        if wrist_damping is None
        else f"{wrist_damping:g} N m s/rad on the wrists (10 on the others)"
    )
    success = (
        "Success is Meta-World's own (info native_success)."
        if task.exact
        else f"Success differs from Meta-World's own (info native_success): {task.note}."
    )
    terms = GRIPPER_TERM_SETS[task.terms]
    observation = _OBSERVATION.format(
        size="(36,), and (54,) in the joint modes (below)" if joint_observation else "(36,)",
        joints=_JOINTS if joint_observation else "",
    )
    return f"""{task.name}: Meta-World's {task.env_name} (Farama Meta-World 3.1.1), as a goal task
on its Sawyer arm with a two-finger gripper.

Starting state: the object and target placement Meta-World draws at every reset from the
task's own ranges (its random reset space), seeded by reset(seed); the hand starts at
Meta-World's place for the task.

Goal (3,): achieved = {task.what}, desired = {_desired(task)}, m.
Goal distance = {task.distance.describe()} < {task.threshold:g}. {success}
Sparse reward = success - 1. {MAX_STEPS} steps of {STEP_SECONDS * 1000:g} ms.

{observation}

Action modes (native: Meta-World's (dx, dy, dz, gripper); the end-effector modes: (dx, dy,
dz, gripper); the joint modes: one entry per arm joint, right_j0 to right_j6, then the
gripper; outside native the gripper is -1 closed, +1 open):
{modes_section(CONTROLLERS)}
{_JOINT_MODES} Joint damping: {damping}.

Rewards: term set "{terms.name}": {terms.doc}, with grip_to_object the fingertips'
midpoint to the task's first object and grasped 1 while both finger pads touch one body.
{_INFO}

Scripted policy: Meta-World's own (metaworld.policies), in native. In the other modes its
actions are translated live: its mocap target (moved 1 cm per unit, clipped to the task's
mocap box) is kept, and the mode is asked for the grip site there.

{_lists(task)}

{_HISTORY}
"""
