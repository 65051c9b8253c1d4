"""Keep third-party import-time chatter out of ``import unified_manip``.

gymnasium-robotics 1.4.2 prints a notice about its Adroit hand rewards (envs this
project does not use) to stderr on import. We drop that notice from the in-memory
notification table before the first import; nothing on disk changes.

robosuite 1.5.2 logs, through its ``robosuite_logs`` logger, warnings at import (no
private macro file, no robosuite_models, no mink whole-body IK) and INFO lines when it
loads controller configs. A filter on that logger drops its records below ERROR; they
come back when the ``robosuite_logs`` logger or the root logger is set to DEBUG
(``logging.basicConfig(level=logging.DEBUG)``). robosuite's own settings (macros,
no file logging) are untouched and nothing is written anywhere.

Set the environment variable ``UNIFIED_MANIP_VERBOSE_IMPORTS=1`` to see everything.
"""

from __future__ import annotations

import logging
import os
import sys

ROBOSUITE_LOGGER = "robosuite_logs"


class _BelowErrorUnlessDebug(logging.Filter):
    """Drop records below ERROR unless the user asked for DEBUG logging."""

    def filter(self, record: logging.LogRecord) -> bool:
        if record.levelno >= logging.ERROR:
            return True
        own = logging.getLogger(ROBOSUITE_LOGGER)
        # robosuite sets its logger to INFO itself, so DEBUG on it is a user's request.
        return own.level == logging.DEBUG or logging.getLogger().level == logging.DEBUG


def silence_import_notices() -> None:
    if os.environ.get("UNIFIED_MANIP_VERBOSE_IMPORTS"):
        return
    robosuite_logger = logging.getLogger(ROBOSUITE_LOGGER)
    if not any(isinstance(f, _BelowErrorUnlessDebug) for f in robosuite_logger.filters):
        robosuite_logger.addFilter(_BelowErrorUnlessDebug())
    if "gymnasium_robotics" in sys.modules:
        return
    try:
        import farama_notifications
    except ImportError:  # gymnasium-robotics then has nothing to print either
        return
    farama_notifications.notifications.pop("gymnasium_robotics", None)
