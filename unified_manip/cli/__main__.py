"""``python -m unified_manip.cli``: the same as ``unified-manip``."""

import sys

from unified_manip.cli.main import main

sys.exit(main())
