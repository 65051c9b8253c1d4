"""Task definitions, one package per family; importing this registers every task.

This folder is installed as ``unified_manip.envs.tasks``. Each family package
(``arm4``, ``fetch``, ``shadow_hand``, ``robosuite_tasks``, ``adroit``,
``kitchen``, ``metaworld``) defines ``SPECS``, its
:class:`~unified_manip.envs.registry.TaskSpec` tuple, without importing its simulator: a
spec names its backend lazily, so the simulator is imported by the first ``gym.make``
of one of the family's IDs. A family may also define ``TASK_LISTS``, named lists of its
IDs (:mod:`unified_manip.envs.task_lists`). A family in another package registers through the
``unified_manip.families`` entry point (:mod:`unified_manip.envs.families`), after these.
"""

from unified_manip.envs.families import load_plugin_families
from unified_manip.envs.registry import register_task
from unified_manip.envs.task_lists import register_task_lists
from unified_manip.envs.tasks import adroit, arm4, fetch, kitchen, metaworld, robosuite_tasks, shadow_hand

#: The built-in families, in registration order (the order ``unified-manip list`` shows).
FAMILIES = (arm4, fetch, shadow_hand, robosuite_tasks, adroit, kitchen, metaworld)

for _spec in (spec for family in FAMILIES for spec in family.SPECS):
    register_task(_spec)
for _family in FAMILIES:  # named task lists (a bench grid's tasks: metaworld:MT10)
    # vars(), not getattr: a family's lazy __getattr__ would import its simulator for a miss.
    if vars(_family).get("TASK_LISTS"):
        register_task_lists(_family.SPECS[0].family, _family.TASK_LISTS)

#: The IDs the installed family plugins added.
PLUGIN_IDS = load_plugin_families(register_task)
