"""Keep third-party import-time chatter out of ``import unified_manip``.

gymnasium-robotics 1.4.2 prints a notice about its Adroit hand rewards (envs this
project does not use) to stderr on import. We drop that notice from the in-memory
notification table before the first import; nothing on disk changes. Set the
environment variable ``UNIFIED_MANIP_VERBOSE_IMPORTS=1`` to see everything.
"""

from __future__ import annotations

import os
import sys


def silence_import_notices() -> None:
    if os.environ.get("UNIFIED_MANIP_VERBOSE_IMPORTS") or "gymnasium_robotics" in sys.modules:
        return
    try:
        import farama_notifications
    except ImportError:  # gymnasium-robotics then has nothing to print either
        return
    farama_notifications.notifications.pop("gymnasium_robotics", None)
