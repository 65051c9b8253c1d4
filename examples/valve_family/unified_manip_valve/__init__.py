"""unified_manip_valve: a family of tasks from outside unified_manip.

A planar two-link finger turns a valve to a target angle. The goal is an angle, not a
position: ``achieved_goal`` is the valve's angle, ``desired_goal`` the target, and the goal
distance is the wrapped angle between them.

Modules: :mod:`.scene` (geometry, timing, reset distributions), :mod:`.terms` (the term
set), :mod:`.observations` (the observation groups), :mod:`.backend` (the MuJoCo backend),
:mod:`.policy` (a scripted policy) and :mod:`.specs` (the task specs the entry point names).
"""

# unified_manip first, whichever module of this package is imported first: importing it
# registers this family, which imports .specs and the modules it needs. Were a module of
# this package half-way through its own imports then, .specs would find it half-built.
import unified_manip  # noqa: F401
