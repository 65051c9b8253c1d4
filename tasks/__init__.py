"""Task definitions, one module per family; importing a module registers its tasks.

This folder is installed as ``unified_manip.tasks``. To add a family, add a module
here that defines a :class:`unified_manip.backend.Backend` and calls
:func:`unified_manip.registry.register_task`, and import it below.
"""

from . import arm4  # noqa: F401
from . import fetch  # noqa: F401
from . import shadow_hand  # noqa: F401
from . import robosuite_tasks  # noqa: F401
