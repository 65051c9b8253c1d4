"""What a subcommand writes besides its main product: its ``--json`` summary."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any


def write_json(path: str | Path, document: Any) -> None:
    """Write ``document`` as indented JSON to ``path``, whole or not at all: written under a
    temporary name beside it, then moved into place (an interrupt leaves no partial file)."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.partial")
    try:
        tmp.write_text(json.dumps(document, indent=2))
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
